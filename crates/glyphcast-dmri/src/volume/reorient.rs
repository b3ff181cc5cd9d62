//! Turning a glyph from voxel axes into world axes: g(u) = f(R^T u), where R is the
//! orthogonal polar factor of the affine's linear part (FURY issue 10 is what happens
//! without it: glyphs drawn in voxel axes on a rotated grid).
//!
//! The coefficients of a volume are taken to be in the voxel frame, the convention of
//! DIPY and of FSL's bvecs. R may be a reflection (det -1, e.g. qfac -1). For an even
//! function (every SH series, every even-order tensor) f(-u) = f(u), so R and -R give the
//! same glyph; those are rotated by whichever of the two is a proper rotation, which is
//! what SH rotation (Wigner matrices) is defined for. Odd-order tensors are not even and
//! take R itself, reflection included: a tensor rotates index by index for any orthogonal
//! matrix. A factor within 1e-9 of the identity is skipped, which spares the common
//! axis-aligned volumes both the work and the rounding.
use glam::DMat3;

use glyphcast::glyph::rotate::rotate_full_tensor;
use glyphcast::glyph::sh;
use glyphcast::glyph::{Symmetry, TensorLayout};
use glyphcast::scene::GlyphKind;
use glyphcast::{Error, Result};

/// Largest entry difference from the identity below which no rotation is applied.
const IDENTITY_TOLERANCE: f64 = 1e-9;

/// The orthogonal factor of a volume's affine, in the two forms the glyph kinds need.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Reorientation {
    /// R: voxel axes to world axes, det +1 or -1.
    pub orthogonal: DMat3,
    /// R or -R, whichever has det +1: the same map for even functions.
    pub proper: DMat3,
}

impl Reorientation {
    /// The reorientation by `orthogonal`, an orthogonal matrix (det +1 or -1) taking
    /// voxel axes to world axes.
    pub fn new(orthogonal: DMat3) -> Self {
        let proper = if orthogonal.determinant() < 0.0 {
            -orthogonal
        } else {
            orthogonal
        };
        Self { orthogonal, proper }
    }

    /// The glyph of `coeffs` (of kind `kind`, in voxel axes) in world axes.
    pub fn apply(&self, kind: GlyphKind, coeffs: &[f64]) -> Result<Vec<f64>> {
        let Some(r) = self.rotation_for(kind) else {
            return Ok(coeffs.to_vec());
        };
        match kind {
            GlyphKind::Sh {
                band,
                basis,
                legacy,
            } => sh::rotate_sh(band, basis, legacy, coeffs, r),
            GlyphKind::Tensor(TensorLayout { order, symmetry }) => match symmetry {
                Symmetry::Symmetric => sh::rotate_symmetric_tensor(order, coeffs, r),
                Symmetry::NonSymmetric => rotate_full_tensor(order, coeffs, r),
            },
        }
    }

    /// The matrix that turns glyphs of `kind`: the proper one for even functions (SH
    /// series, even-order tensors), R itself for odd orders; None near the identity.
    fn rotation_for(&self, kind: GlyphKind) -> Option<DMat3> {
        match kind {
            GlyphKind::Tensor(TensorLayout { order, .. }) if order % 2 == 1 => {
                non_identity(self.orthogonal)
            }
            _ => non_identity(self.proper),
        }
    }
}

/// Coefficient counts up to which [`Reorientation::for_kind`] builds the matrix.
const MATRIX_LIMIT: usize = 512;

/// A [`Reorientation`] for the glyphs of one kind, as a matrix on their coefficients
/// where it pays: the map is linear, so its columns are the images of the unit
/// coefficient vectors, and each voxel then costs one product (an SH series otherwise
/// costs a sampling and a fit per voxel, ~300 us at band 8). Identical to `apply` up to
/// rounding.
pub struct KindReorientation {
    reorientation: Reorientation,
    kind: GlyphKind,
    /// Row-major, count x count; None where no rotation applies or count is too large.
    matrix: Option<Vec<f64>>,
    count: usize,
}

impl KindReorientation {
    /// The glyph of `coeffs` (in voxel axes) in world axes.
    pub fn apply(&self, coeffs: &[f64]) -> Result<Vec<f64>> {
        let Some(matrix) = &self.matrix else {
            return self.reorientation.apply(self.kind, coeffs);
        };
        if coeffs.len() != self.count {
            return Err(Error::data(
                "coefficients of a glyph to reorient",
                glyphcast::error::Problem::Count {
                    expected: self.count,
                    found: coeffs.len(),
                },
            ));
        }
        Ok(matrix
            .chunks_exact(self.count)
            .map(|row| row.iter().zip(coeffs).map(|(m, c)| m * c).sum())
            .collect())
    }
}

impl Reorientation {
    /// This reorientation prepared for the glyphs of `kind` (see `KindReorientation`).
    pub fn for_kind(&self, kind: GlyphKind) -> Result<KindReorientation> {
        let count = kind.coefficient_count();
        let matrix = if self.rotation_for(kind).is_some() && count <= MATRIX_LIMIT {
            let mut matrix = vec![0.0; count * count];
            let mut unit = vec![0.0; count];
            for j in 0..count {
                unit[j] = 1.0;
                let column = self.apply(kind, &unit)?;
                unit[j] = 0.0;
                for (i, value) in column.iter().enumerate() {
                    matrix[i * count + j] = *value;
                }
            }
            Some(matrix)
        } else {
            None
        };
        Ok(KindReorientation {
            reorientation: *self,
            kind,
            matrix,
            count,
        })
    }
}

