//! The on-disk pipeline cache as a cohort pipeline meets it: whole files appear, a
//! corrupt file is ignored and replaced, and processes that start at once (a job array)
//! all succeed with identical outputs and leave one whole cache file behind. And the GPU
//! report's quick table runs end to end on lavapipe.
use crate::common;
use common::{fresh_dir, text};
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// `glyphcast` with validation on and the pipeline cache in `cache`.
fn glyphcast_cached(args: &[&str], cache: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_glyphcast"))
        .args(args)
        .env("GLYPHCAST_VALIDATION", "1")
        .env("GLYPHCAST_CACHE_DIR", cache)
        .env_remove("GLYPHCAST_PIPELINE_CACHE")
        .output()
        .expect("running glyphcast")
}

/// The cache files in `dir` (and fails on anything else there, such as a temporary).
fn cache_files(dir: &Path) -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir)
        .expect("listing the cache folder")
        .map(|e| e.expect("entry").path())
        .collect();
    files.sort();
    for file in &files {
        let name = file.file_name().and_then(|n| n.to_str()).unwrap_or("");
        assert!(
            name.starts_with("pipelines-") && name.ends_with(".bin"),
            "unexpected file in the cache folder: {}",
            file.display()
        );
    }
    files
}

/// FNV-1a, 64 bit, as the cache's header uses.
fn fnv1a(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325_u64, |hash, &b| {
        (hash ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3)
    })
}

/// Whether `file` is a whole cache file: magic, length, checksum, and a Vulkan
/// pipeline-cache header (version one) at the start of the driver's data.
fn is_whole(file: &Path) -> bool {
    let bytes = std::fs::read(file).expect("reading the cache file");
    if bytes.len() < 24 + 32 || &bytes[..8] != b"GCPCACHE" {
        return false;
    }
    let word = |at: usize| u64::from_le_bytes(bytes[at..at + 8].try_into().expect("8 bytes"));
    let data = &bytes[24..];
    let version = u32::from_le_bytes(data[4..8].try_into().expect("4 bytes"));
    word(8) == data.len() as u64 && word(16) == fnv1a(data) && version == 1
}

fn render_demo(cache: &Path, png: &Path) -> Output {
    glyphcast_cached(
        &["demo", "-o", text(png), "--width", "96", "--height", "72"],
        cache,
    )
}

