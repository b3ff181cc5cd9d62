//! The size of a glyph for normalisation: max over unit u of |f(u)|, from the best points
//! of a spherical Fibonacci lattice climbed to their local maxima
//! ([`climbed_max_radius`]): the lobe's peak itself (to about 1e-7 of its value), in
//! about 10 us at band 8, cheap enough for every voxel of a brain slice. (The renderer
//! computes its own guaranteed bound for the ray casting; this number only scales.) SH
//! glyphs are measured through their exact tensor form.
use glyphcast::Result;
use glyphcast::glyph::bounds::{climbed_max_radius, least_abs, sizing_lattice};
use glyphcast::glyph::ellipsoid::Ellipsoid;
use glyphcast::glyph::polynomial::GlyphPolynomial;
use glyphcast::glyph::sh;
use glyphcast::glyph::{GlyphShape, NegativeMode, Symmetry, TensorLayout};
use glyphcast::scene::GlyphKind;

/// How many of the best lattice points are climbed.
const CLIMBS: usize = 3;

/// The size of a glyph drawn as `shape`: [`max_radius`] for the polynomial glyph, the
/// longest semi-axis for the ellipsoid (0 for a tensor without one), 1 / the least |f|
/// found by the bound's search for the reciprocal glyph (0 where f vanishes), the
/// guaranteed bound for a plane or ratio glyph.
pub fn shape_radius(kind: GlyphKind, shape: GlyphShape, coeffs: &[f64]) -> Result<f64> {
    match shape {
        GlyphShape::Polynomial => max_radius(kind, coeffs),
        GlyphShape::Ellipsoid => Ok(Ellipsoid::from_tensor(coeffs).map_or(0.0, |e| e.radius())),
        GlyphShape::Reciprocal => Ok(match polynomial(kind, coeffs)? {
            Glyph::Polynomial(poly) => least_abs(&poly)
                .filter(|l| l.lower > 0.0)
                .map_or(0.0, |l| 1.0 / l.attained),
            Glyph::Sphere(radius) if radius > 0.0 => 1.0 / radius,
            Glyph::Sphere(_) => 0.0,
        }),
        // The guaranteed bound of 1/λ or |λ/Q|, 0 where the roots or Q may vanish.
        GlyphShape::PlaneMin
        | GlyphShape::PlaneMax
        | GlyphShape::RatioMin
        | GlyphShape::RatioMax => {
            use glyphcast::glyph::intersect::{plane_bound, ratio_bound};
            let bound = match shape.pair_forms(coeffs)? {
                (d, t, Some(q)) => ratio_bound(&d, &t, &q),
                (d, t, None) => plane_bound(&d, &t),
            };
            Ok(bound.unwrap_or(0.0))
        }
    }
}

/// A glyph's form: a polynomial, or (band 0 alone) a sphere of the given radius.
enum Glyph {
    Polynomial(GlyphPolynomial),
    Sphere(f64),
}

/// Max of |f(u)| over the unit sphere (climbed from the lattice), for a glyph of `kind`
/// with coefficients `coeffs`.
pub fn max_radius(kind: GlyphKind, coeffs: &[f64]) -> Result<f64> {
    Ok(match polynomial(kind, coeffs)? {
        Glyph::Polynomial(poly) => {
            climbed_max_radius(&poly, NegativeMode::Abs, sizing_lattice(), CLIMBS)
        }
        Glyph::Sphere(radius) => radius,
    })
}

/// The form of a glyph of `kind` with coefficients `coeffs`.
fn polynomial(kind: GlyphKind, coeffs: &[f64]) -> Result<Glyph> {
    let poly = match kind {
        GlyphKind::Tensor(layout) => GlyphPolynomial::from_tensor(layout, coeffs)?,
        GlyphKind::Sh {
            band,
            basis,
            legacy,
        } => {
            let (order, tensor) = sh::sh_to_tensor(band, basis, legacy, coeffs)?;
            if order == 0 {
                // Band 0 only: a sphere of radius |c|, which has no polynomial form here.
                return Ok(Glyph::Sphere(tensor.first().map_or(0.0, |c| c.abs())));
            }
            let layout = TensorLayout {
                order,
                symmetry: Symmetry::Symmetric,
            };
            GlyphPolynomial::from_tensor(layout, &tensor)?
        }
    };
    Ok(Glyph::Polynomial(poly))
}
