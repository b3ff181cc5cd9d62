//! The figure options of issue 13 in the viewer: the colour bar (`--colorbar`) and the
//! montages (`--views`, `--lightbox`). A scripted `glyphcast view` under Xvfb shows, in
//! its window (`--capture-window`) and in its screenshot, the image `glyphcast render`
//! makes with the same options and panel size, also after slice moves and colour
//! changes; combinations that cannot work are usage errors before a window opens.
//!
//! Tolerances: the screenshot is the headless renderer's image, so it must equal the
//! render exactly. The window draws the glyphs with the colour-only build of the same
//! shaders into a BGRA swapchain image (see `common::window::assert_window_matches`: one
//! 8-bit level, and 0.5% of the pixels for silhouette rays); the colour bar's strip is
//! copied into the window byte for byte, so the strip must be exact in the window too.
use crate::common;
use common::window::{
    BIN, Xvfb, assert_clean, assert_window_matches, data, differing_pixels, out, path_str,
};
use glyphcast::io::png::read_png_rgba8;
use std::path::{Path, PathBuf};
use std::process::Command;

/// `glyphcast render` of a scene file or volume (`input`, as arguments) with `options`;
/// returns the PNG.
fn render(input: &[&str], name: &str, options: &[&str]) -> PathBuf {
    let png = out(name);
    let run = Command::new(BIN)
        .arg("render")
        .args(input)
        .args(options)
        .args(["--validation", "-o", path_str(&png)])
        .output()
        .expect("running glyphcast render");
    assert!(
        run.status.success(),
        "glyphcast render {input:?} {options:?}: {}",
        String::from_utf8_lossy(&run.stderr)
    );
    png
}

/// The RGBA pixels of the rectangle (x, y, w, h) of a PNG.
fn crop(png: &Path, (x, y, w, h): (u32, u32, u32, u32)) -> Vec<u8> {
    let (width, height, rgba) = read_png_rgba8(png).expect("reading a PNG");
    assert!(
        x + w <= width && y + h <= height,
        "{} is too small",
        png.display()
    );
    (y..y + h)
        .flat_map(|row| {
            let at = 4 * (row * width + x) as usize;
            rgba[at..at + 4 * w as usize].to_vec()
        })
        .collect()
}

/// `png` with `captions[k]` drawn onto panel k of a grid of two columns of PANEL cells
/// (`render::compose::labels::draw_caption`, as `render` captions a lightbox), written as `name`.
fn with_captions(png: &Path, captions: &[&str], name: &str) -> PathBuf {
    let (width, height, mut rgba) = read_png_rgba8(png).expect("reading a PNG");
    let (w, h) = PANEL;
    assert!(height >= 2 * h, "{}: two rows of panels", png.display());
    for (k, caption) in captions.iter().enumerate() {
        let (x0, y0) = ((k as u32 % 2) * w, (k as u32 / 2) * h);
        let mut cell = crop(png, (x0, y0, w, h));
        glyphcast::render::compose::labels::draw_caption(&mut cell, w, h, caption)
            .expect("caption");
        for (row, line) in cell.chunks_exact(4 * w as usize).enumerate() {
            let at = (4 * ((y0 + row as u32) * width + x0)) as usize;
            rgba[at..at + line.len()].copy_from_slice(line);
        }
    }
    let path = out(name);
    glyphcast::io::png::write_png_rgba8(&path, width, height, &rgba).expect("writing");
    path
}

fn size(png: &Path) -> (u32, u32) {
    let (w, h, _) = read_png_rgba8(png).expect("reading a PNG");
    (w, h)
}

/// The screenshot equals the render; the window equals it within the window tolerance,
/// and exactly in the colour bar's strip (columns from `strip_left` on), if any.
fn assert_shows(window: &Path, shot: &Path, rendered: &Path, strip_left: Option<u32>) {
    assert_eq!(size(window), size(rendered), "{}", window.display());
    let (count, worst, _) = differing_pixels(shot, rendered, 0);
    assert_eq!(
        count,
        0,
        "the screenshot {} differs from the render {} (largest {worst})",
        shot.display(),
        rendered.display()
    );
    assert_window_matches(window, rendered);
    if let Some(left) = strip_left {
        let (w, h) = size(rendered);
        let strip = (left, 0, w - left, h);
        assert!(
            crop(window, strip) == crop(rendered, strip),
            "the window's colour bar strip differs from the render's ({})",
            window.display()
        );
    }
}

