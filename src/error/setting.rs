//! The options a front end hands the library, named in errors by what they are rather
//! than by how one front end spells them. The library's messages never write `--step` or
//! `step=`: they carry [`Setting`]s, as the subject of an [`Error::Setting`](super::Error)
//! or as [`Mention`]s inside any message's text, and each front end spells them its way
//! ([`Error::spelled`](super::Error::spelled)): the command line as its flags
//! (`--magnitude-range 0:1`), the Python module as its keywords (`magnitude_range=0:1`).
//! Shown as they are (`Display`), they read in the library's own words
//! (`magnitude range 0:1`).
//!
//! A mention travels inside the message text as a marker between two ASCII unit
//! separators (U+001F). User text that a message quotes goes through
//! [`quoted`](super::quoted), which escapes control characters, so no input can forge a
//! marker.
use std::fmt;

/// An option of the library's requests ([`RenderOptions`](crate::render::options),
/// `volume::VolumeRequest`, the fits and the benchmarks): what a message names when a
/// value is refused or options do not go together.
///
/// Not `non_exhaustive`: the front ends spell every setting, and a new one must be
/// spelled by each of them (their matches are exhaustive).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Setting {
    /// Image width in pixels.
    Width,
    /// Image height in pixels.
    Height,
    /// How glyphs are drawn (`fixed`, `exact`, `mesh:LEVEL`, ...).
    Method,
    /// Which ray caster runs the method: fragment or compute.
    Path,
    /// The robust methods' segment limit in pixels.
    Precision,
    /// The fixed-step march's step.
    Step,
    /// The refinement of the first sign change.
    Refine,
    /// Glyph colouring.
    Color,
    /// The magnitude colour map's range.
    MagnitudeRange,
    /// The magnitude colour bar.
    Colorbar,
    /// Negative lobes: abs or hide.
    Negative,
    /// Background colour.
    Background,
    /// Isotropic offset of every glyph.
    Offset,
    /// Direction towards the light.
    Light,
    /// Ambient share of the lighting.
    Ambient,
    /// Specular strength.
    Specular,
    /// Specular exponent.
    Shininess,
    /// Samples per pixel.
    Samples,
    /// SH basis of a volume.
    Basis,
    /// The legacy variant of the SH basis.
    Legacy,
    /// The given basis even where the file records another.
    ForceBasis,
    /// Axes of a volume's coefficients: voxel or world.
    Frame,
    /// Highest SH band drawn.
    Lmax,
    /// Tensor order (of a volume, or of a fit).
    Order,
    /// A tensor volume holds all 3^N entries.
    Nonsymmetric,
    /// The slice of a volume drawn.
    Slice,
    /// Three orthogonal slices.
    Slices,
    /// Voxel index ranges.
    Voxels,
    /// Mask of the voxels drawn.
    Mask,
    /// World radius of the largest glyph.
    Scale,
    /// Glyph size normalisation.
    Norm,
    /// Smallest glyph amplitude drawn.
    MinAmplitude,
    /// A perspective camera.
    Perspective,
    /// Radiological or neurological orientation.
    Orientation,
    /// Anatomical direction labels.
    Labels,
    /// Anatomical underlay image.
    Underlay,
    /// The underlay's window.
    UnderlayRange,
    /// Glyph surface: polynomial or ellipsoid.
    Glyph,
    /// The views of a montage.
    Views,
    /// The slice count of a lightbox.
    Lightbox,
    /// A DWI's b-values.
    Bval,
    /// A DWI's gradient directions.
    Bvec,
    /// The frame of the gradient directions.
    BvecConvention,
    /// The fibre ODF model of a fit.
    Odf,
    /// A fit's regularisation weight.
    Lambda,
    /// CSD's threshold.
    Tau,
    /// CSD's fibre response file.
    Response,
    /// The FA threshold of the response estimate.
    ResponseFa,
    /// Peaks per voxel.
    Count,
    /// The relative threshold of peaks.
    RelativeThreshold,
    /// The smallest angle between peaks.
    MinSeparation,
    /// A benchmark's generated workload.
    Workload,
}

