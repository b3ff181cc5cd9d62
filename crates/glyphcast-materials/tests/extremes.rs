//! Global extremes against closed forms and against dense sampling (200 000 random
//! directions, float64, Voigt-form references), and the summary's shape.

mod common;

use common::*;
use glyphcast_materials::{Rotation, Stiffness, rotate};

/// How many random directions the sampling bound uses.
const SAMPLES: usize = 200_000;

/// A function of a direction to minimise.
type Objective = Box<dyn Fn([f64; 3]) -> f64>;

/// The eight extremes, each as a function of `u` to minimise (maxima negated), from
/// the Voigt-form references; for G and ν the extreme over v ⊥ u is [`plane_range`].
fn objectives(s: [[f64; 6]; 6]) -> Vec<(&'static str, Objective)> {
    let g_range = move |u: [f64; 3]| {
        let (e1, e2) = basis(u);
        // 1/G is a quadratic form in v (the formula does not normalise v).
        let (low, high) = plane_range(|x| 1.0 / shear(&s, u, x), e1, e2);
        (1.0 / high, 1.0 / low)
    };
    let nu_range = move |u: [f64; 3]| {
        let (e1, e2) = basis(u);
        plane_range(|x| poisson(&s, u, x), e1, e2)
    };
    vec![
        ("E min", Box::new(move |u| young(&s, u))),
        ("E max", Box::new(move |u| -young(&s, u))),
        ("beta min", Box::new(move |u| compressibility(&s, u))),
        ("beta max", Box::new(move |u| -compressibility(&s, u))),
        ("G min", Box::new(move |u| g_range(u).0)),
        ("G max", Box::new(move |u| -g_range(u).1)),
        ("nu min", Box::new(move |u| nu_range(u).0)),
        ("nu max", Box::new(move |u| -nu_range(u).1)),
    ]
}

/// The crate's extremes are no worse than the best of `SAMPLES` random directions and
/// agree to 1e-9 relative with that best polished by brute-force zooming; random
/// perpendicular pairs (pure brute force) never beat them; the directions and pairs
/// reported give the values reported.
fn check_against_sampling(name: &str, c: [[f64; 6]; 6]) {
    let stiffness = Stiffness::new(c).unwrap();
    let summary = stiffness.summary();
    let s = inverse(&c);
    let found = [
        summary.young.min,
        -summary.young.max,
        summary.linear_compressibility.min,
        -summary.linear_compressibility.max,
        summary.shear.min,
        -summary.shear.max,
        summary.poisson.min,
        -summary.poisson.max,
    ];
    let directions: Vec<[f64; 3]> = {
        let mut random = Random::new(2024);
        (0..SAMPLES).map(|_| random.direction()).collect()
    };
    let mut worst = 0.0_f64;
    for ((label, f), found) in objectives(s).into_iter().zip(found) {
        let (sampled, at) =
            directions
                .iter()
                .map(|&u| (f(u), u))
                .fold(
                    (f64::INFINITY, [0.0; 3]),
                    |a, b| if b.0 < a.0 { b } else { a },
                );
        let polished = zoom(&*f, at);
        let deviation = (found - polished) / polished.abs();
        worst = worst.max(deviation.abs());
        assert!(
            found <= sampled + 1e-12 * sampled.abs(),
            "{name} {label}: {found} vs {sampled}"
        );
        assert!(
            deviation.abs() < 1e-9,
            "{name} {label}: {found} vs polished {polished}"
        );
        eprintln!(
            "{name} {label}: found {:.10e}, sampled best {:+.2e} rel, polished {:+.2e} rel",
            found.abs(),
            (sampled - found) / found.abs(),
            deviation
        );
    }
    eprintln!("{name}: largest relative deviation from the polished sampling {worst:.2e}");
    // Random pairs never beat the search.
    let mut random = Random::new(99);
    for _ in 0..SAMPLES {
        let u = random.direction();
        let (v, _) = random.plane(u);
        let (g, nu) = (shear(&s, u, v), poisson(&s, u, v));
        assert!(summary.shear.min <= g * (1.0 + 1e-12) && g <= summary.shear.max * (1.0 + 1e-12));
        assert!(summary.poisson.min <= nu + 1e-12 && nu <= summary.poisson.max + 1e-12);
    }
    // Re-evaluation at the reported directions and pairs (Voigt-form reference).
    let young_at = |u: [f64; 3]| young(&s, u);
    assert!(relative(young_at(summary.young.min_direction), summary.young.min) < 1e-12);
    assert!(relative(young_at(summary.young.max_direction), summary.young.max) < 1e-12);
    let beta = stiffness.compressibility_extremes();
    assert!((compressibility(&s, beta.min_direction) - beta.min).abs() < 1e-15);
    assert!((compressibility(&s, beta.max_direction) - beta.max).abs() < 1e-15);
    let g = stiffness.shear_extremes();
    let [u, v] = g.min_pair;
    assert!(relative(shear(&s, u, v), g.min) < 1e-12);
    let [u, v] = g.max_pair;
    assert!(relative(shear(&s, u, v), g.max) < 1e-12);
    let nu = stiffness.poisson_extremes();
    for ([u, v], value) in [(nu.min_pair, nu.min), (nu.max_pair, nu.max)] {
        assert!((poisson(&s, u, v) - value).abs() < 1e-12);
        assert!((u[0] * v[0] + u[1] * v[1] + u[2] * v[2]).abs() < 1e-12);
    }
}

