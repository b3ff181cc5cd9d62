//! Real files from DIPY (tests/data/dipy, BSD-3-Clause, see LICENSE-DIPY there).
use glam::{DMat3, DVec3};
use glyphcast::scene::{GlyphKind, ShBasis};
use glyphcast_dmri::io::nifti::{AffineSource, NiftiHeader, VoxelToWorld, read_nifti};
use glyphcast_dmri::volume::{VolumeKind, load_volume};
use nalgebra::{Quaternion, UnitQuaternion};
use std::path::PathBuf;

fn data(name: &str) -> PathBuf {
    PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
        .join("tests/data/dipy")
        .join(name)
}

/// The qform of small_64D.nii from its raw header fields, with nalgebra's quaternion
/// rotation (not the library's formula): R(q) diag(pixdim1, pixdim2, qfac pixdim3) and the
/// quaternion offsets.
fn independent_qform(h: &NiftiHeader) -> (DMat3, DVec3) {
    let (b, c, d) = (h.quatern_b, h.quatern_c, h.quatern_d);
    let a = (1.0 - b * b - c * c - d * d).max(0.0).sqrt();
    let rotation =
        UnitQuaternion::from_quaternion(Quaternion::new(a, b, c, d)).to_rotation_matrix();
    let m = rotation.matrix();
    let qfac = if h.pixdim[0] < 0.0 { -1.0 } else { 1.0 };
    let sizes = [h.pixdim[1], h.pixdim[2], qfac * h.pixdim[3]];
    let col = |j: usize| DVec3::new(m[(0, j)], m[(1, j)], m[(2, j)]) * sizes[j];
    (
        DMat3::from_cols(col(0), col(1), col(2)),
        DVec3::new(h.quatern_x, h.quatern_y, h.quatern_z),
    )
}

#[test]
fn small_64d_affine_matches_its_qform_with_qfac_minus_one() {
    let image = read_nifti(&data("small_64D.nii")).expect("reading small_64D.nii");
    let h = &image.header;
    // Known facts of this file: 10x10x10x65, 2 mm voxels, qfac -1, both codes set.
    assert_eq!(&h.dim[..5], &[4, 10, 10, 10, 65]);
    assert_eq!(h.pixdim[0], -1.0);
    assert_eq!(&h.pixdim[1..4], &[2.0, 2.0, 2.0]);
    assert!(h.qform_code > 0 && h.sform_code > 0);

    let (linear, offset) = independent_qform(h);
    assert!(
        linear.determinant() < 0.0,
        "qfac -1 makes the affine a reflection"
    );
    let check = |map: &VoxelToWorld, what: &str| {
        for voxel in [
            DVec3::ZERO,
            DVec3::X,
            DVec3::Y,
            DVec3::Z,
            DVec3::new(9.0, 4.0, 7.0),
        ] {
            let expected = linear * voxel + offset;
            let got = map.voxel_center(voxel);
            assert!(
                (got - expected).length() < 1e-4,
                "{what} {voxel}: {got} vs {expected}"
            );
        }
        let sizes = map.voxel_sizes();
        assert!(
            (sizes - DVec3::splat(2.0)).abs().max_element() < 1e-5,
            "{sizes}"
        );
    };
    // The file's sform (used, since sform_code > 0) agrees with its qform...
    assert_eq!(image.voxel_to_world.source, AffineSource::Sform);
    check(&image.voxel_to_world, "sform");
    // ...and the library's qform path, forced, gives the same affine.
    let qform_only = NiftiHeader {
        sform_code: 0,
        ..h.clone()
    };
    let map = VoxelToWorld::from_header(&qform_only, "small_64D.nii").expect("qform");
    assert_eq!(map.source, AffineSource::Qform);
    check(&map, "qform");
    // The rotation glyphs get is a reflection too, and orthogonal.
    let r = map.orthogonal_factor().expect("polar factor");
    assert!((r.determinant() + 1.0).abs() < 1e-9);
    assert!(
        (r * r.transpose() - DMat3::IDENTITY)
            .to_cols_array()
            .iter()
            .all(|e| e.abs() < 1e-9)
    );
    let expected_r = DMat3::from_cols(
        linear.x_axis / 2.0,
        linear.y_axis / 2.0,
        linear.z_axis / 2.0,
    );
    assert!(
        (r - expected_r)
            .to_cols_array()
            .iter()
            .all(|e| e.abs() < 1e-5)
    );
}

#[test]
fn small_64d_is_not_a_coefficient_volume() {
    let kind = VolumeKind::Sh {
        basis: ShBasis::Descoteaux07,
        legacy: false,
    };
    let err = load_volume(&data("small_64D.nii"), kind)
        .expect_err("65 is no SH count")
        .to_string();
    assert!(
        err.contains("small_64D.nii") && err.contains("dim[4]") && err.contains("65"),
        "{err}"
    );
}

#[test]
fn func_coef_is_a_band_8_volume() {
    let kind = VolumeKind::Sh {
        basis: ShBasis::Tournier07,
        legacy: true,
    };
    let volume = load_volume(&data("func_coef.nii.gz"), kind).expect("reading func_coef");
    assert_eq!(volume.dims, [2, 3, 4]);
    assert_eq!(
        volume.kind,
        GlyphKind::Sh {
            band: 8,
            basis: ShBasis::Tournier07,
            legacy: true
        }
    );
    assert_eq!(volume.coefficient_count(), 45);
    assert_eq!(volume.voxel_to_world.source, AffineSource::Sform);
    assert_eq!(
        volume
            .voxel_to_world
            .voxel_center(DVec3::new(1.0, 2.0, 3.0)),
        DVec3::new(1.0, 2.0, 3.0)
    );
    // Data, not padding: every voxel has a positive l = 0 term.
    for i in 0..2 {
        for j in 0..3 {
            for k in 0..4 {
                assert!(volume.coefficients([i, j, k])[0] > 0.0);
            }
        }
    }
}