/// The arguments of a scripted view: `frames` frames of `script`, writing the screenshot
/// and the window capture named after `name`.
fn scripted(name: &str, frames: u32, script: &str) -> (Vec<String>, PathBuf, PathBuf) {
    let (shot, window) = (
        out(&format!("{name}-shot.png")),
        out(&format!("{name}-window.png")),
    );
    let mut args = vec!["--frames".to_owned(), frames.to_string()];
    if !script.is_empty() {
        args.extend(["--script".to_owned(), script.to_owned()]);
    }
    args.extend([
        "--screenshot".to_owned(),
        path_str(&shot).to_owned(),
        "--capture-window".to_owned(),
        path_str(&window).to_owned(),
    ]);
    (args, shot, window)
}

fn view(x: &Xvfb, input: &[&str], options: &[&str], run: &[String]) {
    let mut args: Vec<&str> = input.to_vec();
    args.extend_from_slice(options);
    args.extend(run.iter().map(String::as_str));
    assert_clean(&x.view(&args));
}

#[test]
fn the_colour_bar_is_renders_and_follows_the_colour_mode() {
    let Some(x) = Xvfb::start("the_colour_bar_is_renders_and_follows_the_colour_mode") else {
        return;
    };
    let scene = data("tests/scenes/order4_pair.json");
    let input = [scene.as_str()];
    let bar = [
        "--width",
        "200",
        "--height",
        "150",
        "--color",
        "magnitude",
        "--colorbar",
        "--colorbar-label",
        "|f| (mm)",
    ];
    let rendered = render(&input, "bar-render.png", &bar);
    let (width, _) = size(&rendered);
    assert!(width > 230, "the render has no strip: {width} px wide");

    // The window is --width plus the strip, and shows what render appends.
    let (run, shot, window) = scripted("bar", 3, "");
    view(&x, &input, &bar, &run);
    assert_shows(&window, &shot, &rendered, Some(200));

    // From an explicit range to the default one: the bar's ticks follow the range the
    // shaders map (the strip is exact, so its text must have changed with it).
    let mut ranged = bar.to_vec();
    ranged.extend(["--magnitude-range", "0:3"]);
    let (run, shot, window) = scripted("bar-range", 3, "color:magnitude");
    view(&x, &input, &ranged, &run);
    assert_shows(&window, &shot, &rendered, Some(200));
    let before = render(&input, "bar-range-render.png", &ranged);
    assert!(
        crop(&before, (200, 0, width - 200, 150)) != crop(&rendered, (200, 0, width - 200, 150)),
        "the two ranges draw the same strip"
    );

    // Another colour mode has no bar: the glyphs take the whole window, as a render of
    // that size without --colorbar draws them.
    let (run, shot, window) = scripted("bar-off", 3, "color:direction");
    view(&x, &input, &bar, &run);
    let plain = render(
        &input,
        "bar-off-render.png",
        &["--width", &width.to_string(), "--height", "150"],
    );
    assert_shows(&window, &shot, &plain, None);
}

/// `glyphcast fit --order 2` on DIPY's small_64D: 10 x 10 x 10 voxels.
fn dti(dir: &str) -> String {
    let dir = out(dir);
    std::fs::create_dir_all(&dir).expect("folder");
    path_str(&common::fit_dti_small_64d(&dir)).to_owned()
}

const PANEL: (u32, u32) = (72, 56);

fn panel_size() -> [String; 4] {
    [
        "--width".into(),
        PANEL.0.to_string(),
        "--height".into(),
        PANEL.1.to_string(),
    ]
}

