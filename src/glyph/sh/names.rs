//! The SH basis conventions by name: the two bases of the scene format, their names as
//! files and front ends write them, and the aliases users type (`mrtrix`, `dipy`,
//! `dipy-new`). `scene`, `fit` and `volume` take the basis from here; `convert` maps
//! coefficients between the bases.
use crate::{Error, Result, Setting};

/// The real SH basis convention of a coefficient list (docs/scene-format.md).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ShBasis {
    /// MRtrix3's basis.
    Tournier07,
    /// DIPY's default basis.
    Descoteaux07,
}

impl ShBasis {
    /// Both bases, in the scene format's order.
    pub const ALL: [ShBasis; 2] = [ShBasis::Tournier07, ShBasis::Descoteaux07];

    /// The basis's name, as the scene format and the command line write it.
    pub fn name(self) -> &'static str {
        match self {
            ShBasis::Tournier07 => "tournier07",
            ShBasis::Descoteaux07 => "descoteaux07",
        }
    }
}

/// Parses a basis name together with the legacy switch into the basis and its variant
/// ([`parse_basis_choice`] with `--legacy` as `Some(true)` and its absence as `None`).
pub fn parse_basis(name: &str, legacy: bool) -> Result<(ShBasis, bool)> {
    parse_basis_choice(name, legacy.then_some(true))
}

/// Parses a basis name (any case: `DIPY`, `Descoteaux07`) together with the legacy
/// choice into the basis and its variant. Besides the scene format's names (tournier07,
/// descoteaux07; `legacy` picks the variant, absent is the non-legacy one) three aliases
/// name a variant themselves: `mrtrix` (tournier07, as MRtrix3 writes it), `dipy`
/// (descoteaux07 legacy, DIPY's default) and `dipy-new` (descoteaux07, DIPY's
/// `legacy=False`). A legacy choice that contradicts the alias is an error; one that
/// agrees changes nothing.
pub fn parse_basis_choice(name: &str, legacy: Option<bool>) -> Result<(ShBasis, bool)> {
    let lower = name.trim().to_ascii_lowercase();
    let alias = match lower.as_str() {
        "mrtrix" => Some((ShBasis::Tournier07, false)),
        "dipy" => Some((ShBasis::Descoteaux07, true)),
        "dipy-new" => Some((ShBasis::Descoteaux07, false)),
        _ => None,
    };
    if let Some((basis, alias_legacy)) = alias {
        if let Some(legacy) = legacy
            && legacy != alias_legacy
        {
            let why = if alias_legacy {
                crate::message![
                    format!(
                        "names the legacy {} basis (DIPY's default); for the non-legacy one give ",
                        basis.name()
                    ),
                    Setting::Basis.with("dipy-new")
                ]
            } else {
                crate::message![
                    format!("names the non-legacy {} basis; leave out ", basis.name()),
                    Setting::Legacy,
                    " (or give ",
                    Setting::Basis.with(basis.name()),
                    " ",
                    Setting::Legacy,
                    ")"
                ]
            };
            return Err(Error::setting_value(
                Setting::Basis,
                format!("'{}'", crate::error::quoted(name)),
                why,
            ));
        }
        return Ok((basis, alias_legacy));
    }
    ShBasis::ALL
        .into_iter()
        .find(|&b| b.name() == lower)
        .map(|basis| (basis, legacy.unwrap_or(false)))
        .ok_or_else(|| {
            Error::setting_value(
                Setting::Basis,
                format!("'{}'", crate::error::quoted(name)),
                "unknown SH basis, expected tournier07, descoteaux07, mrtrix, dipy or dipy-new \
                 (any case)",
            )
        })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn basis_aliases_name_their_variant() {
        let parse = |name, legacy| parse_basis(name, legacy).unwrap();
        assert_eq!(parse("mrtrix", false), (ShBasis::Tournier07, false));
        assert_eq!(parse("dipy", false), (ShBasis::Descoteaux07, true));
        assert_eq!(parse("dipy", true), (ShBasis::Descoteaux07, true));
        assert_eq!(parse("dipy-new", false), (ShBasis::Descoteaux07, false));
        assert_eq!(parse("tournier07", true), (ShBasis::Tournier07, true));
        assert_eq!(parse("descoteaux07", false), (ShBasis::Descoteaux07, false));
        // Names in any case, as users type them.
        assert_eq!(parse("DIPY", false), (ShBasis::Descoteaux07, true));
        assert_eq!(parse("Descoteaux07", true), (ShBasis::Descoteaux07, true));
        assert_eq!(parse("MRtrix", false), (ShBasis::Tournier07, false));
        // An explicit non-legacy choice contradicts `dipy`.
        let err = parse_basis_choice("dipy", Some(false))
            .unwrap_err()
            .to_string();
        assert!(err.contains("dipy-new"), "{err}");
        assert_eq!(
            parse_basis_choice("dipy-new", Some(false)).unwrap(),
            (ShBasis::Descoteaux07, false)
        );
        for (name, legacy) in [("mrtrix", true), ("dipy-new", true), ("fsl", false)] {
            let err = parse_basis(name, legacy).unwrap_err().to_string();
            assert!(err.contains(name), "{err}");
        }
    }
}
