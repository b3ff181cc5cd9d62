//! The installed C library, as a C++ engine uses it: tools/cpp-example.sh installs the
//! library into a prefix (tools/install-c.sh --debug: the development build this test
//! run has made already, not a second release build), builds examples/cpp/ against that
//! prefix with CMake's find_package (shared and static) and with pkg-config, and runs
//! each build headless on lavapipe with the validation layer on (three frames in flight,
//! the engine's own render pass and memory). The example exits non-zero on any failure
//! or validation message; this test then looks at its picture.
use std::path::{Path, PathBuf};
use std::process::Command;

const WIDTH: usize = 192;
const HEIGHT: usize = 144;

/// The RGBA8 pixels of a PNG of the example's size.
fn decode(path: &Path) -> Vec<u8> {
    let bytes = std::fs::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let mut reader = png::Decoder::new(std::io::Cursor::new(bytes))
        .read_info()
        .expect("a PNG");
    let mut pixels = vec![0; reader.output_buffer_size().expect("a size")];
    let info = reader.next_frame(&mut pixels).expect("its pixels");
    assert_eq!(info.color_type, png::ColorType::Rgba);
    assert_eq!((info.width as usize, info.height as usize), (WIDTH, HEIGHT));
    pixels.truncate(info.buffer_size());
    pixels
}

/// Where the example's camera (7 above the origin looking down, x right, y up, a
/// vertical field of view of 35 degrees) puts the point (x, y, 0): pixel column and row.
fn project(x: f64, y: f64) -> (usize, usize) {
    let h = 1.0 / (35f64.to_radians() / 2.0).tan();
    let aspect = WIDTH as f64 / HEIGHT as f64;
    let ndc_x = x * h / aspect / 7.0;
    let ndc_y = -y * h / 7.0;
    let col = (ndc_x + 1.0) / 2.0 * WIDTH as f64;
    let row = (ndc_y + 1.0) / 2.0 * HEIGHT as f64;
    (col as usize, row as usize)
}

#[test]
fn the_cpp_example_builds_against_the_installed_library_and_draws_its_glyphs() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let dir: PathBuf = Path::new(env!("CARGO_TARGET_TMPDIR")).join("cpp-example");
    std::fs::create_dir_all(&dir).expect("a folder for the pictures");
    let out = dir.join("cpp-example.png");
    let run = Command::new("bash")
        .arg(root.join("tools/cpp-example.sh"))
        .arg("--debug")
        .arg(&out)
        .output()
        .expect("running bash");
    let text = format!(
        "{}{}",
        String::from_utf8_lossy(&run.stdout),
        String::from_utf8_lossy(&run.stderr)
    );
    assert!(run.status.success(), "{text}");
    // Three runs, each with every block given back and no validation message.
    let reports: Vec<&str> = text.lines().filter(|l| l.starts_with("wrote ")).collect();
    assert_eq!(reports.len(), 3, "{text}");
    for report in &reports {
        assert!(report.contains(", 0 not given back;"), "{report}");
        assert!(report.ends_with("; 0 validation message(s)"), "{report}");
    }

    let shared = decode(&out);
    let pixel = |col: usize, row: usize| {
        let i = 4 * (row * WIDTH + col);
        [shared[i], shared[i + 1], shared[i + 2]]
    };
    // The background: linear 0.2 grey, sRGB 124 (rounding may differ by one), at the
    // corners and at the middle of each edge, where no glyph reaches.
    let edges = [
        (2, 2),
        (WIDTH - 3, 2),
        (2, HEIGHT - 3),
        (WIDTH - 3, HEIGHT - 3),
        (WIDTH / 2, 2),
        (WIDTH / 2, HEIGHT - 3),
        (2, HEIGHT / 2),
        (WIDTH - 3, HEIGHT / 2),
    ];
    for (col, row) in edges {
        let p = pixel(col, row);
        assert!(
            p.iter().all(|c| c.abs_diff(124) <= 1),
            "background at ({col}, {row}): {p:?}"
        );
    }
    // A glyph covers each of the nine grid points: coloured by direction (seen from
    // above, mostly blue), far from the grey.
    for k in 0..9 {
        let (x, y) = (1.1 * (k % 3) as f64 - 1.1, 1.1 * (k / 3) as f64 - 1.1);
        let (col, row) = project(x, y);
        let p = pixel(col, row);
        let distance = p.iter().map(|c| c.abs_diff(124)).max().unwrap_or(0);
        assert!(
            distance > 40,
            "no glyph at ({x}, {y}), pixel ({col}, {row}): {p:?}"
        );
    }
    // The three builds drew the same picture.
    for other in ["cpp-example-static.png", "cpp-example-pkgconfig.png"] {
        assert!(decode(&dir.join(other)) == shared, "{other} differs");
    }
}