/// A slice move in the viewer prepares the new glyphs on a worker thread: `move_slice`
/// returns with the preparation under way (the window goes on drawing what it has), a
/// move asked for meanwhile waits for it, and the glyphs handed back are exactly those
/// of preparing that slice directly.
#[test]
fn viewer_slice_moves_are_prepared_in_the_background() {
    use glyphcast::render::RenderSettings;
    use glyphcast::render::glyph_data::prepare_scene;
    use glyphcast_dmri::volume::{Slice, SliceAxis, VolumeOptions, volume_scene};
    use glyphcast_viewer::{Content, ViewSource};
    let kind = VolumeKind::Sh {
        basis: ShBasis::Tournier07,
        legacy: true,
    };
    let volume = load_volume(&data("func_coef.nii.gz"), kind).expect("reading func_coef");
    let slice = |index| Slice {
        axis: SliceAxis::Axial,
        index: Some(index),
    };
    let mut options = VolumeOptions {
        slice: slice(0),
        ..VolumeOptions::default()
    };
    let view = volume_scene(&volume, &options).expect("slice 0");
    let source = ViewSource::Volume {
        volume: Box::new(volume.clone()),
        options: Box::new(options.clone()),
        view: Box::new(view),
    };
    let mut content = Content::new(source, RenderSettings::default(), None).expect("content");
    let version = content.version;
    assert!(content.move_slice(1).expect("move to 1"));
    assert!(content.busy().is_some(), "no preparation under way");
    assert_eq!(
        content.version, version,
        "the glyphs changed before they were ready"
    );
    // Asked for while slice 1 is prepared: waits for it, then runs.
    assert!(content.move_slice(1).expect("move to 2"));
    assert!(content.poll(true).expect("slice 1"));
    assert!(content.busy().is_some(), "the queued move did not start");
    assert!(content.poll(true).expect("slice 2"));
    assert!(content.busy().is_none());
    assert_eq!(content.version, version + 2);
    options.slice = slice(2);
    let direct = volume_scene(&volume, &options).expect("slice 2");
    assert_eq!(content.scene.glyph_sets, direct.scene.glyph_sets);
    let direct_sets = prepare_scene(&direct.scene, 0.0).expect("preparing slice 2");
    assert_eq!(content.sets.len(), direct_sets.len());
    for (shown, expected) in content.sets.iter().zip(&direct_sets) {
        assert_eq!(shown.instances, expected.instances);
        assert_eq!(shown.boxes, expected.boxes);
        assert_eq!(shown.coefficients, expected.coefficients);
    }
    // The negative-lobe switch is prepared the same way.
    content.set_negative(None).expect("negative switch");
    assert!(content.busy().is_some());
    assert!(content.poll(true).expect("negative lobes"));
    assert!(
        content
            .scene
            .glyph_sets
            .iter()
            .all(|s| s.negative == glyphcast::glyph::NegativeMode::Hide)
    );
}

/// The drawn max radius of every glyph of a volume view's scene: each glyph's largest
/// |f| over 4,000 directions times its scale.
fn drawn_radii(scene: &glyphcast::Scene) -> Vec<f64> {
    use glyphcast::glyph::bounds::sampled_max_radius;
    let sets = glyphcast::render::glyph_data::prepare_scene(scene, 0.0).expect("prepared");
    sets.iter()
        .flat_map(|set| set.world.iter())
        .map(|w| w.scale * sampled_max_radius(&w.poly, w.negative, 4000))
        .collect()
}

/// The default sizes on real fibre ODFs, MRtrix's dwi2fod of its test data
/// (tests/data/mrtrix/fod_dirs300.mif) and DIPY's CSD of small_64D (fitted here by
/// `glyphcast fit --odf csd --csd-algorithm dipy --order 8 --basis dipy`), each as the
/// default axial slice and as a block: the median glyph is drawn at least half of the
/// scale (0.45 of the voxel), and none beyond it, so none is larger than its voxel.
#[test]
fn default_sizes_fill_the_voxels_of_real_fodfs() {
    use glyphcast_dmri::volume::{Coefficients, ImageRequest, VolumeRequest, volume_scene};
    let fit = crate::common::dipy_csd_fit();
    let mrtrix = crate::common::test_data("mrtrix", "fod_dirs300.mif");
    for path in [fit, mrtrix] {
        for block in [false, true] {
            let request = VolumeRequest {
                block,
                ..VolumeRequest::default()
            };
            let volume = request
                .read_volume(Coefficients::Sh, &path)
                .expect("volume");
            let options = request.options(ImageRequest::default()).expect("options");
            let view = volume_scene(&volume, &options).expect("scene");
            let scale = 0.45 * volume.voxel_to_world.voxel_sizes().min_element();
            let mut radii = drawn_radii(&view.scene);
            radii.sort_by(f64::total_cmp);
            let median = radii[radii.len() / 2];
            let largest = radii[radii.len() - 1];
            let what = format!(
                "{} (block: {block}, {} glyphs)",
                path.display(),
                radii.len()
            );
            assert!(
                median >= 0.5 * scale,
                "{what}: median {median}, scale {scale}"
            );
            assert!(
                largest <= scale * (1.0 + 1e-9),
                "{what}: largest {largest}, scale {scale}"
            );
        }
    }
}
