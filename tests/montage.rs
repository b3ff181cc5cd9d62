//! Montages (`--views`, `--lightbox`, issue 13): every panel of the montage is pixel for
//! pixel, in colour and depth, the single-view render of the same view at the panel's
//! size (a lightbox panel with its slice written in its corner, issue 28), with the
//! same underlay; the grid's geometry; the errors for bad lists.
use crate::common;
use common::{fresh_dir, glyphcast};
use glyphcast::io::npy::read_npy_f32;
use glyphcast::io::png::read_png_rgba8;
use std::path::Path;

const W: u32 = 72;
const H: u32 = 56;

fn path_str(p: &Path) -> &str {
    p.to_str().expect("utf-8 path")
}

/// `glyphcast fit --order 2` on DIPY's small_64D (10x10x10 voxels).
struct Picture {
    width: u32,
    height: u32,
    rgba: Vec<u8>,
    depth: Vec<f32>,
}

/// `glyphcast render --tensor DTI --order 2 --width W --height H` with `extra`.
fn render(dir: &Path, dti: &Path, name: &str, extra: &[&str]) -> Picture {
    render_with(dir, dti, name, true, extra)
}

/// [`render`], with the edge labels or without them.
fn render_with(dir: &Path, dti: &Path, name: &str, labels: bool, extra: &[&str]) -> Picture {
    let (png, npy) = (
        dir.join(format!("{name}.png")),
        dir.join(format!("{name}.npy")),
    );
    let (w, h) = (W.to_string(), H.to_string());
    let mut args = vec![
        "render",
        "--tensor",
        path_str(dti),
        "--order",
        "2",
        "--width",
        &w,
        "--height",
        &h,
        "-o",
        path_str(&png),
        "--depth-out",
        path_str(&npy),
    ];
    if labels {
        args.push("--labels");
    }
    args.extend_from_slice(extra);
    let run = glyphcast(&args);
    assert!(
        run.status.success(),
        "{extra:?}: {}",
        String::from_utf8_lossy(&run.stderr)
    );
    let (width, height, rgba) = read_png_rgba8(&png).expect("png");
    let (shape, depth) = read_npy_f32(&npy).expect("npy");
    assert_eq!(shape, [height as usize, width as usize]);
    Picture {
        width,
        height,
        rgba,
        depth,
    }
}

/// Panel (column, row) of a montage against a single view: identical colour and depth
/// (NaN where the single view has NaN), the single view's colour with `caption` written
/// in its corner (`render::compose::labels::draw_caption`) if given, which must change pixels.
fn assert_panel(
    montage: &Picture,
    column: u32,
    row: u32,
    single: &Picture,
    caption: Option<&str>,
    what: &str,
) {
    assert_eq!((single.width, single.height), (W, H), "{what}");
    let mut expected = single.rgba.clone();
    if let Some(caption) = caption {
        glyphcast::render::compose::labels::draw_caption(&mut expected, W, H, caption)
            .expect("caption");
        let written = (0..expected.len())
            .filter(|&n| expected[n] != single.rgba[n])
            .count();
        assert!(
            written > 20,
            "{what}: the caption {caption} changes {written} bytes"
        );
    }
    let mut glyph_pixels = 0;
    for y in 0..H {
        for x in 0..W {
            let m = ((row * H + y) * montage.width + column * W + x) as usize;
            let s = (y * W + x) as usize;
            assert_eq!(
                montage.rgba[4 * m..4 * m + 4],
                expected[4 * s..4 * s + 4],
                "{what}: colour at ({x}, {y})"
            );
            let (a, b) = (montage.depth[m], single.depth[s]);
            assert!(
                a.to_bits() == b.to_bits(),
                "{what}: depth {a} vs {b} at ({x}, {y})"
            );
            glyph_pixels += usize::from(!b.is_nan());
        }
    }
    // (Small panels: the band kept free for the labels leaves the glyphs about half.)
    assert!(glyph_pixels > 30, "{what}: {glyph_pixels} glyph pixels");
}

#[test]
fn each_panel_of_views_is_the_single_view_render() {
    let dir = fresh_dir("montage-views");
    let dti = common::fit_dti_small_64d(&dir);
    let montage = render(
        &dir,
        &dti,
        "views",
        &["--views", "sagittal,axial,coronal:3"],
    );
    assert_eq!((montage.width, montage.height), (3 * W, H));
    for (column, slice) in ["sagittal", "axial", "coronal:3"].iter().enumerate() {
        let single = render(&dir, &dti, slice, &["--slice", slice]);
        assert_panel(&montage, column as u32, 0, &single, None, slice);
    }
    // The same with ellipsoids: panels are ordinary renders whatever is drawn.
    let ellipsoids = render(
        &dir,
        &dti,
        "ellipsoids",
        &["--views", "coronal", "--glyph", "ellipsoid"],
    );
    let single = render(
        &dir,
        &dti,
        "ellipsoid",
        &["--slice", "coronal", "--glyph", "ellipsoid"],
    );
    assert_eq!((ellipsoids.width, ellipsoids.height), (W, H));
    assert_panel(&ellipsoids, 0, 0, &single, None, "coronal ellipsoids");
}