fn assert_success(out: &Output, what: &str) {
    assert!(
        out.status.success(),
        "{what} failed:\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

#[test]
fn a_corrupt_cache_file_is_ignored_and_replaced() {
    let dir = fresh_dir("pipeline-cache-corrupt");
    let cache = dir.join("cache");
    let first = dir.join("first.png");
    let out = render_demo(&cache, &first);
    assert_success(&out, "the first render");
    let files = cache_files(&cache);
    assert_eq!(files.len(), 1, "one cache file per device: {files:?}");
    assert!(is_whole(&files[0]), "the written cache file is whole");

    // A file cut short by a crash, then one of random bytes: each is ignored with a
    // note, the image is the same, and a whole file takes its place.
    let whole = std::fs::read(&files[0]).expect("reading");
    let damaged: [Vec<u8>; 2] = [
        whole[..whole.len() - 5].to_vec(),
        (0..4096u32)
            .map(|i| (i.wrapping_mul(2_654_435_761) >> 13) as u8)
            .collect(),
    ];
    for (case, bytes) in damaged.iter().enumerate() {
        std::fs::write(&files[0], bytes).expect("damaging the cache");
        let again = dir.join(format!("again-{case}.png"));
        let out = render_demo(&cache, &again);
        assert_success(&out, "a render over a damaged cache");
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(
            stderr.contains("ignoring the pipeline cache"),
            "case {case}: the damaged cache is named in a note:\n{stderr}"
        );
        assert_eq!(
            std::fs::read(&first).expect("first"),
            std::fs::read(&again).expect("again"),
            "case {case}: the image does not depend on the cache"
        );
        assert_eq!(cache_files(&cache), files);
        assert!(
            is_whole(&files[0]),
            "case {case}: the damaged file was replaced"
        );
        // Once replaced, the next run reads it without a note.
        let out = render_demo(&cache, &again);
        assert_success(&out, "a render over the replaced cache");
        assert!(!String::from_utf8_lossy(&out.stderr).contains("ignoring"));
    }

    // Turned off: no file is read or written.
    let off = dir.join("off");
    let out = Command::new(env!("CARGO_BIN_EXE_glyphcast"))
        .args([
            "demo",
            "-o",
            text(&dir.join("off.png")),
            "--width",
            "96",
            "--height",
            "72",
        ])
        .env("GLYPHCAST_VALIDATION", "1")
        .env("GLYPHCAST_CACHE_DIR", &off)
        .env("GLYPHCAST_PIPELINE_CACHE", "0")
        .output()
        .expect("running glyphcast");
    assert_success(&out, "a render without the cache");
    assert!(!off.exists(), "GLYPHCAST_PIPELINE_CACHE=0 writes no cache");
}

#[test]
fn four_processes_at_once_share_the_cache_and_agree() {
    let dir = fresh_dir("pipeline-cache-concurrent");
    let cache = dir.join("cache");
    let scene = dir.join("scene.json");
    let out = glyphcast_cached(
        &[
            "demo",
            "-o",
            text(&dir.join("saved.png")),
            "--width",
            "64",
            "--height",
            "48",
            "--save-scene",
            text(&scene),
        ],
        &cache,
    );
    assert_success(&out, "saving the demo scene");
    std::fs::remove_dir_all(&cache).expect("starting from no cache");
    // The same render in four processes started together, as a job array on one node.
    let children: Vec<_> = (0..4)
        .map(|i| {
            let png = dir.join(format!("out-{i}.png"));
            let npy = dir.join(format!("out-{i}.npy"));
            let child = Command::new(env!("CARGO_BIN_EXE_glyphcast"))
                .args([
                    "render",
                    text(&scene),
                    "-o",
                    text(&png),
                    "--depth-out",
                    text(&npy),
                ])
                .env("GLYPHCAST_VALIDATION", "1")
                .env("GLYPHCAST_CACHE_DIR", &cache)
                .env_remove("GLYPHCAST_PIPELINE_CACHE")
                .stderr(std::process::Stdio::piped())
                .spawn()
                .expect("starting glyphcast");
            (child, png, npy)
        })
        .collect();
    let mut outputs = Vec::new();
    for (child, png, npy) in children {
        let out = child.wait_with_output().expect("waiting for glyphcast");
        assert_success(&out, "a concurrent render");
        outputs.push((
            std::fs::read(png).expect("png"),
            std::fs::read(npy).expect("npy"),
        ));
    }
    for (i, output) in outputs.iter().enumerate().skip(1) {
        assert!(
            output == &outputs[0],
            "process {i}'s outputs differ from process 0's"
        );
    }
    let files = cache_files(&cache);
    assert_eq!(
        files.len(),
        1,
        "one whole cache file, no temporaries: {files:?}"
    );
    assert!(is_whole(&files[0]));
}

#[test]
fn the_quick_gpu_report_writes_its_table() {
    let dir = fresh_dir("gpu-report");
    let script =
        Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../..")).join("tools/gpu-report.sh");
    let out = Command::new("bash")
        .arg(&script)
        .args([
            "--quick",
            "--bin",
            env!("CARGO_BIN_EXE_glyphcast"),
            text(&dir),
        ])
        .env("GLYPHCAST_VALIDATION", "1")
        .output()
        .expect("running tools/gpu-report.sh");
    assert_success(&out, "tools/gpu-report.sh --quick");
    let reports: Vec<PathBuf> = std::fs::read_dir(&dir)
        .expect("listing")
        .map(|e| e.expect("entry").path())
        .filter(|p| p.extension().is_some_and(|e| e == "md"))
        .collect();
    assert_eq!(reports.len(), 1, "one report: {reports:?}");
    let report = std::fs::read_to_string(&reports[0]).expect("reading the report");
    // It names the device and its driver, times the first image, and has a row per
    // field and size with every method, the compute path included.
    assert!(report.contains("- Device: llvmpipe"), "{report}");
    assert!(report.contains("Mesa"), "the driver is named:\n{report}");
    assert!(report.contains("| demo scene"), "{report}");
    for method in [
        "exact",
        "affine",
        "interval",
        "fixed",
        "impostor",
        "mesh:3",
        "mesh:5",
        "exact (compute)",
        "exact (auto)",
    ] {
        assert!(
            report.contains(&format!(" {method} |")),
            "column {method}:\n{report}"
        );
    }
    for row in ["| 100 | 320x180 |", "| 1000 | 640x360 |"] {
        let line = report
            .lines()
            .find(|l| l.starts_with(row))
            .unwrap_or_else(|| panic!("row {row} missing:\n{report}"));
        assert!(!line.contains(" - |"), "every method measured: {line}");
    }
    // The accuracy of the smallest field against the float64 reference: the default
    // method leaves no hole.
    let exact = report
        .lines()
        .find(|l| l.starts_with("| fodf:100:8 320x180 exact | exact |"))
        .unwrap_or_else(|| panic!("accuracy row missing:\n{report}"));
    let holes: Vec<&str> = exact.split('|').map(str::trim).collect();
    assert_eq!(holes[10], "0", "exact leaves no hole: {exact}");
    assert!(!String::from_utf8_lossy(&out.stderr).contains("failed"));
    // The raw results lie beside the report.
    let raw = reports[0].with_extension("");
    assert!(raw.join("gpu/results.json").is_file(), "{}", raw.display());
    // `auto` took the fragment path on lavapipe, in every row.
    let results: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(raw.join("gpu/results.json")).expect("results"),
    )
    .expect("JSON");
    let auto: Vec<&str> = results["results"]
        .as_array()
        .expect("results")
        .iter()
        .filter_map(|r| r["path"].as_str())
        .filter(|p| p.starts_with("auto"))
        .collect();
    assert_eq!(auto, vec!["auto: fragment"; 4], "{results}");
}
