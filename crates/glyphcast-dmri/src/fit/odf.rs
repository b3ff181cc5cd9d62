//! Fibre orientation distribution functions from single-shell DWI, as SH series:
//! `glyphcast fit --odf csa|qball|csd`.
//!
//! - **Q-ball** (Descoteaux et al. 2007, "Regularized, fast, and robust analytical
//!   Q-ball imaging", MRM 58): the Funk-Radon transform of E = S/S0 (its integral over
//!   the great circle perpendicular to u) multiplies band l of E's SH series by
//!   2 pi P_l(0) (Funk-Hecke). The series of E is the Laplace-Beltrami regularised fit
//!   of `fit --sh` (`glyph::sh::ShFitter`). The result is divided by 2 pi, i.e. the ODF
//!   is the *mean* of E over the great circle (1 for E = 1), the scaling DIPY's
//!   `QballModel` writes.
//! - **CSA** (Aganj et al. 2010, "Reconstruction of the orientation distribution function
//!   in single- and multiple-shell q-ball imaging within constant solid angle", MRM 64,
//!   Eq. 13): ODF(u) = 1/(4 pi) + 1/(16 pi^2) FRT{ Delta_b ln(-ln E) }(u). With E clipped
//!   to [0.001, 0.999] so that ln(-ln E) is finite, the series of ln(-ln E) is fitted as
//!   above, band l is multiplied by 2 pi P_l(0) (-l(l+1)) / (16 pi^2) (the
//!   Laplace-Beltrami eigenvalue times the FRT), and the l = 0 coefficient is set to
//!   1/(2 sqrt(pi)), which makes the ODF integrate to 1.
//! - **CSD** (Tournier et al. 2007, "Robust determination of the fibre orientation
//!   distribution in diffusion MRI: non-negativity constrained super-resolved spherical
//!   deconvolution", NeuroImage 35): see `csd`.
//!
//! Every series is computed in the orthonormal descoteaux07 basis (the Laplace-Beltrami
//! penalty and CSD's constraint are stated for an orthonormal basis) and mapped to the
//! requested basis at the end by the exact per-band permutation of `sh::convert_basis`.
use glam::DVec3;
use nalgebra::DMatrix;

use crate::setting::DmriSetting;
use glyphcast::glyph::sh::{ShFitter, sh_count, sh_orders};
use glyphcast::scene::ShBasis;
use glyphcast::{Error, Result};

use super::basis::{WORK_BASIS, basis_change, legendre};

/// Default Laplace-Beltrami weight of CSA and Q-ball (as `fit --sh`).
pub const DEFAULT_ODF_LAMBDA: f64 = super::DEFAULT_LAMBDA;

/// The lower and upper clip of E before ln(-ln E) in CSA (Aganj et al. 2010 and DIPY
/// use these).
pub const CSA_CLIP: (f64, f64) = (0.001, 0.999);

/// Which ODF to reconstruct.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum OdfMethod {
    /// Constant solid angle ODF (Aganj et al. 2010).
    Csa,
    /// Analytical Q-ball ODF (Descoteaux et al. 2007).
    Qball,
    /// Constrained spherical deconvolution fibre ODF (Tournier et al. 2007).
    Csd,
    /// Multi-shell multi-tissue CSD (Jeurissen et al. 2014): the WM fODF (`msmt`).
    Msmt,
}

impl OdfMethod {
    /// The name `--odf` takes.
    pub fn name(self) -> &'static str {
        match self {
            OdfMethod::Csa => "csa",
            OdfMethod::Qball => "qball",
            OdfMethod::Csd => "csd",
            OdfMethod::Msmt => "msmt",
        }
    }

    /// Parses the ODF model's name.
    pub fn parse(name: &str) -> Result<Self> {
        [
            OdfMethod::Csa,
            OdfMethod::Qball,
            OdfMethod::Csd,
            OdfMethod::Msmt,
        ]
        .into_iter()
        .find(|m| m.name() == name)
        .ok_or_else(|| {
            Error::setting_value(
                DmriSetting::Odf,
                format!("'{}'", glyphcast::error::quoted(name)),
                "unknown ODF model, expected csd, msmt, csa or qball",
            )
        })
    }
}

/// CSA or Q-ball: a fixed linear map from the (transformed) samples to the ODF series.
#[derive(Clone, Debug)]
pub struct LinearOdfFitter {
    method: OdfMethod,
    /// One row per output coefficient (requested basis), one column per direction.
    matrix: DMatrix<f64>,
    /// The fixed value of the l = 0 coefficient (CSA: 1/(2 sqrt(pi))), if any.
    fixed_dc: Option<f64>,
}

