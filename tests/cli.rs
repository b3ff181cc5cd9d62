//! The command line as a user meets it: bad input gives one clear line naming the file
//! and the field, a non-zero exit and no output files; good input writes a PNG and a
//! depth map in the scene format's .npy layout.
use crate::common;
use common::{fresh_dir, glyphcast};
use std::path::{Path, PathBuf};

fn scenes() -> PathBuf {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../..")).join("tests/scenes")
}

/// Runs `render` on `scene`, expects failure, and returns the error line.
fn expect_failure(scene: &Path, extra: &[&str], dir: &Path) -> String {
    let png = dir.join("out.png");
    let npy = dir.join("out.npy");
    let mut args = vec![
        "render",
        scene.to_str().expect("utf-8 path"),
        "-o",
        png.to_str().expect("path"),
    ];
    args.extend([
        "--depth-out",
        npy.to_str().expect("path"),
        "--width",
        "32",
        "--height",
        "32",
    ]);
    args.extend(extra);
    let out = glyphcast(&args);
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(
        !out.status.success(),
        "{}: expected failure, got success",
        scene.display()
    );
    assert_ne!(out.status.code(), Some(0), "{}: exit code", scene.display());
    let errors: Vec<&str> = stderr.lines().filter(|l| l.starts_with("error:")).collect();
    assert_eq!(
        errors.len(),
        1,
        "{}: one error line expected, got:\n{stderr}",
        scene.display()
    );
    assert!(
        !stderr.contains("panicked"),
        "{}: panic:\n{stderr}",
        scene.display()
    );
    let leftovers: Vec<_> = std::fs::read_dir(dir).expect("listing").collect();
    assert!(
        leftovers.is_empty(),
        "{}: output left behind: {leftovers:?}",
        scene.display()
    );
    errors[0].to_owned()
}

#[test]
fn every_bad_scene_fails_cleanly_naming_file_and_field() {
    let dir = fresh_dir("bad-scenes");
    // File -> a word the message must contain (the field, or the kind of problem).
    let expected = [
        ("wrong_coeff_count.json", "coeffs"),
        ("order_out_of_range.json", "order"),
        ("nan.json", "NaN"),
        ("huge_number.json", "range"),
        ("unknown_value.json", "kind"),
        ("unknown_key.json", "centres"),
        ("malformed.json", "line"),
        ("missing_field.json", "version"),
        ("count_mismatch.json", "coeffs"),
        ("nonpositive_scale.json", "scale"),
        ("camera_up_parallel.json", "up"),
        ("wrong_type.json", "centers"),
    ];
    let mut seen = 0;
    let mut entries: Vec<_> = std::fs::read_dir(scenes().join("bad"))
        .expect("bad scenes")
        .flatten()
        .collect();
    entries.sort_by_key(|e| e.file_name());
    for entry in entries {
        let path = entry.path();
        let name = entry.file_name().to_string_lossy().into_owned();
        let line = expect_failure(&path, &[], &dir);
        assert!(
            line.contains(&name),
            "{name}: the error must name the file: {line}"
        );
        if let Some((_, word)) = expected.iter().find(|(f, _)| *f == name) {
            assert!(
                line.to_lowercase().contains(&word.to_lowercase()),
                "{name}: expected '{word}' in: {line}"
            );
        }
        seen += 1;
    }
    assert!(seen >= expected.len(), "only {seen} bad scenes found");
}

#[test]
fn missing_file_and_bad_options_fail_cleanly() {
    let dir = fresh_dir("bad-options");
    let missing = scenes().join("no-such-scene.json");
    let line = expect_failure(&missing, &[], &dir);
    assert!(line.contains("no-such-scene.json"), "{line}");
    let sphere = scenes().join("sphere.json");
    for (option, value) in [
        ("--refine", "bisect:x"),
        ("--step", "-1"),
        ("--color", "rainbow"),
        ("--method", "magic"),
        ("--precision", "0"),
        ("--method", "mesh:9"),
        ("--method", "latlong:1"),
    ] {
        let line = expect_failure(&sphere, &[&format!("{option}={value}")], &dir);
        assert!(line.contains(option), "{option} {value}: {line}");
    }
    // A negative value after a space is the option's value, refused for its range,
    // not taken for an unknown flag (with a tip to write `-- -0.5`, which would be wrong).
    for (option, value) in [
        ("--offset", "-0.5"),
        ("--step", "-1"),
        ("--precision", "-2"),
    ] {
        let line = expect_failure(&sphere, &[option, value], &dir);
        assert!(
            line.contains(option) && !line.contains("unexpected argument"),
            "{option} {value}: {line}"
        );
    }
    // An unknown method is answered with every method there is.
    let line = expect_failure(&sphere, &["--method=magic"], &dir);
    assert!(
        line.contains("fixed, interval, affine, exact, impostor"),
        "{line}"
    );
    // Offset glyphs are not polynomial surfaces: exact refuses them, naming both options.
    let line = expect_failure(&sphere, &["--method=exact", "--offset=0.1"], &dir);
    assert!(
        line.contains("--offset") && line.contains("exact"),
        "{line}"
    );
}

