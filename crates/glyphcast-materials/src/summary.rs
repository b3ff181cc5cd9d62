//! The summary of a crystal's elastic anisotropy: a serialisable record and a text table.

use std::fmt::Write;

use serde::{Deserialize, Serialize};

use crate::averages::Vrh;
use crate::extremes::DirectionalExtremes;
use crate::stiffness::Stiffness;

/// The extremes of a modulus without their directions.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct MinMax {
    /// The smallest value.
    pub min: f64,
    /// The largest value.
    pub max: f64,
}

/// The summary ELATE reports, as JSON:
/// `{"young": {"min", "max", "min_direction", "max_direction"},
/// "linear_compressibility": {"min", "max"}, "shear": {"min", "max"},
/// "poisson": {"min", "max"}, "bulk": {"voigt", "reuss", "hill"},
/// "shear_average": {"voigt", "reuss", "hill"}}`.
///
/// Values are in the input's units (compressibility in their inverse); directions are
/// unit vectors `[x, y, z]` in the frame of the tensor summarised (the sample frame of
/// a rotated one).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Summary {
    /// Young's modulus over all directions.
    pub young: DirectionalExtremes,
    /// Linear compressibility over all directions.
    pub linear_compressibility: MinMax,
    /// Shear modulus over all perpendicular pairs of directions.
    pub shear: MinMax,
    /// Poisson's ratio over all perpendicular pairs of directions.
    pub poisson: MinMax,
    /// The averaged bulk modulus.
    pub bulk: Vrh,
    /// The averaged shear modulus.
    pub shear_average: Vrh,
}

impl Stiffness {
    /// The global extremes and averages of this stiffness.
    pub fn summary(&self) -> Summary {
        let compressibility = self.compressibility_extremes();
        let shear = self.shear_extremes();
        let poisson = self.poisson_extremes();
        let averages = self.averages();
        Summary {
            young: self.young_extremes(),
            linear_compressibility: MinMax {
                min: compressibility.min,
                max: compressibility.max,
            },
            shear: MinMax {
                min: shear.min,
                max: shear.max,
            },
            poisson: MinMax {
                min: poisson.min,
                max: poisson.max,
            },
            bulk: averages.bulk,
            shear_average: averages.shear,
        }
    }
}

impl Summary {
    /// A plain-text table like ELATE's: the averages (with the isotropic Young's
    /// modulus `9KG/(3K+G)` and Poisson's ratio `(3K-2G)/(2(3K+G))` of each), then the
    /// extremes with the anisotropy `max/min` and the axes of Young's extremes.
    /// `units` names the input's units, e.g. `"GPa"`.
    pub fn to_table(&self, units: &str) -> String {
        let mut out = String::new();
        self.write_averages(&mut out, units);
        out.push('\n');
        self.write_variations(&mut out, units);
        out
    }

    /// The table of averages.
    fn write_averages(&self, out: &mut String, units: &str) {
        let _ = writeln!(out, "Average properties");
        let headers = [
            format!("Bulk modulus ({units})"),
            format!("Young's modulus ({units})"),
            format!("Shear modulus ({units})"),
            "Poisson's ratio".to_owned(),
        ];
        // Each column two characters wider than its header, whatever the units' name.
        let widths = headers.clone().map(|h| h.chars().count().max(14) + 2);
        let _ = write!(out, "{:<8}", "");
        for (header, width) in headers.iter().zip(widths) {
            let _ = write!(out, "{header:>width$}");
        }
        out.push('\n');
        for (name, k, g) in [
            ("Voigt", self.bulk.voigt, self.shear_average.voigt),
            ("Reuss", self.bulk.reuss, self.shear_average.reuss),
            ("Hill", self.bulk.hill, self.shear_average.hill),
        ] {
            let young = 9.0 * k * g / (3.0 * k + g);
            let poisson = (3.0 * k - 2.0 * g) / (2.0 * (3.0 * k + g));
            let _ = write!(out, "{name:<8}");
            for (value, width) in [k, young, g, poisson].into_iter().zip(widths) {
                let _ = write!(out, "{:>width$}", significant(value));
            }
            out.push('\n');
        }
    }