#[test]
fn views_are_renders_panels_and_move_their_slices() {
    let Some(x) = Xvfb::start("views_are_renders_panels_and_move_their_slices") else {
        return;
    };
    let tensor = dti("viewer-views");
    let input = ["--tensor", tensor.as_str(), "--order", "2"];
    let size_args = panel_size();
    let mut options: Vec<&str> = size_args.iter().map(String::as_str).collect();
    options.extend(["--color", "magnitude", "--colorbar"]);
    let mut views = options.clone();
    views.extend(["--views", "axial:4,coronal:5,sagittal:5"]);
    let rendered = render(&input, "views-render.png", &views);
    assert_eq!(size(&rendered).1, PANEL.1);
    let (run, shot, window) = scripted("views", 3, "");
    view(&x, &input, &views, &run);
    assert_shows(&window, &shot, &rendered, Some(3 * PANEL.0));

    // `active:2` makes the second panel, the coronal one, the one that moves.
    let (run, shot, window) = scripted("views-moved", 4, "active:2,slice:+1");
    view(&x, &input, &views, &run);
    let mut moved = options.clone();
    moved.extend(["--views", "axial:4,coronal:6,sagittal:5"]);
    let moved = render(&input, "views-moved-render.png", &moved);
    assert_shows(&window, &shot, &moved, Some(3 * PANEL.0));
    let coronal = (PANEL.0, 0, PANEL.0, PANEL.1);
    assert!(
        crop(&moved, coronal) != crop(&rendered, coronal),
        "the coronal panel did not change"
    );

    // Resizes, camera moves and colour switches keep the window and the screenshot
    // together (and the validation layer quiet): the offscreen target and the strip
    // are made again for each size.
    let script = "resize:300x120,orbit:20:10,zoom:0.8,color:direction,resize:250x90,\
                  color:magnitude,pan:4:-2";
    let (run, shot, window) = scripted("views-resized", 9, script);
    view(&x, &input, &views, &run);
    assert_eq!(size(&shot), (250, 90));
    assert_window_matches(&window, &shot);
}

/// The voxel indices `--lightbox count` shows along an axis of `length` voxels.
fn lightbox_slices(count: usize, length: usize) -> Vec<usize> {
    (0..count)
        .map(|k| (2 * k + 1) * length / (2 * count))
        .collect()
}

