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
    /// Polynomial glyphs of `kind` from flat arrays, as an application holds them: three
    /// `centers` per glyph (x, y, z in world units), one of `scales` per glyph or one for
    /// all (the world length of radius 1), and [`GlyphKind::coefficient_count`]
    /// `coefficients` per glyph in the scene format's order (monomials for tensors, the
    /// basis's order for SH), negative lobes drawn as their absolute value. No scene or
    /// camera is needed: [`prepare_set`](crate::render::glyph_data::prepare_set) makes
    /// the set the renderers draw. Refuses arrays of lengths that disagree, values that
    /// are not finite or beyond float32, and scales that are not positive, naming the
    /// array (`source` names where they came from in the message).
    pub fn from_arrays(
        source: &str,
        kind: GlyphKind,
        centers: &[f64],
        scales: &[f64],
        coefficients: &[f64],
    ) -> Result<GlyphSet> {
        let wrong = |field: &str, message: String| Error::input(source, field, message);
        if !centers.len().is_multiple_of(3) {
            return Err(wrong(
                "centers",
                format!(
                    "3 values per glyph, and {} is not a multiple of 3",
                    centers.len()
                ),
            ));
        }
        let n = centers.len() / 3;
        if !(scales.len() == n || scales.len() == 1) {
            return Err(wrong(
                "scales",
                format!("one per glyph ({n}) or one for all, not {}", scales.len()),
            ));
        }
        let per_glyph = kind.coefficient_count();
        if coefficients.len() != n * per_glyph {
            return Err(wrong(
                "coefficients",
                format!(
                    "{per_glyph} per glyph of {kind} for {n} glyphs ({}), not {}",
                    n * per_glyph,
                    coefficients.len()
                ),
            ));
        }
        for (field, values) in [("centers", centers), ("coefficients", coefficients)] {
            if let Some(k) = values
                .iter()
                .position(|v| !(v.is_finite() && fits_float32(*v)))
            {
                return Err(wrong(
                    field,
                    format!(
                        "value {k} is {}: finite values within float32 only",
                        values[k]
                    ),
                ));
            }
        }
        if let Some(k) = scales
            .iter()
            .position(|&v| !(v > 0.0 && v.is_finite() && fits_float32(v)))
        {
            return Err(wrong(
                "scales",
                format!("value {k} is {}: positive finite values only", scales[k]),
            ));
        }
        Ok(GlyphSet {
            kind,
            negative: NegativeMode::Abs,
            shape: GlyphShape::Polynomial,
            centers: centers
                .chunks_exact(3)
                .map(|p| DVec3::new(p[0], p[1], p[2]))
                .collect(),
            scales: match scales {
                [all] => vec![*all; n],
                each => each.to_vec(),
            },
            coeffs: coefficients
                .chunks(per_glyph.max(1))
                .take(n)
                .map(<[f64]>::to_vec)
                .collect(),
        })
    }

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

#[cfg(test)]
mod array_tests {
    use super::*;

    fn sh8() -> GlyphKind {
        GlyphKind::Sh {
            band: 8,
            basis: ShBasis::Descoteaux07,
            legacy: true,
        }
    }

    #[test]
    fn arrays_make_the_set_they_describe() {
        let centers = [0.0, 1.0, 2.0, 3.0, 4.0, 5.0];
        let coefficients: Vec<f64> = (0..90).map(f64::from).collect();
        let set =
            GlyphSet::from_arrays("arrays", sh8(), &centers, &[0.4], &coefficients).expect("a set");
        assert_eq!(set.len(), 2);
        assert_eq!(set.centers[1], DVec3::new(3.0, 4.0, 5.0));
        assert_eq!(set.scales, vec![0.4, 0.4]);
        assert_eq!(set.coeffs[1][0], 45.0);
        assert_eq!(set.coeffs[1].len(), 45);
        let each = GlyphSet::from_arrays("arrays", sh8(), &centers, &[0.4, 0.5], &coefficients)
            .expect("a set");
        assert_eq!(each.scales, vec![0.4, 0.5]);
    }

    #[test]
    fn arrays_that_disagree_are_refused_with_the_array_named() {
        let coefficients = vec![1.0; 90];
        let refused = |centers: &[f64], scales: &[f64], coefficients: &[f64]| {
            GlyphSet::from_arrays("my arrays", sh8(), centers, scales, coefficients)
                .expect_err("refused")
                .to_string()
        };
        let six = [0.0; 6];
        let message = refused(&six[..5], &[1.0], &coefficients);
        assert!(message.starts_with("my arrays: centers:"), "{message}");
        assert!(refused(&six, &[1.0; 3], &coefficients).contains("scales"));
        assert!(refused(&six, &[1.0], &coefficients[..89]).contains("coefficients: 45 per glyph"));
        assert!(refused(&six, &[0.0], &coefficients).contains("scales"));
        assert!(
            refused(&[0.0, f64::NAN, 0.0, 0.0, 0.0, 0.0], &[1.0], &coefficients)
                .contains("centers: value 1 is NaN")
        );
        let mut huge = coefficients.clone();
        huge[7] = 1e300;
        assert!(refused(&six, &[1.0], &huge).contains("coefficients: value 7"));
    }
}
