//! Which voxels become glyphs (slice, ranges, mask, bad values) and how big they are.
use super::fixtures::*;
use glyphcast::glyph::{Symmetry, TensorLayout};
use glyphcast_dmri::volume::{
    Mask, Normalisation, Slice, SliceAxis, Slices, Volume, VolumeKind, VolumeOptions, VolumeReport,
    load_mask, load_volume, volume_scene,
};
use ndarray::Array3;
use std::collections::BTreeSet;

const DIMS: [usize; 3] = [4, 5, 6];

fn labelled(name: &str, edit: impl Fn([usize; 3], Vec<f64>) -> Vec<f64>) -> Volume {
    let data = volume(DIMS, 6, |v| edit(v, labelled_sphere(v)));
    let path = scratch(name).join("labelled.nii");
    write4(&path, Storage::Sform, &data);
    let kind = VolumeKind::Tensor(TensorLayout {
        order: 2,
        symmetry: Symmetry::Symmetric,
    });
    load_volume(&path, kind).expect("loading")
}

fn drawn_voxels(volume: &Volume, options: &VolumeOptions) -> (BTreeSet<[usize; 3]>, VolumeReport) {
    let view = volume_scene(volume, options).expect("scene");
    let set = &view.scene.glyph_sets[0];
    let voxels = set.coeffs.iter().map(|c| label_voxel(c[0])).collect();
    (voxels, view.report)
}

#[test]
fn slice_ranges_and_mask_pick_exactly_their_voxels() {
    let volume = labelled("pick", |_, c| c);
    let keep = |[i, _, k]: [usize; 3]| (i + k) % 2 == 0;
    let mask_values = Array3::from_shape_fn((DIMS[0], DIMS[1], DIMS[2]), |(i, j, k)| {
        if keep([i, j, k]) { 1.0 } else { 0.0 }
    });
    let mask_path = scratch("pick-mask").join("mask.nii.gz");
    write_mask(&mask_path, Storage::Sform, &mask_values);
    let options = VolumeOptions {
        slice: Slice {
            axis: SliceAxis::Coronal,
            index: Some(2),
        },
        voxels: "1:3,:,2:".parse().expect("ranges"),
        mask: Some(load_mask(&mask_path).expect("mask")),
        ..Default::default()
    };
    let (voxels, report) = drawn_voxels(&volume, &options);
    let mut expected = BTreeSet::new();
    let mut selected = 0;
    for i in 1..3 {
        for k in 2..6 {
            selected += 1;
            if keep([i, 2, k]) {
                expected.insert([i, 2, k]);
            }
        }
    }
    assert_eq!(voxels, expected);
    assert_eq!(report.selected, selected);
    assert_eq!(report.masked_out, selected - expected.len());
    assert_eq!(report.drawn, expected.len());

    // The default: the middle axial slice, every voxel.
    let (voxels, _) = drawn_voxels(&volume, &VolumeOptions::default());
    assert_eq!(voxels.len(), 4 * 5);
    assert!(voxels.iter().all(|v| v[2] == 3));
}

#[test]
fn a_mask_of_another_shape_is_refused_naming_both_shapes() {
    let volume = labelled("shape", |_, c| c);
    let mask = Mask::new("small-mask.nii", &Array3::ones((4, 5, 5)));
    let options = VolumeOptions {
        mask: Some(mask),
        ..Default::default()
    };
    let err = volume_scene(&volume, &options)
        .expect_err("shape mismatch")
        .to_string();
    assert!(
        err.contains("small-mask.nii") && err.contains("4x5x5") && err.contains("4x5x6"),
        "{err}"
    );
    assert!(err.contains("labelled.nii"), "{err}");
}

