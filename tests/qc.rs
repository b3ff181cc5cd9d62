//! `glyphcast qc` (issue 24): the figure set's files, its sidecar, its determinism, its
//! refusals; and many glyphcast processes at once. Every run has the validation layer
//! on (`common::glyphcast`) and draws CSD fODFs fitted from DIPY's small_64D.
use crate::common;

use common::{dipy_data, fit_small_64d, fresh_dir, glyphcast, output_dir, text, write_nifti};
use serde_json::Value;
use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::sync::OnceLock;

/// Small panels keep the suite lean; the set is the same at any size.
const PANEL: &str = "128";

/// CSD fODFs (band 8) of small_64D, fitted once for every test of this file.
fn fod() -> &'static Path {
    static FOD: OnceLock<PathBuf> = OnceLock::new();
    FOD.get_or_init(|| {
        let out = output_dir().join("qc-fod.nii.gz");
        let run = fit_small_64d(&["--odf", "csd", "--order", "8", "--quiet"], &out);
        assert!(run.status.success(), "{}", stderr(&run));
        out
    })
}

fn stderr(run: &Output) -> String {
    String::from_utf8_lossy(&run.stderr).into_owned()
}

fn qc(args: &[&str]) -> Output {
    let mut all = vec!["qc", text(fod()), "--panel-size", PANEL, "--quiet"];
    all.extend_from_slice(args);
    glyphcast(&all)
}

fn names(dir: &Path) -> BTreeSet<String> {
    std::fs::read_dir(dir)
        .expect("listing")
        .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
        .collect()
}

/// The files of the figures a sidecar lists, in order.
fn figure_files(doc: &Value) -> Vec<&str> {
    doc["figures"]
        .as_array()
        .unwrap()
        .iter()
        .map(|f| f["file"].as_str().unwrap())
        .collect()
}

fn sidecar(dir: &Path) -> Value {
    let text = std::fs::read_to_string(dir.join("qc.json")).expect("qc.json");
    serde_json::from_str(&text).expect("qc.json is JSON")
}

/// SHA-256 by coreutils, independent of the crate's own.
fn sha256sum(path: &Path) -> String {
    let run = Command::new("sha256sum")
        .arg(path)
        .output()
        .expect("sha256sum");
    String::from_utf8_lossy(&run.stdout)
        .split_whitespace()
        .next()
        .expect("a digest")
        .to_owned()
}

/// Width, height and RGBA8 pixels of a PNG.
fn decode(path: &Path) -> (u32, u32, Vec<u8>) {
    let decoder = png::Decoder::new(std::io::BufReader::new(
        std::fs::File::open(path).expect("opening a PNG"),
    ));
    let mut reader = decoder.read_info().expect("a PNG header");
    let mut pixels = vec![0; reader.output_buffer_size().expect("a size")];
    let info = reader.next_frame(&mut pixels).expect("PNG pixels");
    assert_eq!(info.color_type, png::ColorType::Rgba);
    pixels.truncate(info.buffer_size());
    (info.width, info.height, pixels)
}

/// Pixels of the cell (column, row) of a grid of `cell`-pixel cells that differ from
/// the top-left pixel (the background).
fn drawn_pixels(image: &(u32, u32, Vec<u8>), cell: (u32, u32), column: u32, row: u32) -> usize {
    let (width, _, pixels) = image;
    let background = &pixels[..4];
    let mut count = 0;
    for y in row * cell.1..(row + 1) * cell.1 {
        for x in column * cell.0..(column + 1) * cell.0 {
            let at = 4 * (y * width + x) as usize;
            if &pixels[at..at + 4] != background {
                count += 1;
            }
        }
    }
    count
}

