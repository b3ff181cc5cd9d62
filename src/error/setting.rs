//! The options a front end hands the library, named in errors by what they are rather
//! than by how one front end spells them. The library's messages never write `--step` or
//! `step=`: they carry [`Setting`]s as typed fields (the subject of an
//! [`Error::Setting`](super::Error), the two sides of an [`Error::Conflict`](super::Error))
//! or as typed pieces of a [`Message`](super::Message), and each front end spells them its
//! way ([`Error::spelled`](super::Error::spelled)): the command line as its flags
//! (`--magnitude-range 0:1`), the Python module as its keywords (`magnitude_range=0:1`).
//! Shown as they are (`Display`), they read in the library's own words
//! (`magnitude range 0:1`).
use std::fmt;

/// A setting's spelling: its key (`magnitude_range`; the flag `--magnitude-range`, the
/// Python keyword `magnitude_range`, the C field) and its name in the library's own words
/// (`magnitude range`). Settings are constants made by [`setting!`](crate::setting): the
/// ones below, the render settings of
/// [`RENDER_SETTINGS`](crate::render::table::RENDER_SETTINGS), and a front end's own (the
/// diffusion crate's fits declare theirs). A reference to its spelling, so that errors
/// that carry settings stay small.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Setting {
    /// The spelling ([`setting!`](crate::setting) makes it).
    #[doc(hidden)]
    pub spelling: &'static SettingName,
}

/// A setting's key, name and kind (see [`Setting`]).
#[derive(Debug, PartialEq, Eq, Hash)]
pub struct SettingName {
    key: &'static str,
    name: &'static str,
    kind: Kind,
}

/// Whether a setting takes a value, and how a keyword spells a switch.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
enum Kind {
    /// A value (`--step 0.01`, `step=0.01`).
    Value,
    /// A switch, on when given (`--legacy`, `legacy=True`).
    Switch,
    /// A switch whose keyword is the opposite one (`--nonsymmetric`, `symmetric=False`).
    InvertedKeyword(&'static str),
}

/// A [`Setting`] constant: `setting!(value("lambda", "lambda"))` for a setting that takes a
/// value, `setting!(switch("legacy", "legacy"))` for a switch, and
/// `setting!(switch("nonsymmetric", "nonsymmetric").keyword_inverted("symmetric"))` for
/// a switch whose keyword says the opposite.
#[macro_export]
macro_rules! setting {
    ($ctor:ident($key:expr, $name:expr) $(.$more:ident($arg:expr))*) => {
        $crate::Setting {
            spelling: &$crate::error::SettingName::$ctor($key, $name)$(.$more($arg))*,
        }
    };
}

impl SettingName {
    /// A setting that takes a value: `key` in snake case, `name` in words.
    pub const fn value(key: &'static str, name: &'static str) -> SettingName {
        SettingName {
            key,
            name,
            kind: Kind::Value,
        }
    }

    /// A switch: on when given.
    pub const fn switch(key: &'static str, name: &'static str) -> SettingName {
        SettingName {
            key,
            name,
            kind: Kind::Switch,
        }
    }

    /// This switch with a keyword (Python's) that means the opposite, `False` for on.
    pub const fn keyword_inverted(self, keyword: &'static str) -> SettingName {
        SettingName {
            kind: Kind::InvertedKeyword(keyword),
            ..self
        }
    }
}

impl Setting {
    /// The key: snake case, the Python keyword and the C field (`magnitude_range`).
    pub fn key(self) -> &'static str {
        self.spelling.key
    }

    /// The setting in the library's own words: lower case, words apart
    /// (`magnitude range`). Unique, and free of control characters.
    pub fn name(self) -> &'static str {
        self.spelling.name
    }

    /// The command line's flag: the key with `-` for `_` (`--magnitude-range`).
    pub fn flag(self) -> String {
        format!("--{}", self.key().replace('_', "-"))
    }

    /// The keyword (Python's): the key, or the opposite switch's.
    pub fn keyword(self) -> &'static str {
        match self.spelling.kind {
            Kind::InvertedKeyword(keyword) => keyword,
            _ => self.key(),
        }
    }

    /// For a switch, the keyword's value that turns it on (`True`, or `False` for an
    /// inverted keyword); `None` for a setting that takes a value.
    pub fn keyword_on(self) -> Option<&'static str> {
        match self.spelling.kind {
            Kind::Value => None,
            Kind::Switch => Some("True"),
            Kind::InvertedKeyword(_) => Some("False"),
        }
    }
}

