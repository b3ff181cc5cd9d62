//! The allocation-free evaluator against the band-by-band evaluation it replaced: a
//! full table of Q_l^m (`legendre_table`, still used to build the proxy's quadrature)
//! and a table of azimuthal powers, assembled coefficient by coefficient.
use glam::DVec3;

use super::{ALL_BASES, Rng, test_directions};
use crate::glyph::sh::{
    ShBasis, ShEvaluator, legendre_index, legendre_table, sh_basis_values, sh_eval, sh_orders,
};

/// The values as the module computed them before `ShEvaluator`.
fn table_values(band: u32, basis: ShBasis, legacy: bool, u: DVec3) -> Vec<f64> {
    let u = u.normalize_or(DVec3::Z);
    let q = legendre_table(band, u.z);
    let mut powers = vec![(1.0, 0.0)];
    for k in 1..=band as usize {
        let (re, im): (f64, f64) = powers[k - 1];
        powers.push((re * u.x - im * u.y, re * u.y + im * u.x));
    }
    sh_orders(band)
        .map(|(l, m)| {
            let k = m.unsigned_abs();
            let (part, factor) = super::super::basis::basis_term(basis, legacy, m);
            let (re, im) = powers[k as usize];
            let trig = if part == super::super::basis::Part::Re {
                re
            } else {
                im
            };
            factor * q[legendre_index(l, k)] * trig
        })
        .collect()
}

#[test]
fn evaluator_matches_the_table_evaluation_in_every_band() {
    let mut rng = Rng::new(11);
    let dirs = test_directions(&mut rng, 300);
    for band in (2..=12).step_by(2).chain([16]) {
        for (basis, legacy) in ALL_BASES {
            let evaluator = ShEvaluator::new(band, basis, legacy);
            let mut got = vec![f64::NAN; evaluator.count()];
            let coeffs = rng.coefficients(evaluator.count());
            for &u in &dirs {
                // Unnormalised input is normalised the same way.
                let u = 1.7 * u;
                let want = table_values(band, basis, legacy, u);
                evaluator.values_into(u, &mut got);
                assert_eq!(got.len(), want.len());
                for ((l, m), (g, w)) in sh_orders(band).zip(got.iter().zip(&want)) {
                    // Relative to the band's bound: sum_m Y_lm^2 = (2l + 1) / (4 pi).
                    let scale = ((2 * l + 1) as f64 / (4.0 * std::f64::consts::PI)).sqrt();
                    assert!(
                        (g - w).abs() <= 1e-12 * scale.max(w.abs()),
                        "band {band} {basis:?} legacy={legacy} (l={l}, m={m}) at {u}: {g} vs {w}"
                    );
                }
                let series: f64 = want.iter().zip(&coeffs).map(|(y, c)| y * c).sum();
                let eval = evaluator.eval(&coeffs, u);
                assert!((eval - series).abs() <= 1e-12 * series.abs().max(1.0));
                assert_eq!(sh_eval(band, basis, legacy, &coeffs, u), eval);
                assert_eq!(sh_basis_values(band, basis, legacy, u), got);
            }
        }
    }
}

#[test]
fn evaluator_writes_a_short_slice_partly_and_past_the_cached_band() {
    let u = DVec3::new(0.3, -0.5, 0.8);
    let full = sh_basis_values(8, ShBasis::Tournier07, false, u);
    let mut short = [f64::NAN; 10];
    ShEvaluator::new(8, ShBasis::Tournier07, false).values_into(u, &mut short);
    assert_eq!(short[..], full[..10]);
    // Band 18 is past the shared recurrence table: its factors are computed on the way.
    let high = sh_basis_values(18, ShBasis::Descoteaux07, true, u);
    let want = table_values(18, ShBasis::Descoteaux07, true, u);
    for (g, w) in high.iter().zip(&want) {
        assert!((g - w).abs() <= 1e-12 * w.abs().max(1.0));
    }
    assert_eq!(
        sh_basis_values(7, ShBasis::Tournier07, false, u),
        full[..28]
    );
}