#[test]
fn lightbox_draws_evenly_spaced_slices_in_a_grid() {
    let dir = fresh_dir("montage-lightbox");
    let dti = common::fit_dti_small_64d(&dir);
    // 5 slices: 3 columns, 2 rows; the sixth cell is background with NaN depth.
    let montage = render(
        &dir,
        &dti,
        "lightbox",
        &["--lightbox", "5", "--slice", "coronal"],
    );
    assert_eq!((montage.width, montage.height), (3 * W, 2 * H));
    // 10 slices: floor((2k + 1) 10 / 10) = 1, 3, 5, 7, 9, each captioned with its index
    // along the voxel axis of the coronal plane (i in this rotated volume).
    for (k, index) in [1, 3, 5, 7, 9].iter().enumerate() {
        let slice = format!("coronal:{index}");
        let single = render(&dir, &dti, &slice, &["--slice", &slice]);
        let caption = format!("i={index}");
        assert_panel(
            &montage,
            k as u32 % 3,
            k as u32 / 3,
            &single,
            Some(&caption),
            &slice,
        );
    }
    let corner = montage.rgba[4 * ((H + 3) * montage.width + 2 * W + 3) as usize..][..4].to_vec();
    // (The top-left pixel is under panel 0's caption: the background is the renderer's.)
    let settings = glyphcast::render::RenderSettings::default();
    let background =
        glyphcast::render::compose::montage::background_bytes(settings.background).to_vec();
    assert_eq!(corner, background, "the empty cell is background");
    for y in H..2 * H {
        for x in 2 * W..3 * W {
            assert!(montage.depth[(y * montage.width + x) as usize].is_nan());
        }
    }
}

/// An FA map of the DTI volume `dti` (on its grid, with its affine), computed here.
pub(crate) fn fa_map(dir: &Path, dti: &Path) -> std::path::PathBuf {
    let image = glyphcast_dmri::io::image::read_image(dti).expect("dti");
    let shape = image.shape(4);
    let mut fa = ndarray::ArrayD::<f64>::zeros(ndarray::IxDyn(&shape[..3]));
    for ((i, j, k), value) in fa
        .view_mut()
        .into_dimensionality::<ndarray::Ix3>()
        .expect("3D")
        .indexed_iter_mut()
    {
        let d: Vec<f64> = (0..6)
            .map(|n| image.data[[i, j, k, n].as_slice()])
            .collect();
        // xx, xy, xz, yy, yz, zz: FA = sqrt(3/2) |D - tr/3 I| / |D|.
        let mean = (d[0] + d[3] + d[5]) / 3.0;
        let dev = (d[0] - mean).powi(2) + (d[3] - mean).powi(2) + (d[5] - mean).powi(2);
        let off = 2.0 * (d[1] * d[1] + d[2] * d[2] + d[4] * d[4]);
        let norm = d[0] * d[0] + d[3] * d[3] + d[5] * d[5] + off;
        *value = if norm > 0.0 {
            (1.5 * (dev + off) / norm).sqrt()
        } else {
            0.0
        };
    }
    let path = dir.join("fa.nii");
    common::write_nifti(&path, &fa, image.voxel_to_world.affine);
    path
}

/// An underlay goes under every panel of a montage (issue 28): each panel of a lightbox
/// and of the three views is the single view with the same underlay.
#[test]
fn a_montage_draws_the_underlay_under_every_panel() {
    let dir = fresh_dir("montage-underlay");
    let dti = common::fit_dti_small_64d(&dir);
    let fa = fa_map(&dir, &dti);
    let under = ["--underlay", path_str(&fa)];
    let with = |extra: &[&str]| -> Vec<String> {
        under.iter().chain(extra).map(|s| s.to_string()).collect()
    };
    let run = |name: &str, extra: &[&str]| {
        let args = with(extra);
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        render(&dir, &dti, name, &args)
    };
    let lightbox = run("lightbox", &["--lightbox", "2", "--slice", "axial"]);
    for (k, index) in [2, 7].iter().enumerate() {
        let slice = format!("axial:{index}");
        let single = run(&slice, &["--slice", &slice]);
        let caption = format!("k={index}");
        assert_panel(&lightbox, k as u32, 0, &single, Some(&caption), &slice);
    }
    let views = run("views", &["--views", "axial,coronal,sagittal"]);
    for (column, slice) in ["axial", "coronal", "sagittal"].iter().enumerate() {
        let single = run(slice, &["--slice", slice]);
        assert_panel(&views, column as u32, 0, &single, None, slice);
    }
}

