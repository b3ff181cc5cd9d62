//! Every figure feature on the compute ray caster (`--path compute`) against the fragment
//! path, through the command line on DIPY's small_64D: an underlay (its plane behind the
//! glyphs and through their centres, hiding their far halves), the underlay and the
//! glyphs receiving shadows and ambient occlusion, peaks in the glyphs' depth buffer,
//! supersampling, negative lobes hidden and sign colours, a lightbox and three views.
//!
//! The compute path's outputs are drawn into the same attachments as the fragment
//! path's glyphs (compose.frag), so both paths compose with the underlay, the peaks and
//! the shadow passes through one depth test. Both run the same float32 root isolation
//! and shading on the same pixel rays: the images agree to one unit of the 8-bit sRGB
//! encoding (the compute shader encodes its colour itself, the colour attachment may
//! round the other way), the depth maps to float32 rounding of the ray distance, and no
//! pixel is covered by one path and not the other.
use crate::common;
use crate::montage::fa_map;
use crate::peaks::fod_and_peaks;
use common::{fresh_dir, glyphcast, text};
use glyphcast::io::npy::read_npy_f32;
use glyphcast::io::png::read_png_rgba8;
use std::path::Path;

/// A PNG and its depth map.
struct Picture {
    rgba: Vec<u8>,
    depth: Vec<f32>,
}

/// `glyphcast render ARGS --path PATH` into `dir`.
fn render(dir: &Path, name: &str, path: &str, args: &[&str]) -> Picture {
    let (png, npy) = (
        dir.join(format!("{name}-{path}.png")),
        dir.join(format!("{name}-{path}.npy")),
    );
    let mut all = vec!["render", "--path", path, "--width", "96", "--height", "80"];
    all.extend_from_slice(args);
    all.extend_from_slice(&["-o", text(&png), "--depth-out", text(&npy)]);
    let run = glyphcast(&all);
    assert!(
        run.status.success(),
        "{name} on {path}: {}",
        String::from_utf8_lossy(&run.stderr)
    );
    let (_, _, rgba) = read_png_rgba8(&png).expect("png");
    let (_, depth) = read_npy_f32(&npy).expect("npy");
    Picture { rgba, depth }
}

/// Renders `args` on both paths and asserts that they draw the same picture; returns
/// the compute path's picture and the pixels the glyphs (or peaks) cover.
fn same_on_both_paths(dir: &Path, name: &str, args: &[&str]) -> (Picture, usize) {
    let fragment = render(dir, name, "fragment", args);
    let compute = render(dir, name, "compute", args);
    assert_eq!(fragment.rgba.len(), compute.rgba.len(), "{name}: sizes");
    let (mut coverage, mut far, mut colour, mut covered) = (0, 0, 0, 0);
    for (f, c) in fragment.depth.iter().zip(&compute.depth) {
        match (f.is_nan(), c.is_nan()) {
            (true, true) => {}
            (false, false) => {
                covered += 1;
                far += usize::from((f - c).abs() > 1e-5 * f.abs().max(1.0));
            }
            _ => coverage += 1,
        }
    }
    for (f, c) in fragment
        .rgba
        .chunks_exact(4)
        .zip(compute.rgba.chunks_exact(4))
    {
        colour += usize::from(f.iter().zip(c).any(|(a, b)| a.abs_diff(*b) > 1));
    }
    eprintln!(
        "{name}: {covered} covered; the paths differ in coverage {coverage}, depth {far}, \
         colour {colour}"
    );
    assert!(
        coverage + far + colour == 0,
        "{name}: the paths differ (images in {})",
        dir.display()
    );
    (compute, covered)
}

#[test]
fn every_figure_feature_draws_the_same_picture_on_both_paths() {
    let dir = fresh_dir("compute-figures");
    let dti = common::fit_dti_small_64d(&dir);
    let fa = fa_map(&dir, &dti);
    let (fod, peaks) = fod_and_peaks(&dir);
    let tensor = ["--tensor", text(&dti), "--order", "2"];
    // Four by four voxels, so that the fODFs' lobes span many pixels each.
    let sh = [
        "--sh",
        text(&fod),
        "--basis",
        "dipy",
        "--voxels",
        "3:7,3:7,:",
    ];
    let with = |base: &[&str], extra: &[&str]| -> Vec<String> {
        base.iter().chain(extra).map(|s| s.to_string()).collect()
    };
    let cases: Vec<(&str, Vec<String>)> = vec![
        ("plain", with(&tensor, &[])),
        ("sh", with(&sh, &[])),
        ("underlay", with(&tensor, &["--underlay", text(&fa)])),
        (
            "underlay-centre",
            with(
                &tensor,
                &["--underlay", text(&fa), "--underlay-plane", "centre"],
            ),
        ),
        (
            "shadows",
            with(&sh, &["--underlay", text(&fa), "--shadows", "hard"]),
        ),
        (
            "soft-shadows-occlusion",
            with(
                &sh,
                &[
                    "--shadows",
                    "soft:5",
                    "--ambient-occlusion",
                    "on",
                    "--ambient",
                    "0.4",
                ],
            ),
        ),
        ("peaks", with(&sh, &["--peaks", text(&peaks)])),
        ("samples", with(&sh, &["--samples", "4"])),
        (
            "hide-sign",
            with(&sh, &["--negative", "hide", "--color", "sign"]),
        ),
        ("sign", with(&sh, &["--color", "sign"])),
        (
            "lightbox",
            with(
                &tensor,
                &[
                    "--underlay",
                    text(&fa),
                    "--lightbox",
                    "2",
                    "--slice",
                    "axial",
                ],
            ),
        ),
        (
            "views",
            with(
                &sh,
                &["--views", "axial,coronal,sagittal", "--peaks", text(&peaks)],
            ),
        ),
    ];
    let mut pictures = std::collections::HashMap::new();
    for (name, args) in &cases {
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        let (picture, covered) = same_on_both_paths(&dir, name, &args);
        assert!(covered > 100, "{name}: {covered} pixels covered");
        pictures.insert(*name, picture);
    }
    // Each feature changed the picture it was compared on (the CSD fit leaves few
    // negative lobes to hide).
    for (name, plain, least) in [
        ("underlay", "plain", 20),
        ("underlay-centre", "underlay", 20),
        ("soft-shadows-occlusion", "sh", 20),
        ("peaks", "sh", 20),
        ("samples", "sh", 20),
        ("hide-sign", "sign", 1),
        ("sign", "sh", 20),
    ] {
        let changed = pictures[name]
            .rgba
            .chunks_exact(4)
            .zip(pictures[plain].rgba.chunks_exact(4))
            .filter(|(a, b)| a != b)
            .count();
        assert!(
            changed >= least,
            "{name} changes {changed} pixels of {plain}"
        );
    }
}