#[test]
fn exact_method_renders() {
    let dir = fresh_dir("render-exact");
    let png = dir.join("sphere.png");
    let npy = dir.join("sphere.npy");
    let scene = scenes().join("sphere.json");
    let out = glyphcast(&[
        "render",
        scene.to_str().expect("path"),
        "-o",
        png.to_str().expect("path"),
        "--depth-out",
        npy.to_str().expect("path"),
        "--width",
        "64",
        "--height",
        "48",
        "--method",
        "exact",
    ]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "render failed:\n{stderr}");
    let (_, depth) = glyphcast::io::npy::read_npy_f32(&npy).expect("reading the depth map");
    let hits = depth.iter().filter(|d| !d.is_nan()).count();
    assert!(hits > 50 && hits < depth.len(), "{hits} hits");
}

#[test]
fn render_writes_png_and_depth_map() {
    let dir = fresh_dir("render-ok");
    let png = dir.join("sphere.png");
    let npy = dir.join("sphere.npy");
    let scene = scenes().join("sphere.json");
    let out = glyphcast(&[
        "render",
        scene.to_str().expect("path"),
        "-o",
        png.to_str().expect("path"),
        "--depth-out",
        npy.to_str().expect("path"),
        "--width",
        "64",
        "--height",
        "48",
    ]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "render failed:\n{stderr}");
    assert!(
        stderr.contains("device:"),
        "the chosen device is printed:\n{stderr}"
    );
    let (w, h, rgba) = glyphcast::io::png::read_png_rgba8(&png).expect("reading the PNG");
    assert_eq!((w, h, rgba.len()), (64, 48, 64 * 48 * 4));
    let (shape, depth) = glyphcast::io::npy::read_npy_f32(&npy).expect("reading the depth map");
    assert_eq!(shape, vec![48, 64], "shape is (height, width)");
    let hits = depth.iter().filter(|d| !d.is_nan()).count();
    assert!(
        hits > 50 && hits < depth.len(),
        "the sphere covers part of the image: {hits}"
    );
    assert!(depth.iter().all(|d| d.is_nan() || *d > 0.0));
}

