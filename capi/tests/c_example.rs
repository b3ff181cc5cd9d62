//! The C example engine (examples/c/) built against include/glyphcast.h and this crate's
//! library by tools/c-example.sh, and run: two frames in flight on its own instance and
//! device with the validation layer on, a plane cutting through glyphs, a PNG out. The
//! example exits non-zero on any failure or validation message, or when the picture
//! shows too few glyph pixels.
use std::path::Path;
use std::process::Command;

#[test]
fn the_c_example_draws_glyphs_with_no_validation_message() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let out = Path::new(env!("CARGO_TARGET_TMPDIR")).join("c-example.png");
    let _ = std::fs::remove_file(&out);
    let run = Command::new("bash")
        .arg(root.join("tools/c-example.sh"))
        .arg(&out)
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
}
