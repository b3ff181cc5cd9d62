//! Stiffness tensors from the command line: `glyphcast stiffness` turns a Voigt matrix
//! file into a scene, `glyphcast demo --stiffness` renders a field of copper crystals
//! (on lavapipe, with the validation layer), and the same field rendered in the library
//! matches the float64 reference.
use crate::common;
use common::text;
use glyphcast::demo::stiffness_demo_scene;
use glyphcast::glyph::Symmetry;
use glyphcast::render::RenderSettings;
use glyphcast::render::headless::HeadlessRenderer;
use glyphcast::scene::{GlyphKind, Scene};
use std::path::PathBuf;
use std::process::{Command, Output};

const LAVAPIPE: &str = "/usr/share/vulkan/icd.d/lvp_icd.x86_64.json";

fn glyphcast(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_glyphcast"))
        .args(args)
        .env("VK_DRIVER_FILES", LAVAPIPE)
        .env("GLYPHCAST_VALIDATION", "1")
        .output()
        .expect("running glyphcast")
}

/// A fresh folder for one test of this file.
fn fresh_dir(name: &str) -> PathBuf {
    common::fresh_dir(&format!("stiffness/{name}"))
}

const COPPER_CSV: &str = "# copper, GPa, standard Voigt order\n\
    168.4 121.4 121.4 0 0 0\n121.4 168.4 121.4 0 0 0\n121.4 121.4 168.4 0 0 0\n\
    0 0 0 75.4 0 0\n0 0 0 0 75.4 0\n0 0 0 0 0 75.4\n";

#[test]
fn stiffness_command_writes_a_one_glyph_scene() {
    let dir = fresh_dir("scene");
    let csv = dir.join("copper.csv");
    std::fs::write(&csv, COPPER_CSV).unwrap();
    for (name, extra, symmetry, count) in [
        ("full.json", vec![], Symmetry::NonSymmetric, 81),
        (
            "sym.json",
            vec!["--symmetric-part"],
            Symmetry::Symmetric,
            15,
        ),
        (
            "reversed.json",
            vec!["--shear-order", "12,13,23"],
            Symmetry::NonSymmetric,
            81,
        ),
    ] {
        let scene_path = dir.join(name);
        let mut args = vec!["stiffness", text(&csv), "-o", text(&scene_path)];
        args.extend(extra);
        let out = glyphcast(&args);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let scene = Scene::load(&scene_path).expect("the written scene loads");
        let set = &scene.glyph_sets[0];
        let GlyphKind::Tensor(layout) = set.kind else {
            panic!("{name}: a tensor glyph set");
        };
        assert_eq!((layout.order, layout.symmetry), (4, symmetry), "{name}");
        assert_eq!(set.coeffs[0].len(), count, "{name}");
        if count == 81 {
            // C_1111 is the first entry; copper is cubic, so the shear order does not
            // change it (the diagonal shear entries are all C44).
            assert_eq!(set.coeffs[0][0], 168.4);
            // C_2323: indices (1, 2, 1, 2), row major.
            assert_eq!(set.coeffs[0][27 + 2 * 9 + 3 + 2], 75.4);
        }
    }
}