#[test]
fn demo_renders() {
    let dir = fresh_dir("demo");
    let png = dir.join("demo.png");
    let out = glyphcast(&[
        "demo",
        "-o",
        png.to_str().expect("path"),
        "--width",
        "160",
        "--height",
        "120",
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let (_, _, rgba) = glyphcast::io::png::read_png_rgba8(&png).expect("demo PNG");
    // Glyphs are drawn: a good share of pixels differ from the background.
    let background = &rgba[0..4];
    let drawn = rgba.chunks_exact(4).filter(|p| *p != background).count();
    assert!(
        drawn > 160 * 120 / 10,
        "only {drawn} pixels differ from the background"
    );
}

#[test]
fn device_is_chosen_by_name_and_an_unknown_name_is_an_error() {
    let dir = fresh_dir("device");
    let png = dir.join("d.png");
    let out = glyphcast(&[
        "demo",
        "-o",
        png.to_str().expect("path"),
        "--width",
        "32",
        "--height",
        "24",
        "--device",
        "0",
    ]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "device 0 must work:\n{stderr}");
    let name = stderr
        .lines()
        .find_map(|l| l.strip_prefix("device: "))
        .and_then(|l| l.split(" (").next())
        .expect("device line")
        .to_owned();
    std::fs::remove_file(&png).expect("removing");
    let out = glyphcast(&[
        "demo",
        "-o",
        png.to_str().expect("path"),
        "--width",
        "32",
        "--height",
        "24",
        "--device",
        &name,
    ]);
    assert!(out.status.success(), "device by name '{name}' must work");
    std::fs::remove_file(&png).expect("removing");
    let out = glyphcast(&[
        "demo",
        "-o",
        png.to_str().expect("path"),
        "--device",
        "no-such-gpu",
    ]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success());
    assert!(
        stderr.contains("no-such-gpu") && stderr.contains(&name),
        "the error lists the devices:\n{stderr}"
    );
    assert!(!png.exists(), "no output on error");
}

#[test]
fn accuracy_command_writes_a_table_for_every_scene() {
    let dir = fresh_dir("accuracy");
    let csv = dir.join("acc.csv");
    let out = glyphcast(&[
        "accuracy",
        "--size",
        "48",
        "--steps",
        "0.05,0.3",
        "--refine",
        "secant:4",
        "--csv",
        csv.to_str().expect("path"),
    ]);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(
        stdout.contains("| scene | method |"),
        "Markdown table on stdout:\n{stdout}"
    );
    let text = std::fs::read_to_string(&csv).expect("CSV written");
    let rows: Vec<Vec<&str>> = text
        .lines()
        .skip(1)
        .map(|l| l.split(',').collect())
        .collect();
    let scenes = glyphcast::accuracy::suite::suite(48).len();
    // Fixed: one row per step; interval, affine and exact: one row each.
    assert_eq!(
        rows.len(),
        5 * scenes,
        "rows per scene: two steps and three other methods"
    );
    for row in &rows {
        assert_eq!(row.len(), 12, "{row:?}");
        let holes: usize = row[4].parse().expect("holes is a count");
        let median: f64 = row[6].parse().expect("median is a number");
        if row[1] != "fixed" || row[2] == "0.05" {
            assert_eq!(holes, 0, "no holes at 48 px: {row:?}");
            assert!(median < 1e-4, "{row:?}");
        }
    }
    // The coarse step is worse somewhere: the table tells the settings apart.
    assert!(
        rows.iter().any(|r| r[2] == "0.3" && r[4] != "0"),
        "step 0.3 leaves holes somewhere"
    );
}

#[test]
fn bench_quick_writes_valid_csv_and_json() {
    let dir = fresh_dir("bench");
    let out = glyphcast(&[
        "bench",
        "--quick",
        "--sweep",
        "steps",
        "--workload",
        "grid:4:6",
        "--width",
        "48",
        "--height",
        "40",
        "--out",
        dir.to_str().expect("path"),
    ]);
    let json = bench_results(&out, &dir);
    let results = json["results"].as_array().expect("results array");
    // Quick steps sweep: 2 steps x 6 refinements x 2 centre modes.
    assert_eq!(results.len(), 24);
    for r in results {
        let median = r["gpu_ms_median"].as_f64().expect("median");
        let (min, max) = (
            r["gpu_ms_min"].as_f64().expect("min"),
            r["gpu_ms_max"].as_f64().expect("max"),
        );
        assert!(min > 0.0 && min <= median && median <= max, "{r}");
        assert_eq!(r["glyphs"], 4);
        assert_eq!(
            r["coefficient_bytes"],
            4 * 28 * 4,
            "order 6 has 28 floats per glyph"
        );
        assert_eq!(
            r["instance_bytes"],
            4 * (16 + 32),
            "a 16-byte instance and a 32-byte box per glyph"
        );
    }
    let csv = std::fs::read_to_string(dir.join("results.csv")).expect("results.csv");
    let lines: Vec<&str> = csv.lines().collect();
    assert_eq!(lines.len(), 25);
    let columns = lines[0].split(',').count();
    assert!(
        lines.iter().all(|l| l.split(',').count() == columns),
        "every CSV row has {columns} fields"
    );
}

/// The baselines draw from the command line: tessellations report their triangle count and
/// generation time, and every method writes an image and a depth map of the sphere.
#[test]
fn render_draws_meshes_and_impostors() {
    let dir = fresh_dir("render-methods");
    let scene = scenes().join("sphere.json");
    for method in ["mesh:3", "latlong:12", "impostor"] {
        let png = dir.join(format!("{method}.png").replace(':', "-"));
        let npy = dir.join(format!("{method}.npy").replace(':', "-"));
        let out = glyphcast(&[
            "render",
            scene.to_str().expect("path"),
            "-o",
            png.to_str().expect("path"),
            "--depth-out",
            npy.to_str().expect("path"),
            "--width",
            "64",
            "--height",
            "48",
            "--method",
            method,
        ]);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(out.status.success(), "{method}:\n{stderr}");
        assert_eq!(
            stderr.contains("triangles"),
            method != "impostor",
            "{method}: the mesh statistics are printed for meshes:\n{stderr}"
        );
        let (shape, depth) = glyphcast::io::npy::read_npy_f32(&npy).expect("depth map");
        assert_eq!(shape, vec![48, 64]);
        let hits = depth.iter().filter(|d| !d.is_nan()).count();
        assert!(hits > 50 && hits < depth.len(), "{method}: {hits} hits");
    }
}

/// `bench --quick --sweep table2`: the ray caster, the impostor and icosphere levels 1 to
/// 6 on a small workload, each held against the float64 reference, written as CSV and
/// JSON with the ratios.
#[test]
fn bench_quick_table2_writes_valid_csv_and_json() {
    let dir = fresh_dir("bench-table2");
    let out = glyphcast(&[
        "bench",
        "--quick",
        "--sweep",
        "table2",
        "--workload",
        "grid:4:6",
        "--width",
        "48",
        "--height",
        "40",
        "--out",
        dir.to_str().expect("path"),
    ]);
    let json = bench_results(&out, &dir);
    let results = json["results"].as_array().expect("results array");
    let methods: Vec<&str> = results
        .iter()
        .map(|r| r["method"].as_str().expect("method"))
        .collect();
    assert_eq!(
        methods,
        [
            "fixed", "interval", "affine", "exact", "impostor", "mesh:1", "mesh:2", "mesh:3",
            "mesh:4", "mesh:5", "mesh:6"
        ]
    );
    let error = |r: &serde_json::Value| r["accuracy"]["error_px"].as_f64().expect("error_px");
    for r in results {
        let median = r["gpu_ms_median"].as_f64().expect("median");
        assert!(median > 0.0, "{r}");
        assert!(error(r) >= 0.0, "{r}");
        assert_eq!(r["glyphs"], 4);
    }
    for (level, r) in results[5..].iter().enumerate() {
        let triangles = 4 * 20 * 4u64.pow(level as u32 + 1);
        assert_eq!(r["triangles"].as_u64(), Some(triangles), "{r}");
        assert!(r["generate_ms"].as_f64().expect("generation time") >= 0.0);
        assert_eq!(r["coefficient_bytes"], 0, "meshes need no coefficients");
    }
    // The ray caster is far below a pixel; the coarsest mesh is not, the finest is.
    for r in &results[..3] {
        assert!(
            error(r) < 0.1,
            "ray casting is below a tenth of a pixel: {r}"
        );
    }
    assert!(error(&results[4]) > error(&results[9]));
    let ratios = json["ratios"].as_array().expect("ratios array");
    assert!(
        ratios
            .iter()
            .any(|r| r["name"] == "ray-cast / impostor GPU time" && r["value"].as_f64() > Some(0.0)),
        "{ratios:?}"
    );
    // The ratios hold the default method (exact) against the others.
    assert!(
        ratios
            .iter()
            .all(|r| r["value"].is_null()
                || r["detail"].as_str().is_some_and(|d| d.contains("exact"))),
        "{ratios:?}"
    );
    let csv = std::fs::read_to_string(dir.join("results.csv")).expect("results.csv");
    let lines: Vec<&str> = csv.lines().collect();
    assert_eq!(lines.len(), 12);
    let columns = lines[0].split(',').count();
    assert!(
        lines.iter().all(|l| l.split(',').count() == columns),
        "every CSV row has {columns} fields"
    );
    let markdown = std::fs::read_to_string(dir.join("results.md")).expect("results.md");
    assert!(markdown.contains("Ratios"), "{markdown}");
    // The plots: valid PNGs of the promised size.
    for name in ["gpu_time.png", "error_vs_time.png"] {
        let file = std::fs::File::open(dir.join(name)).expect(name);
        let decoder = png::Decoder::new(std::io::BufReader::new(file));
        let reader = decoder.read_info().expect("a valid PNG");
        let info = reader.info();
        assert_eq!((info.width, info.height), (900, 500), "{name}");
    }
}

/// The generated fODF workload (one to three fibres per glyph, SH band 8): drawn with the
/// default method, it matches the float64 reference, and the scene it saves is a valid
/// scene file of that many SH glyphs.
#[test]
fn bench_fodf_workload_matches_the_reference() {
    let dir = fresh_dir("bench-fodf");
    let saved = dir.join("fodf.json");
    let out = glyphcast(&[
        "bench",
        "--workload",
        "fodf:24:8",
        "--width",
        "160",
        "--height",
        "90",
        "--frames",
        "1",
        "--warmup",
        "0",
        "--accuracy",
        "--save-scene",
        saved.to_str().expect("path"),
        "--out",
        dir.to_str().expect("path"),
    ]);
    let json = bench_results(&out, &dir);
    let r = &json["results"][0];
    assert_eq!(r["glyphs"], 24, "{r}");
    assert_eq!(r["method"], "exact", "{r}");
    assert_eq!(r["accuracy"]["holes"], 0, "{r}");
    assert_eq!(r["accuracy"]["false_hits"], 0, "{r}");
    let scene = glyphcast::scene::Scene::load(&saved).expect("the saved scene");
    assert_eq!(scene.glyph_sets.len(), 1);
    assert_eq!(scene.glyph_sets[0].len(), 24);
    let with_sweep = glyphcast(&[
        "bench",
        "--sweep",
        "ratios",
        "--save-scene",
        saved.to_str().expect("path"),
    ]);
    assert_eq!(
        with_sweep.status.code(),
        Some(2),
        "--save-scene with a sweep is refused"
    );
    let bad = glyphcast(&["bench", "--workload", "fodf:24:7"]);
    assert!(!bad.status.success());
    assert!(
        String::from_utf8_lossy(&bad.stderr).contains("band 7"),
        "{}",
        String::from_utf8_lossy(&bad.stderr)
    );
}

/// Without --method the default is exact; with an --offset it is affine (exact refuses
/// offsets), and the render matches the float64 reference either way.
#[test]
fn the_default_method_follows_the_offset() {
    let dir = fresh_dir("default-method");
    let scene = scenes().join("order4_pair.json");
    for offset in ["0", "0.1"] {
        let npy = dir.join(format!("d{offset}.npy"));
        let png = dir.join(format!("d{offset}.png"));
        let out = glyphcast(&[
            "render",
            scene.to_str().expect("path"),
            "-o",
            png.to_str().expect("path"),
            "--depth-out",
            npy.to_str().expect("path"),
            "--offset",
            offset,
            "--width",
            "64",
            "--height",
            "48",
        ]);
        assert!(
            out.status.success(),
            "offset {offset}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        let (shape, depth) = glyphcast::io::npy::read_npy_f32(&npy).expect("depth");
        assert_eq!(shape, vec![48, 64]);
        assert!(
            depth.iter().filter(|d| !d.is_nan()).count() > 100,
            "offset {offset}: glyphs drawn"
        );
    }
}

/// The `results.json` a successful `bench --out DIR` run wrote.
fn bench_results(out: &std::process::Output, dir: &std::path::Path) -> serde_json::Value {
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_str(&std::fs::read_to_string(dir.join("results.json")).expect("results.json"))
        .expect("valid JSON")
}

/// Output paths are checked before any work, and a set of outputs is written all or
/// nothing: a missing folder fails at once (before a device is opened) and writes
/// nothing; the same file for two outputs is a usage error (exit 2); when one output
/// cannot be written (here /dev/full, which a root user's run must also leave a device),
/// the user's earlier outputs keep their contents and no temporary is left.
#[test]
fn outputs_are_checked_first_and_written_together() {
    let dir = fresh_dir("outputs");
    let scene = scenes().join("sphere.json");
    let scene = scene.to_str().expect("path");
    let path = |name: &str| dir.join(name).to_str().expect("path").to_owned();

    let missing = glyphcast(&["render", scene, "-o", &path("no-such-folder/out.png")]);
    assert_eq!(missing.status.code(), Some(1));
    let stderr = String::from_utf8_lossy(&missing.stderr);
    assert!(
        stderr.contains("no-such-folder") && stderr.contains("does not exist"),
        "{stderr}"
    );
    assert!(
        !stderr.contains("device:"),
        "checked only after opening a device: {stderr}"
    );

    let twice = glyphcast(&[
        "render",
        scene,
        "-o",
        &path("a.png"),
        "--depth-out",
        &path("a.png"),
    ]);
    assert_eq!(
        twice.status.code(),
        Some(2),
        "{}",
        String::from_utf8_lossy(&twice.stderr)
    );
    assert!(String::from_utf8_lossy(&twice.stderr).contains("same file"));
    assert!(
        std::fs::read_dir(&dir).expect("folder").next().is_none(),
        "nothing written"
    );

    std::fs::write(dir.join("old.png"), b"the user's image").expect("old image");
    std::fs::write(dir.join("old.json"), b"the user's scene").expect("old scene");
    let full = Path::new("/dev/full");
    let is_device = |p: &Path| {
        use std::os::unix::fs::FileTypeExt;
        std::fs::symlink_metadata(p).is_ok_and(|m| m.file_type().is_char_device())
    };
    if is_device(full) {
        let failed = glyphcast(&[
            "render",
            scene,
            "-o",
            &path("old.png"),
            "--save-scene",
            &path("old.json"),
            "--depth-out",
            "/dev/full",
        ]);
        assert_eq!(failed.status.code(), Some(1));
        assert!(is_device(full), "/dev/full must stay a device");
        assert_eq!(
            std::fs::read(dir.join("old.png")).expect("old"),
            b"the user's image"
        );
        assert_eq!(
            std::fs::read(dir.join("old.json")).expect("old"),
            b"the user's scene"
        );
        let mut names: Vec<String> = std::fs::read_dir(&dir)
            .expect("folder")
            .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
            .collect();
        names.sort();
        assert_eq!(names, ["old.json", "old.png"], "no temporary left");
    }
    let written = glyphcast(&[
        "render",
        scene,
        "-o",
        &path("old.png"),
        "--save-scene",
        &path("old.json"),
    ]);
    assert!(
        written.status.success(),
        "{}",
        String::from_utf8_lossy(&written.stderr)
    );
    assert_ne!(
        std::fs::read(dir.join("old.png")).expect("new"),
        b"the user's image"
    );
    assert!(glyphcast::scene::Scene::load(&dir.join("old.json")).is_ok());
}

/// The paragraph of `option` in `glyphcast <command> --help`, without its
/// `[default: ...]`: what the help itself says the option takes.
fn help_paragraph(command: &str, option: &str) -> String {
    let run = glyphcast(&[command, "--help"]);
    assert!(run.status.success(), "{command} --help");
    let help = String::from_utf8_lossy(&run.stdout).into_owned();
    let mut lines = help.lines().skip_while(|line| {
        let line = line.trim_start();
        !(line.starts_with('-') && line.split([' ', ',']).any(|word| word == option))
    });
    let head = lines
        .next()
        .unwrap_or_else(|| panic!("{option} not in {help}"));
    let body = lines.take_while(|line| !line.trim_start().starts_with('-'));
    let mut paragraph = std::iter::once(head)
        .chain(body)
        .collect::<Vec<_>>()
        .join(" ");
    // Without the default: clap writes `[default: ...]` inline or on a line of its own.
    while let Some(at) = paragraph.find("[default:") {
        let end = paragraph[at..]
            .find(']')
            .map_or(paragraph.len(), |e| at + e + 1);
        paragraph.replace_range(at..end, "");
    }
    paragraph
}

/// Every option that takes methods lists every method in its help, the default
/// (`exact`) included, not only in its `[default: ...]`.
#[test]
fn method_options_name_every_method_in_their_help() {
    for (command, option) in [
        ("bench", "--method"),
        ("accuracy", "--methods"),
        ("render", "--method"),
    ] {
        let paragraph = help_paragraph(command, option);
        for method in [
            "exact", "fixed", "interval", "affine", "impostor", "mesh:", "latlong:",
        ] {
            assert!(
                paragraph.contains(method),
                "{command} {option}'s help does not name {method}: {paragraph}"
            );
        }
    }
}

/// The covered pixels' box of a depth map (`--depth-out`): (left, top, right, bottom),
/// inclusive.
fn covered_box(npy: &Path) -> (usize, usize, usize, usize) {
    let (shape, depth) = glyphcast::io::npy::read_npy_f32(npy).expect("reading the depth map");
    let width = shape[1];
    let mut covered = (usize::MAX, usize::MAX, 0, 0);
    for (i, d) in depth.iter().enumerate() {
        if !d.is_nan() {
            let (x, y) = (i % width, i / width);
            covered = (
                covered.0.min(x),
                covered.1.min(y),
                covered.2.max(x),
                covered.3.max(y),
            );
        }
    }
    assert!(covered.0 <= covered.2, "nothing drawn in {}", npy.display());
    covered
}

/// `glyphcast demo` frames its glyphs at any size: square, the default 4:3 and a wide
/// strip; the covered pixels stay inside the image with a margin on every side, centred
/// to within a few pixels both ways, and fill the limiting side but for the margins.
#[test]
fn the_demo_is_framed_centred_at_any_aspect_ratio() {
    let dir = fresh_dir("demo-framing");
    for (stiffness, width, height) in [
        (false, 400, 400),
        (false, 800, 600),
        (false, 1600, 400),
        (true, 400, 400),
        (true, 1600, 400),
    ] {
        let name = format!("demo-{stiffness}-{width}x{height}");
        let png = dir.join(format!("{name}.png"));
        let npy = dir.join(format!("{name}.npy"));
        let (w, h) = (width.to_string(), height.to_string());
        let mut args = vec!["demo", "-o", png.to_str().unwrap(), "--depth-out"];
        args.extend([npy.to_str().unwrap(), "--width", &w, "--height", &h]);
        if stiffness {
            args.push("--stiffness");
        }
        let out = glyphcast(&args);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let (left, top, right, bottom) = covered_box(&npy);
        let margins = [left, width - 1 - right, top, height - 1 - bottom];
        let least = |side: usize| side / 50;
        assert!(
            margins[0] >= least(width) && margins[1] >= least(width),
            "{name}: glyphs at the left or right edge: {margins:?}"
        );
        assert!(
            margins[2] >= least(height) && margins[3] >= least(height),
            "{name}: glyphs at the top or bottom edge: {margins:?}"
        );
        assert!(
            margins[0].abs_diff(margins[1]) <= 4 && margins[2].abs_diff(margins[3]) <= 4,
            "{name}: not centred: left, right, top, bottom margins {margins:?}"
        );
        let fills = |covered: usize, side: usize| covered as f64 > 0.8 * side as f64;
        assert!(
            fills(right - left + 1, width) || fills(bottom - top + 1, height),
            "{name}: the glyphs fill too little of the image: {margins:?}"
        );
    }
}

/// The keyword names a Rust source file of the Python module reads: the string
/// literal of each `self.ACCESSOR("name"` or `kwargs.ACCESSOR("name"` call.
fn keywords_read_in(source: &str) -> Vec<String> {
    let mut found = Vec::new();
    for receiver in ["self.", "kwargs."] {
        for (at, _) in source.match_indices(receiver) {
            let rest = &source[at + receiver.len()..];
            let accessor: String = rest
                .chars()
                .take_while(|c| c.is_ascii_lowercase() || *c == '_')
                .collect();
            let Some(call) = rest[accessor.len()..].strip_prefix("(\"") else {
                continue;
            };
            let name: String = call
                .chars()
                .take_while(|c| c.is_ascii_lowercase() || *c == '_')
                .collect();
            if !accessor.is_empty() && call[name.len()..].starts_with('"') {
                found.push(name);
            }
        }
    }
    found
}

/// The Python guide's keyword list cannot drift from the command line or the module:
/// every option of `glyphcast render --help` is a keyword of the list or one of the
/// exceptions it names, and every keyword the module reads (python/src) is in it.
#[test]
fn the_python_guide_names_every_render_option_and_keyword() {
    let root = PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."));
    let guide = std::fs::read_to_string(root.join("docs/guide/python.md")).expect("python.md");
    let from = guide
        .find("- The keywords are the options of `glyphcast render`")
        .expect("the guide's keyword list");
    let to = from
        + guide[from..]
            .find("The module and the CLI call")
            .expect("its end");
    let section = &guide[from..to];
    let run = glyphcast(&["render", "--help"]);
    assert!(run.status.success());
    let help = String::from_utf8_lossy(&run.stdout).into_owned();
    let mut flags: Vec<&str> = help
        .lines()
        .map(str::trim_start)
        .filter(|line| line.starts_with('-'))
        .filter_map(|line| line.split([' ', ',', '=']).find(|w| w.starts_with("--")))
        .filter(|flag| !["--help", "--version"].contains(flag))
        .collect();
    flags.dedup();
    assert!(flags.len() > 40, "{flags:?}");
    // The guide names the output by its short flag.
    let spelled = [("--output", "-o")];
    for flag in flags {
        let keyword = flag.trim_start_matches("--").replace('-', "_");
        let other = spelled.iter().find(|(f, _)| *f == flag).map(|(_, k)| *k);
        let named = section.contains(&format!("`{keyword}`"))
            || section.contains(&format!("`{flag}`"))
            || other.is_some_and(|k| section.contains(&format!("`{k}")));
        assert!(
            named,
            "docs/guide/python.md names neither `{keyword}` nor `{flag}` as an exception"
        );
    }
    let mut read = Vec::new();
    for file in std::fs::read_dir(root.join("python/src")).expect("python/src") {
        let path = file.expect("entry").path();
        if path.extension().is_some_and(|e| e == "rs") {
            read.extend(keywords_read_in(&std::fs::read_to_string(&path).unwrap()));
        }
    }
    assert!(read.len() > 25, "{read:?}");
    for keyword in read {
        assert!(
            section.contains(&format!("`{keyword}`")),
            "the module reads `{keyword}`, which docs/guide/python.md does not list"
        );
    }
}

/// `bench` explains its table: the device once (on stdout, with the table), a legend
/// with the frames timed and warmed up and what the per-pixel counters count, `-` where
/// a counter does not apply (the impostor), and a `cull` column that says what was
/// asked and what was done. Its help names every `--path` it takes and its default.
#[test]
fn bench_explains_its_table() {
    let out = glyphcast(&[
        "bench",
        "--workload",
        "grid:4:2",
        "--method",
        "impostor",
        "--width",
        "64",
        "--height",
        "64",
        "--frames",
        "2",
        "--warmup",
        "1",
    ]);
    let (stdout, stderr) = (
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr),
    );
    assert!(out.status.success(), "{stderr}");
    let devices = stdout.matches("Device: ").count() + stderr.matches("device: ").count();
    assert_eq!(devices, 1, "the device once:\n{stdout}\n{stderr}");
    for words in [
        "over 2 timed frame(s) after 1 warm-up frame(s)",
        "upload ms: CPU time",
        "per covered pixel",
    ] {
        assert!(stdout.contains(words), "'{words}' not in:\n{stdout}");
    }
    let header = stdout
        .lines()
        .find(|l| l.starts_with("| label |"))
        .expect("the table's header");
    let row = stdout
        .lines()
        .find(|l| l.starts_with("| default |"))
        .expect("the measured row");
    let cell = |name: &str| {
        let columns: Vec<&str> = header.split('|').map(str::trim).collect();
        let at = columns.iter().position(|c| *c == name).expect(name);
        row.split('|')
            .map(str::trim)
            .nth(at)
            .expect("cell")
            .to_owned()
    };
    assert_eq!(cell("fragments/px"), "-", "{row}");
    assert_eq!(cell("evaluations/px"), "-", "{row}");
    assert_eq!(
        cell("cull"),
        "occluded: none (impostor draws every glyph; 1 pass)",
        "{row}"
    );
    let help = glyphcast(&["bench", "--help"]);
    let help = String::from_utf8_lossy(&help.stdout);
    let path = help
        .split("--path")
        .nth(1)
        .and_then(|rest| rest.split("\n      --").next())
        .expect("--path in the help");
    assert!(
        path.contains("auto") && path.contains("[default: fragment]"),
        "{path}"
    );
}

/// `render` says in one line what culling did: what was asked, then the passes, the
/// early outs, or none and why.
#[test]
fn render_reports_what_culling_did() {
    let dir = fresh_dir("render-culling");
    let png = dir.join("out.png");
    let scene = scenes().join("order4_pair.json");
    // A flat pair: nothing hidden where early outs would be taken (Mesa 25), fewer
    // layers than passes pay for where they would not (Mesa 22.3).
    let flat = [
        "culling: occluded: none needed (1 pass)",
        "culling: occluded: none (passes pay from 3 layers of glyphs, the frame has fewer; \
         1 pass)",
    ];
    for (extra, lines) in [
        (&[][..], &flat[..]),
        (&["--cull", "off"][..], &["culling: off (1 pass)"][..]),
        (
            &["--method", "impostor"][..],
            &["culling: occluded: none (impostor draws every glyph; 1 pass)"][..],
        ),
    ] {
        let mut args = vec![
            "render",
            scene.to_str().expect("path"),
            "--width",
            "64",
            "--height",
            "64",
            "-o",
            png.to_str().expect("path"),
        ];
        args.extend(extra);
        let out = glyphcast(&args);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(out.status.success(), "{args:?}:\n{stderr}");
        assert!(
            stderr.lines().any(|l| lines.contains(&l)),
            "{args:?}: none of {lines:?} in:\n{stderr}"
        );
    }
}
