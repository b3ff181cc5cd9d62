//! The order in which a file stores the six unique entries of a diffusion tensor D, and
//! the conversions to and from glyphcast's own order (the scene format's: sorted index
//! tuples in lexicographic order).
//!
//! | name | writer | stored order |
//! |---|---|---|
//! | `glyphcast` | the scene format, `glyphcast fit` to NIfTI | xx, xy, xz, yy, yz, zz |
//! | `mrtrix` | `dwi2tensor` (every `.mif` tensor) | xx, yy, zz, xy, xz, yz |
//! | `fsl` | `dtifit --save_tensor` | xx, xy, xz, yy, yz, zz |
//! | `dipy` | `TensorFit.lower_triangular()` (NIfTI's symmetric-matrix order) | xx, xy, yy, xz, yz, zz |
//!
//! FSL's order is glyphcast's, but not its frame: `dtifit` fits in the frame of FSL's
//! bvecs, the voxel axes with x negated when the affine's determinant is positive (FSL
//! flips such "neurological" images in x), so on those images its xy and xz entries have
//! the opposite sign of the voxel axes' ([`TensorOrder::negates_x`]). Higher tensor
//! orders have one order only, glyphcast's; so do non-symmetric tensors.
//!
//! A file of six values per voxel whose writer is not known may be in any of these
//! orders. Read in the wrong one, the tensors of real DTI turn indefinite (a diagonal
//! entry lands off the diagonal), so [`OrderEvidence`] counts the tensors that are not
//! positive definite in each order: when the assumed order makes many of them so and
//! another order few, the file is not in the assumed order.
use std::fmt;
use std::str::FromStr;

use crate::error::quoted;
use crate::{Error, Result, Setting};

/// The number of unique entries of a symmetric 3x3 tensor.
pub const DTI_COUNT: usize = 6;

/// The tensor with its x axis negated (F D F, F = diag(-1, 1, 1)): its xy and xz entries
/// (glyphcast's order) change sign.
pub fn negate_x(entries: &mut [f64; DTI_COUNT]) {
    entries[1] = -entries[1];
    entries[2] = -entries[2];
}

/// The stored order of a symmetric order-2 tensor's six unique entries.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
pub enum TensorOrder {
    /// xx, xy, xz, yy, yz, zz: the scene format's order (also every higher order's).
    #[default]
    Glyphcast,
    /// xx, yy, zz, xy, xz, yz: MRtrix's `dwi2tensor`.
    Mrtrix,
    /// xx, xy, xz, yy, yz, zz: FSL's `dtifit --save_tensor` (glyphcast's order, in FSL's
    /// frame: [`TensorOrder::negates_x`]).
    Fsl,
    /// xx, xy, yy, xz, yz, zz: DIPY's `lower_triangular()`.
    Dipy,
}

impl TensorOrder {
    /// Every order, glyphcast's first.
    pub const ALL: [TensorOrder; 4] = [
        TensorOrder::Glyphcast,
        TensorOrder::Mrtrix,
        TensorOrder::Fsl,
        TensorOrder::Dipy,
    ];