#[test]
fn bad_values_zero_glyphs_and_small_glyphs_are_left_out_and_counted() {
    // Axial slice k = 0: labels 1 + i + 10 j. Voxel (0,0) is NaN, (1,0) infinite in one
    // entry, (2,0) zero.
    let volume = labelled("values", |[i, j, k], mut c| {
        match (i, j, k) {
            (0, 0, 0) => c[0] = f64::NAN,
            (1, 0, 0) => c[4] = f64::INFINITY,
            (2, 0, 0) => c = vec![0.0; 6],
            _ => {}
        }
        c
    });
    let base = VolumeOptions {
        slice: Slice {
            axis: SliceAxis::Axial,
            index: Some(0),
        },
        ..Default::default()
    };
    let (voxels, report) = drawn_voxels(&volume, &base);
    assert_eq!(report.non_finite, 2);
    assert_eq!(report.zero, 1);
    assert_eq!(report.drawn, 20 - 3);
    assert!(!voxels.contains(&[0, 0, 0]) && !voxels.contains(&[2, 0, 0]));

    let options = VolumeOptions {
        min_amplitude: 12.0,
        ..base.clone()
    };
    let (voxels, report) = drawn_voxels(&volume, &options);
    // Labels below 12: 4 (i = 3, j = 0) and 11 (0, 1).
    assert_eq!(report.below_min_amplitude, 2);
    assert!(voxels.iter().all(|&v| voxel_label(v) >= 12.0));

    let options = VolumeOptions {
        min_amplitude: 1e9,
        ..base
    };
    let err = volume_scene(&volume, &options)
        .expect_err("nothing left")
        .to_string();
    assert!(
        err.contains("labelled.nii") && err.contains("no glyph"),
        "{err}"
    );
}

#[test]
fn normalisation_sizes_glyphs_as_asked() {
    let volume = labelled("norm", |_, c| c);
    let slice = Slice {
        axis: SliceAxis::Axial,
        index: Some(1),
    };
    // Labels 101 + i + 10 j; the largest, (3, 4), is 144. A sphere c I has radius c.
    let largest = 144.0;
    for (norm, scale) in [
        (Normalisation::Robust, None),
        (Normalisation::Global, None),
        (Normalisation::Global, Some(1.5)),
        (Normalisation::PerGlyph, Some(1.5)),
        (Normalisation::None, Some(0.01)),
    ] {
        let options = VolumeOptions {
            slice,
            norm,
            scale,
            ..Default::default()
        };
        let scene = volume_scene(&volume, &options).expect("scene").scene;
        let set = &scene.glyph_sets[0];
        // Default: 0.45 of the smallest voxel size (2 mm).
        let s = scale.unwrap_or(0.9);
        for (coeffs, &glyph_scale) in set.coeffs.iter().zip(&set.scales) {
            let radius = coeffs[0];
            let world_radius = glyph_scale * radius;
            let expected = match norm {
                // No outlier here: 144 is within 1.5 times the 99th percentile.
                Normalisation::Robust | Normalisation::Global => s * radius / largest,
                Normalisation::PerGlyph => s,
                Normalisation::None => s * radius,
                // (Not among the cases: its own test below.)
                Normalisation::Sqrt => unreachable!("not measured here"),
            };
            assert!(
                (world_radius - expected).abs() < 1e-3 * expected,
                "{norm:?}: label {radius}: world radius {world_radius}, expected {expected}"
            );
        }
    }
}

/// One glyph ten times larger than the rest (a CSF-like voxel) leaves the others'
/// drawn size as it was under the robust normalisation, and is itself drawn at the
/// largest size, counted and warned of; under global normalisation it shrinks them by
/// 7x.
#[test]
fn an_outlier_does_not_shrink_the_other_glyphs_by_default() {
    let outlier = [1, 1, 1];
    let plain = labelled("plain", |_, c| c);
    let spiked = labelled("spiked", |v, c| {
        if v == outlier {
            c.iter().map(|x| 10.0 * x).collect()
        } else {
            c
        }
    });
    let world_radii = |volume: &Volume, norm: Normalisation| {
        let options = VolumeOptions {
            slice: Slice {
                axis: SliceAxis::Axial,
                index: Some(1),
            },
            norm,
            ..Default::default()
        };
        let view = volume_scene(volume, &options).expect("scene");
        let set = &view.scene.glyph_sets[0];
        let radii: Vec<(glam::DVec3, f64)> = set
            .centers
            .iter()
            .zip(set.coeffs.iter().zip(&set.scales))
            .map(|(&centre, (c, &scale))| (centre, scale * c[0]))
            .collect();
        (radii, view.report)
    };
    let (before, _) = world_radii(&plain, Normalisation::Robust);
    let (after, report) = world_radii(&spiked, Normalisation::Robust);
    assert_eq!(report.capped, 1);
    let warnings = report.warnings("spiked.nii");
    assert!(
        warnings
            .iter()
            .any(|w| w.to_string().contains("1 glyph(s) larger than")),
        "{warnings:?}"
    );
    let largest = after.iter().map(|r| r.1).fold(0.0, f64::max);
    assert!(
        (largest - 0.9).abs() < 1e-9,
        "the outlier at the scale: {largest}"
    );
    let mut compared = 0;
    for ((centre, a), (same, b)) in before.iter().zip(&after) {
        assert_eq!(centre, same);
        if (*b - largest).abs() < 1e-12 && (*a - largest).abs() > 1e-9 {
            // The outlier, capped at the scale.
            continue;
        }
        assert!((a / b - 1.0).abs() < 1e-12, "{centre}: {a} then {b}");
        compared += 1;
    }
    assert_eq!(compared, DIMS[0] * DIMS[1] - 1);
    // Global normalisation: the outlier takes the scale, the rest shrink by 1011 / 144.
    let (global, _) = world_radii(&spiked, Normalisation::Global);
    let shrunk = before[0].1 / global[0].1;
    assert!(shrunk > 5.0, "{shrunk}");
}

