//! No command destroys a file it did not write: an output that is one of the command's
//! inputs (by any spelling, link or hard link) is refused before any work; `qc` replaces
//! only the files of its own earlier set; `accuracy` and `bench` check their outputs
//! before the work and write them as sets.
use crate::common;
use common::{dipy_data, fresh_dir, glyphcast, text};
use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use std::process::Output;

fn stderr(run: &Output) -> String {
    String::from_utf8_lossy(&run.stderr).into_owned()
}

fn names(dir: &Path) -> BTreeSet<String> {
    std::fs::read_dir(dir)
        .expect("listing")
        .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
        .collect()
}

/// Runs `args`, expects exit 2 with one error line naming each of `words`.
fn refused(args: &[&str], words: &[&str]) {
    let run = glyphcast(args);
    let err = stderr(&run);
    assert_eq!(run.status.code(), Some(2), "{args:?}:\n{err}");
    for word in words {
        assert!(err.contains(word), "{args:?}: '{word}' not in:\n{err}");
    }
}

/// A copy of tests/scenes/sphere.json in `dir`.
fn sphere_scene(dir: &Path) -> PathBuf {
    let scene = dir.join("s.json");
    let source =
        Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../..")).join("tests/scenes/sphere.json");
    std::fs::copy(source, &scene).expect("copying the scene");
    scene
}

/// The SH image of DIPY's test data (descoteaux07 legacy, no basis record).
fn sh_copy(dir: &Path, name: &str) -> PathBuf {
    let path = dir.join(name);
    std::fs::copy(dipy_data("func_coef.nii.gz"), &path).expect("copying");
    path
}

#[test]
fn qc_replaces_only_its_own_set_and_refuses_any_other_folder() {
    let dir = fresh_dir("outputs-qc");
    let fod = sh_copy(&dir, "fod.nii.gz");
    let qc = |out: &Path, fod: &Path| {
        let args = [
            "qc",
            text(fod),
            "-o",
            text(out),
            "--basis",
            "dipy",
            "--panel-size",
            "64",
            "--quiet",
        ];
        glyphcast(&args)
    };
    // Another tool's qc.json beside the user's files: refused, every file kept.
    let other = dir.join("other");
    std::fs::create_dir_all(other.join("sub")).expect("mkdir");
    std::fs::write(other.join("qc.json"), "{}").expect("writing");
    std::fs::write(other.join("data.txt"), "precious").expect("writing");
    let run = qc(&other, &fod);
    assert_eq!(run.status.code(), Some(2), "{}", stderr(&run));
    assert!(stderr(&run).contains(text(&other)), "{}", stderr(&run));
    assert!(stderr(&run).contains("data.txt"), "{}", stderr(&run));
    assert_eq!(
        names(&other),
        ["data.txt", "qc.json", "sub"].map(String::from).into()
    );
    assert_eq!(
        std::fs::read_to_string(other.join("data.txt")).unwrap(),
        "precious"
    );

    // The input inside the output folder survives.
    let inside = dir.join("inside");
    std::fs::create_dir(&inside).expect("mkdir");
    let own = sh_copy(&inside, "fod.nii.gz");
    let run = qc(&inside, &own);
    assert_eq!(run.status.code(), Some(2), "{}", stderr(&run));
    assert!(stderr(&run).contains("fod.nii.gz"), "{}", stderr(&run));
    assert_eq!(std::fs::read(&own).unwrap(), std::fs::read(&fod).unwrap());

    // A real set is replaced by a new run, but not once a foreign file joins it.
    let set = dir.join("set");
    let run = qc(&set, &fod);
    assert!(run.status.success(), "{}", stderr(&run));
    let files = names(&set);
    assert!(
        files.contains("qc.json") && files.contains("index.html"),
        "{files:?}"
    );
    std::fs::write(set.join("notes.txt"), "mine").expect("writing");
    let run = qc(&set, &fod);
    assert_eq!(run.status.code(), Some(2), "{}", stderr(&run));
    assert!(stderr(&run).contains("notes.txt"), "{}", stderr(&run));
    assert!(set.join("notes.txt").is_file());
    std::fs::remove_file(set.join("notes.txt")).expect("removing");
    let run = qc(&set, &fod);
    assert!(run.status.success(), "{}", stderr(&run));
    assert_eq!(names(&set), files);
    assert_eq!(
        names(&dir),
        ["fod.nii.gz", "inside", "other", "set"]
            .map(String::from)
            .into()
    );
}

