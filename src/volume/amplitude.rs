//! The size of a glyph for normalisation: max over unit u of |f(u)|, taken over a dense
//! spherical Fibonacci lattice ([`sampled_max_radius`]). A lattice of 2000 points is
//! about 0.08 rad apart, so a band-8 lobe's peak is missed by a few percent at most:
//! enough to size glyphs, and cheap enough for every voxel of a slice. (The renderer
//! computes its own guaranteed bound for the ray casting; this number only scales.)
//! SH glyphs are measured through their exact tensor form.
use crate::Result;
use crate::glyph::bounds::sampled_max_radius;
use crate::glyph::polynomial::GlyphPolynomial;
use crate::glyph::sh;
use crate::glyph::{NegativeMode, Symmetry, TensorLayout};
use crate::io::scene::GlyphKind;

/// Lattice points per glyph.
const SAMPLES: usize = 2000;

/// Max of |f(u)| over the lattice, for a glyph of `kind` with coefficients `coeffs`.
pub fn max_radius(kind: GlyphKind, coeffs: &[f64]) -> Result<f64> {
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
                return Ok(tensor.first().map_or(0.0, |c| c.abs()));
            }
            let layout = TensorLayout {
                order,
                symmetry: Symmetry::Symmetric,
            };
            GlyphPolynomial::from_tensor(layout, &tensor)?
        }
    };
    Ok(sampled_max_radius(&poly, NegativeMode::Abs, SAMPLES))
}