impl Setting {
    /// Every setting.
    pub const ALL: [Setting; 52] = [
        Setting::Width,
        Setting::Height,
        Setting::Method,
        Setting::Path,
        Setting::Precision,
        Setting::Step,
        Setting::Refine,
        Setting::Color,
        Setting::MagnitudeRange,
        Setting::Colorbar,
        Setting::Negative,
        Setting::Background,
        Setting::Offset,
        Setting::Light,
        Setting::Ambient,
        Setting::Specular,
        Setting::Shininess,
        Setting::Samples,
        Setting::Basis,
        Setting::Legacy,
        Setting::ForceBasis,
        Setting::Frame,
        Setting::Lmax,
        Setting::Order,
        Setting::Nonsymmetric,
        Setting::Slice,
        Setting::Slices,
        Setting::Voxels,
        Setting::Mask,
        Setting::Scale,
        Setting::Norm,
        Setting::MinAmplitude,
        Setting::Perspective,
        Setting::Orientation,
        Setting::Labels,
        Setting::Underlay,
        Setting::UnderlayRange,
        Setting::Glyph,
        Setting::Views,
        Setting::Lightbox,
        Setting::Bval,
        Setting::Bvec,
        Setting::BvecConvention,
        Setting::Odf,
        Setting::Lambda,
        Setting::Tau,
        Setting::Response,
        Setting::ResponseFa,
        Setting::Count,
        Setting::RelativeThreshold,
        Setting::MinSeparation,
        Setting::Workload,
    ];

    /// The setting in the library's own words: lower case, words apart
    /// (`magnitude range`). Unique, and free of control characters.
    pub fn name(self) -> &'static str {
        match self {
            Setting::Width => "width",
            Setting::Height => "height",
            Setting::Method => "method",
            Setting::Path => "path",
            Setting::Precision => "precision",
            Setting::Step => "step",
            Setting::Refine => "refine",
            Setting::Color => "color",
            Setting::MagnitudeRange => "magnitude range",
            Setting::Colorbar => "colour bar",
            Setting::Negative => "negative",
            Setting::Background => "background",
            Setting::Offset => "offset",
            Setting::Light => "light",
            Setting::Ambient => "ambient",
            Setting::Specular => "specular",
            Setting::Shininess => "shininess",
            Setting::Samples => "samples",
            Setting::Basis => "basis",
            Setting::Legacy => "legacy",
            Setting::ForceBasis => "force basis",
            Setting::Frame => "frame",
            Setting::Lmax => "lmax",
            Setting::Order => "order",
            Setting::Nonsymmetric => "nonsymmetric",
            Setting::Slice => "slice",
            Setting::Slices => "slices",
            Setting::Voxels => "voxels",
            Setting::Mask => "mask",
            Setting::Scale => "scale",
            Setting::Norm => "norm",
            Setting::MinAmplitude => "minimum amplitude",
            Setting::Perspective => "perspective",
            Setting::Orientation => "orientation",
            Setting::Labels => "labels",
            Setting::Underlay => "underlay",
            Setting::UnderlayRange => "underlay range",
            Setting::Glyph => "glyph",
            Setting::Views => "views",
            Setting::Lightbox => "lightbox",
            Setting::Bval => "b-values",
            Setting::Bvec => "b-vectors",
            Setting::BvecConvention => "b-vector convention",
            Setting::Odf => "ODF model",
            Setting::Lambda => "lambda",
            Setting::Tau => "tau",
            Setting::Response => "response",
            Setting::ResponseFa => "response FA",
            Setting::Count => "count",
            Setting::RelativeThreshold => "relative threshold",
            Setting::MinSeparation => "minimum separation",
            Setting::Workload => "workload",
        }
    }

    /// The setting named in a message's text; front ends spell it as theirs
    /// (`--lmax`, `lmax=`).
    pub fn mention(self) -> Mention {
        Mention {
            setting: self,
            value: None,
        }
    }

    /// The setting with a value, named in a message's text (`use {}`, with
    /// `Setting::Method.with("fixed")`: `--method fixed`, `method=fixed`).
    pub fn with(self, value: impl fmt::Display) -> Mention {
        Mention {
            setting: self,
            value: Some(value.to_string()),
        }
    }

    /// The library's own spelling: the name, then the value if any (`step 0.0001`).
    pub fn plain(self, value: Option<&str>) -> String {
        match value {
            Some(value) => format!("{} {value}", self.name()),
            None => self.name().to_owned(),
        }
    }
}

