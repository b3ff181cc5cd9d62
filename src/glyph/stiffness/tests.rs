use glam::{DMat3, DVec3};

use super::*;
use crate::glyph::polynomial::GlyphPolynomial;
use crate::glyph::polynomial::test_support::Rng;
use crate::glyph::{Symmetry, TensorLayout};

/// Copper, GPa (Simmons and Wang 1971, as quoted in most textbooks).
fn copper() -> VoigtStiffness {
    VoigtStiffness::cubic(168.4, 121.4, 75.4)
}

fn entry(full: &[f64], i: usize, j: usize, k: usize, l: usize) -> f64 {
    full[((i * 3 + j) * 3 + k) * 3 + l]
}

fn polynomial(symmetry: Symmetry, coeffs: &[f64]) -> GlyphPolynomial {
    GlyphPolynomial::from_tensor(TensorLayout { order: 4, symmetry }, coeffs).unwrap()
}

/// A symmetric matrix with every entry distinct, so that a wrong permutation shows.
fn general_matrix() -> [[f64; 6]; 6] {
    std::array::from_fn(|p| {
        std::array::from_fn(|q| 10.0 * (p.min(q) + 1) as f64 + (p.max(q) + 1) as f64)
    })
}

#[test]
fn copper_has_minor_and_major_symmetries_and_its_constants() {
    let c = copper().full_tensor();
    assert_eq!(c.len(), 81);
    for flat in 0..81 {
        let [i, j, k, l] = indices(flat);
        let v = entry(&c, i, j, k, l);
        assert_eq!(v, entry(&c, j, i, k, l), "minor ij at {flat}");
        assert_eq!(v, entry(&c, i, j, l, k), "minor kl at {flat}");
        assert_eq!(v, entry(&c, k, l, i, j), "major at {flat}");
    }
    // 1-based C_1111, C_1122, C_2323 are 0-based (0000), (0011), (1212).
    assert_eq!(entry(&c, 0, 0, 0, 0), 168.4);
    assert_eq!(entry(&c, 0, 0, 1, 1), 121.4);
    assert_eq!(entry(&c, 1, 2, 1, 2), 75.4);
    assert_eq!(entry(&c, 1, 2, 2, 1), 75.4);
    assert_eq!(entry(&c, 0, 0, 1, 2), 0.0);
}

#[test]
fn voigt_index_maps_pairs_both_ways() {
    let pairs = [(0, 0), (1, 1), (2, 2), (1, 2), (0, 2), (0, 1)];
    for (p, &(i, j)) in pairs.iter().enumerate() {
        assert_eq!(voigt_index(i, j), p);
        assert_eq!(voigt_index(j, i), p);
    }
}

#[test]
fn shear_orders_agree_when_the_matrix_is_permuted() {
    let standard = general_matrix();
    // 12,13,23 lists rows 4 and 6 of the standard order swapped.
    let swap = [0, 1, 2, 5, 4, 3];
    let mut reversed = [[0.0; 6]; 6];
    for p in 0..6 {
        for q in 0..6 {
            reversed[p][q] = standard[swap[p]][swap[q]];
        }
    }
    let a = VoigtStiffness::from_matrix(standard, ShearOrder::Standard, "a").unwrap();
    let b = VoigtStiffness::from_matrix(reversed, ShearOrder::Reversed, "b").unwrap();
    assert_eq!(a.full_tensor(), b.full_tensor());
    assert_eq!(b.in_order(ShearOrder::Reversed), reversed);
    // C_1212 is row 6 in the standard order and row 4 in the reversed one.
    assert_eq!(entry(&a.full_tensor(), 0, 1, 0, 1), standard[5][5]);
    assert_eq!(entry(&b.full_tensor(), 0, 1, 0, 1), reversed[3][3]);
    // Same matrix read with the other order is another tensor.
    let c = VoigtStiffness::from_matrix(standard, ShearOrder::Reversed, "c").unwrap();
    assert_ne!(a.full_tensor(), c.full_tensor());
}

#[test]
fn symmetric_part_is_the_same_glyph_function() {
    let mut rng = Rng::new(40);
    let rotation = DMat3::from_axis_angle(DVec3::new(1.0, 2.0, 0.5).normalize(), 0.7);
    let general = VoigtStiffness::from_matrix(general_matrix(), ShearOrder::Standard, "g").unwrap();
    for stiffness in [copper(), general] {
        for full in [stiffness.full_tensor(), stiffness.rotated(rotation)] {
            let sym = fully_symmetric_part(4, &full);
            let f_full = polynomial(Symmetry::NonSymmetric, &full);
            let f_sym = polynomial(Symmetry::Symmetric, &sym);
            for _ in 0..50 {
                let u = rng.unit_vector();
                let (a, b) = (f_full.eval(u), f_sym.eval(u));
                assert!((a - b).abs() < 1e-12 * f_full.abs_eval(u), "{a} vs {b}");
            }
        }
    }
    // For a cubic crystal: sym_1122 = (C12 + 2 C44) / 3 (unique entry 0011 is index 3).
    let sym = copper().symmetric_part();
    assert!((sym[3] - (121.4 + 2.0 * 75.4) / 3.0).abs() < 1e-12);
    assert_eq!(sym[0], 168.4);
}