/// Pixels of a grid of square `side`-pixel panels that lie in a panel's edge band and are
/// neither its background (its top-left pixel) nor a letter's: white letters with a dark
/// outline, blended onto the background, keep its grey (red = green, blue at most the
/// background's excess of blue over red above red); a glyph's shaded colour does not.
fn glyphs_in_edge_bands(image: &(u32, u32, Vec<u8>), side: u32) -> usize {
    let (width, height, pixels) = image;
    let band = glyphcast::render::compose::labels::edge_band(side, side);
    let blue_excess = i32::from(pixels[2]) - i32::from(pixels[0]);
    let mut count = 0;
    for y in 0..*height {
        for x in 0..*width {
            let (px, py) = (f64::from(x % side) + 0.5, f64::from(y % side) + 0.5);
            let edge = px
                .min(py)
                .min(f64::from(side) - px)
                .min(f64::from(side) - py);
            if edge >= band {
                continue;
            }
            let at = 4 * (y * width + x) as usize;
            let [r, g, b] = [0, 1, 2].map(|c| i32::from(pixels[at + c]));
            let grey = (r - g).abs() <= 1 && (-1..=blue_excess + 1).contains(&(b - r));
            count += usize::from(!grey);
        }
    }
    count
}

#[test]
fn the_set_is_its_fixed_files_described_by_its_sidecar_and_deterministic() {
    let root = fresh_dir("qc-set");
    let (first, second) = (root.join("first"), root.join("second"));
    for out in [&first, &second] {
        let run = qc(&["-o", text(out)]);
        assert!(run.status.success(), "{}", stderr(&run));
    }
    let expected: BTreeSet<String> = [
        "index.html",
        "odf-mosaic.png",
        "qc.json",
        "zoom-1.png",
        "zoom-2.png",
        "zoom-3.png",
    ]
    .map(String::from)
    .into();
    assert_eq!(names(&first), expected);
    assert_eq!(names(&root), ["first", "second"].map(String::from).into());
    // Determinism: the same bytes, but for the sidecar's `run` (device and timings).
    for name in &expected {
        if name != "qc.json" {
            let (a, b) = (first.join(name), second.join(name));
            assert_eq!(
                std::fs::read(&a).unwrap(),
                std::fs::read(&b).unwrap(),
                "{name}"
            );
        }
    }
    let (mut a, mut b) = (sidecar(&first), sidecar(&second));
    for doc in [&a, &b] {
        assert!(doc["run"]["device"].as_str().is_some_and(|d| !d.is_empty()));
        for step in [
            "read", "survey", "build", "device", "render", "encode", "total",
        ] {
            assert!(doc["run"]["timings_ms"][step].as_f64().is_some(), "{step}");
        }
    }
    a.as_object_mut().unwrap().remove("run");
    b.as_object_mut().unwrap().remove("run");
    assert_eq!(a, b);

    // The sidecar: version, the input with its size and checksum, settings, choices and
    // every figure with its size and checksum.
    assert_eq!(a["format"], "glyphcast qc 1");
    assert_eq!(a["glyphcast_version"], env!("CARGO_PKG_VERSION"));
    let input = &a["inputs"][0];
    assert_eq!(input["role"], "fod");
    assert_eq!(input["name"], "qc-fod.nii.gz");
    assert_eq!(
        input["bytes"].as_u64(),
        Some(std::fs::metadata(fod()).unwrap().len())
    );
    assert_eq!(input["sha256"].as_str(), Some(sha256sum(fod()).as_str()));
    assert_eq!(a["volume"]["dims"], serde_json::json!([10, 10, 10]));
    assert_eq!(a["volume"]["sh_band"], 8);
    // The basis the coefficients were read in (the fit records MRtrix3's tournier07).
    assert_eq!(a["volume"]["basis"], "tournier07");
    assert_eq!(a["volume"]["legacy"], false);
    assert_eq!(a["settings"]["panel_size"], 128);
    assert_eq!(a["settings"]["orientation"], "radiological");
    assert_eq!(a["settings"]["negative"], "hide");
    let cuts = a["selection"]["cuts"].as_array().unwrap();
    let planes: Vec<&str> = cuts.iter().map(|c| c["plane"].as_str().unwrap()).collect();
    assert_eq!(planes, ["axial", "coronal", "sagittal"]);
    for cut in cuts {
        let indices: Vec<u64> = cut["indices"]
            .as_array()
            .unwrap()
            .iter()
            .map(|i| i.as_u64().unwrap())
            .collect();
        assert_eq!(indices.len(), 3);
        assert!(indices.windows(2).all(|w| w[0] < w[1]), "{indices:?}");
        assert!(indices.iter().all(|&i| i < 10));
    }
    let regions = a["selection"]["regions"].as_array().unwrap();
    assert_eq!(regions.len(), 3);
    let gfa: Vec<f64> = regions
        .iter()
        .map(|r| r["mean_gfa"].as_f64().unwrap())
        .collect();
    assert!(
        gfa.windows(2).all(|w| w[0] >= w[1]),
        "ranked by GFA: {gfa:?}"
    );
    assert!(gfa.iter().all(|g| (0.0..=1.0).contains(g)));
    let figures = a["figures"].as_array().unwrap();
    assert_eq!(figures.len(), 4);
    for figure in figures {
        let file = first.join(figure["file"].as_str().unwrap());
        assert_eq!(figure["sha256"].as_str(), Some(sha256sum(&file).as_str()));
        assert_eq!(
            figure["bytes"].as_u64(),
            Some(std::fs::metadata(&file).unwrap().len())
        );
        let (w, h, _) = decode(&file);
        assert_eq!(
            (figure["width"].as_u64(), figure["height"].as_u64()),
            (Some(w.into()), Some(h.into()))
        );
    }

    // The mosaic: three rows of three panels, each of cells at most 128 pixels a side,
    // and every panel drew glyphs.
    let mosaic = decode(&first.join("odf-mosaic.png"));
    let cell = (mosaic.0 / 3, mosaic.1 / 3);
    assert!(cell.0 <= 128 && cell.1 <= 128, "{cell:?}");
    for row in 0..3 {
        for column in 0..3 {
            let drawn = drawn_pixels(&mosaic, cell, column, row);
            assert!(drawn > 200, "panel ({column}, {row}): {drawn} pixels");
        }
    }
    // Every panel's edge labels keep off its glyphs: in the band along each panel edge
    // (`render::compose::labels::edge_band`) every pixel is the background or a letter.
    for figure in a["figures"].as_array().unwrap() {
        let name = figure["file"].as_str().unwrap();
        let image = decode(&first.join(name));
        let columns = figure["columns"].as_u64().unwrap() as u32;
        let side = image.0 / columns;
        let in_band = glyphs_in_edge_bands(&image, side);
        assert_eq!(
            in_band, 0,
            "{name}: {in_band} glyph pixels under the edge labels"
        );
    }
    // The page shows every figure and names the input and the convention.
    let page = std::fs::read_to_string(first.join("index.html")).unwrap();
    for figure in [
        "odf-mosaic.png",
        "zoom-1.png",
        "zoom-2.png",
        "zoom-3.png",
        "qc.json",
    ] {
        assert!(page.contains(&format!("\"{figure}\"")), "{figure}");
    }
    assert!(page.contains("qc-fod.nii.gz") && page.contains("Radiological convention"));
    assert!(page.contains(input["sha256"].as_str().unwrap()));
}