    /// The table of extremes.
    fn write_variations(&self, out: &mut String, units: &str) {
        let _ = writeln!(out, "Variations of the elastic moduli");
        let _ = writeln!(
            out,
            "{:<34}{:>24}{:>24}{:>12}",
            "", "Min", "Max", "Anisotropy"
        );
        let rows = [
            (
                format!("Young's modulus ({units})"),
                self.young.min,
                self.young.max,
            ),
            (
                format!("Linear compressibility (1/{units})"),
                self.linear_compressibility.min,
                self.linear_compressibility.max,
            ),
            (
                format!("Shear modulus ({units})"),
                self.shear.min,
                self.shear.max,
            ),
            (
                "Poisson's ratio".to_string(),
                self.poisson.min,
                self.poisson.max,
            ),
        ];
        for (index, (name, min, max)) in rows.into_iter().enumerate() {
            let _ = writeln!(
                out,
                "{name:<34}{:>24}{:>24}{:>12}",
                significant(min),
                significant(max),
                anisotropy(min, max)
            );
            if index == 0 {
                let _ = writeln!(
                    out,
                    "{:<34}{:>24}{:>24}",
                    "  axis",
                    axis(self.young.min_direction),
                    axis(self.young.max_direction)
                );
            }
        }
    }
}

/// `max/min` where both are positive, `∞` otherwise (a sign change).
fn anisotropy(min: f64, max: f64) -> String {
    if min > 0.0 && max > 0.0 {
        format!("{:.4}", max / min)
    } else {
        "∞".to_string()
    }
}

/// A direction as three components to 4 decimals.
fn axis(u: [f64; 3]) -> String {
    format!("{:.4} {:.4} {:.4}", u[0], u[1], u[2])
}

/// `x` to 6 significant digits in fixed notation.
fn significant(x: f64) -> String {
    if x == 0.0 || !x.is_finite() {
        return format!("{x}");
    }
    let magnitude = x.abs().log10().floor() as i32;
    let decimals = (5 - magnitude).clamp(0, 12) as usize;
    format!("{x:.decimals$}")
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An allowed unstable crystal (negative bulk modulus) still summarises, without
    /// a panic, and serialises.
    #[test]
    fn unstable_crystal_summarises() {
        let (lambda, mu) = (-30.0, 30.0);
        let c: crate::Voigt = std::array::from_fn(|i| {
            std::array::from_fn(|j| match (i < 3, j < 3) {
                (true, true) => lambda + if i == j { 2.0 * mu } else { 0.0 },
                _ if i == j => mu,
                _ => 0.0,
            })
        });
        let options = crate::Options {
            allow_unstable: true,
        };
        let summary = Stiffness::with_options(c, options).unwrap().summary();
        assert!(summary.linear_compressibility.max < 0.0);
        assert!(serde_json::to_string(&summary).is_ok());
        assert!(!summary.to_table("GPa").is_empty());
    }

    /// The averages' header keeps its four titles apart (two spaces at least) whatever
    /// the units are called, and each row has a number under each.
    #[test]
    fn the_averages_columns_stay_apart() {
        let c: crate::Voigt = std::array::from_fn(|i| {
            std::array::from_fn(|j| match (i < 3, j < 3) {
                (true, true) => 50.0 + if i == j { 60.0 } else { 0.0 },
                _ if i == j => 30.0,
                _ => 0.0,
            })
        });
        let summary = Stiffness::new(c).unwrap().summary();
        for units in ["GPa", "input units", "kbar (10^8 Pa)"] {
            let table = summary.to_table(units);
            let lines: Vec<&str> = table.lines().collect();
            let titles: Vec<&str> = lines[1]
                .split("  ")
                .map(str::trim)
                .filter(|t| !t.is_empty())
                .collect();
            assert_eq!(titles.len(), 4, "{units}: {:?}", lines[1]);
            assert!(
                titles[1].starts_with("Young's modulus"),
                "{units}: {titles:?}"
            );
            for row in &lines[2..5] {
                assert_eq!(row.split_whitespace().count(), 5, "{units}: {row:?}");
            }
        }
    }

    #[test]
    fn significant_digits() {
        assert_eq!(significant(168.4), "168.400");
        assert_eq!(significant(0.00123456789), "0.00123457");
        assert_eq!(significant(-0.5), "-0.500000");
        assert_eq!(anisotropy(-0.1, 0.3), "∞");
        assert_eq!(anisotropy(2.0, 3.0), "1.5000");
    }
}