#[test]
fn stiffness_command_rejects_bad_files() {
    let dir = fresh_dir("bad");
    let out_dir = fresh_dir("bad-out");
    let output = out_dir.join("scene.json");
    let cases = [
        (
            "five_rows.csv",
            COPPER_CSV.lines().take(6).collect::<Vec<_>>().join("\n"),
            "rows",
        ),
        (
            "asymmetric.csv",
            COPPER_CSV.replacen("121.4", "120", 1),
            "C12",
        ),
        ("nan.csv", COPPER_CSV.replacen("75.4", "nan", 1), "C44"),
        (
            "word.csv",
            COPPER_CSV.replacen("168.4", "hard", 1),
            "'hard'",
        ),
        ("zero.csv", "0 0 0 0 0 0\n".repeat(6), "zero"),
        ("bad.json", "{\"voigt\": [[1, 2]]}".to_string(), "voigt"),
    ];
    for (name, content, word) in cases {
        let input = dir.join(name);
        std::fs::write(&input, content).unwrap();
        let out = glyphcast(&["stiffness", text(&input), "-o", text(&output)]);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "{name}: expected failure");
        let errors: Vec<&str> = stderr.lines().filter(|l| l.starts_with("error:")).collect();
        assert_eq!(errors.len(), 1, "{name}: {stderr}");
        assert!(
            errors[0].contains(name) && errors[0].contains(word),
            "{name}: {}",
            errors[0]
        );
        assert_eq!(
            std::fs::read_dir(&out_dir).unwrap().count(),
            0,
            "{name}: no output"
        );
    }
    let input = dir.join("good.csv");
    std::fs::write(&input, COPPER_CSV).unwrap();
    let out = glyphcast(&[
        "stiffness",
        text(&input),
        "-o",
        text(&output),
        "--shear-order",
        "1,2,3",
    ]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        !out.status.success() && stderr.contains("--shear-order"),
        "{stderr}"
    );
    assert_eq!(std::fs::read_dir(&out_dir).unwrap().count(), 0);
}