#[test]
fn copper_against_sampling() {
    check_against_sampling("copper", copper());
}

#[test]
fn quartz_against_sampling() {
    check_against_sampling("quartz", quartz());
}

#[test]
fn cristobalite_against_sampling() {
    check_against_sampling("cristobalite", cristobalite());
}

#[test]
fn rotated_quartz_against_sampling() {
    let g = Rotation::from_bunge_degrees(35.0, 50.0, 70.0).unwrap();
    check_against_sampling("quartz rotated", rotate(&quartz(), &g));
}

/// Copper (A = 2C44/(C11-C12) = 3.2 > 1): E is largest along <111> and smallest along
/// <100>; G ranges over [(C11-C12)/2, C44]; ν is extreme for tension along <110>
/// (Baughman et al., Nature 392, 362 (1998): negative across [1-10]).
#[test]
fn copper_extremes_are_the_closed_forms() {
    let (c11, c12, c44) = COPPER;
    let d = (c11 - c12) * (c11 + 2.0 * c12);
    let (s11, s12, s44) = ((c11 + c12) / d, -c12 / d, 1.0 / c44);
    let e111 = 1.0 / (s11 - 2.0 * (s11 - s12 - s44 / 2.0) / 3.0);
    let nu_min = -(2.0 * s11 + 2.0 * s12 - s44) / (2.0 * s11 + 2.0 * s12 + s44);
    let nu_max = -4.0 * s12 / (2.0 * s11 + 2.0 * s12 + s44);
    let summary = Stiffness::new(copper()).unwrap().summary();
    let errors = [
        relative(summary.young.min, 1.0 / s11),
        relative(summary.young.max, e111),
        relative(summary.shear.min, (c11 - c12) / 2.0),
        relative(summary.shear.max, c44),
        relative(summary.poisson.min, nu_min),
        relative(summary.poisson.max, nu_max),
    ];
    eprintln!(
        "copper relative errors (Emin Emax Gmin Gmax numin numax): {:?}",
        errors.map(|e| format!("{e:.2e}"))
    );
    assert!(errors.iter().all(|e| *e < 1e-9), "{errors:?}");
    assert!(nu_min < 0.0, "copper is auxetic across [1-10]");
    // The directions: a <100> and a <111>.
    let sorted = |u: [f64; 3]| {
        let mut a = u.map(f64::abs);
        a.sort_by(f64::total_cmp);
        a
    };
    let min_dir = sorted(summary.young.min_direction);
    let max_dir = sorted(summary.young.max_direction);
    assert!(min_dir[0] < 1e-6 && min_dir[1] < 1e-6 && (min_dir[2] - 1.0).abs() < 1e-9);
    let third = 1.0 / 3.0_f64.sqrt();
    assert!(
        max_dir.iter().all(|x| (x - third).abs() < 1e-6),
        "{max_dir:?}"
    );
}