    /// The name of `--tensor-order` and of the record in a file.
    pub fn name(self) -> &'static str {
        match self {
            TensorOrder::Glyphcast => "glyphcast",
            TensorOrder::Mrtrix => "mrtrix",
            TensorOrder::Fsl => "fsl",
            TensorOrder::Dipy => "dipy",
        }
    }

    /// Whose order it is, for messages: glyphcast, MRtrix, FSL or DIPY.
    pub fn owner(self) -> &'static str {
        match self {
            TensorOrder::Glyphcast => "glyphcast",
            TensorOrder::Mrtrix => "MRtrix",
            TensorOrder::Fsl => "FSL",
            TensorOrder::Dipy => "DIPY",
        }
    }

    /// The stored entries spelled out, for messages and the README.
    pub fn entries(self) -> &'static str {
        match self {
            TensorOrder::Glyphcast | TensorOrder::Fsl => "xx, xy, xz, yy, yz, zz",
            TensorOrder::Mrtrix => "xx, yy, zz, xy, xz, yz",
            TensorOrder::Dipy => "xx, xy, yy, xz, yz, zz",
        }
    }

    /// For each stored position, the index of the same entry in glyphcast's order
    /// (xx 0, xy 1, xz 2, yy 3, yz 4, zz 5).
    fn positions(self) -> [usize; DTI_COUNT] {
        match self {
            TensorOrder::Glyphcast | TensorOrder::Fsl => [0, 1, 2, 3, 4, 5],
            TensorOrder::Mrtrix => [0, 3, 5, 1, 2, 4],
            TensorOrder::Dipy => [0, 1, 3, 2, 4, 5],
        }
    }

    /// Whether the stored order is glyphcast's (nothing to convert).
    pub fn is_glyphcast(self) -> bool {
        self.stores_like(TensorOrder::Glyphcast)
    }

    /// Whether the entries are in a frame whose x is the voxel axes' negated, on an image
    /// whose voxel-to-world map has this `determinant`: FSL's on a positive determinant
    /// (the frame of its bvecs, `fit::gradients::BvecConvention::Fsl`).
    pub fn negates_x(self, determinant: f64) -> bool {
        self == TensorOrder::Fsl && determinant > 0.0
    }

    /// Whether the two orders store the entries alike (glyphcast's and FSL's do).
    pub fn stores_like(self, other: TensorOrder) -> bool {
        self.positions() == other.positions()
    }

    /// Six stored entries in glyphcast's order.
    pub fn to_glyphcast(self, stored: &[f64; DTI_COUNT]) -> [f64; DTI_COUNT] {
        let mut out = [0.0; DTI_COUNT];
        for (value, position) in stored.iter().zip(self.positions()) {
            out[position] = *value;
        }
        out
    }

    /// Six entries in glyphcast's order, stored in this order.
    pub fn from_glyphcast(self, glyphcast: &[f64; DTI_COUNT]) -> [f64; DTI_COUNT] {
        self.positions().map(|position| glyphcast[position])
    }

    /// Checks that this order can store tensors of `order` (`symmetric` or not): every
    /// order stores order-2 symmetric tensors; the others are glyphcast's alone.
    pub fn check_applies(self, order: u32, symmetric: bool) -> Result<()> {
        if self.is_glyphcast() || (order == 2 && symmetric) {
            return Ok(());
        }
        Err(Error::setting_value(
            Setting::TensorOrder,
            self.name(),
            format!(
                "orders the six entries of DTI (symmetric order-2) tensors; {} tensors of \
                 order {order} are stored in glyphcast's order only",
                if symmetric {
                    "symmetric"
                } else {
                    "non-symmetric"
                }
            ),
        ))
    }
}

impl fmt::Display for TensorOrder {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for TensorOrder {
    type Err = Error;

    /// glyphcast, mrtrix, fsl or dipy, in any case.
    fn from_str(text: &str) -> Result<Self> {
        TensorOrder::ALL
            .into_iter()
            .find(|order| order.name().eq_ignore_ascii_case(text.trim()))
            .ok_or_else(|| {
                Error::setting_value(
                    Setting::TensorOrder,
                    format!("'{}'", quoted(text)),
                    "not one of glyphcast, mrtrix, fsl, dipy",
                )
            })
    }
}

/// Whether the tensor of entries `t` (glyphcast's order) is positive definite, by
/// Sylvester's criterion: its leading principal minors are all positive.
pub(crate) fn is_positive_definite(t: &[f64; DTI_COUNT]) -> bool {
    let [xx, xy, xz, yy, yz, zz] = *t;
    let minor2 = xx * yy - xy * xy;
    let det = xx * (yy * zz - yz * yz) - xy * (xy * zz - yz * xz) + xz * (xy * yz - yy * xz);
    xx > 0.0 && minor2 > 0.0 && det > 0.0
}

/// How many of a volume's tensors each stored order makes positive definite: the
/// evidence on which order six values per voxel are in.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct OrderEvidence {
    /// Tensors counted: finite, not all zero.
    pub tensors: usize,
    /// Per order of [`TensorOrder::ALL`], the tensors that are not positive definite
    /// when read in that order.
    pub not_positive: [usize; 4],
}

impl OrderEvidence {
    /// Adds one voxel's six stored values (skipped when not finite or all zero).
    pub fn add(&mut self, stored: &[f64; DTI_COUNT]) {
        if stored.iter().any(|v| !v.is_finite()) || stored.iter().all(|&v| v == 0.0) {
            return;
        }
        self.tensors += 1;
        for (count, order) in self.not_positive.iter_mut().zip(TensorOrder::ALL) {
            if !is_positive_definite(&order.to_glyphcast(stored)) {
                *count += 1;
            }
        }
    }