impl fmt::Display for Setting {
    /// The name ([`Setting::name`]).
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// A [`Setting`] (and maybe its value) inside a message's text: written into the text
/// as a marker that [`spell`] replaces with a front end's spelling.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Mention {
    setting: Setting,
    value: Option<String>,
}

/// Around a marker.
const MARK: char = '\u{1f}';
/// Between a marker's setting and its value.
const VALUE: char = '\u{1e}';

impl fmt::Display for Mention {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{MARK}{}", self.setting.name())?;
        if let Some(value) = &self.value {
            // A control character would end the marker early: escaped, as quoted text is.
            write!(f, "{VALUE}")?;
            for c in value.chars() {
                if c.is_control() {
                    write!(f, "{}", c.escape_default())?;
                } else {
                    write!(f, "{c}")?;
                }
            }
        }
        write!(f, "{MARK}")
    }
}

/// `text` with each mention's marker replaced by `spell(setting, value)`. A stray
/// separator that starts no well-formed marker is dropped, so that no control character
/// reaches the user.
pub fn spell(text: &str, spell: &dyn Fn(Setting, Option<&str>) -> String) -> String {
    let mut out = String::with_capacity(text.len());
    let mut rest = text;
    while let Some(start) = rest.find(MARK) {
        out.push_str(&rest[..start]);
        let after = &rest[start + MARK.len_utf8()..];
        let Some(end) = after.find(MARK) else {
            out.push_str(after);
            return out;
        };
        let inner = &after[..end];
        let (name, value) = match inner.split_once(VALUE) {
            Some((name, value)) => (name, Some(value)),
            None => (inner, None),
        };
        match Setting::ALL.iter().find(|s| s.name() == name) {
            Some(setting) => {
                out.push_str(&spell(*setting, value));
                rest = &after[end + MARK.len_utf8()..];
            }
            None => rest = after,
        }
    }
    out.push_str(rest);
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_are_unique_and_every_setting_is_listed() {
        for (k, a) in Setting::ALL.iter().enumerate() {
            assert!(!a.name().contains(['-', '_', '=']), "{a:?}");
            for b in &Setting::ALL[k + 1..] {
                assert_ne!(a.name(), b.name(), "{a:?} and {b:?}");
            }
        }
    }

    #[test]
    fn mentions_are_spelled_by_the_front_end() {
        let text = format!(
            "{} needs offset 0; use {}",
            Setting::Method.with("exact"),
            Setting::Method.with("fixed")
        );
        let flag = |s: Setting, v: Option<&str>| match v {
            Some(v) => format!("--{} {v}", s.name()),
            None => format!("--{}", s.name()),
        };
        assert_eq!(
            spell(&text, &flag),
            "--method exact needs offset 0; use --method fixed"
        );
        assert_eq!(
            spell(&text, &|s, v| s.plain(v)),
            "method exact needs offset 0; use method fixed"
        );
    }

    #[test]
    fn values_cannot_break_a_marker_and_stray_separators_vanish() {
        let text = format!("{} and \u{1f}nonsense", Setting::Slice.with("a\u{1f}b"));
        let spelled = spell(&text, &|s, v| s.plain(v));
        assert_eq!(spelled, "slice a\\u{1f}b and nonsense");
        assert!(!spelled.chars().any(char::is_control));
    }
}