#[test]
fn bad_montage_requests_are_usage_errors() {
    let dir = fresh_dir("montage-errors");
    let dti = common::fit_dti_small_64d(&dir);
    let png = dir.join("out").join("x.png");
    std::fs::create_dir_all(png.parent().expect("parent")).expect("folder");
    let scene = dir.join("scene.json");
    std::fs::write(
        &scene,
        glyphcast::accuracy::suite::touching_centre(32).to_json(),
    )
    .expect("scene");
    let tensor = ["--tensor", path_str(&dti), "--order", "2"];
    let cases: Vec<(Vec<&str>, &str)> = vec![
        (vec!["--views", "axial,axial"], "listed twice"),
        (vec!["--views", "axial,top"], "'top' is not axial"),
        (vec!["--views", ""], "is not axial"),
        (
            vec!["--views", "axial", "--lightbox", "4"],
            "either --views or --lightbox",
        ),
        (vec!["--views", "axial", "--slice", "coronal"], "no --slice"),
        (vec!["--lightbox", "0"], "1 to 64"),
        (vec!["--lightbox", "11"], "has 10 slices"),
        (
            vec!["--views", "axial", "--save-scene", "s.json"],
            "--save-scene",
        ),
    ];
    for (extra, words) in cases {
        let mut args = vec!["render", "-o", path_str(&png)];
        args.extend_from_slice(&tensor);
        args.extend_from_slice(&extra);
        let run = glyphcast(&args);
        let stderr = String::from_utf8_lossy(&run.stderr);
        assert_eq!(run.status.code(), Some(2), "{extra:?}: {stderr}");
        assert!(
            stderr.contains(words),
            "{extra:?}: no '{words}' in {stderr}"
        );
        assert!(!png.exists());
    }
    let run = glyphcast(&[
        "render",
        path_str(&scene),
        "--views",
        "axial",
        "-o",
        path_str(&png),
    ]);
    assert_eq!(run.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&run.stderr).contains("volume input"));
    // The viewer shows montages too (tests/viewer_figures.rs) and refuses the same bad
    // lists, before a window opens.
    let run = std::process::Command::new(env!("CARGO_BIN_EXE_glyphcast"))
        .args(["view", "--tensor", path_str(&dti), "--order", "2"])
        .args(["--views", "axial,axial", "--frames", "1"])
        .env_remove("DISPLAY")
        .output()
        .expect("running glyphcast view");
    assert_eq!(run.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&run.stderr).contains("listed twice"));
}

/// Edge labels and a lightbox's captions never cover glyphs: the view is framed so that
/// no glyph reaches the band along each edge where letters go
/// (`render::compose::labels::edge_band`), and every letter lies in that band. Letters
/// are the pixels that no glyph covers (NaN depth) and that are not the background. A
/// lightbox keeps the band for its captions without `--labels` too.
#[test]
fn labels_and_captions_keep_off_the_glyphs() {
    let dir = fresh_dir("montage-label-band");
    let dti = common::fit_dti_small_64d(&dir);
    let settings = glyphcast::render::RenderSettings::default();
    let background =
        glyphcast::render::compose::montage::background_bytes(settings.background).to_vec();
    let (w, h) = (W as usize, H as usize);
    let band = glyphcast::render::compose::labels::edge_band(W, H);
    for (name, labels, extra, cells) in [
        ("single", true, vec!["--slice", "axial"], (1, 1)),
        ("lightbox", true, vec!["--lightbox", "4"], (2, 2)),
        ("lightbox-captions", false, vec!["--lightbox", "4"], (2, 2)),
    ] {
        let picture = render_with(&dir, &dti, name, labels, &extra);
        assert_eq!((picture.width, picture.height), (cells.0 * W, cells.1 * H));
        let (mut glyphs, mut letters) = (0, 0);
        for y in 0..picture.height as usize {
            for x in 0..picture.width as usize {
                // Distance from the pixel's centre to its panel's nearest edge.
                let (px, py) = ((x % w) as f64 + 0.5, (y % h) as f64 + 0.5);
                let edge = px.min(py).min(w as f64 - px).min(h as f64 - py);
                let i = y * picture.width as usize + x;
                let covered = picture.depth[i].is_finite();
                let letter = !covered && picture.rgba[4 * i..4 * i + 4] != background[..];
                glyphs += usize::from(covered);
                letters += usize::from(letter);
                assert!(
                    !(covered && edge < band),
                    "{name}: a glyph at ({x}, {y}) in the band"
                );
                assert!(
                    !(letter && edge >= band),
                    "{name}: a letter at ({x}, {y}) off the band"
                );
            }
        }
        assert!(
            glyphs > 30 && letters > 20,
            "{name}: {glyphs} glyph, {letters} letter pixels"
        );
    }
}
