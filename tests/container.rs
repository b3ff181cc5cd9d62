//! The container recipes (container/Dockerfile, container/glyphcast.def) cannot be built
//! on the test machine (no container runtime, no registry for their base images), so
//! this checks what can go wrong in them without one: the build context they copy is a
//! whole Cargo workspace that resolves from the lock file (a member left out, such as
//! capi/, failed `cargo build` in the recipe), and both recipes copy the same paths.
use std::path::{Path, PathBuf};
use std::process::Command;

use crate::common;

fn repo() -> PathBuf {
    PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
}

fn recipe(name: &str) -> String {
    std::fs::read_to_string(repo().join("container").join(name)).expect("reading the recipe")
}

/// The sources of the Dockerfile's build-stage `COPY SRC... DEST` lines (not
/// `COPY --from`, which copies between stages).
fn docker_context(text: &str) -> Vec<String> {
    let mut paths: Vec<String> = text
        .lines()
        .filter_map(|line| line.trim().strip_prefix("COPY "))
        .filter(|args| !args.starts_with("--from"))
        .flat_map(|args| {
            let words: Vec<&str> = args.split_whitespace().collect();
            let sources = &words[..words.len().saturating_sub(1)];
            sources.iter().map(|s| s.to_string()).collect::<Vec<_>>()
        })
        .collect();
    paths.sort();
    paths
}

/// The sources of the first `%files` section (the build stage) of the Apptainer recipe.
fn apptainer_context(text: &str) -> Vec<String> {
    let mut lines = text.lines().skip_while(|l| l.trim() != "%files");
    lines.next();
    let mut paths: Vec<String> = lines
        .take_while(|l| !l.trim().starts_with('%'))
        .filter_map(|l| l.split_whitespace().next().map(str::to_string))
        .collect();
    paths.sort();
    paths
}

fn copy_tree(from: &Path, to: &Path) {
    if from.is_dir() {
        if from.file_name().is_some_and(|n| n == "target") {
            return;
        }
        std::fs::create_dir_all(to).expect("a folder of the context");
        for entry in std::fs::read_dir(from).expect("listing") {
            let entry = entry.expect("an entry");
            copy_tree(&entry.path(), &to.join(entry.file_name()));
        }
    } else {
        std::fs::copy(from, to).expect("copying into the context");
    }
}

#[test]
fn both_recipes_copy_the_same_build_context() {
    let docker = docker_context(&recipe("Dockerfile"));
    let apptainer = apptainer_context(&recipe("glyphcast.def"));
    assert!(docker.contains(&"Cargo.toml".to_string()), "{docker:?}");
    assert_eq!(docker, apptainer);
}

#[test]
fn the_recipes_build_context_is_a_whole_workspace() {
    let context = common::fresh_dir("container-context");
    for path in docker_context(&recipe("Dockerfile")) {
        let from = repo().join(&path);
        assert!(
            from.exists(),
            "the Dockerfile copies {path}, which does not exist"
        );
        copy_tree(&from, &context.join(&path));
    }
    let run = Command::new(env!("CARGO"))
        .args(["metadata", "--locked", "--format-version", "1"])
        .current_dir(&context)
        .output()
        .expect("running cargo metadata");
    assert!(
        run.status.success(),
        "the recipes' build context is not a workspace that resolves from Cargo.lock: {}",
        String::from_utf8_lossy(&run.stderr)
    );
    let metadata = String::from_utf8_lossy(&run.stdout);
    assert!(
        metadata.contains("\"name\":\"glyphcast\"")
            && metadata.contains("\"name\":\"glyphcast-cli\""),
        "the glyphcast and glyphcast-cli packages"
    );
}

#[test]
fn the_recipes_build_with_plain_cargo() {
    // Debian 12's split shaderc links with nothing sourced and no variable set
    // (crates/glyphcast-shaderc-link): the recipes build as an engine or `cargo install`
    // does, and set no SHADERC_LIB_DIR of their own.
    for name in ["Dockerfile", "glyphcast.def"] {
        let text = recipe(name);
        let builds: Vec<&str> = text
            .lines()
            .filter(|line| line.contains("cargo build") || line.contains("maturin build"))
            .collect();
        assert_eq!(
            builds.len(),
            2,
            "{name}: the binary's and the wheel's builds"
        );
        for line in builds {
            assert!(
                !line.contains("tools/env.sh") && !line.contains("SHADERC_LIB_DIR"),
                "{name} builds with an environment of its own: {line}"
            );
        }
        assert!(
            !text.contains("SHADERC_LIB_DIR") && !text.contains("shaderc-lib"),
            "{name} names a shaderc of its own"
        );
    }
}