#[test]
fn a_lightbox_is_renders_and_its_slices_move_together() {
    let Some(x) = Xvfb::start("a_lightbox_is_renders_and_its_slices_move_together") else {
        return;
    };
    let tensor = dti("viewer-lightbox");
    let input = ["--tensor", tensor.as_str(), "--order", "2"];
    let size_args = panel_size();
    let panel: Vec<&str> = size_args.iter().map(String::as_str).collect();
    let mut options = panel.clone();
    options.extend(["--lightbox", "4", "--color", "magnitude", "--colorbar"]);
    let rendered = render(&input, "lightbox-render.png", &options);
    assert_eq!(size(&rendered).1, 2 * PANEL.1, "two rows of two");
    let (run, shot, window) = scripted("lightbox", 3, "");
    view(&x, &input, &options, &run);
    // Each panel is captioned with its slice, as `render` captions it (k=1, 3, 6, 8).
    assert_shows(&window, &shot, &rendered, Some(2 * PANEL.0));

    // One slice on: every panel shows the next slice, as a single view of it renders
    // it (the panels of a montage are single views, tests/montage.rs; direction
    // colours, since the montage's magnitude range is shared): the expected picture is
    // the four single renders in the lightbox's grid, captioned with their new slices.
    // A lightbox keeps the band along each edge free of glyphs for its captions, as a
    // single view does for its edge labels: the single views are rendered with
    // `--labels`, so that they are framed as the panels are, and their band (which holds
    // only their letters and the background) is cleared to the background.
    let mut moved_options = panel.clone();
    moved_options.extend(["--lightbox", "4"]);
    let (run, shot, window) = scripted("lightbox-moved", 4, "slice:+1");
    view(&x, &input, &moved_options, &run);
    let slices = lightbox_slices(4, 10);
    assert_eq!(slices, [1, 3, 6, 8]);
    let (width, height) = (2 * PANEL.0, 2 * PANEL.1);
    let mut expected = vec![0u8; (4 * width * height) as usize];
    for (k, index) in slices.iter().enumerate() {
        let slice = format!("axial:{}", index + 1);
        let mut single = panel.clone();
        single.extend(["--slice", slice.as_str(), "--labels"]);
        let png = render(&input, &format!("lightbox-k{}.png", index + 1), &single);
        let mut pixels = crop(&png, (0, 0, PANEL.0, PANEL.1));
        let band = glyphcast::render::compose::labels::edge_band(PANEL.0, PANEL.1).floor() as u32;
        let background: [u8; 4] = pixels[..4].try_into().expect("a pixel");
        for (n, pixel) in pixels.chunks_exact_mut(4).enumerate() {
            let (px, py) = (n as u32 % PANEL.0, n as u32 / PANEL.0);
            if px < band || py < band || px >= PANEL.0 - band || py >= PANEL.1 - band {
                pixel.copy_from_slice(&background);
            }
        }
        let (x0, y0) = ((k as u32 % 2) * PANEL.0, (k as u32 / 2) * PANEL.1);
        for (row, line) in pixels.chunks_exact(4 * PANEL.0 as usize).enumerate() {
            let at = (4 * ((y0 + row as u32) * width + x0)) as usize;
            expected[at..at + line.len()].copy_from_slice(line);
        }
    }
    let composed = out("lightbox-moved-expected.png");
    glyphcast::io::png::write_png_rgba8(&composed, width, height, &expected)
        .expect("writing the expected picture");
    let captions: Vec<String> = slices
        .iter()
        .map(|index| format!("k={}", index + 1))
        .collect();
    let captions: Vec<&str> = captions.iter().map(String::as_str).collect();
    let composed = with_captions(&composed, &captions, "lightbox-moved-captioned.png");
    assert_shows(&window, &shot, &composed, None);

    // The last slice is at 8 + 1 = 9, the volume's end: a further move is refused
    // whole, so the spacing stays.
    let (run, end, _) = scripted("lightbox-end", 4, "slice:+1,slice:+1");
    view(&x, &input, &moved_options, &run);
    assert_eq!(differing_pixels(&end, &shot, 0).0, 0);
}

/// An underlay under every panel of a montage, as `render` draws it: the lightbox (with
/// its captions over the underlay) and views, whose underlay moves with the panel's
/// slice.
#[test]
fn underlays_are_renders_under_every_panel_and_move_with_their_slices() {
    let Some(x) = Xvfb::start("underlays_are_renders_under_every_panel_and_move_with_their_slices")
    else {
        return;
    };
    let (tensors, fa) = common::underlay::tensors_with_underlay(&out("viewer-montage-underlay"));
    let input = [
        "--tensor",
        tensors.as_str(),
        "--order",
        "2",
        "--underlay",
        fa.as_str(),
    ];
    let size_args = panel_size();
    let panel: Vec<&str> = size_args.iter().map(String::as_str).collect();
    // The 4 axial slices of the 6 x 5 x 4 volume, one a panel.
    let mut lightbox = panel.clone();
    lightbox.extend(["--lightbox", "4"]);
    let rendered = render(&input, "lightbox-underlay-render.png", &lightbox);
    let (run, shot, window) = scripted("lightbox-underlay", 3, "");
    view(&x, &input, &lightbox, &run);
    assert_shows(&window, &shot, &rendered, None);
    let without = render(&input[..4], "lightbox-no-underlay.png", &lightbox);
    // The underlay shows around the glyphs of every panel (framed inside the captions'
    // band, the volume fills less than half of each small panel).
    assert!(
        differing_pixels(&rendered, &without, 10).0 > (4 * PANEL.0 * PANEL.1 / 8) as usize,
        "the lightbox's underlay is missing"
    );

    let mut views = panel.clone();
    views.extend(["--views", "axial:1,coronal:2"]);
    let rendered = render(&input, "views-underlay-render.png", &views);
    let (run, shot, window) = scripted("views-underlay-moved", 4, "slice:+1");
    view(&x, &input, &views, &run);
    let mut moved = panel.clone();
    moved.extend(["--views", "axial:2,coronal:2"]);
    let moved = render(&input, "views-underlay-moved-render.png", &moved);
    assert_shows(&window, &shot, &moved, None);
    let axial = (0, 0, PANEL.0, PANEL.1);
    assert!(
        crop(&moved, axial) != crop(&rendered, axial),
        "the axial panel did not change"
    );
}