#[test]
fn an_output_that_is_an_input_is_refused_before_any_work() {
    let dir = fresh_dir("outputs-inputs");
    let keep = |path: &Path| std::fs::read(path).expect("reading an input");

    let odf = sh_copy(&dir, "in.nii.gz");
    let before = keep(&odf);
    refused(
        &["peaks", text(&odf), "-o", text(&odf), "--basis", "dipy"],
        &["in.nii.gz"],
    );
    assert_eq!(keep(&odf), before);

    let dwi = dir.join("dwi.nii");
    std::fs::copy(dipy_data("small_64D.nii"), &dwi).expect("copying");
    let bval = dipy_data("small_64D.bval");
    let bvec = dipy_data("small_64D.bvec");
    let before = keep(&dwi);
    let fit = |output: &Path| {
        let args = [
            "fit",
            text(&dwi),
            "--bval",
            text(&bval),
            "--bvec",
            text(&bvec),
            "--order",
            "2",
            "--quiet",
            "-o",
            text(output),
        ];
        args.map(String::from)
    };
    let args = fit(&dwi);
    refused(&args.each_ref().map(String::as_str), &["dwi.nii"]);
    assert_eq!(keep(&dwi), before);

    let voigt = dir.join("v.json");
    let matrix = "[[168.4,121.4,121.4,0,0,0],[121.4,168.4,121.4,0,0,0],[121.4,121.4,168.4,0,0,0],\
                  [0,0,0,75.4,0,0],[0,0,0,0,75.4,0],[0,0,0,0,0,75.4]]";
    std::fs::write(&voigt, matrix).expect("writing");
    refused(
        &["stiffness", text(&voigt), "-o", text(&voigt)],
        &["v.json"],
    );
    assert_eq!(std::fs::read_to_string(&voigt).unwrap(), matrix);

    // The scene through a symbolic link, a hard link, another spelling, and a scene's
    // array file as the depth map.
    let scene = sphere_scene(&dir);
    let before = keep(&scene);
    let link = dir.join("out.png");
    std::os::unix::fs::symlink("s.json", &link).expect("linking");
    refused(
        &["render", text(&scene), "-o", text(&link)],
        &["out.png", "s.json"],
    );
    let hard = dir.join("hard.json");
    std::fs::hard_link(&scene, &hard).expect("hard link");
    let png = dir.join("x.png");
    refused(
        &[
            "render",
            text(&scene),
            "-o",
            text(&png),
            "--save-scene",
            text(&hard),
        ],
        &["hard.json", "s.json"],
    );
    let spelled = dir.join(".").join("s.json");
    refused(
        &["bench", text(&scene), "--save-scene", text(&spelled)],
        &["s.json"],
    );
    assert_eq!(keep(&scene), before);
    let with_arrays = dir.join("a.json");
    glyphcast::scene::Scene::load(&scene)
        .expect("loading")
        .save(&with_arrays, true)
        .expect("saving with arrays");
    let coeffs = dir.join("a.0.coeffs.npy");
    let before = keep(&coeffs);
    refused(
        &[
            "render",
            text(&with_arrays),
            "-o",
            text(&png),
            "--depth-out",
            text(&coeffs),
        ],
        &["a.0.coeffs.npy"],
    );
    assert_eq!(keep(&coeffs), before);
    assert!(!png.exists() && !dir.join("a.png").exists());
}

#[test]
fn accuracy_checks_both_tables_before_the_suite() {
    let dir = fresh_dir("outputs-accuracy");
    let table = dir.join("t.md");
    let missing = dir.join("nodir").join("x.csv");
    let args = [
        "accuracy",
        "--size",
        "16",
        "--methods",
        "impostor",
        "--markdown",
    ];
    let run = glyphcast(&[&args[..], &[text(&table), "--csv", text(&missing)]].concat());
    assert_eq!(run.status.code(), Some(1), "{}", stderr(&run));
    assert!(stderr(&run).contains("does not exist"), "{}", stderr(&run));
    assert!(
        !stderr(&run).contains("[1/"),
        "the suite ran first:\n{}",
        stderr(&run)
    );
    let same = dir.join("same.md");
    refused(
        &[&args[..], &[text(&same), "--csv", text(&same)]].concat(),
        &["same.md"],
    );
    assert!(names(&dir).is_empty(), "{:?}", names(&dir));
}

#[test]
fn bench_refuses_a_missing_out_folder_and_foreign_array_files() {
    let dir = fresh_dir("outputs-bench");
    let scene = sphere_scene(&dir);
    let missing = dir.join("nonexistent").join("dir");
    let run = glyphcast(&["bench", text(&scene), "--out", text(&missing)]);
    assert_eq!(run.status.code(), Some(1), "{}", stderr(&run));
    assert!(stderr(&run).contains("does not exist"), "{}", stderr(&run));
    assert!(
        !dir.join("nonexistent").exists(),
        "bench created the folder"
    );

    let saved = dir.join("w.json");
    let bench = [
        "bench",
        text(&scene),
        "--frames",
        "1",
        "--warmup",
        "0",
        "--save-scene",
        text(&saved),
        "--scene-arrays",
    ];
    let foreign = dir.join("w.0.coeffs.npy");
    std::fs::write(&foreign, "not glyphcast's").expect("writing");
    refused(&bench, &["w.0.coeffs.npy"]);
    assert_eq!(
        std::fs::read_to_string(&foreign).unwrap(),
        "not glyphcast's"
    );
    assert!(!saved.exists());
    // Without it the scene and its arrays are written; a second run replaces them.
    std::fs::remove_file(&foreign).expect("removing");
    for _ in 0..2 {
        let run = glyphcast(&bench);
        assert!(run.status.success(), "{}", stderr(&run));
    }
    assert_eq!(
        names(&dir),
        ["s.json", "w.0.centers.npy", "w.0.coeffs.npy", "w.json"]
            .map(String::from)
            .into()
    );
}