#[test]
fn isotropic_extremes_are_constant() {
    let (k, g) = (140.0, 48.0);
    let summary = Stiffness::new(isotropic(k, g)).unwrap().summary();
    let e = 9.0 * k * g / (3.0 * k + g);
    let nu = (3.0 * k - 2.0 * g) / (2.0 * (3.0 * k + g));
    for (value, expected) in [
        (summary.young.min, e),
        (summary.young.max, e),
        (summary.shear.min, g),
        (summary.shear.max, g),
        (summary.poisson.min, nu),
        (summary.poisson.max, nu),
        (summary.linear_compressibility.min, 1.0 / (3.0 * k)),
        (summary.linear_compressibility.max, 1.0 / (3.0 * k)),
    ] {
        assert!(relative(value, expected) < 1e-12, "{value} vs {expected}");
    }
}

/// α-cristobalite: ν < 0 in some directions (down to about -0.5) and about -0.16
/// for the Hill aggregate, as Yeganeh-Haeri et al. (1992) report.
#[test]
fn cristobalite_is_auxetic() {
    let stiffness = Stiffness::new(cristobalite()).unwrap();
    let summary = stiffness.summary();
    let averages = stiffness.averages();
    let (k, g) = (averages.bulk.hill, averages.shear.hill);
    let hill_nu = (3.0 * k - 2.0 * g) / (2.0 * (3.0 * k + g));
    eprintln!(
        "cristobalite: nu in [{:.4}, {:.4}], Hill aggregate nu {hill_nu:.4}",
        summary.poisson.min, summary.poisson.max
    );
    assert!(summary.poisson.min < -0.4 && summary.poisson.min > -0.6);
    assert!((hill_nu + 0.16).abs() < 0.02, "{hill_nu}");
}

/// Extremes are rotation invariants; the reported direction moves with the frame.
#[test]
fn extremes_are_invariant_under_rotation() {
    let g = Rotation::from_bunge_degrees(123.0, 34.0, 245.0).unwrap();
    let crystal = Stiffness::new(quartz()).unwrap();
    let sample = crystal.rotated(&g);
    let (a, b) = (crystal.summary(), sample.summary());
    let pairs = [
        (a.young.min, b.young.min),
        (a.young.max, b.young.max),
        (a.linear_compressibility.min, b.linear_compressibility.min),
        (a.linear_compressibility.max, b.linear_compressibility.max),
        (a.shear.min, b.shear.min),
        (a.shear.max, b.shear.max),
        (a.poisson.min, b.poisson.min),
        (a.poisson.max, b.poisson.max),
    ];
    for (x, y) in pairs {
        assert!(relative(x, y) < 1e-9, "{x} vs {y}");
    }
    // The sample-frame direction of the maximum, taken to the crystal frame, is a
    // direction of the crystal's maximum.
    let back = g.to_crystal(b.young.max_direction);
    assert!(relative(crystal.young(back).unwrap(), a.young.max) < 1e-12);
}

#[test]
fn summary_json_has_the_agreed_shape() {
    let summary = Stiffness::new(copper()).unwrap().summary();
    let json = serde_json::to_value(summary).unwrap();
    let keys = |v: &serde_json::Value| {
        let mut k: Vec<String> = v.as_object().unwrap().keys().cloned().collect();
        k.sort();
        k
    };
    assert_eq!(
        keys(&json),
        [
            "bulk",
            "linear_compressibility",
            "poisson",
            "shear",
            "shear_average",
            "young"
        ]
    );
    assert_eq!(
        keys(&json["young"]),
        ["max", "max_direction", "min", "min_direction"]
    );
    for key in ["linear_compressibility", "shear", "poisson"] {
        assert_eq!(keys(&json[key]), ["max", "min"]);
    }
    for key in ["bulk", "shear_average"] {
        assert_eq!(keys(&json[key]), ["hill", "reuss", "voigt"]);
    }
    assert_eq!(json["young"]["max_direction"].as_array().unwrap().len(), 3);
    assert_eq!(json["bulk"]["voigt"].as_f64(), Some(summary.bulk.voigt));
    let table = summary.to_table("GPa");
    eprintln!("{table}");
    for needle in [
        "Voigt",
        "Reuss",
        "Hill",
        "Young's modulus (GPa)",
        "Poisson's ratio",
    ] {
        assert!(table.contains(needle), "{needle}");
    }
}
