//! Where glyphs land and which way they point: centres from the affine (sform, qform,
//! qform with qfac -1), shapes turned by the affine's rotation, and the camera framing.
use super::fixtures::*;
use glam::{DVec3, DVec4};
use glyphcast::camera::Projection;
use glyphcast::glyph::polynomial::GlyphPolynomial;
use glyphcast::glyph::{Symmetry, TensorLayout};
use glyphcast::scene::{GlyphKind, Scene};
use glyphcast_dmri::io::nifti::AffineSource;
use glyphcast_dmri::volume::{
    ImageRequest, Slice, SliceAxis, ViewProjection, Volume, VolumeKind, VolumeOptions, load_volume,
    volume_scene,
};

const ORDER2: TensorLayout = TensorLayout {
    order: 2,
    symmetry: Symmetry::Symmetric,
};

fn tensor_kind(order: u32, symmetry: Symmetry) -> VolumeKind {
    VolumeKind::Tensor(TensorLayout { order, symmetry })
}

/// Writes `data` with `storage` and reads it back as a volume of `kind`.
fn round_trip(
    name: &str,
    storage: Storage,
    data: &ndarray::Array4<f64>,
    kind: VolumeKind,
) -> Volume {
    let path = scratch(name).join("volume.nii.gz");
    write4(&path, storage, data);
    load_volume(&path, kind).expect("loading the test volume")
}

fn scene_of(volume: &Volume, slice: Slice) -> Scene {
    let options = VolumeOptions {
        slice,
        ..Default::default()
    };
    volume_scene(volume, &options)
        .expect("building the scene")
        .scene
}

fn slice(axis: SliceAxis, index: usize) -> Slice {
    Slice {
        axis,
        index: Some(index),
    }
}

#[test]
fn voxel_centres_are_the_affine_applied_to_the_indices() {
    let dims = [3, 4, 5];
    let data = volume(dims, 6, labelled_sphere);
    for storage in ALL_STORAGES {
        let volume = round_trip(
            &format!("centres-{storage:?}"),
            storage,
            &data,
            tensor_kind(2, Symmetry::Symmetric),
        );
        let expected_source = match storage {
            Storage::Sform | Storage::Oblique => AffineSource::Sform,
            Storage::Qform | Storage::QformFlipped => AffineSource::Qform,
        };
        assert_eq!(volume.voxel_to_world.source, expected_source);
        let affine = expected_affine(storage);
        let difference = (volume.voxel_to_world.affine - affine).to_cols_array();
        assert!(
            difference.iter().all(|d| d.abs() < 1e-5),
            "{storage:?}: {:?} vs {affine:?}",
            volume.voxel_to_world.affine
        );
        for (axis, index, count) in [
            (SliceAxis::Axial, 2, 3 * 4),
            (SliceAxis::Coronal, 3, 3 * 5),
            (SliceAxis::Sagittal, 0, 4 * 5),
        ] {
            let scene = scene_of(&volume, slice(axis, index));
            let set = &scene.glyph_sets[0];
            assert_eq!(set.len(), count, "{storage:?} {axis:?}");
            for (center, coeffs) in set.centers.iter().zip(&set.coeffs) {
                let voxel = label_voxel(coeffs[0]);
                assert_eq!(
                    voxel[axis_index(axis)],
                    index,
                    "{storage:?} {axis:?}: {voxel:?}"
                );
                let [i, j, k] = voxel.map(|v| v as f64);
                let expected = (affine * DVec4::new(i, j, k, 1.0)).truncate();
                assert!(
                    (*center - expected).length() < 1e-4,
                    "{storage:?} voxel {voxel:?}: centre {center} expected {expected}"
                );
            }
        }
    }
}

fn axis_index(axis: SliceAxis) -> usize {
    match axis {
        SliceAxis::Sagittal => 0,
        SliceAxis::Coronal => 1,
        SliceAxis::Axial => 2,
    }
}

/// Directions spread over the sphere.
fn directions() -> Vec<DVec3> {
    (0..60)
        .map(|n| {
            let z = 1.0 - (2.0 * n as f64 + 1.0) / 60.0;
            let phi = 2.399963 * n as f64;
            let r = (1.0 - z * z).sqrt();
            DVec3::new(r * phi.cos(), r * phi.sin(), z)
        })
        .collect()
}