fn non_identity(r: DMat3) -> Option<DMat3> {
    let difference = (r - DMat3::IDENTITY).to_cols_array();
    let largest = difference.iter().fold(0.0f64, |m, d| m.max(d.abs()));
    (largest > IDENTITY_TOLERANCE).then_some(r)
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec3;
    use glyphcast::glyph::polynomial::GlyphPolynomial;

    fn layout(order: u32, symmetry: Symmetry) -> TensorLayout {
        TensorLayout { order, symmetry }
    }

    /// A rotation and a reflection that move every axis.
    fn matrices() -> [DMat3; 2] {
        let rotation = DMat3::from_axis_angle(DVec3::new(1.0, 2.0, -0.5).normalize(), 0.7);
        [
            rotation,
            rotation * DMat3::from_diagonal(DVec3::new(1.0, 1.0, -1.0)),
        ]
    }

    fn directions() -> impl Iterator<Item = DVec3> {
        (0..40).map(|k| {
            let t = k as f64 * 0.61;
            DVec3::new(t.cos(), (1.3 * t).sin(), (0.7 * t).cos() - 0.2).normalize()
        })
    }

    fn pseudo_random(count: usize) -> Vec<f64> {
        (0..count)
            .map(|k| ((k * 7919 % 113) as f64 / 56.0) - 1.0)
            .collect()
    }

    fn assert_rotated(kind: TensorLayout, coeffs: &[f64], r: DMat3) {
        let rotated = Reorientation::new(r)
            .apply(GlyphKind::Tensor(kind), coeffs)
            .unwrap();
        let f = GlyphPolynomial::from_tensor(kind, coeffs).unwrap();
        let g = GlyphPolynomial::from_tensor(kind, &rotated).unwrap();
        for u in directions() {
            let (expected, got) = (f.eval(r.transpose() * u), g.eval(u));
            assert!(
                (expected - got).abs() < 1e-12 * (1.0 + expected.abs()),
                "{kind:?} at {u}: {got} vs {expected}"
            );
        }
    }

    #[test]
    fn tensors_rotate_as_g_of_u_equals_f_of_r_transpose_u() {
        for r in matrices() {
            for order in 1..=5 {
                for symmetry in [Symmetry::Symmetric, Symmetry::NonSymmetric] {
                    let kind = layout(order, symmetry);
                    assert_rotated(kind, &pseudo_random(kind.coefficient_count()), r);
                }
            }
        }
    }

    #[test]
    fn odd_orders_keep_the_reflection() {
        // A vector along voxel z under a reflection of z points to world -z.
        let flip = DMat3::from_diagonal(DVec3::new(1.0, 1.0, -1.0));
        let kind = GlyphKind::Tensor(layout(1, Symmetry::Symmetric));
        let rotated = Reorientation::new(flip)
            .apply(kind, &[0.0, 0.0, 1.0])
            .unwrap();
        assert_eq!(rotated, vec![0.0, 0.0, -1.0]);
        // An even order is rotated by -R = diag(-1, -1, 1) instead, a proper rotation
        // that maps the same even glyph: a z-lobe stays a z-lobe.
        let kind = GlyphKind::Tensor(layout(2, Symmetry::Symmetric));
        let lobe = [0.1, 0.0, 0.0, 0.1, 0.0, 1.0];
        let rotated = Reorientation::new(flip).apply(kind, &lobe).unwrap();
        assert!(rotated.iter().zip(lobe).all(|(a, b)| (a - b).abs() < 1e-15));
    }

    /// The prepared matrix gives what `apply` gives, for SH series and tensors, under a
    /// rotation and a reflection; the identity prepares no matrix; a wrong count is an
    /// error.
    #[test]
    fn prepared_matrix_matches_apply() {
        let sh = GlyphKind::Sh {
            band: 8,
            basis: glyphcast::scene::ShBasis::Tournier07,
            legacy: false,
        };
        let kinds = [
            sh,
            GlyphKind::Tensor(layout(4, Symmetry::Symmetric)),
            GlyphKind::Tensor(layout(3, Symmetry::NonSymmetric)),
        ];
        for r in matrices() {
            let reorientation = Reorientation::new(r);
            for kind in kinds {
                let prepared = reorientation.for_kind(kind).unwrap();
                assert!(prepared.matrix.is_some(), "{kind:?}");
                let coeffs = pseudo_random(kind.coefficient_count());
                let direct = reorientation.apply(kind, &coeffs).unwrap();
                let through = prepared.apply(&coeffs).unwrap();
                let scale = direct.iter().fold(0.0f64, |m, v| m.max(v.abs()));
                for (a, b) in direct.iter().zip(&through) {
                    assert!((a - b).abs() < 1e-12 * scale, "{kind:?}: {a} vs {b}");
                }
                let err = prepared.apply(&coeffs[1..]).unwrap_err();
                assert!(err.to_string().contains("coefficients"), "{err}");
            }
        }
        let identity = Reorientation::new(DMat3::IDENTITY).for_kind(sh).unwrap();
        assert!(identity.matrix.is_none());
        let coeffs = pseudo_random(45);
        assert_eq!(identity.apply(&coeffs).unwrap(), coeffs);
    }

    #[test]
    fn wrong_length_is_an_error() {
        let err = rotate_full_tensor(2, &[1.0; 8], DMat3::IDENTITY).unwrap_err();
        assert!(err.to_string().contains("expected 9, found 8"), "{err}");
    }
}