/// The constants and their list from one table, so that the list misses none.
macro_rules! settings {
    ($($(#[doc = $doc:literal])* $variant:ident = $ctor:ident($key:literal, $name:literal) $(.$more:ident($arg:literal))*;)*) => {
        /// The settings of figures and volumes; the render settings are
        /// [`RENDER_SETTINGS`](crate::render::table::RENDER_SETTINGS)'.
        #[allow(non_upper_case_globals)]
        impl Setting {
            $($(#[doc = $doc])* pub const $variant: Setting =
                crate::setting!($ctor($key, $name)$(.$more($arg))*);)*

            /// Every setting declared here (the render settings are in
            /// [`RENDER_SETTINGS`](crate::render::table::RENDER_SETTINGS)).
            pub const ALL: &'static [Setting] = &[$(Setting::$variant,)*];
        }
    };
}

settings! {
    /// Image width in pixels.
    Width = value("width", "width");
    /// Image height in pixels.
    Height = value("height", "height");
    /// A factor on the image's size that keeps its framing.
    ScaleFactor = value("scale_factor", "scale factor");
    /// The print resolution recorded in a PNG.
    Dpi = value("dpi", "dpi");
    /// The magnitude colour bar.
    Colorbar = value("colorbar", "colour bar");
    /// SH basis of a volume.
    Basis = value("basis", "basis");
    /// The legacy variant of the SH basis.
    Legacy = switch("legacy", "legacy");
    /// The given basis even where the file records another.
    ForceBasis = switch("force_basis", "force basis");
    /// Axes of a volume's coefficients: voxel or world.
    Frame = value("frame", "frame");
    /// Highest SH band drawn.
    Lmax = value("lmax", "lmax");
    /// Tensor order (of a volume, or of a fit).
    Order = value("order", "order");
    /// A tensor volume holds all 3^N entries.
    Nonsymmetric = switch("nonsymmetric", "nonsymmetric").keyword_inverted("symmetric");
    /// The stored order of a DTI tensor's six entries (glyphcast, mrtrix, fsl, dipy).
    TensorOrder = value("tensor_order", "tensor order");
    /// The slice of a volume drawn.
    Slice = value("slice", "slice");
    /// Three orthogonal slices.
    Slices = value("slices", "slices");
    /// Every voxel of the voxel ranges, in 3D.
    Block = switch("block", "block");
    /// Voxel index ranges.
    Voxels = value("voxels", "voxels");
    /// Mask of the voxels drawn.
    Mask = value("mask", "mask");
    /// World radius of the largest glyph.
    Scale = value("scale", "scale");
    /// Glyph size normalisation.
    Norm = value("norm", "norm");
    /// Smallest glyph amplitude drawn.
    MinAmplitude = value("min_amplitude", "minimum amplitude");
    /// A perspective camera.
    Perspective = switch("perspective", "perspective");
    /// Radiological or neurological orientation.
    Orientation = value("orientation", "orientation");
    /// Anatomical direction labels.
    Labels = switch("labels", "labels");
    /// Anatomical underlay image.
    Underlay = value("underlay", "underlay");
    /// The underlay's window.
    UnderlayRange = value("underlay_range", "underlay range");
    /// Where the underlay's plane lies: behind the glyphs or through their centres.
    UnderlayPlane = value("underlay_plane", "underlay plane");
    /// Fibre peaks drawn over the glyphs (a peaks image).
    Peaks = value("peaks", "peaks");
    /// The amplitudes of unit peak directions (DIPY's peak_values).
    PeakValues = value("peak_values", "peak values");
    /// The peaks' colour: direction or one colour.
    PeaksColor = value("peaks_color", "peaks colour");
    /// How peak lengths follow their amplitudes.
    PeaksNorm = value("peaks_norm", "peaks norm");
    /// World half length of the longest peak.
    PeaksScale = value("peaks_scale", "peaks scale");
    /// The peaks' width in pixels.
    PeaksWidth = value("peaks_width", "peaks width");
    /// Axes of the peaks' directions: voxel or world.
    PeaksFrame = value("peaks_frame", "peaks frame");
    /// Glyph surface: polynomial or ellipsoid.
    Glyph = value("glyph", "glyph");
    /// The views of a montage.
    Views = value("views", "views");
    /// The slice count of a lightbox.
    Lightbox = value("lightbox", "lightbox");
    /// A benchmark's generated workload.
    Workload = value("workload", "workload");
}

impl Setting {
    /// The setting with a value, as a piece of a [`Message`](super::Message)
    /// (`Setting::Method.with("fixed")`: `--method fixed`, `method=fixed`).
    pub fn with(self, value: impl fmt::Display) -> super::Piece {
        super::Piece::Setting(self, Some(value.to_string()))
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_are_unique_and_read_as_words() {
        let all: Vec<Setting> = Setting::ALL
            .iter()
            .copied()
            .chain(
                crate::render::table::RENDER_SETTINGS
                    .iter()
                    .map(|s| s.setting),
            )
            .collect();
        for (k, a) in all.iter().enumerate() {
            assert!(!a.name().starts_with('-'), "{a:?}");
            assert!(!a.name().contains(['_', '=']), "{a:?}");
            for b in &all[k + 1..] {
                assert_ne!(a.key(), b.key(), "{a:?} and {b:?}");
                assert_ne!(a.name(), b.name(), "{a:?} and {b:?}");
            }
        }
    }
}