/// One long lobe along voxel axis i ends up along the world direction of that axis:
/// world +y for the quarter turns about z, R e_x for the oblique affine.
#[test]
fn a_lobe_along_voxel_axis_i_points_along_the_rotated_world_axis() {
    let data = volume([2, 2, 2], 6, |_| lobe_tensor(DVec3::X));
    for storage in ALL_STORAGES {
        let r = expected_rotation(storage);
        if storage != Storage::Oblique {
            assert!((r * DVec3::X - DVec3::Y).length() < 1e-12);
        }
        let (lobe, across) = (r * DVec3::X, [r * DVec3::Y, r * DVec3::Z]);
        let volume = round_trip(
            &format!("lobe-{storage:?}"),
            storage,
            &data,
            tensor_kind(2, Symmetry::Symmetric),
        );
        let scene = scene_of(&volume, Slice::default());
        for coeffs in &scene.glyph_sets[0].coeffs {
            let g = GlyphPolynomial::from_tensor(ORDER2, coeffs).expect("tensor");
            let along = |u: DVec3| g.eval(u);
            assert!(
                (along(lobe) - 1.0).abs() < 1e-6,
                "{storage:?}: {}",
                along(lobe)
            );
            for across in across {
                assert!(
                    (along(across) - 0.1).abs() < 1e-6,
                    "{storage:?} {across}: {}",
                    along(across)
                );
            }
            // The lobe is the longest direction.
            assert!(directions().iter().all(|&u| along(u) <= along(lobe) + 1e-9));
        }
    }
}

/// g(u) = f(R^T u) for several tensor kinds, odd ones included: an order-1 glyph along
/// voxel k points to world -z when the qform flips k (qfac -1), not to +z.
#[test]
fn every_tensor_kind_turns_with_the_affine_rotation() {
    let cases = [
        (1, Symmetry::Symmetric),
        (2, Symmetry::Symmetric),
        (3, Symmetry::NonSymmetric),
        (4, Symmetry::Symmetric),
        (3, Symmetry::Symmetric),
    ];
    for (order, symmetry) in cases {
        let layout = TensorLayout { order, symmetry };
        let count = layout.coefficient_count();
        let input: Vec<f64> = (0..count)
            .map(|n| ((n * 37 % 17) as f64 - 8.0) / 8.0)
            .collect();
        let f = GlyphPolynomial::from_tensor(layout, &input).expect("input tensor");
        let data = volume([2, 2, 1], count, |_| input.clone());
        for storage in ALL_STORAGES {
            let name = format!("turn-{order}-{symmetry:?}-{storage:?}");
            let volume = round_trip(&name, storage, &data, VolumeKind::Tensor(layout));
            let scene = scene_of(&volume, Slice::default());
            let set = &scene.glyph_sets[0];
            assert_eq!(set.kind, GlyphKind::Tensor(layout));
            let r = expected_rotation(storage);
            let g = GlyphPolynomial::from_tensor(layout, &set.coeffs[0]).expect("scene tensor");
            for u in directions() {
                // The input went through float32.
                let (expected, got) = (f.eval(r.transpose() * u), g.eval(u));
                assert!(
                    (expected - got).abs() < 1e-5,
                    "order {order} {symmetry:?} {storage:?} at {u}: {got} vs {expected}"
                );
            }
        }
    }
    // The odd case spelled out.
    let data = volume([1, 1, 1], 3, |_| vec![0.0, 0.0, 1.0]);
    let volume = round_trip(
        "vector-flip",
        Storage::QformFlipped,
        &data,
        tensor_kind(1, Symmetry::Symmetric),
    );
    let coeffs = &scene_of(&volume, Slice::default()).glyph_sets[0].coeffs[0];
    assert!(
        (coeffs[2] + 1.0).abs() < 1e-6 && coeffs[0].abs() < 1e-6,
        "{coeffs:?}"
    );
}

