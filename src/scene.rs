//! The domain model: a scene of glyph sets (kind, order, options, and per glyph a
//! centre, a scale and coefficients), a camera and an image size. File formats read and
//! write it (`io::scene`), volumes build it (`volume`), and the renderers draw it after
//! `render::glyph_data` prepared it; none of this module does I/O.
use std::fmt;

use glam::DVec3;

use crate::camera::Camera;
use crate::glyph::monomials::symmetric_count;
pub use crate::glyph::sh::ShBasis;
use crate::glyph::{GlyphShape, NegativeMode, Symmetry, TensorLayout};
use crate::{Error, Result, Setting};

/// What the coefficients of a glyph set describe.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum GlyphKind {
    /// A Cartesian tensor of the given order and symmetry, in monomial coefficients.
    Tensor(TensorLayout),
    /// Even bands 0, 2, ..., `band`; `legacy` is DIPY's `legacy=True` variant.
    Sh {
        /// The highest band L, even.
        band: u32,
        /// The basis convention of the coefficients.
        basis: ShBasis,
        /// Whether the basis is the legacy variant (no sqrt2 factors, other phases).
        legacy: bool,
    },
}

/// Glyphs sharing kind, order and options; one center, scale and coefficient list each.
#[derive(Clone, Debug, PartialEq)]
pub struct GlyphSet {
    /// What the coefficients describe; fixes the count per glyph.
    pub kind: GlyphKind,
    /// How negative values of f are drawn.
    pub negative: NegativeMode,
    /// The polynomial glyph, or (order-2 symmetric tensors only) the DTI ellipsoid.
    pub shape: GlyphShape,
    /// Per glyph its centre, in world units.
    pub centers: Vec<DVec3>,
    /// One per glyph, expanded from `scale` when the file gives a single value.
    /// The world length of radius 1.
    pub scales: Vec<f64>,
    /// Per glyph its [`GlyphKind::coefficient_count`] coefficients, in the scene format's
    /// order.
    pub coeffs: Vec<Vec<f64>>,
}

/// The largest image side anything is drawn at, in pixels, supersampling's samples
/// included: scene files, `--width`/`--height`, montages and the viewer stop here
/// (devices commonly stop there too; a device's own smaller limit is checked when it is
/// known, `DeviceContext::max_image_dimension_2d`).
pub const MAX_IMAGE_SIDE: u32 = 16384;

/// The largest magnitude a scene value (a coefficient, a centre, a scale, a camera
/// coordinate) may have: the GPU draws in float32, where anything larger is infinite and
/// the glyph or the whole view would vanish without a word. Readers refuse larger values.
pub const MAX_SCENE_MAGNITUDE: f64 = f32::MAX as f64;

/// Whether `value` is finite and within [`MAX_SCENE_MAGNITUDE`].
pub fn fits_float32(value: f64) -> bool {
    value.abs() <= MAX_SCENE_MAGNITUDE
}

/// Output image size in pixels.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ImageSize {
    /// Columns, in pixels.
    pub width: u32,
    /// Rows, in pixels.
    pub height: u32,
}

/// Glyph sets seen by a camera, drawn at an image size (a validated scene file, or one
/// built from a volume or by code).
#[derive(Clone, Debug, PartialEq)]
pub struct Scene {
    /// The glyphs, grouped by kind and options.
    pub glyph_sets: Vec<GlyphSet>,
    /// The camera the image is seen through.
    pub camera: Camera,
    /// The output image size.
    pub image: ImageSize,
}
/// The scene format's default image side, in pixels.
const DEFAULT_IMAGE_SIDE: u32 = 512;

impl Scene {
    /// Draws every glyph set as `shape` (the glyph setting, for a whole scene): the
    /// ellipsoid only for symmetric tensors of order 2, else an [`Error::Setting`] naming
    /// the first set that is not one, and the scene is left as it was.
    pub fn set_shape(&mut self, shape: GlyphShape) -> Result<()> {
        let ellipsoid = GlyphKind::Tensor(crate::glyph::ellipsoid::ELLIPSOID_LAYOUT);
        if shape == GlyphShape::Ellipsoid
            && let Some((index, set)) = self
                .glyph_sets
                .iter()
                .enumerate()
                .find(|(_, set)| set.kind != ellipsoid)
        {
            return Err(Error::setting_value(
                Setting::Glyph,
                "ellipsoid",
                format!(
                    "draws symmetric tensors of order 2 (DTI), and glyph set {index} is a {}",
                    set.kind
                ),
            ));
        }
        self.glyph_sets.iter_mut().for_each(|set| set.shape = shape);
        Ok(())
    }
}

impl GlyphKind {
    /// Coefficients per glyph: (n+1)(n+2)/2 symmetric, 3^n non-symmetric, and for SH
    /// up to band L the same (L+1)(L+2)/2 as a symmetric tensor of order L.
    pub fn coefficient_count(&self) -> usize {
        match self {
            GlyphKind::Tensor(layout) => layout.coefficient_count(),
            GlyphKind::Sh { band, .. } => symmetric_count(*band),
        }
    }
}

impl fmt::Display for GlyphKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            GlyphKind::Tensor(TensorLayout { order, symmetry }) => {
                let symmetry = match symmetry {
                    Symmetry::Symmetric => "symmetric",
                    Symmetry::NonSymmetric => "non-symmetric",
                };
                write!(f, "{symmetry} tensor of order {order}")
            }
            GlyphKind::Sh {
                band,
                basis,
                legacy,
            } => {
                let legacy = if *legacy { "legacy " } else { "" };
                write!(f, "SH up to band {band}, {legacy}{} basis", basis.name())
            }
        }
    }
}

impl GlyphSet {
    /// Number of glyphs.
    pub fn len(&self) -> usize {
        self.centers.len()
    }

    /// Whether the set has no glyphs.
    pub fn is_empty(&self) -> bool {
        self.centers.is_empty()
    }
}

impl Default for ImageSize {
    /// The format's default, 512 x 512.
    fn default() -> Self {
        ImageSize {
            width: DEFAULT_IMAGE_SIDE,
            height: DEFAULT_IMAGE_SIDE,
        }
    }
}
