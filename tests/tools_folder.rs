//! The tools write only into the checkout (its `target/`) or their named outputs, never
//! into the folder they are run from: a user running `tools/cohort-slurm.sh` from a
//! study folder finds nothing of glyphcast's build there.
use crate::common::fresh_dir;
use std::path::PathBuf;
use std::process::Command;

fn repo() -> PathBuf {
    PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
}

#[test]
fn sourcing_the_environment_script_writes_nothing_into_the_current_folder() {
    let here = fresh_dir("tools-folder-env");
    let script = repo().join("tools/env.sh");
    let run = Command::new("bash")
        .arg("-c")
        .arg(format!(
            ". '{}' && test -n \"$VK_DRIVER_FILES\"",
            script.display()
        ))
        .current_dir(&here)
        .env("GLYPHCAST_LAVAPIPE", "1")
        .env_remove("VK_DRIVER_FILES")
        .env_remove("CARGO_TARGET_DIR")
        .output()
        .expect("running bash");
    assert!(
        run.status.success(),
        "sourcing tools/env.sh failed or chose no driver: {}",
        String::from_utf8_lossy(&run.stderr)
    );
    let left: Vec<_> = std::fs::read_dir(&here)
        .expect("reading the folder")
        .map(|entry| entry.expect("an entry").file_name())
        .collect();
    assert!(
        left.is_empty(),
        "tools/env.sh wrote {left:?} into the current folder"
    );
}

#[test]
fn every_tool_that_names_the_current_folder_moves_into_the_checkout_first() {
    // A script that builds paths from $PWD (target/, examples/) must have changed into
    // the repository before, or those paths land in the caller's folder.
    let mut checked = 0;
    for entry in std::fs::read_dir(repo().join("tools")).expect("reading tools/") {
        let path = entry.expect("an entry").path();
        if path.extension().is_none_or(|e| e != "sh") {
            continue;
        }
        let text = std::fs::read_to_string(&path).expect("reading a tool");
        let code: Vec<&str> = text
            .lines()
            .filter(|line| !line.trim_start().starts_with('#'))
            .collect();
        let Some(first_pwd) = code.iter().position(|line| line.contains("$PWD")) else {
            continue;
        };
        let moved = code[..first_pwd]
            .iter()
            .any(|line| line.contains("cd \"$(dirname \"$0\")/..\""));
        assert!(
            moved,
            "{} builds paths from $PWD without first changing into the checkout",
            path.display()
        );
        checked += 1;
    }
    assert!(
        checked >= 5,
        "only {checked} tools name $PWD: is tools/ where it was?"
    );
}