#[test]
fn a_mask_underlay_and_peaks_are_used_and_recorded() {
    let root = fresh_dir("qc-mask");
    // A mask of the voxels with i < 5, and its copy as a (scalar) underlay.
    let mut mask = ndarray::ArrayD::<f64>::zeros(ndarray::IxDyn(&[10, 10, 10]));
    mask.slice_mut(ndarray::s![..5, .., ..]).fill(1.0);
    let affine = glyphcast_dmri::io::image::read_image(fod())
        .expect("reading the fit")
        .voxel_to_world
        .affine;
    let mask_file = root.join("mask.nii.gz");
    write_nifti(&mask_file, &mask, affine);
    let peaks = root.join("peaks.nii.gz");
    let run = glyphcast(&["peaks", text(fod()), "-o", text(&peaks), "--quiet"]);
    assert!(run.status.success(), "{}", stderr(&run));
    let out = root.join("set");
    let run = qc(&[
        "--mask",
        text(&mask_file),
        "--underlay",
        text(&mask_file),
        // Mid grey: white pixels are the peaks'.
        "--underlay-range",
        "0:2",
        "--peaks",
        text(&peaks),
        "-o",
        text(&out),
    ]);
    assert!(run.status.success(), "{}", stderr(&run));
    // The peaks mosaic: the ODF mosaic's panels with white capsules drawn over them.
    let odf = glyphcast::io::png::read_png_rgba8(&out.join("odf-mosaic.png")).expect("odf");
    let peaks_png = glyphcast::io::png::read_png_rgba8(&out.join("peaks-mosaic.png"))
        .expect("the peaks mosaic is written");
    assert_eq!(
        (odf.0, odf.1),
        (peaks_png.0, peaks_png.1),
        "the same panels"
    );
    let white = |rgba: &[u8]| {
        rgba.chunks(4)
            .filter(|p| p[0] > 240 && p[1] > 240 && p[2] > 240)
            .count()
    };
    assert!(
        white(&peaks_png.2) > white(&odf.2) + 100,
        "peaks drawn: {} white pixels against {}",
        white(&peaks_png.2),
        white(&odf.2)
    );
    let doc = sidecar(&out);
    let roles: Vec<&str> = doc["inputs"]
        .as_array()
        .unwrap()
        .iter()
        .map(|i| i["role"].as_str().unwrap())
        .collect();
    assert_eq!(roles, ["fod", "mask", "underlay", "peaks"]);
    assert_eq!(doc["selection"]["voxels"], 500);
    let figures = figure_files(&doc);
    assert!(figures.contains(&"peaks-mosaic.png"), "{figures:?}");
    // Every region lies mostly inside the mask: its centre voxel is.
    for region in doc["selection"]["regions"].as_array().unwrap() {
        let i = region["centre_voxel"][0].as_u64().unwrap();
        assert!(i < 5, "{region}");
    }
    // The cuts of the plane across i stay inside the mask.
    for cut in doc["selection"]["cuts"].as_array().unwrap() {
        if cut["voxel_axis"] == "i" {
            for index in cut["indices"].as_array().unwrap() {
                assert!(index.as_u64().unwrap() < 5, "{cut}");
            }
        }
    }
    // The underlay fills the panels' background where the mask image is 1: the mosaic
    // has many more non-background pixels than glyphs alone would cover.
    let mosaic = decode(&out.join("odf-mosaic.png"));
    let (w, h, _) = mosaic;
    let covered: usize = (0..3)
        .flat_map(|r| (0..3).map(move |c| (c, r)))
        .map(|(c, r)| drawn_pixels(&mosaic, (w / 3, h / 3), c, r))
        .sum();
    assert!(
        covered > (w * h / 6) as usize,
        "{covered} of {} pixels",
        w * h
    );
}

