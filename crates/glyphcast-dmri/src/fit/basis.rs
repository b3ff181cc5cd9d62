//! The SH basis the fits compute in, and what maps it to the basis asked for: shared
//! by the linear ODFs (`odf`), CSD (`csd`, `msmt`) and the response (`response`).
use nalgebra::DMatrix;

use glyphcast::Result;
use glyphcast::glyph::sh::{convert_basis, sh_count};
use glyphcast::scene::ShBasis;

/// The Legendre polynomial P_l(x), by Bonnet's recurrence.
pub(crate) fn legendre(l: u32, x: f64) -> f64 {
    let (mut prev, mut cur) = (1.0, x);
    if l == 0 {
        return 1.0;
    }
    for k in 1..l {
        let k = f64::from(k);
        (prev, cur) = (cur, ((2.0 * k + 1.0) * x * cur - k * prev) / (k + 1.0));
    }
    cur
}

/// The orthonormal basis every ODF is computed in.
pub(crate) const WORK_BASIS: (ShBasis, bool) = (ShBasis::Descoteaux07, false);

/// The matrix that maps coefficients in [`WORK_BASIS`] to `to` (a signed, scaled
/// permutation within each band).
pub(crate) fn basis_change(band: u32, to: (ShBasis, bool)) -> Result<DMatrix<f64>> {
    let k = sh_count(band);
    let mut change = DMatrix::zeros(k, k);
    for j in 0..k {
        let mut unit = vec![0.0; k];
        unit[j] = 1.0;
        let column = convert_basis(band, WORK_BASIS, to, &unit)?;
        change.column_mut(j).copy_from_slice(&column);
    }
    Ok(change)
}
