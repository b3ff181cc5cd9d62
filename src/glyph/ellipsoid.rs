//! The diffusion-tensor ellipsoid of an order-2 symmetric tensor D (`--glyph ellipsoid`):
//! the surface { D^(1/2) u : |u| = 1 }, which for positive definite D is the quadric
//! x^T D^-1 x = 1, with semi-axes sqrt(lambda_i) along the eigenvectors of D. (The
//! polynomial glyph of the same tensor is the "peanut" r(u) = u^T D u.)
//!
//! Being a quadric, it is intersected in closed form: along q(t) = a + t d,
//! Q(q(t)) = Q(a) + t (2 a^T Q d) + t^2 Q(d) = 1 with Q = D^-1, a quadratic in t solved
//! with the cancellation-free form of its roots (`first_hit`). Its bounds are exact: the
//! bounding radius is the largest semi-axis, and the box along the eigenvectors has the
//! semi-axes as half extents.
//!
//! Tensors that are not positive definite (noise in a fitted DTI, the negative
//! eigenvalues of a bad voxel) have no ellipsoid. As mrview and FURY do, each eigenvalue
//! is raised to a floor, `EIGENVALUE_FLOOR` times the largest: a semi-axis is never
//! below 1/1000 of the longest, so a planar or linear tensor is drawn as a flat disk or a
//! thin needle rather than rejected. A tensor whose largest eigenvalue is not positive
//! (zero, or negative definite) has no surface and is left out, like a zero tensor of
//! the polynomial glyph.
use glam::{DMat3, DVec3};

use super::polynomial::GlyphPolynomial;
use super::proxy::{GlyphBounds, diagonal_directions};
use super::{Symmetry, TensorLayout};
use crate::Result;

/// The least eigenvalue drawn, relative to the largest: semi-axes (square roots) keep at
/// least 1/1000 of the longest one (module notes).
pub(crate) const EIGENVALUE_FLOOR: f64 = 1e-6;

/// The ellipsoid { D^(1/2) u } of one tensor, eigenvalues floored (module notes).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ellipsoid {
    /// Unit eigenvectors of D, a right-handed frame, ordered by decreasing eigenvalue.
    pub axes: [DVec3; 3],
    /// The semi-axes sqrt(lambda_i) along `axes`, decreasing, after the floor.
    pub semi_axes: [f64; 3],
}

/// The order-2 symmetric layout, the only one with an ellipsoid.
pub const ELLIPSOID_LAYOUT: TensorLayout = TensorLayout {
    order: 2,
    symmetry: Symmetry::Symmetric,
};

impl Ellipsoid {
    /// The ellipsoid of the symmetric tensor with unique entries (xx, xy, xz, yy, yz, zz)
    /// (the scene format's order-2 coefficients); None when its largest eigenvalue is not
    /// positive or an entry is not finite.
    pub fn from_tensor(t: &[f64]) -> Option<Ellipsoid> {
        let &[xx, xy, xz, yy, yz, zz] = t else {
            return None;
        };
        if t.iter().any(|v| !v.is_finite()) {
            return None;
        }
        let matrix = nalgebra::Matrix3::new(xx, xy, xz, xy, yy, yz, xz, yz, zz);
        let eigen = nalgebra::SymmetricEigen::new(matrix);
        let mut order = [0usize, 1, 2];
        order.sort_by(|&i, &j| eigen.eigenvalues[j].total_cmp(&eigen.eigenvalues[i]));
        let largest = eigen.eigenvalues[order[0]];
        if !(largest > 0.0 && largest.is_finite()) {
            return None;
        }
        let floor = largest * EIGENVALUE_FLOOR;
        let column = |k: usize| {
            let v = eigen.eigenvectors.column(order[k]);
            DVec3::new(v[0], v[1], v[2]).normalize()
        };
        let (a0, a1) = (column(0), column(1));
        let semi_axes = order.map(|k| eigen.eigenvalues[k].max(floor).sqrt());
        Some(Ellipsoid {
            axes: [a0, a1, a0.cross(a1)],
            semi_axes,
        })
    }

    /// The longest semi-axis: the radius of the smallest sphere about the centre that
    /// holds the ellipsoid.
    pub fn radius(&self) -> f64 {
        self.semi_axes[0]
    }

    /// The principal eigenvector (the DTI colour convention's direction).
    pub fn principal_axis(&self) -> DVec3 {
        self.axes[0]
    }

    /// Exact bounds: the sphere of the longest semi-axis and the box along the axes.
    pub fn bounds(&self) -> GlyphBounds {
        let semi_axes = DVec3::from_array(self.semi_axes);
        GlyphBounds {
            radius: self.radius(),
            axes: self.axes,
            extents: self.semi_axes,
            // The support of the ellipsoid along n (on its axes): |diag(s) n|.
            diagonals: diagonal_directions().map(|n| (n * semi_axes).length()),
        }
    }

    /// The matrix Q = V diag(1 / s_i^2) V^T of the quadric x^T Q x = 1, with the
    /// semi-axes measured in units of `unit` (Q of the ellipsoid scaled by 1 / unit).
    pub fn quadric(&self, unit: f64) -> DMat3 {
        let v = DMat3::from_cols(self.axes[0], self.axes[1], self.axes[2]);
        let inverse_squares = DVec3::from_array(self.semi_axes.map(|s| (unit / s).powi(2)));
        v * DMat3::from_diagonal(inverse_squares) * v.transpose()
    }