#[test]
fn bad_input_is_refused_before_any_output() {
    let root = fresh_dir("qc-refusals");
    let out = root.join("set");
    let expect = |args: &[&str], code: i32, words: &[&str]| {
        let run = glyphcast(args);
        let message = stderr(&run);
        assert_eq!(run.status.code(), Some(code), "{args:?}: {message}");
        assert!(!message.contains("panicked"), "{message}");
        for word in words {
            assert!(
                message.contains(word),
                "{args:?}: '{word}' not in {message}"
            );
        }
        assert!(!out.exists(), "{args:?} left {}", out.display());
    };
    let missing = root.join("missing.nii.gz");
    expect(
        &["qc", text(&missing), "-o", text(&out)],
        1,
        &["missing.nii.gz"],
    );
    expect(
        &["qc", text(fod()), "--negative", "both", "-o", text(&out)],
        2,
        &["--negative"],
    );
    expect(
        &["qc", text(fod()), "--panel-size", "10", "-o", text(&out)],
        2,
        &["--panel-size"],
    );
    expect(
        &["qc", text(fod()), "--basis", "fsl", "-o", text(&out)],
        2,
        &["--basis"],
    );
    // Peaks of another grid (func_coef is 2x3x4 with 45 volumes).
    let other = dipy_data("func_coef.nii.gz");
    expect(
        &["qc", text(fod()), "--peaks", text(&other), "-o", text(&out)],
        1,
        &["func_coef.nii.gz", "dim"],
    );
    // A folder of other files is never replaced.
    let foreign = root.join("foreign");
    std::fs::create_dir(&foreign).unwrap();
    std::fs::write(foreign.join("notes.txt"), "mine").unwrap();
    let run = glyphcast(&["qc", text(fod()), "-o", text(&foreign)]);
    assert_eq!(run.status.code(), Some(2), "{}", stderr(&run));
    assert!(stderr(&run).contains("foreign"), "{}", stderr(&run));
    assert!(stderr(&run).contains("notes.txt"), "{}", stderr(&run));
    assert_eq!(names(&foreign), ["notes.txt".to_string()].into());
    // Nothing half-written beside them.
    assert_eq!(names(&root), ["foreign".to_string()].into());
}