    /// Tensors not positive definite when read in `order`.
    pub fn not_positive_in(&self, order: TensorOrder) -> usize {
        let index = TensorOrder::ALL
            .iter()
            .position(|&o| o == order)
            .unwrap_or(0);
        self.not_positive[index]
    }

    /// The order the values point to instead of `assumed`, if any: when more than a
    /// tenth of the tensors (and at least one) are not positive definite in `assumed`
    /// and another order leaves at most a quarter as many so. Measured DTI has a few
    /// indefinite tensors from noise in any order; a wrong order makes most of them
    /// indefinite, since a diagonal entry then lands off the diagonal.
    pub fn contradicts(&self, assumed: TensorOrder) -> Option<TensorOrder> {
        let bad = self.not_positive_in(assumed);
        if bad == 0 || bad * 10 <= self.tensors {
            return None;
        }
        TensorOrder::ALL
            .into_iter()
            .filter(|order| !order.stores_like(assumed))
            .min_by_key(|&order| self.not_positive_in(order))
            .filter(|&order| self.not_positive_in(order) * 4 <= bad)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A positive definite tensor with distinct entries, in glyphcast's order.
    const D: [f64; 6] = [1.7, 0.2, -0.1, 0.6, 0.05, 0.4];

    #[test]
    fn every_order_round_trips_and_names_its_entries() {
        for order in TensorOrder::ALL {
            let stored = order.from_glyphcast(&D);
            assert_eq!(order.to_glyphcast(&stored), D, "{order}");
            assert_eq!(order.name().parse::<TensorOrder>().unwrap(), order);
            assert_eq!(
                order.name().to_uppercase().parse::<TensorOrder>().unwrap(),
                order
            );
        }
        // The stored sequences spelled by each writer's documentation.
        let [xx, xy, xz, yy, yz, zz] = D;
        assert_eq!(
            TensorOrder::Mrtrix.from_glyphcast(&D),
            [xx, yy, zz, xy, xz, yz]
        );
        assert_eq!(
            TensorOrder::Fsl.from_glyphcast(&D),
            [xx, xy, xz, yy, yz, zz]
        );
        assert_eq!(
            TensorOrder::Dipy.from_glyphcast(&D),
            [xx, xy, yy, xz, yz, zz]
        );
        assert!("lower".parse::<TensorOrder>().is_err());
    }

    #[test]
    fn only_dti_tensors_have_other_orders() {
        assert!(TensorOrder::Dipy.check_applies(2, true).is_ok());
        assert!(TensorOrder::Glyphcast.check_applies(4, true).is_ok());
        assert!(TensorOrder::Fsl.check_applies(4, true).is_ok());
        let err = TensorOrder::Mrtrix.check_applies(4, true).unwrap_err();
        assert_eq!(err.setting_of(), Some(Setting::TensorOrder));
        assert!(TensorOrder::Dipy.check_applies(2, false).is_err());
    }

    #[test]
    fn a_misread_order_shows_in_the_values() {
        assert!(is_positive_definite(&D));
        let mut evidence = OrderEvidence::default();
        for k in 0..50 {
            let scale = 1.0 + k as f64 * 0.01;
            evidence.add(&TensorOrder::Mrtrix.from_glyphcast(&D.map(|v| v * scale)));
        }
        evidence.add(&[0.0; 6]);
        evidence.add(&[f64::NAN; 6]);
        assert_eq!(evidence.tensors, 50);
        assert_eq!(evidence.not_positive_in(TensorOrder::Mrtrix), 0);
        assert_eq!(evidence.not_positive_in(TensorOrder::Glyphcast), 50);
        assert_eq!(
            evidence.contradicts(TensorOrder::Glyphcast),
            Some(TensorOrder::Mrtrix)
        );
        assert_eq!(evidence.contradicts(TensorOrder::Mrtrix), None);
        // Indefinite in every order: no order is pointed to.
        let mut indefinite = OrderEvidence::default();
        indefinite.add(&[1.0, 0.0, 0.0, -1.0, 0.0, -1.0]);
        assert_eq!(indefinite.contradicts(TensorOrder::Glyphcast), None);
    }
}