#[test]
fn axial_view_is_radiological_with_anterior_up_and_fits_the_slice() {
    let data = volume([3, 4, 5], 6, labelled_sphere);
    let volume = round_trip(
        "framing",
        Storage::Sform,
        &data,
        tensor_kind(2, Symmetry::Symmetric),
    );
    let scene = scene_of(&volume, Slice::default());
    let frame = scene.camera.frame();
    // Radiological by default: seen from inferior, the subject's right on the left.
    assert!((frame.fwd - DVec3::Z).length() < 1e-12, "{:?}", frame.fwd);
    assert!((frame.up - DVec3::Y).length() < 1e-12, "{:?}", frame.up);
    // The slice spans 3 voxels of 2 mm along world y and 4 of 3 mm along x.
    assert_eq!((scene.image.width, scene.image.height), (1024, 512));
    let Projection::Orthographic { height } = scene.camera.projection else {
        panic!("orthographic by default: {:?}", scene.camera.projection);
    };
    assert!((height - 6.0).abs() < 1e-9, "view height {height}");
    let middle = (expected_affine(Storage::Sform) * DVec4::new(1.0, 1.5, 2.0, 1.0)).truncate();
    let off_axis =
        (scene.camera.target - middle) - (scene.camera.target - middle).dot(frame.fwd) * frame.fwd;
    assert!(
        off_axis.length() < 1e-9,
        "the view is centred on the slice: {off_axis}"
    );

    for projection in [ViewProjection::Orthographic, ViewProjection::Perspective] {
        let options = VolumeOptions {
            projection,
            image: ImageRequest {
                width: Some(200),
                height: None,
                ..Default::default()
            },
            ..Default::default()
        };
        let scene = volume_scene(&volume, &options).expect("scene").scene;
        assert_eq!((scene.image.width, scene.image.height), (200, 100));
        // Every voxel box corner of the slice is in view, and the box touches an edge.
        let view = scene.camera.view_projection(200, 100, 0.01, 1000.0);
        let mut widest = 0.0f64;
        for corner in 0..8 {
            let pick = |bit: usize, n: f64| if corner & bit == 0 { -0.5 } else { n - 0.5 };
            let voxel = DVec4::new(pick(1, 3.0), pick(2, 4.0), 2.0 + pick(4, 1.0), 1.0);
            let world = expected_affine(Storage::Sform) * voxel;
            let clip = view * world;
            let ndc = clip.truncate() / clip.w;
            assert!(
                ndc.x.abs() <= 1.0 + 1e-9 && ndc.y.abs() <= 1.0 + 1e-9,
                "{projection:?}: {ndc}"
            );
            widest = widest.max(ndc.x.abs()).max(ndc.y.abs());
        }
        assert!(
            widest > 0.999,
            "{projection:?}: the slice fills the view ({widest})"
        );
    }
}

#[test]
fn the_camera_looks_along_the_world_axis_closest_to_the_slice_normal() {
    // Voxel axis j points to world -x here, so a slice of constant j ("coronal" by voxel
    // axis) is seen from the subject's left, along +x, with +z up.
    let data = volume([3, 4, 5], 6, labelled_sphere);
    let volume = round_trip(
        "normal",
        Storage::Qform,
        &data,
        tensor_kind(2, Symmetry::Symmetric),
    );
    let scene = scene_of(&volume, slice(SliceAxis::Coronal, 1));
    let frame = scene.camera.frame();
    assert!((frame.fwd - DVec3::X).length() < 1e-12, "{:?}", frame.fwd);
    assert!((frame.up - DVec3::Z).length() < 1e-12, "{:?}", frame.up);
    // Anterior (+y) is on the left of the image.
    assert!(
        (frame.right - DVec3::NEG_Y).length() < 1e-12,
        "{:?}",
        frame.right
    );
    // And i ("sagittal" by voxel axis) points along world y: seen from anterior.
    let scene = scene_of(&volume, slice(SliceAxis::Sagittal, 1));
    assert!((scene.camera.frame().fwd - DVec3::NEG_Y).length() < 1e-12);
}

/// The rotation the glyphs get is the affine's orthogonal factor, not the raw matrix:
/// anisotropic voxels do not stretch glyphs.
#[test]
fn sphere_glyphs_stay_spheres_in_anisotropic_voxels() {
    let data = volume([2, 2, 1], 6, |_| vec![1.0, 0.0, 0.0, 1.0, 0.0, 1.0]);
    for storage in ALL_STORAGES {
        let volume = round_trip(
            &format!("sphere-{storage:?}"),
            storage,
            &data,
            tensor_kind(2, Symmetry::Symmetric),
        );
        let scene = scene_of(&volume, Slice::default());
        let g =
            GlyphPolynomial::from_tensor(ORDER2, &scene.glyph_sets[0].coeffs[0]).expect("tensor");
        for u in directions() {
            assert!((g.eval(u) - 1.0).abs() < 1e-6, "{storage:?} {u}");
        }
    }
}