/// The README's quick start in a new folder: `-o sub-01/qc` (relative, its parent
/// missing) creates `sub-01/` and writes the whole set into `sub-01/qc`; nothing else
/// appears beside it. A file in the way of the parent is refused before any work.
#[test]
fn a_nested_output_in_a_new_folder_is_created() {
    let root = fresh_dir("qc-nested");
    let run = Command::new(env!("CARGO_BIN_EXE_glyphcast"))
        .args(["qc", text(fod()), "--panel-size", PANEL, "--quiet"])
        .args(["-o", "sub-01/qc"])
        .current_dir(&root)
        .env("GLYPHCAST_VALIDATION", "1")
        .output()
        .expect("running glyphcast");
    assert!(run.status.success(), "{}", stderr(&run));
    assert_eq!(names(&root), ["sub-01".to_string()].into());
    assert_eq!(names(&root.join("sub-01")), ["qc".to_string()].into());
    let set = root.join("sub-01").join("qc");
    assert!(names(&set).contains("qc.json"), "{:?}", names(&set));
    assert!(names(&set).contains("index.html"), "{:?}", names(&set));
    // A file where a parent folder would go: refused, nothing created.
    std::fs::write(root.join("plain"), "x").unwrap();
    let blocked = root.join("plain").join("sub-02").join("qc");
    let run = qc(&["-o", text(&blocked)]);
    assert_eq!(run.status.code(), Some(1), "{}", stderr(&run));
    assert!(stderr(&run).contains("is not a folder"), "{}", stderr(&run));
    assert_eq!(
        names(&root),
        ["plain".to_string(), "sub-01".to_string()].into()
    );
}

/// A job array's processes on one node: four renders of the same montage at once all
/// succeed with the same bytes.
#[test]
fn four_processes_at_once_give_identical_outputs() {
    let root = fresh_dir("qc-many");
    let children: Vec<(PathBuf, PathBuf, std::process::Child)> = (0..4)
        .map(|k| {
            let png = root.join(format!("render-{k}.png"));
            let depth = root.join(format!("render-{k}.npy"));
            let child = Command::new(env!("CARGO_BIN_EXE_glyphcast"))
                .args([
                    "render",
                    "--sh",
                    text(fod()),
                    "--views",
                    "axial,coronal,sagittal",
                    "--labels",
                    "--width",
                    "96",
                    "--height",
                    "96",
                    "-o",
                    text(&png),
                    "--depth-out",
                    text(&depth),
                ])
                .env("GLYPHCAST_VALIDATION", "1")
                .stdout(std::process::Stdio::null())
                .stderr(std::process::Stdio::piped())
                .spawn()
                .expect("starting glyphcast");
            (png, depth, child)
        })
        .collect();
    let mut outputs = Vec::new();
    for (png, depth, child) in children {
        let done = child.wait_with_output().expect("waiting for glyphcast");
        assert!(done.status.success(), "{}", stderr(&done));
        outputs.push((std::fs::read(png).unwrap(), std::fs::read(depth).unwrap()));
    }
    for other in &outputs[1..] {
        assert!(
            other.0 == outputs[0].0,
            "PNG bytes differ between processes"
        );
        assert!(
            other.1 == outputs[0].1,
            "depth maps differ between processes"
        );
    }
    // Something was drawn.
    assert!(outputs[0].1.len() > 128);
}