/// The default sizing (square root): the glyph at the 95th percentile of the sizes is
/// drawn at the scale, a smaller one at the scale times the square root of its size
/// over that one's, a larger one (the outlier) at the scale, without a warning; the
/// order of the sizes is kept, and the median glyph is drawn at more than half the
/// scale.
#[test]
fn the_default_sizes_glyphs_by_the_square_root_up_to_a_high_percentile() {
    let outlier = [1, 1, 1];
    let spiked = labelled("spiked", |v, c| {
        if v == outlier {
            c.iter().map(|x| 10.0 * x).collect()
        } else {
            c
        }
    });
    let options = VolumeOptions {
        slice: Slice {
            axis: SliceAxis::Axial,
            index: Some(1),
        },
        ..Default::default()
    };
    assert_eq!(options.norm, Normalisation::Sqrt);
    let view = volume_scene(&spiked, &options).expect("scene");
    assert_eq!(view.report.capped, 0);
    assert!(view.report.warnings("spiked.nii").is_empty());
    let set = &view.scene.glyph_sets[0];
    // Labels are the radii (a sphere c I has radius c).
    let radii: Vec<f64> = set.coeffs.iter().map(|c| c[0]).collect();
    let drawn: Vec<f64> = set
        .coeffs
        .iter()
        .zip(&set.scales)
        .map(|(c, s)| s * c[0])
        .collect();
    let reference = glyphcast_dmri::volume::percentile(&radii, 95.0);
    let scale = 0.9;
    for (&r, &d) in radii.iter().zip(&drawn) {
        let expected = scale * (r / reference).sqrt().min(1.0);
        assert!(
            (d - expected).abs() < 1e-9 * scale,
            "radius {r}: drawn {d}, expected {expected}"
        );
        assert!(
            d <= scale * (1.0 + 1e-12),
            "radius {r}: drawn {d} beyond the scale"
        );
    }
    let mut order: Vec<usize> = (0..radii.len()).collect();
    order.sort_by(|&a, &b| radii[a].total_cmp(&radii[b]));
    assert!(
        order
            .windows(2)
            .all(|w| drawn[w[0]] <= drawn[w[1]] * (1.0 + 1e-12))
    );
    let median = drawn[order[order.len() / 2]];
    assert!(median > 0.5 * scale, "median glyph drawn at {median}");
}

