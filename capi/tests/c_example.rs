//! The C example engine (examples/c/) built against include/glyphcast.h and this crate's
//! library by tools/c-example.sh, and run: two frames in flight on its own instance and
//! device with the validation layer on, a plane cutting through glyphs, a PNG out. The
//! example exits non-zero on any failure or validation message, or when the picture
//! shows too few glyph pixels.
use std::path::{Path, PathBuf};
use std::process::Command;

/// One run of the example at a time: tools/c-example.sh compiles it into one place.
static ONE_AT_A_TIME: std::sync::Mutex<()> = std::sync::Mutex::new(());

/// Runs the example with `args`; its output text and the PNG it wrote. One run at a
/// time: tools/c-example.sh compiles the example into one place before running it.
fn run_example(name: &str, args: &[&str]) -> (String, Vec<u8>) {
    let _turn = ONE_AT_A_TIME.lock().unwrap_or_else(|e| e.into_inner());
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

/// `--no-fragment-stores`: an engine whose device lacks fragmentStoresAndAtomics (glyphcast
/// asks a host only for dynamic rendering) draws the default picture byte for byte, with
/// no validation message.
#[test]
fn a_device_without_fragment_stores_draws_the_same_picture() {
    let (_, default) = run_example("c-example-stores.png", &[]);
    let (_, without) = run_example("c-example-no-stores.png", &["--no-fragment-stores"]);
    assert!(default == without, "the pictures differ");
}

/// `--compute`: glyphcast's compute ray caster dispatched before the engine's rendering
/// and composed into its attachments, with no validation message, draws the fragment
/// path's picture (the sRGB bytes within one unit: the compute shader encodes its colour
/// itself), the glyphs cut by the engine's plane alike; without the plane too.
#[test]
fn the_compute_path_draws_the_fragment_path_picture() {
    for (name, args) in [("plane", &[][..]), ("no-plane", &["--no-plane"][..])] {
        let (_, fragment) = run_example(&format!("c-fragment-{name}.png"), args);
        let mut with = args.to_vec();
        with.push("--compute");
        let (_, compute) = run_example(&format!("c-compute-{name}.png"), &with);
        let far = differing_pixels(&fragment, &compute)
            .into_iter()
            .filter(|(a, b)| a.iter().zip(b).any(|(x, y)| x.abs_diff(*y) > 1))
            .count();
        assert_eq!(far, 0, "{name}: pixels differ by more than one unit");
    }
}

/// The pixels of two RGBA8 PNGs of the same size that differ, as (left, right) RGB.
fn differing_pixels(a: &[u8], b: &[u8]) -> Vec<([u8; 3], [u8; 3])> {
    let decode = |bytes: &[u8]| {
        let mut reader = png::Decoder::new(std::io::Cursor::new(bytes.to_vec()))
            .read_info()
            .expect("a PNG");
        let mut pixels = vec![0; reader.output_buffer_size().expect("a size")];
        let info = reader.next_frame(&mut pixels).expect("its pixels");
        assert_eq!(info.color_type, png::ColorType::Rgba);
        pixels.truncate(info.buffer_size());
        pixels
    };
    let (a, b) = (decode(a), decode(b));
    assert_eq!(a.len(), b.len());
    a.chunks(4)
        .zip(b.chunks(4))
        .filter(|(p, q)| p[..3] != q[..3])
        .map(|(p, q)| ([p[0], p[1], p[2]], [q[0], q[1], q[2]]))
        .collect()
}

/// The host's settings reach the picture: with one red for every glyph (and no
/// highlight) every glyph pixel is red-dominated, where the default colours by
/// direction show green and blue ones; the engine's own plane is the same in both.
#[test]
fn the_c_example_follows_its_settings() {
    let (_, direction) = run_example("c-example-direction.png", &[]);
    let (_, red) = run_example("c-example-red.png", &["--uniform-red"]);
    let changed = differing_pixels(&direction, &red);
    assert!(changed.len() > 1000, "{} glyph pixels", changed.len());
    let not_red = changed
        .iter()
        .filter(|(_, [r, g, b])| r < g || r < b)
        .count();
    assert_eq!(not_red, 0, "glyph pixels that are not red");
    let green_or_blue = changed
        .iter()
        .filter(|([r, g, b], _)| g > r || b > r)
        .count();
    assert!(
        green_or_blue * 4 > changed.len(),
        "{green_or_blue} of {} direction-coloured pixels are green or blue",
        changed.len()
    );
}

/// The SH basis is the host's to say: the same coefficients read as DIPY's default
/// (descoteaux07, legacy), as descoteaux07 without the legacy flag and as MRtrix's
/// tournier07 are three different sets of glyphs (the example's last frame shows SH
/// glyphs when `--basis` is given).
#[test]
fn the_sh_basis_and_its_legacy_flag_are_honoured() {
    let (_, legacy) = run_example("c-example-legacy.png", &["--basis", "descoteaux07-legacy"]);
    let (_, plain) = run_example("c-example-plain-basis.png", &["--basis", "descoteaux07"]);
    let (_, tournier) = run_example("c-example-tournier.png", &["--basis", "tournier07"]);
    for (pair, a, b) in [
        ("legacy, plain", &legacy, &plain),
        ("legacy, tournier07", &legacy, &tournier),
        ("plain, tournier07", &plain, &tournier),
    ] {
        let changed = differing_pixels(a, b).len();
        assert!(changed > 100, "{pair}: {changed} pixels differ");
    }
}

/// The host's shadows reach the picture: with the light from the side, `settings.shadows`
/// hard darkens glyph pixels and brightens none (the engine's plane keeps its colour), soft shadows differ again; a
/// soft light of radius 0 is refused at creation, naming the field.
#[test]
fn the_c_example_casts_shadows_when_asked() {
    // Lit from the left, so that the glyphs' lobes shadow each other where the camera
    // sees them.
    let (_, plain) = run_example("c-example-unshadowed.png", &["--side-light"]);
    let (_, hard) = run_example("c-example-shadows.png", &["--side-light", "--shadows"]);
    let (_, soft) = run_example(
        "c-example-soft.png",
        &["--side-light", "--soft-shadows", "6"],
    );
    let changed = differing_pixels(&plain, &hard);
    assert!(changed.len() > 20, "{} pixels shadowed", changed.len());
    let brighter = changed
        .iter()
        .filter(|(before, after)| (0..3).any(|c| after[c] > before[c]))
        .count();
    assert_eq!(brighter, 0, "pixels brightened by shadows");
    assert!(!differing_pixels(&hard, &soft).is_empty());
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let out = Path::new(env!("CARGO_TARGET_TMPDIR")).join("c-example-refused.png");
    let _turn = ONE_AT_A_TIME.lock().unwrap_or_else(|e| e.into_inner());
    let run = Command::new("bash")
        .arg(root.join("tools/c-example.sh"))
        .arg(&out)
        .args(["--soft-shadows", "0"])
        .output()
        .expect("running bash");
    let text = String::from_utf8_lossy(&run.stderr);
    assert!(!run.status.success(), "{text}");
    assert!(text.contains("settings.shadows 'soft:0'"), "{text}");
}

/// The host's ambient occlusion reaches the picture: `settings.ambient_occlusion` 1 (with
/// the example's strong ambient term) darkens glyph pixels where lobes crowd each other
/// and brightens none against the same ambient term without it; a negative reach is
/// refused at creation, naming the field.
#[test]
fn the_c_example_occludes_when_asked() {
    let (_, plain) = run_example("c-example-ao-off.png", &["--ambient-occlusion", "0"]);
    let (_, occluded) = run_example("c-example-ao.png", &["--ambient-occlusion", "1"]);
    let changed = differing_pixels(&plain, &occluded);
    assert!(changed.len() > 20, "{} pixels occluded", changed.len());
    let brighter = changed
        .iter()
        .filter(|(before, after)| (0..3).any(|c| after[c] > before[c]))
        .count();
    assert_eq!(brighter, 0, "pixels brightened by ambient occlusion");
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let out = Path::new(env!("CARGO_TARGET_TMPDIR")).join("c-example-ao-refused.png");
    let _turn = ONE_AT_A_TIME.lock().unwrap_or_else(|e| e.into_inner());
    let run = Command::new("bash")
        .arg(root.join("tools/c-example.sh"))
        .arg(&out)
        .args(["--ambient-occlusion", "-2"])
        .output()
        .expect("running bash");
    let text = String::from_utf8_lossy(&run.stderr);
    assert!(!run.status.success(), "{text}");
    assert!(
        text.contains("settings.ambient_occlusion -2") && text.contains("above 0"),
        "{text}"
    );
}