impl LinearOdfFitter {
    /// The fitter for `directions` (one per diffusion-weighted volume). `method` must be
    /// CSA or Q-ball. Err when the directions do not determine the series.
    pub fn new(
        method: OdfMethod,
        band: u32,
        basis: (ShBasis, bool),
        directions: &[DVec3],
        lambda: f64,
    ) -> Result<Self> {
        let sh = ShFitter::new(band, WORK_BASIS.0, WORK_BASIS.1, directions, lambda)?;
        let n = directions.len();
        let k = sh_count(band);
        // The SH fit's solve matrix, recovered column by column from unit samples.
        let mut solve = DMatrix::zeros(k, n);
        let mut unit = vec![0.0; n];
        for i in 0..n {
            unit[i] = 1.0;
            solve.column_mut(i).copy_from_slice(&sh.fit(&unit));
            unit[i] = 0.0;
        }
        let pi = std::f64::consts::PI;
        for (row, (l, _)) in sh_orders(band).enumerate() {
            let funk_radon = 2.0 * pi * legendre(l, 0.0);
            let factor = match method {
                OdfMethod::Qball => funk_radon / (2.0 * pi),
                OdfMethod::Csa => {
                    let laplace_beltrami = -f64::from(l * (l + 1));
                    funk_radon * laplace_beltrami / (16.0 * pi * pi)
                }
                OdfMethod::Csd | OdfMethod::Msmt => {
                    return Err(Error::Call {
                        call: "LinearOdfFitter::new",
                        expected: "a linear ODF (CSD is fitted by CsdFitter or MsmtFitter)",
                    });
                }
            };
            solve.row_mut(row).scale_mut(factor);
        }
        let fixed_dc = (method == OdfMethod::Csa).then(|| 0.5 / pi.sqrt());
        Ok(Self {
            method,
            matrix: basis_change(band, basis)? * solve,
            fixed_dc,
        })
    }

    /// The model.
    pub fn method(&self) -> OdfMethod {
        self.method
    }

    /// The ODF series for E = S/S0 at the fitter's directions (one value each), in
    /// `coeffs`.
    pub fn fit_into(&self, ratio: &[f64], coeffs: &mut [f64]) {
        let transformed: Vec<f64> = match self.method {
            OdfMethod::Csa => ratio
                .iter()
                .map(|e| (-(e.clamp(CSA_CLIP.0, CSA_CLIP.1)).ln()).ln())
                .collect(),
            _ => ratio.to_vec(),
        };
        for (c, row) in coeffs.iter_mut().zip(self.matrix.row_iter()) {
            *c = row.iter().zip(&transformed).map(|(a, b)| a * b).sum();
        }
        // l = 0 is the same function in every basis, at index 0.
        if let (Some(dc), Some(first)) = (self.fixed_dc, coeffs.first_mut()) {
            *first = dc;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glyphcast::glyph::sh::sh_eval;

    #[test]
    fn legendre_matches_closed_forms() {
        for x in [-1.0, -0.3, 0.0, 0.5, 1.0] {
            assert!((legendre(2, x) - (3.0 * x * x - 1.0) / 2.0).abs() < 1e-14);
            let p4 = (35.0 * x.powi(4) - 30.0 * x * x + 3.0) / 8.0;
            assert!((legendre(4, x) - p4).abs() < 1e-14);
        }
        assert!((legendre(6, 0.0) + 5.0 / 16.0).abs() < 1e-15);
    }

    /// The Q-ball ODF of E = exp(-b D(u)) for a prolate tensor peaks on the fibre axis,
    /// and the isotropic E = 1 gives the ODF 1 everywhere (mean over a great circle).
    #[test]
    fn qball_of_a_prolate_tensor_peaks_on_its_axis() {
        let sphere = super::super::sphere::GeodesicSphere::new(5);
        let directions: Vec<DVec3> = sphere
            .vertices
            .iter()
            .copied()
            .filter(|v| v.z > 0.0 || (v.z == 0.0 && v.y > 0.0))
            .collect();
        let axis = DVec3::new(1.0, 2.0, 0.5).normalize();
        let e: Vec<f64> = directions
            .iter()
            .map(|u| (-1000.0 * (0.3e-3 + 1.4e-3 * u.dot(axis).powi(2))).exp())
            .collect();
        for basis in [(ShBasis::Tournier07, false), (ShBasis::Descoteaux07, true)] {
            let fitter =
                LinearOdfFitter::new(OdfMethod::Qball, 6, basis, &directions, 0.0).unwrap();
            let mut c = vec![0.0; sh_count(6)];
            fitter.fit_into(&e, &mut c);
            let on_axis = sh_eval(6, basis.0, basis.1, &c, axis);
            let across = sh_eval(6, basis.0, basis.1, &c, axis.any_orthonormal_vector());
            assert!(on_axis > 1.5 * across, "{on_axis} vs {across}");
            fitter.fit_into(&vec![1.0; directions.len()], &mut c);
            for u in [DVec3::X, axis] {
                assert!((sh_eval(6, basis.0, basis.1, &c, u) - 1.0).abs() < 1e-9);
            }
        }
    }
}
