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

/// The enum, its list and its names from one table, so that none can miss a setting.
macro_rules! settings {
    ($($(#[doc = $doc:literal])* $variant:ident => $name:literal,)*) => {
        /// An option of the library's requests ([`RenderOptions`](crate::render::options),
        /// `volume::VolumeRequest`, the fits and the benchmarks): what a message names
        /// when a value is refused or options do not go together.
        ///
        /// Not `non_exhaustive`: the front ends spell every setting, and a new one must
        /// be spelled by each of them (their matches are exhaustive).
        #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
        pub enum Setting {
            $($(#[doc = $doc])* $variant,)*
        }

        impl Setting {
            /// Every setting.
            pub const ALL: &'static [Setting] = &[$(Setting::$variant,)*];

            /// The setting in the library's own words: lower case, words apart
            /// (`magnitude range`). Unique, and free of control characters.
            pub fn name(self) -> &'static str {
                match self {
                    $(Setting::$variant => $name,)*
                }
            }
        }
    };
}

settings! {
    /// Image width in pixels.
    Width => "width",
    /// Image height in pixels.
    Height => "height",
    /// How glyphs are drawn (`fixed`, `exact`, `mesh:LEVEL`, ...).
    Method => "method",
    /// Which ray caster runs the method: fragment or compute.
    Path => "path",
    /// The robust methods' segment limit in pixels.
    Precision => "precision",
    /// The fixed-step march's step.
    Step => "step",
    /// The refinement of the first sign change.
    Refine => "refine",
    /// Glyph colouring.
    Color => "color",
    /// The magnitude colour map's range.
    MagnitudeRange => "magnitude range",
    /// The magnitude colour bar.
    Colorbar => "colour bar",
    /// Negative lobes: abs or hide.
    Negative => "negative",
    /// Background colour.
    Background => "background",
    /// Isotropic offset of every glyph.
    Offset => "offset",
    /// Direction towards the light.
    Light => "light",
    /// Ambient share of the lighting.
    Ambient => "ambient",
    /// Specular strength.
    Specular => "specular",
    /// Specular exponent.
    Shininess => "shininess",
    /// Samples per pixel.
    Samples => "samples",
    /// SH basis of a volume.
    Basis => "basis",
    /// The legacy variant of the SH basis.
    Legacy => "legacy",
    /// The given basis even where the file records another.
    ForceBasis => "force basis",
    /// Axes of a volume's coefficients: voxel or world.
    Frame => "frame",
    /// Highest SH band drawn.
    Lmax => "lmax",
    /// Tensor order (of a volume, or of a fit).
    Order => "order",
    /// A tensor volume holds all 3^N entries.
    Nonsymmetric => "nonsymmetric",
    /// The stored order of a DTI tensor's six entries (glyphcast, mrtrix, fsl, dipy).
    TensorOrder => "tensor order",
    /// The slice of a volume drawn.
    Slice => "slice",
    /// Three orthogonal slices.
    Slices => "slices",
    /// Voxel index ranges.
    Voxels => "voxels",
    /// Mask of the voxels drawn.
    Mask => "mask",
    /// World radius of the largest glyph.
    Scale => "scale",
    /// Glyph size normalisation.
    Norm => "norm",
    /// Smallest glyph amplitude drawn.
    MinAmplitude => "minimum amplitude",
    /// A perspective camera.
    Perspective => "perspective",
    /// Radiological or neurological orientation.
    Orientation => "orientation",
    /// Anatomical direction labels.
    Labels => "labels",
    /// Anatomical underlay image.
    Underlay => "underlay",
    /// The underlay's window.
    UnderlayRange => "underlay range",
    /// Where the underlay's plane lies: behind the glyphs or through their centres.
    UnderlayPlane => "underlay plane",
    /// Fibre peaks drawn over the glyphs (a peaks image).
    Peaks => "peaks",
    /// The amplitudes of unit peak directions (DIPY's peak_values).
    PeakValues => "peak values",
    /// The peaks' colour: direction or one colour.
    PeaksColor => "peaks colour",
    /// How peak lengths follow their amplitudes.
    PeaksNorm => "peaks norm",
    /// World half length of the longest peak.
    PeaksScale => "peaks scale",
    /// The peaks' width in pixels.
    PeaksWidth => "peaks width",
    /// Axes of the peaks' directions: voxel or world.
    PeaksFrame => "peaks frame",
    /// Glyph surface: polynomial or ellipsoid.
    Glyph => "glyph",
    /// The views of a montage.
    Views => "views",
    /// The slice count of a lightbox.
    Lightbox => "lightbox",
    /// A DWI's b-values.
    Bval => "b-values",
    /// A DWI's gradient directions.
    Bvec => "b-vectors",
    /// The frame of the gradient directions.
    BvecConvention => "b-vector convention",
    /// The fibre ODF model of a fit.
    Odf => "ODF model",
    /// A fit's regularisation weight.
    Lambda => "lambda",
    /// Which CSD is fitted: MRtrix's or DIPY's.
    CsdAlgorithm => "CSD algorithm",
    /// CSD's threshold.
    Tau => "tau",
    /// CSD's fibre response file.
    Response => "response",
    /// The FA threshold of the response estimate.
    ResponseFa => "response FA",
    /// Peaks per voxel.
    Count => "count",
    /// The relative threshold of peaks.
    RelativeThreshold => "relative threshold",
    /// The smallest angle between peaks.
    MinSeparation => "minimum separation",
    /// The side of each panel of a quality-control set, in pixels.
    PanelSize => "panel size",
    /// A benchmark's generated workload.
    Workload => "workload",
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
        for (k, a) in Setting::ALL.iter().enumerate() {
            assert!(!a.name().starts_with('-'), "{a:?}");
            assert!(!a.name().contains(['_', '=']), "{a:?}");
            for b in &Setting::ALL[k + 1..] {
                assert_ne!(a.name(), b.name(), "{a:?} and {b:?}");
            }
        }
    }
}
