//! The C example engine (examples/c/) built against include/glyphcast.h and this crate's
//! library by tools/c-example.sh, and run: two frames in flight on its own instance and
//! device with the validation layer on, a plane cutting through glyphs, a PNG out. The
//! example exits non-zero on any failure or validation message, or when the picture
//! shows too few glyph pixels.
use std::path::{Path, PathBuf};
use std::process::Command;

/// Runs the example with `args`; its output text and the PNG it wrote.
fn run_example(name: &str, args: &[&str]) -> (String, Vec<u8>) {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let out: PathBuf = Path::new(env!("CARGO_TARGET_TMPDIR")).join(name);
    let _ = std::fs::remove_file(&out);
    let run = Command::new("bash")
        .arg(root.join("tools/c-example.sh"))
        .arg(&out)
        .args(args)
        .output()
        .expect("running bash");
    let text = format!(
        "{}{}",
        String::from_utf8_lossy(&run.stdout),
        String::from_utf8_lossy(&run.stderr)
    );
    assert!(run.status.success(), "{text}");
    assert!(text.contains("0 validation message(s)"), "{text}");
    let png = std::fs::read(&out).expect("the PNG");
    assert_eq!(&png[1..4], b"PNG");
    (text, png)
}

/// The example with glyphcast's memory from gpu-allocator (the default) and from the
/// engine's own allocation callbacks (`--plain-memory`): both without a validation
/// message, the callbacks given every block back, and the two PNGs byte for byte equal.
#[test]
fn the_c_example_draws_glyphs_with_no_validation_message() {
    let (_, default) = run_example("c-example.png", &[]);
    let (text, plain) = run_example("c-example-plain.png", &["--plain-memory"]);
    let counts = text
        .lines()
        .find_map(|l| l.strip_prefix("plain memory: "))
        .unwrap_or_else(|| panic!("no block counts in {text}"));
    let blocks: usize = counts
        .split(' ')
        .next()
        .and_then(|n| n.parse().ok())
        .expect("a block count");
    assert!(blocks >= 5, "{counts}");
    assert!(counts.ends_with(", 0 not given back"), "{counts}");
    assert!(default == plain, "the pictures differ");
}
