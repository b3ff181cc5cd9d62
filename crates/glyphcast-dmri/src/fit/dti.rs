//! The classic diffusion tensor read off an order-2 fit: eigenvalues, principal
//! direction and fractional anisotropy (Basser and Pierpaoli 1996). CSD's response is
//! estimated from the high-FA voxels, and the ODF tests compare peaks with the principal
//! direction.
use glam::DVec3;
use nalgebra::{Matrix3, SymmetricEigen};

/// Eigen-decomposition of one diffusion tensor.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DiffusionTensor {
    /// Eigenvalues, largest first.
    pub eigenvalues: [f64; 3],
    /// Unit eigenvector of the largest eigenvalue (the principal diffusion direction).
    pub principal: DVec3,
}

impl DiffusionTensor {
    /// From the six unique coefficients of an order-2 symmetric tensor in the scene
    /// format's order (xx, xy, xz, yy, yz, zz), as `FitModel::Tensor { order: 2 }`
    /// writes them. `None` when a coefficient is not finite.
    pub fn from_coefficients(c: &[f64]) -> Option<Self> {
        if c.len() != 6 || c.iter().any(|v| !v.is_finite()) {
            return None;
        }
        let m = Matrix3::new(c[0], c[1], c[2], c[1], c[3], c[4], c[2], c[4], c[5]);
        let eigen = SymmetricEigen::new(m);
        let mut order = [0usize, 1, 2];
        order.sort_by(|&a, &b| eigen.eigenvalues[b].total_cmp(&eigen.eigenvalues[a]));
        let eigenvalues = order.map(|i| eigen.eigenvalues[i]);
        let v = eigen.eigenvectors.column(order[0]);
        let principal = DVec3::new(v[0], v[1], v[2]).normalize_or(DVec3::Z);
        Some(Self {
            eigenvalues,
            principal,
        })
    }

    /// Fractional anisotropy `sqrt(3/2) |l - <l>| / |l|` of the eigenvalues l; 0 for the
    /// zero tensor.
    pub fn fractional_anisotropy(&self) -> f64 {
        let l = self.eigenvalues;
        let mean = (l[0] + l[1] + l[2]) / 3.0;
        let deviation: f64 = l.iter().map(|v| (v - mean).powi(2)).sum();
        let norm: f64 = l.iter().map(|v| v * v).sum();
        if norm <= 0.0 {
            return 0.0;
        }
        (1.5 * deviation / norm).sqrt()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn prolate_tensor_has_its_axis_and_fa() {
        // Eigenvalues (1.7, 0.3, 0.3) e-3 with the long axis along y.
        let t =
            DiffusionTensor::from_coefficients(&[0.3e-3, 0.0, 0.0, 1.7e-3, 0.0, 0.3e-3]).unwrap();
        assert!((t.principal.y.abs() - 1.0).abs() < 1e-12);
        assert!((t.eigenvalues[0] - 1.7e-3).abs() < 1e-15);
        let (a, b) = (1.7f64, 0.3f64);
        let mean = (a + 2.0 * b) / 3.0;
        let expected =
            (1.5 * ((a - mean).powi(2) + 2.0 * (b - mean).powi(2)) / (a * a + 2.0 * b * b)).sqrt();
        assert!((t.fractional_anisotropy() - expected).abs() < 1e-12);
        let iso = DiffusionTensor::from_coefficients(&[1.0, 0.0, 0.0, 1.0, 0.0, 1.0]).unwrap();
        assert!(iso.fractional_anisotropy().abs() < 1e-12);
        assert!(DiffusionTensor::from_coefficients(&[f64::NAN; 6]).is_none());
    }
}