#[test]
fn three_slices_pick_the_voxels_of_their_planes_each_once() {
    let volume = labelled("three", |_, c| c);
    let planes = [1, 2, 3];
    let options = VolumeOptions {
        slices: Some(Slices {
            indices: planes.map(Some),
        }),
        ..Default::default()
    };
    let view = volume_scene(&volume, &options).expect("scene");
    assert_eq!(view.scene.glyph_sets.len(), 3, "one glyph set per slice");
    let drawn: Vec<[usize; 3]> = view
        .scene
        .glyph_sets
        .iter()
        .flat_map(|set| set.coeffs.iter().map(|c| label_voxel(c[0])))
        .collect();
    let unique: BTreeSet<[usize; 3]> = drawn.iter().copied().collect();
    assert_eq!(unique.len(), drawn.len(), "a voxel drawn twice");
    let mut expected = BTreeSet::new();
    for i in 0..DIMS[0] {
        for j in 0..DIMS[1] {
            for k in 0..DIMS[2] {
                let v = [i, j, k];
                if (0..3).any(|axis| v[axis] == planes[axis]) {
                    expected.insert(v);
                }
            }
        }
    }
    assert_eq!(unique, expected);
    assert_eq!(view.report.selected, expected.len());
    assert_eq!(view.report.drawn, expected.len());
    // Each set holds its own plane's voxels, in sagittal, coronal, axial order.
    for (axis, set) in view.scene.glyph_sets.iter().enumerate() {
        assert!(
            set.coeffs
                .iter()
                .all(|c| label_voxel(c[0])[axis] == planes[axis]),
            "set {axis}"
        );
    }
    // The camera is in perspective, off every axis, looking at the volume's centre.
    let camera = view.scene.camera;
    assert!(matches!(
        camera.projection,
        glyphcast::camera::Projection::Perspective { .. }
    ));
    let dir = (camera.eye - camera.target).normalize();
    assert!(dir.abs().min_element() > 0.3, "{dir}");
    // mid is the middle of each axis.
    let options = VolumeOptions {
        slices: Some("mid".parse().expect("mid")),
        ..Default::default()
    };
    let view = volume_scene(&volume, &options).expect("scene");
    let middles: Vec<usize> = view.regions.iter().map(|r| r.index).collect();
    assert_eq!(middles, [2, 2, 3]);
}

/// One voxel of a 10 x 10 slice ten times larger than the rest (a CSF-like outlier):
/// under the robust sizing the other 99 glyphs keep their pixels, drawn on lavapipe with
/// validation (the outlier's own glyph left out of both pictures, so that only the
/// others count). The rule that capped at 1.5 times the 99th percentile kept 0.44 of
/// them; at least half is what a figure needs, and all of them is what it gets.
#[test]
fn one_outlier_in_a_ten_by_ten_slice_keeps_the_others_pixels() {
    const SLICE: [usize; 3] = [10, 10, 1];
    let outlier = [4, 5, 0];
    let radius = |[i, j, _]: [usize; 3]| 1.0 + 0.05 * ((7 * i + 3 * j) % 10) as f64;
    let load = |name: &str, spike: f64| {
        let data = volume(SLICE, 6, |v| {
            let c = radius(v) * if v == outlier { spike } else { 1.0 };
            vec![c, 0.0, 0.0, c, 0.0, c]
        });
        let path = scratch(name).join("slice.nii");
        write4(&path, Storage::Sform, &data);
        let kind = VolumeKind::Tensor(TensorLayout {
            order: 2,
            symmetry: Symmetry::Symmetric,
        });
        load_volume(&path, kind).expect("loading")
    };
    let (plain, spiked) = (load("outlier-plain", 1.0), load("outlier-spiked", 10.0));
    let gpu = crate::common::gpu();
    let mut renderer = glyphcast::HeadlessRenderer::new(&gpu).expect("renderer");
    let settings = glyphcast::RenderSettings::default();
    // The outlier's index in the glyph list: the largest coefficient of the spiked slice.
    let robust = VolumeOptions {
        norm: Normalisation::Robust,
        ..Default::default()
    };
    let spiked_view = volume_scene(&spiked, &robust).expect("scene");
    assert_eq!(spiked_view.report.capped, 1, "one outlier");
    let coeffs = &spiked_view.scene.glyph_sets[0].coeffs;
    let index = (0..coeffs.len())
        .max_by(|&a, &b| coeffs[a][0].total_cmp(&coeffs[b][0]))
        .expect("glyphs");
    let mut covered = |volume: &Volume| {
        let view = volume_scene(volume, &robust).expect("scene");
        let mut scene = view.scene;
        let set = &mut scene.glyph_sets[0];
        assert_eq!(set.centers.len(), 100);
        set.centers.remove(index);
        set.scales.remove(index);
        set.coeffs.remove(index);
        let sets = glyphcast::prepare_scene(&scene, settings.offset as f64).expect("prepared");
        let frame = glyphcast::FrameView::new(&scene.camera, 400, 400);
        let image = renderer
            .render_view(&gpu, &sets, &frame, &settings)
            .expect("rendered");
        image.distance.iter().filter(|d| d.is_finite()).count()
    };
    let before = covered(&plain);
    let after = covered(&spiked);
    assert!(before > 10_000, "{before} pixels without the outlier");
    let kept = after as f64 / before as f64;
    assert!(kept >= 0.5, "the others keep {kept} of their pixels");
    assert!(kept > 0.98, "an outlier changes no other glyph: {kept}");
}