#[test]
fn montages_and_bars_that_cannot_work_are_usage_errors() {
    let scene = data("tests/scenes/sphere.json");
    let volume = data("tests/data/dipy/func_coef.nii.gz");
    let sh = ["--sh", volume.as_str(), "--basis", "tournier07", "--legacy"];
    let with_sh =
        |extra: &[&str]| -> Vec<String> { sh.iter().chain(extra).map(|s| s.to_string()).collect() };
    let cases: Vec<(Vec<String>, &str)> = vec![
        (
            vec![scene.clone(), "--views".into(), "axial".into()],
            "volume input",
        ),
        (with_sh(&["--colorbar"]), "--color magnitude"),
        (with_sh(&["--lightbox", "2", "--slices", "mid"]), "--slice"),
        (
            with_sh(&["--views", "axial", "--save-scene", "x.json"]),
            "--save-scene",
        ),
    ];
    for (args, words) in cases {
        let run = Command::new(BIN)
            .arg("view")
            .args(&args)
            .args(["--frames", "1"])
            .env_remove("DISPLAY")
            .output()
            .expect("running glyphcast view");
        let stderr = String::from_utf8_lossy(&run.stderr);
        assert_eq!(run.status.code(), Some(2), "{args:?}: {stderr}");
        assert!(stderr.contains(words), "{args:?}: no '{words}' in {stderr}");
    }
}

/// `glyphcast peaks` of DIPY's func_coef (2 x 3 x 4 voxels, the DIPY basis).
fn func_coef_peaks(dir: &str) -> (String, String) {
    let dir = out(dir);
    std::fs::create_dir_all(&dir).expect("folder");
    let fod = data("tests/data/dipy/func_coef.nii.gz");
    let peaks = dir.join("peaks.nii.gz");
    let run = Command::new(BIN)
        .args(["peaks", &fod, "--basis", "dipy", "--quiet", "-o"])
        .arg(&peaks)
        .output()
        .expect("running glyphcast peaks");
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    (fod, path_str(&peaks).to_owned())
}

#[test]
fn peaks_are_renders_and_follow_the_slice() {
    let Some(x) = Xvfb::start("peaks_are_renders_and_follow_the_slice") else {
        return;
    };
    let (fod, peaks) = func_coef_peaks("viewer-peaks");
    let size_args = panel_size();
    let mut options: Vec<&str> = size_args.iter().map(String::as_str).collect();
    options.extend(["--peaks", peaks.as_str(), "--peaks-width", "3"]);
    let glyphs = ["--sh", fod.as_str(), "--basis", "dipy", "--scale", "0.3"];
    // With glyphs (axial slice 2 of 0..3, then 3), and alone (the peaks' grid).
    for (name, input) in [("peaks-glyphs", &glyphs[..]), ("peaks-alone", &[][..])] {
        let rendered = render(input, &format!("{name}-render.png"), &options);
        let (run, shot, window) = scripted(name, 3, "");
        view(&x, input, &options, &run);
        assert_shows(&window, &shot, &rendered, None);

        let (run, shot, window) = scripted(&format!("{name}-moved"), 4, "slice:+1");
        view(&x, input, &options, &run);
        let mut moved = options.clone();
        moved.extend(["--slice", "axial:3"]);
        let moved = render(input, &format!("{name}-moved-render.png"), &moved);
        assert_shows(&window, &shot, &moved, None);
        let (changed, _, _) = differing_pixels(&moved, &rendered, 0);
        assert!(changed > 100, "{name}: the next slice looks the same");
    }
    // In a montage, each panel's peaks, in the window and in the screenshot.
    let mut views = options.clone();
    views.extend(["--views", "axial,coronal"]);
    let rendered = render(&glyphs, "peaks-views-render.png", &views);
    let (run, shot, window) = scripted("peaks-views", 3, "");
    view(&x, &glyphs, &views, &run);
    assert_shows(&window, &shot, &rendered, None);
    // The peaks are in the picture: without them it differs.
    let plain = render(
        &glyphs,
        "peaks-none-render.png",
        &panel_size().each_ref().map(String::as_str),
    );
    let with = render(&glyphs, "peaks-glyphs-again.png", &options);
    let (count, _, _) = differing_pixels(&plain, &with, 0);
    assert!(count > 100, "the peaks change {count} pixels");
}