/// `qc --tracks`: the tracks mosaic, the ODF mosaic's panels with the streamlines near
/// each slice drawn over the glyphs as tubes coloured by direction, is written, differs
/// from the ODF mosaic, and is recorded (the input with its checksum, the figure).
#[test]
fn tracks_draw_a_mosaic_of_their_own_and_are_recorded() {
    let root = fresh_dir("qc-tracks");
    // Straight lines through the volume's world box (x 2..20, y 3..25, z 12..25 mm)
    // along each axis: every mosaic row's slices meet some.
    let mut tractogram = glyphcast_dmri::io::tracks::Tractogram::default();
    for k in 0..12 {
        let t = k as f32 / 11.0;
        let lines: [([f32; 3], [f32; 3]); 3] = [
            (
                [0.0, 5.0 + 18.0 * t, 14.0 + 9.0 * t],
                [22.0, 5.0 + 18.0 * t, 14.0 + 9.0 * t],
            ),
            (
                [4.0 + 14.0 * t, 1.0, 14.0 + 9.0 * t],
                [4.0 + 14.0 * t, 27.0, 14.0 + 9.0 * t],
            ),
            (
                [4.0 + 14.0 * t, 5.0 + 18.0 * t, 10.0],
                [4.0 + 14.0 * t, 5.0 + 18.0 * t, 27.0],
            ),
        ];
        for (a, b) in lines {
            tractogram.offsets.push(tractogram.points.len() as u64);
            tractogram.points.extend((0..41).map(|s| {
                let s = s as f32 / 40.0;
                [0, 1, 2].map(|c| a[c] + (b[c] - a[c]) * s)
            }));
        }
    }
    let tck = root.join("lines.tck");
    crate::tracks::write_tck(&tck, &tractogram);
    let out = root.join("set");
    let run = qc(&["--tracks", text(&tck), "-o", text(&out)]);
    assert!(run.status.success(), "{}", stderr(&run));
    let odf = glyphcast::io::png::read_png_rgba8(&out.join("odf-mosaic.png")).expect("odf");
    let tracks = glyphcast::io::png::read_png_rgba8(&out.join("tracks-mosaic.png"))
        .expect("the tracks mosaic is written");
    assert_eq!((odf.0, odf.1), (tracks.0, tracks.1), "the same panels");
    // Strongly red, green or blue pixels (the tubes along x, y and z) are many more.
    let pure = |rgba: &[u8]| {
        rgba.chunks(4)
            .filter(|p| {
                let (max, min) = (p[..3].iter().max().unwrap(), p[..3].iter().min().unwrap());
                *max > 150 && *min < 40 && p[..3].iter().filter(|&&c| c > 100).count() == 1
            })
            .count()
    };
    assert!(
        pure(&tracks.2) > pure(&odf.2) + 300,
        "tubes drawn: {} pure-colour pixels against {}",
        pure(&tracks.2),
        pure(&odf.2)
    );
    let doc = sidecar(&out);
    let tracks_input = doc["inputs"]
        .as_array()
        .unwrap()
        .iter()
        .find(|i| i["role"] == "tracks")
        .expect("the tractogram among the inputs");
    assert_eq!(tracks_input["sha256"].as_str().map(str::len), Some(64));
    let figures = figure_files(&doc);
    assert!(figures.contains(&"tracks-mosaic.png"), "{figures:?}");
}