#[test]
fn demo_stiffness_renders() {
    let dir = fresh_dir("demo");
    let png = dir.join("x.png");
    let out = glyphcast(&[
        "demo",
        "--stiffness",
        "-o",
        text(&png),
        "--width",
        "64",
        "--height",
        "64",
    ]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    let (w, h, rgba) = glyphcast::io::png::read_png_rgba8(&png).expect("demo PNG");
    assert_eq!((w, h), (64, 64));
    let background = &rgba[0..4];
    let drawn = rgba.chunks_exact(4).filter(|p| *p != background).count();
    assert!(drawn > 64 * 64 / 8, "only {drawn} pixels drawn:\n{stderr}");
}

#[test]
fn stiffness_demo_matches_the_float64_reference() {
    let gpu = common::gpu();
    let mut renderer = HeadlessRenderer::new(&gpu).expect("renderer");
    let mut scene = stiffness_demo_scene();
    assert_eq!(scene.glyph_sets[0].len(), 25);
    assert!(scene.glyph_sets[0].coeffs.iter().all(|c| c.len() == 81));
    (scene.image.width, scene.image.height) = (120, 108);
    let rendered =
        common::render_and_compare(&gpu, &mut renderer, &scene, &RenderSettings::default());
    let c = &rendered.comparison;
    eprintln!("stiffness demo: {c:?}");
    if c.holes > 0 || c.false_hits > 0 || c.median_error > 1e-3 {
        common::save_failure_images("stiffness-demo", &rendered);
    }
    assert!(c.covered > 1000, "glyphs cover the image: {c:?}");
    // The bar of tests/depth_accuracy.rs: no holes, no false hits away from the
    // silhouette band, median depth error below 1e-3 of the glyph scale.
    assert_eq!((c.holes, c.false_hits), (0, 0), "{c:?}");
    assert!(c.median_error < 1e-3, "{c:?}");
}

/// The `glyphcast` commands of a Markdown file's `sh` blocks, block by block, each as
/// its words (continuation lines joined, comments dropped).
fn documented_commands(page: &str) -> Vec<Vec<Vec<String>>> {
    let text = std::fs::read_to_string(repo_root().join(page)).expect("reading the page");
    let mut blocks = Vec::new();
    let mut block: Option<Vec<Vec<String>>> = None;
    let mut pending = String::new();
    for line in text.lines() {
        match (&mut block, line.trim_end()) {
            (None, "```sh") => block = Some(Vec::new()),
            (Some(_), "```") => blocks.extend(block.take()),
            (Some(commands), line) => {
                let line = line.trim();
                if line.starts_with('#') {
                    continue;
                }
                pending.push_str(line.trim_end_matches('\\'));
                pending.push(' ');
                if !line.ends_with('\\') {
                    let words: Vec<String> =
                        pending.split_whitespace().map(str::to_owned).collect();
                    pending.clear();
                    if words.first().is_some_and(|w| w == "glyphcast") {
                        commands.push(words);
                    }
                }
            }
            (None, _) => {}
        }
    }
    blocks
}

/// The files a command writes (`-o`, `--summary`) and the ones it reads (the other
/// words that name a file).
fn outputs_and_inputs(command: &[String]) -> (Vec<String>, Vec<String>) {
    let (mut outputs, mut inputs) = (Vec::new(), Vec::new());
    let mut words = command.iter().skip(2);
    while let Some(word) = words.next() {
        if ["-o", "--output", "--summary"].contains(&word.as_str()) {
            outputs.extend(words.next().cloned());
        } else if word.starts_with('-') {
            words.next();
        } else {
            inputs.push(word.clone());
        }
    }
    (outputs, inputs)
}

fn file_name(path: &str) -> String {
    std::path::Path::new(path)
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default()
}

/// The stiffness commands of the README and the materials guide name their outputs
/// apart from their inputs: a user who copies them, in a folder that holds their own
/// copies of the example files, overwrites none of them. Every command's output names
/// are checked; the README's quick start and the guide's first block are run in such a
/// folder, and the copies are the same bytes afterwards.
#[test]
fn documented_stiffness_commands_overwrite_no_input() {
    let examples = repo_root().join("examples/stiffness");
    let mut example_names: Vec<String> = std::fs::read_dir(&examples)
        .expect("examples/stiffness")
        .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
        .collect();
    example_names.sort();
    let pages = ["README.md", "docs/guide/materials.md"];
    let mut to_run = Vec::new();
    for page in pages {
        let blocks = documented_commands(page);
        let stiffness_blocks: Vec<&Vec<Vec<String>>> = blocks
            .iter()
            .filter(|block| block.iter().any(|c| c[1] == "stiffness"))
            .collect();
        assert!(!stiffness_blocks.is_empty(), "{page}: no stiffness command");
        for command in stiffness_blocks.iter().flat_map(|b| b.iter()) {
            let (outputs, inputs) = outputs_and_inputs(command);
            for output in &outputs {
                let name = file_name(output);
                assert!(
                    !example_names.contains(&name)
                        && !inputs.iter().any(|input| file_name(input) == name),
                    "{page}: `{}` writes {output}, the name of an input",
                    command.join(" ")
                );
            }
        }
        to_run.push((page, stiffness_blocks[0].clone()));
    }
    let dir = fresh_dir("documented");
    let copied = dir.join("examples/stiffness");
    std::fs::create_dir_all(&copied).unwrap();
    for name in &example_names {
        let bytes = std::fs::read(examples.join(name)).unwrap();
        std::fs::write(copied.join(name), &bytes).unwrap();
        std::fs::write(dir.join(name), &bytes).unwrap();
    }
    for (page, block) in to_run {
        for command in block {
            let run = Command::new(env!("CARGO_BIN_EXE_glyphcast"))
                .args(&command[1..])
                .current_dir(&dir)
                .env("VK_DRIVER_FILES", LAVAPIPE)
                .env("GLYPHCAST_VALIDATION", "1")
                .output()
                .expect("running glyphcast");
            assert!(
                run.status.success(),
                "{page}: `{}`: {}",
                command.join(" "),
                String::from_utf8_lossy(&run.stderr)
            );
        }
    }
    for name in &example_names {
        let original = std::fs::read(examples.join(name)).unwrap();
        for copy in [dir.join(name), copied.join(name)] {
            assert!(
                std::fs::read(&copy).unwrap() == original,
                "{} was overwritten",
                copy.display()
            );
        }
    }
}

fn repo_root() -> PathBuf {
    PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
}