#[test]
fn rotation_turns_the_glyph_and_keeps_the_symmetries() {
    let rotation = DMat3::from_rotation_z(0.4) * DMat3::from_rotation_x(-1.1);
    let c = copper().full_tensor();
    let turned = copper().rotated(rotation);
    let f = polynomial(Symmetry::NonSymmetric, &c);
    let g = polynomial(Symmetry::NonSymmetric, &turned);
    let mut rng = Rng::new(41);
    for _ in 0..20 {
        let u = rng.unit_vector();
        assert!((g.eval(rotation * u) - f.eval(u)).abs() < 1e-10);
    }
    for flat in 0..81 {
        let [i, j, k, l] = indices(flat);
        let v = entry(&turned, i, j, k, l);
        assert!((v - entry(&turned, j, i, l, k)).abs() < 1e-10);
        assert!((v - entry(&turned, k, l, i, j)).abs() < 1e-10);
    }
}

#[test]
fn reads_csv_and_json_alike() {
    let csv = "# copper, GPa\n168.4, 121.4, 121.4, 0, 0, 0\n121.4 168.4 121.4 0 0 0 # row 2\n\n\
               121.4,121.4,168.4,0,0,0\n0 0 0 75.4 0 0\n0 0 0 0 75.4 0\n0 0 0 0 0 75.4\n";
    let json = r#"{"voigt": [[168.4,121.4,121.4,0,0,0],[121.4,168.4,121.4,0,0,0],
        [121.4,121.4,168.4,0,0,0],[0,0,0,75.4,0,0],[0,0,0,0,75.4,0],[0,0,0,0,0,75.4]],
        "shear_order": "12, 13, 23"}"#;
    let a = VoigtStiffness::from_text(csv, "cu.csv", None).unwrap();
    let b = VoigtStiffness::from_text(json, "cu.json", None).unwrap();
    assert_eq!(a, copper());
    assert_eq!(b, copper());
    let err = VoigtStiffness::from_text(json, "cu.json", Some(ShearOrder::Standard)).unwrap_err();
    assert!(err.to_string().contains("shear_order"), "{err}");
}

#[test]
fn bad_files_name_file_and_problem() {
    let err = |text: &str| {
        VoigtStiffness::from_text(text, "bad.csv", None)
            .unwrap_err()
            .to_string()
    };
    let row = "1 0 0 0 0 0\n";
    let five_rows = row.repeat(5);
    assert!(err(&five_rows).contains("5 rows"));
    assert!(err(&format!("{five_rows}1 2 3 4 5\n")).contains("line 6: 5 numbers"));
    assert!(err(&format!("{five_rows}1 2 x 4 5 6\n")).contains("'x' is not a number"));
    let text = |m: [[f64; 6]; 6]| -> String {
        m.iter()
            .map(|r| format!("{}\n", r.map(|v| v.to_string()).join(" ")))
            .collect()
    };
    let mut asymmetric = general_matrix();
    asymmetric[1][4] += 1.0;
    let message = err(&text(asymmetric));
    assert!(
        message.contains("C25") && message.contains("symmetric"),
        "{message}"
    );
    let mut nan = general_matrix();
    nan[2][3] = f64::NAN;
    assert!(err(&text(nan)).contains("C34: NaN is not a finite number"));
    let mut inf = general_matrix();
    inf[5][5] = f64::INFINITY;
    assert!(err(&text(inf)).contains("C66"));
    assert!(err("{\"voigt\": [[1]]}").contains("6 rows of 6"));
    assert!(err("{\"voigt\": 3, \"extra\": 1}").contains("extra"));
    assert!(err("{\"voigt\": ").contains("JSON"));
    assert!(err("{\"shear_order\": \"21\"}").contains("shear_order"));
    for message in [err(""), err("{}")] {
        assert!(message.starts_with("bad.csv: "), "{message}");
    }
    let missing = VoigtStiffness::load(Path::new("/no/such/file.csv"), None).unwrap_err();
    assert!(missing.to_string().contains("/no/such/file.csv"));
}

use std::path::Path;
