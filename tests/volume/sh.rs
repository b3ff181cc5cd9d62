//! SH volumes: the band is read off the coefficient count, and the glyphs turn with the
//! affine like tensors do. The rotation itself comes from `glyph::sh`, which is merged
//! from the SH branch; until then the tests that need it are ignored (run them with
//! `cargo test -p glyphcast-cli --test integration volume:: -- --ignored` after the merge).
use super::fixtures::*;
use glam::{DMat3, DVec3};
use glyphcast::scene::{GlyphKind, ShBasis};
use glyphcast_dmri::volume::{VolumeKind, VolumeOptions, load_volume, volume_scene};
use std::f64::consts::PI;

const TOURNIER: VolumeKind = VolumeKind::Sh {
    basis: ShBasis::Tournier07,
    legacy: false,
};

#[test]
fn the_band_follows_from_the_coefficient_count() {
    for (count, band) in [
        (1, 0),
        (6, 2),
        (15, 4),
        (28, 6),
        (45, 8),
        (66, 10),
        (91, 12),
    ] {
        let path = scratch(&format!("band-{band}")).join("sh.nii.gz");
        write4(
            &path,
            Storage::Sform,
            &volume([2, 1, 1], count, |_| vec![1.0; count]),
        );
        let volume = load_volume(&path, TOURNIER).expect("loading");
        assert_eq!(
            volume.kind,
            GlyphKind::Sh {
                band,
                basis: ShBasis::Tournier07,
                legacy: false
            }
        );
    }
    for count in [2, 44, 46, 120] {
        let path = scratch(&format!("count-{count}")).join("sh.nii.gz");
        write4(
            &path,
            Storage::Sform,
            &volume([2, 1, 1], count, |_| vec![1.0; count]),
        );
        let err = load_volume(&path, TOURNIER)
            .expect_err("not an SH count")
            .to_string();
        assert!(
            err.contains("sh.nii.gz") && err.contains("dim[4]") && err.contains(&count.to_string()),
            "{err}"
        );
    }
}

#[test]
fn lmax_must_be_even_and_within_the_file() {
    let path = scratch("lmax").join("sh.nii.gz");
    write4(
        &path,
        Storage::Sform,
        &volume([2, 1, 1], 15, |_| vec![1.0; 15]),
    );
    let volume = load_volume(&path, TOURNIER).expect("loading");
    for lmax in [3, 6] {
        let options = VolumeOptions {
            lmax: Some(lmax),
            ..Default::default()
        };
        let err = volume_scene(&volume, &options)
            .expect_err("bad lmax")
            .to_string();
        // The field is the setting, in the library's words (the CLI spells `--lmax`).
        assert!(err.contains("sh.nii.gz: lmax: "), "{err}");
    }
}

/// Real tournier07 SH (with the Condon-Shortley phase) of bands 0 and 2, written out by
/// hand; index l(l+1)/2 + m.
fn tournier_band2(c: &[f64], u: DVec3) -> f64 {
    let (x, y, z) = (u.x, u.y, u.z);
    let k = (15.0 / PI).sqrt();
    let basis = [
        0.5 / PI.sqrt(),
        0.5 * k * x * y,
        -0.5 * k * y * z,
        0.25 * (5.0 / PI).sqrt() * (3.0 * z * z - 1.0),
        -0.5 * k * x * z,
        0.25 * k * (x * x - y * y),
    ];
    basis.iter().zip(c).map(|(b, c)| b * c).sum()
}

/// f(u) = x^2: one lobe along voxel axis i.
fn x_squared() -> Vec<f64> {
    let (c00, c20, c22) = (
        2.0 * PI.sqrt() / 3.0,
        -(2.0 / 3.0) / (5.0 / PI).sqrt(),
        2.0 / (15.0 / PI).sqrt(),
    );
    vec![c00, 0.0, 0.0, c20, 0.0, c22]
}

#[test]
fn the_hand_written_basis_gives_x_squared() {
    let c = x_squared();
    for u in [
        DVec3::X,
        DVec3::Y,
        DVec3::Z,
        DVec3::new(0.6, 0.8, 0.0),
        DVec3::new(0.0, 0.6, 0.8),
    ] {
        assert!((tournier_band2(&c, u) - u.x * u.x).abs() < 1e-12, "{u}");
    }
}

#[test]
fn sh_glyphs_turn_with_the_affine_rotation() {
    let inputs = [x_squared(), vec![1.0, 0.3, -0.2, 0.5, 0.4, 0.7]];
    for (n, input) in inputs.iter().enumerate() {
        for storage in ALL_STORAGES {
            let path = scratch(&format!("sh-turn-{n}-{storage:?}")).join("sh.nii.gz");
            write4(&path, storage, &volume([1, 1, 1], 6, |_| input.clone()));
            let volume = load_volume(&path, TOURNIER).expect("loading");
            let scene = volume_scene(&volume, &VolumeOptions::default())
                .expect("scene")
                .scene;
            let set = &scene.glyph_sets[0];
            assert_eq!(set.kind, volume.kind);
            let r: DMat3 = expected_rotation(storage);
            for k in 0..50 {
                let t = k as f64 * 0.37;
                let u = DVec3::new(t.cos(), (1.7 * t).sin(), (0.3 * t).cos() - 0.4).normalize();
                let expected = tournier_band2(input, r.transpose() * u);
                let got = tournier_band2(&set.coeffs[0], u);
                assert!(
                    (got - expected).abs() < 1e-5,
                    "{storage:?} at {u}: {got} vs {expected}"
                );
            }
            if n == 0 {
                // The lobe along voxel axis i lies along the rotated axis R x.
                let lobe = tournier_band2(&set.coeffs[0], r * DVec3::X);
                assert!((lobe - 1.0).abs() < 1e-5, "{storage:?}: {lobe}");
            }
        }
    }
}