/// `--tracks` with `--slab` in the viewer: the window shows what `render` draws, tubes
/// and glyphs in one depth buffer, and after a slice step the slab has moved with the
/// slice (the window shows `render --slice` of the next slice, and that differs); `T`
/// hides the tubes and shows them again.
#[test]
fn tracks_are_renders_and_their_slab_follows_the_slice() {
    let Some(x) = Xvfb::start("tracks_are_renders_and_their_slab_follows_the_slice") else {
        return;
    };
    let dir = out("viewer-tracks");
    std::fs::create_dir_all(&dir).expect("folder");
    let fod = data("tests/data/dipy/func_coef.nii.gz");
    // Lines along x at the heights of axial slices 2 and 3 (identity affine), and one
    // that climbs through both.
    let mut tractogram = glyphcast_dmri::io::tracks::Tractogram::default();
    for (y, z0, z1) in [(0.4, 2.0, 2.0), (1.6, 3.0, 3.0), (1.0, 1.5, 3.5)] {
        tractogram.offsets.push(tractogram.points.len() as u64);
        tractogram.points.extend((0..21).map(|k| {
            let s = k as f32 / 20.0;
            [-0.5 + 2.0 * s, y, z0 + (z1 - z0) * s]
        }));
    }
    let tck = dir.join("lines.tck");
    crate::tracks::write_tck(&tck, &tractogram);
    let size_args = panel_size();
    let mut options: Vec<&str> = size_args.iter().map(String::as_str).collect();
    options.extend([
        "--tracks",
        path_str(&tck),
        "--slab",
        "0.3",
        "--tracks-radius",
        "0.1",
    ]);
    let glyphs = ["--sh", fod.as_str(), "--basis", "dipy", "--scale", "0.3"];
    let rendered = render(&glyphs, "tracks-render.png", &options);
    let (run, shot, window) = scripted("tracks", 3, "");
    view(&x, &glyphs, &options, &run);
    assert_shows(&window, &shot, &rendered, None);
    let (run, shot, window) = scripted("tracks-moved", 4, "slice:+1");
    view(&x, &glyphs, &options, &run);
    let mut moved = options.clone();
    moved.extend(["--slice", "axial:3"]);
    let moved = render(&glyphs, "tracks-moved-render.png", &moved);
    assert_shows(&window, &shot, &moved, None);
    let (changed, _, _) = differing_pixels(&moved, &rendered, 0);
    assert!(changed > 100, "the next slice looks the same");
    // The tubes are in the picture: without them it differs.
    let plain = render(
        &glyphs,
        "tracks-none-render.png",
        &panel_size().each_ref().map(String::as_str),
    );
    let (count, _, _) = differing_pixels(&plain, &rendered, 0);
    assert!(count > 60, "the tubes change {count} pixels");
    // `T` hides them (the window shows the render without --tracks), and shows them again.
    let (run, shot, window) = scripted("tracks-hidden", 4, "tracks:toggle");
    view(&x, &glyphs, &options, &run);
    assert_shows(&window, &shot, &plain, None);
    let (run, shot, window) = scripted("tracks-shown-again", 6, "tracks:off,tracks:toggle");
    view(&x, &glyphs, &options, &run);
    assert_shows(&window, &shot, &rendered, None);
}
