//! `glyphcast stiffness`: a one-glyph scene file from a Voigt stiffness matrix (CSV or
//! JSON, see `glyphcast::glyph::stiffness`), to render with `glyphcast render`.
use clap::Args;
use glyphcast::demo::stiffness_scene;
use glyphcast::error::quoted;
use glyphcast::glyph::stiffness::{ShearOrder, VoigtStiffness};
use glyphcast::{Error, Result};
use std::path::PathBuf;

#[derive(Args)]
pub struct StiffnessArgs {
    /// 6 x 6 stiffness matrix in Voigt notation: CSV (6 lines of 6 numbers) or JSON.
    #[arg(value_name = "FILE")]
    input: PathBuf,
    /// Output scene file (JSON).
    #[arg(short = 'o', long = "output", value_name = "SCENE")]
    output: PathBuf,
    /// Voigt shear order of the file: 23,13,12 (standard) or 12,13,23.
    #[arg(long, value_name = "ORDER")]
    shear_order: Option<String>,
    /// Write the fully symmetric part (15 coefficients) instead of all 81 C_ijkl.
    #[arg(long)]
    symmetric_part: bool,
}

pub fn run(args: StiffnessArgs) -> Result<()> {
    let shear = match &args.shear_order {
        Some(text) => Some(ShearOrder::parse(text).ok_or_else(|| Error::Flag {
            flag: "--shear-order",
            message: format!("'{}': expected 23,13,12 or 12,13,23", quoted(text)).into(),
        })?),
        None => None,
    };
    glyphcast::io::atomic::check_outputs(&[&args.output], &[&args.input])?;
    glyphcast::io::atomic::check_ending(&args.output, "-o/--output", &[".json"])?;
    let stiffness = VoigtStiffness::load(&args.input, shear)?;
    let scene = stiffness_scene(&stiffness, args.symmetric_part)
        .map_err(|e| Error::input(args.input.display().to_string(), "voigt", e.to_string()))?;
    glyphcast::io::atomic::write_atomic(&args.output, scene.to_json().as_bytes())?;
    eprintln!("wrote {}", args.output.display());
    Ok(())
}
