//! A wgpu application that draws its own mesh (a checkered plane through the glyph
//! field) and glyphcast's exact glyphs in one frame, each hiding the other where it is
//! in front: the plane by a wgpu render pass, the glyphs by glyphcast-wgpu into the same
//! colour and depth textures.
//!
//! ```text
//! cargo run -p glyphcast-wgpu --example wgpu_plane [-- --frames N]     # a window
//! cargo run -p glyphcast-wgpu --example wgpu_plane -- --headless out.png
//!     [--frames N] [--in-flight K] [--samples 1|2|4|8]
//! ```
//! Headless, it draws N frames (30) with K in flight (3) under the Vulkan validation
//! layer, synchronization validation included, saves the last one and exits with 1 on
//! any validation message; a bad option exits with 2.
// The wgpu glyphcast-wgpu was built for (its feature wgpu30, the default, or wgpu29).
#[cfg(all(feature = "wgpu29", not(feature = "wgpu30")))]
extern crate wgpu29 as wgpu;
#[cfg(feature = "wgpu30")]
extern crate wgpu30 as wgpu;

mod frames;
mod plane;
mod scene;
mod window;

use std::path::PathBuf;

/// The command line.
#[derive(Debug)]
enum Mode {
    /// Until the window is closed, or for `--frames N`.
    Window(Option<u32>),
    Headless {
        out: PathBuf,
        options: frames::Options,
    },
}

fn parse(args: &[String]) -> Result<Mode, String> {
    let mut out = None;
    let mut options = frames::Options::default();
    let mut frames = None;
    let mut args = args.iter();
    while let Some(arg) = args.next() {
        let mut value = || args.next().ok_or_else(|| format!("{arg} needs a value"));
        let mut number = |min: u32| -> Result<u32, String> {
            let text = value()?;
            match text.parse::<u32>() {
                Ok(n) if n >= min => Ok(n),
                _ => Err(format!("{arg}: '{text}' is not a whole number >= {min}")),
            }
        };
        match arg.as_str() {
            "--headless" => out = Some(PathBuf::from(value()?)),
            "--frames" => frames = Some(number(1)?),
            "--in-flight" => options.in_flight = number(1)? as usize,
            "--samples" => {
                options.samples = number(1)?;
                if ![1, 2, 4, 8].contains(&options.samples) {
                    return Err(format!(
                        "--samples: {} is not 1, 2, 4 or 8",
                        options.samples
                    ));
                }
            }
            other => return Err(format!("unknown option '{other}'")),
        }
    }
    Ok(match out {
        Some(out) => {
            options.frames = frames.unwrap_or(options.frames);
            Mode::Headless { out, options }
        }
        None => Mode::Window(frames),
    })
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let mode = match parse(&args) {
        Ok(mode) => mode,
        Err(message) => {
            eprintln!("wgpu_plane: {message}");
            eprintln!(
                "usage: wgpu_plane [--frames N] [--headless OUT.png [--in-flight K] \
                 [--samples 1|2|4|8]]"
            );
            std::process::exit(2);
        }
    };
    let result = match mode {
        Mode::Window(frames) => window::run(frames),
        Mode::Headless { out, options } => headless(&out, &options),
    };
    if let Err(e) = result {
        eprintln!("wgpu_plane: {e}");
        std::process::exit(1);
    }
}

fn headless(out: &std::path::Path, options: &frames::Options) -> frames::Result<()> {
    let run = frames::run(options)?;
    glyphcast::io::png::write_png_rgba8(out, scene::WIDTH, scene::HEIGHT, &run.rgba)?;
    println!(
        "wrote {}: {} frames, {} in flight, {} sample(s) on {}, {} validation message(s)",
        out.display(),
        options.frames,
        options.in_flight,
        options.samples,
        run.adapter,
        run.validation.len()
    );
    if !run.validation.is_empty() {
        return Err(format!("{} validation message(s)", run.validation.len()).into());
    }
    Ok(())
}

#[cfg(test)]
mod tests;
