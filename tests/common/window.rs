//! `glyphcast view` in a real window on a virtual X server (Xvfb), and the comparisons
//! of what it showed with `glyphcast render`'s images (tests/viewer.rs,
//! tests/viewer_figures.rs).
//!
//! Each test starts its own Xvfb (`-displayfd` picks a free display and says when it is
//! ready). Where Xvfb is missing the tests are skipped with a message, except in CI
//! (CI=true), where a missing Xvfb fails them: tools/install-deps.sh installs it.
use glyphcast::io::png::read_png_rgba8;
use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Output, Stdio};

pub const BIN: &str = env!("CARGO_BIN_EXE_glyphcast");

/// A virtual X server for one test, stopped when dropped.
pub struct Xvfb {
    child: Child,
    pub display: String,
}

impl Xvfb {
    /// None (with a message) where Xvfb is not installed, outside CI.
    pub fn start(test: &str) -> Option<Xvfb> {
        let spawned = Command::new("Xvfb")
            .args([
                "-displayfd",
                "1",
                "-screen",
                "0",
                "1024x768x24",
                "-nolisten",
                "tcp",
            ])
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn();
        let mut child = match spawned {
            Ok(child) => child,
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
                let ci = std::env::var("CI").is_ok_and(|v| v == "true" || v == "1");
                assert!(
                    !ci,
                    "{test}: Xvfb is not installed, and CI must run the viewer tests \
                     (tools/install-deps.sh installs xvfb)"
                );
                eprintln!("SKIPPED {test}: Xvfb is not installed (Debian: apt-get install xvfb)");
                return None;
            }
            Err(e) => panic!("{test}: starting Xvfb: {e}"),
        };
        // Xvfb writes the display number once it accepts connections.
        let mut line = String::new();
        let stdout = child.stdout.take().expect("Xvfb's stdout");
        BufReader::new(stdout)
            .read_line(&mut line)
            .expect("reading Xvfb's display number");
        let number = line.trim();
        assert!(
            !number.is_empty() && number.chars().all(|c| c.is_ascii_digit()),
            "{test}: Xvfb did not start (said {line:?})"
        );
        Some(Xvfb {
            display: format!(":{number}"),
            child,
        })
    }

    /// Runs `glyphcast view` with `args` on this display, validation on with
    /// synchronization validation (GLYPHCAST_SYNC_VALIDATION=1): the window's frames in
    /// flight must not race, and any hazard is a validation message.
    pub fn view(&self, args: &[&str]) -> Output {
        let output = Command::new(BIN)
            .arg("view")
            .args(args)
            .arg("--validation")
            .env("DISPLAY", &self.display)
            .env("GLYPHCAST_SYNC_VALIDATION", "1")
            .output()
            .expect("running glyphcast view");
        let stderr = String::from_utf8_lossy(&output.stderr);
        eprintln!("glyphcast view {}:\n{stderr}", args.join(" "));
        output
    }
}

impl Drop for Xvfb {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

pub fn out(name: &str) -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("viewer");
    std::fs::create_dir_all(&dir).expect("creating the test output folder");
    dir.join(name)
}

pub fn data(path: &str) -> String {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
        .join(path)
        .display()
        .to_string()
}

pub fn path_str(p: &Path) -> &str {
    p.to_str().expect("UTF-8 test path")
}

/// Asserts a clean exit with no validation message on stderr.
pub fn assert_clean(output: &Output) {
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(output.status.success(), "glyphcast view failed: {stderr}");
    assert!(
        !stderr.contains("validation error") && !stderr.contains("validation:"),
        "the validation layer spoke: {stderr}"
    );
}

/// Renders `scene` with `glyphcast render` and the given options; returns the PNG path.
pub fn render(scene: &Path, name: &str, options: &[&str]) -> PathBuf {
    let png = out(name);
    let status = Command::new(BIN)
        .arg("render")
        .arg(scene)
        .arg("-o")
        .arg(&png)
        .args(options)
        .arg("--validation")
        .status()
        .expect("running glyphcast render");
    assert!(status.success(), "glyphcast render {}", scene.display());
    png
}

/// Pixels whose channels differ by more than `threshold`, and the largest difference.
pub fn differing_pixels(a: &Path, b: &Path, threshold: u8) -> (usize, u8, (u32, u32)) {
    let (wa, ha, pa) = read_png_rgba8(a).expect("reading the first image");
    let (wb, hb, pb) = read_png_rgba8(b).expect("reading the second image");
    assert_eq!((wa, ha), (wb, hb), "{} and {}", a.display(), b.display());
    let mut worst = 0;
    let count = pa
        .chunks_exact(4)
        .zip(pb.chunks_exact(4))
        .filter(|(x, y)| {
            let d = x
                .iter()
                .zip(*y)
                .map(|(p, q)| p.abs_diff(*q))
                .max()
                .unwrap_or(0);
            worst = worst.max(d);
            d > threshold
        })
        .count();
    (count, worst, (wa, ha))
}

/// The window against the headless render. The window's pipeline runs the colour-only
/// build of the same fragment shader, into a B8G8R8A8_SRGB swapchain image instead of
/// the R8G8B8A8_SRGB target: the same float colour is encoded the same way, so a pixel
/// may differ by one step of rounding (threshold 1) where the two builds order float
/// operations differently. Such differences can also move a hit by an ulp at a grazing
/// silhouette ray and change a whole pixel: a budget of 0.5% of the pixels allows a
/// thin rim of those and nothing like a wrong camera, size or setting, which changes
/// most glyph pixels (each scene covers well over 5% of its image).
pub const CHANNEL_THRESHOLD: u8 = 1;
pub const PIXEL_BUDGET_FRACTION: f64 = 0.005;

pub fn assert_window_matches(window: &Path, headless: &Path) {
    let (count, worst, (w, h)) = differing_pixels(window, headless, CHANNEL_THRESHOLD);
    let budget = (PIXEL_BUDGET_FRACTION * f64::from(w * h)) as usize;
    eprintln!(
        "window vs headless: {count} of {} pixels differ by more than {CHANNEL_THRESHOLD} \
         (largest difference {worst}); budget {budget}",
        w * h
    );
    if count > budget {
        let diff = window.with_extension("diff.png");
        write_diff(window, headless, &diff);
        panic!(
            "the window ({}) differs from the headless render ({}) in {count} pixels; \
             differences in red: {}",
            window.display(),
            headless.display(),
            diff.display()
        );
    }
}

/// Red where the images differ by more than the threshold, grey elsewhere.
pub fn write_diff(a: &Path, b: &Path, diff: &Path) {
    let (w, h, pa) = read_png_rgba8(a).expect("reading the first image");
    let (_, _, pb) = read_png_rgba8(b).expect("reading the second image");
    let pixels: Vec<u8> = pa
        .chunks_exact(4)
        .zip(pb.chunks_exact(4))
        .flat_map(|(x, y)| {
            let d = x
                .iter()
                .zip(y)
                .map(|(p, q)| p.abs_diff(*q))
                .max()
                .unwrap_or(0);
            if d > CHANNEL_THRESHOLD {
                [255, 0, 0, 255]
            } else {
                [x[0] / 3, x[1] / 3, x[2] / 3, 255]
            }
        })
        .collect();
    let _ = glyphcast::io::png::write_png_rgba8(diff, w, h, &pixels);
}