    /// The quadric form x^T Q x as an order-2 polynomial (in units of `unit`): what the
    /// GPU's closed-form shader reads as its coefficients, and the reference intersects.
    pub fn quadric_polynomial(&self, unit: f64) -> Result<GlyphPolynomial> {
        let q = self.quadric(unit);
        let entries = [
            q.x_axis.x, q.y_axis.x, q.z_axis.x, q.y_axis.y, q.z_axis.y, q.z_axis.z,
        ];
        GlyphPolynomial::from_tensor(ELLIPSOID_LAYOUT, &entries)
    }
}

/// The smallest t > 0 with Q(a + t d) = 1, for the quadric form `quadric` (an order-2
/// polynomial): the entry point of a ray that starts outside, the exit of one that starts
/// inside; None if the line misses or the ellipsoid lies behind. Roots by the
/// cancellation-free pair q / A and C / q.
pub fn first_hit(quadric: &GlyphPolynomial, a: DVec3, d: DVec3) -> Option<f64> {
    let line = quadric.along_line(a, d);
    let &[c0, b, c2] = line.as_slice() else {
        return None;
    };
    let c = c0 - 1.0;
    let disc = b * b - 4.0 * c2 * c;
    if !(disc > 0.0 && c2 > 0.0) {
        return None;
    }
    let q = -0.5 * (b + b.signum() * disc.sqrt());
    let (r0, r1) = (q / c2, c / q);
    let (near, far) = if r0 <= r1 { (r0, r1) } else { (r1, r0) };
    if near > 0.0 {
        Some(near)
    } else if far > 0.0 {
        Some(far)
    } else {
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::glyph::polynomial::test_support::Rng;

    /// A tensor with the given eigenvalues along a rotated frame, as unique entries.
    fn tensor(eigenvalues: [f64; 3], rotation: glam::DQuat) -> [f64; 6] {
        let v = DMat3::from_quat(rotation);
        let d = v * DMat3::from_diagonal(DVec3::from_array(eigenvalues)) * v.transpose();
        [
            d.x_axis.x, d.y_axis.x, d.z_axis.x, d.y_axis.y, d.z_axis.y, d.z_axis.z,
        ]
    }

    #[test]
    fn semi_axes_are_square_roots_of_the_eigenvalues_along_the_eigenvectors() {
        let rotation = glam::DQuat::from_euler(glam::EulerRot::XYZ, 0.3, -0.7, 1.1);
        let e = Ellipsoid::from_tensor(&tensor([4.0, 9.0, 1.0], rotation)).expect("ellipsoid");
        assert_eq!(
            e.semi_axes.map(|s| (s * 1e12).round() / 1e12),
            [3.0, 2.0, 1.0]
        );
        let y = rotation * DVec3::Y;
        assert!(e.principal_axis().dot(y).abs() > 1.0 - 1e-12);
        let frame = e.axes[0].cross(e.axes[1]).dot(e.axes[2]);
        assert!((frame - 1.0).abs() < 1e-12, "right-handed");
        // Points D^(1/2) u lie on the quadric x^T D^-1 x = 1.
        let q = e.quadric_polynomial(1.0).expect("quadric");
        let mut rng = Rng::new(3);
        for _ in 0..100 {
            let u = rng.vector(-1.0, 1.0).normalize();
            let root = e
                .axes
                .iter()
                .zip(e.semi_axes)
                .fold(DVec3::ZERO, |acc, (a, s)| acc + a * (s * a.dot(u)));
            assert!((q.eval(root) - 1.0).abs() < 1e-12);
        }
    }

    #[test]
    fn eigenvalues_below_the_floor_are_raised_and_non_positive_tensors_have_none() {
        let flat = Ellipsoid::from_tensor(&tensor([1.0, -0.5, 0.0], glam::DQuat::IDENTITY))
            .expect("floored");
        assert_eq!(flat.semi_axes, [1.0, 1e-3, 1e-3]);
        let negative = tensor([-1.0, -2.0, 0.0], glam::DQuat::IDENTITY);
        assert_eq!(Ellipsoid::from_tensor(&negative), None);
        assert_eq!(Ellipsoid::from_tensor(&[0.0; 6]), None);
        assert_eq!(
            Ellipsoid::from_tensor(&[f64::NAN, 0., 0., 1., 0., 1.]),
            None
        );
        assert_eq!(Ellipsoid::from_tensor(&[1.0; 5]), None);
    }

    #[test]
    fn hits_along_an_axis_are_at_the_semi_axis() {
        let rotation = glam::DQuat::from_euler(glam::EulerRot::XYZ, 0.2, 0.4, -0.9);
        let e = Ellipsoid::from_tensor(&tensor([0.25, 1.0, 0.04], rotation)).expect("ok");
        let q = e.quadric_polynomial(1.0).expect("quadric");
        for (axis, s) in e.axes.iter().zip(e.semi_axes) {
            // From 5 units out along the axis, towards the centre.
            let t = first_hit(&q, 5.0 * *axis, -*axis).expect("hit");
            assert!((t - (5.0 - s)).abs() < 1e-12, "{t} vs {}", 5.0 - s);
            // From the centre: the exit, at the semi-axis.
            let t = first_hit(&q, DVec3::ZERO, *axis).expect("exit");
            assert!((t - s).abs() < 1e-12);
            // Pointing away: nothing ahead.
            assert_eq!(first_hit(&q, 5.0 * *axis, *axis), None);
        }
        // A ray past the ellipsoid, just beyond its extent along axes[1].
        let past = first_hit(
            &q,
            1.001 * e.semi_axes[1] * e.axes[1] - 5.0 * e.axes[0],
            e.axes[0],
        );
        assert_eq!(past, None);
    }
}
