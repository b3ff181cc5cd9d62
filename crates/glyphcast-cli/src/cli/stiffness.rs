//! `glyphcast stiffness`: scene files and the elastic numbers of Voigt stiffness
//! matrices (CSV, whitespace-separated text as ELATE takes it, or JSON; see
//! `glyphcast::io::stiffness`). The scene draws each material's Reynolds glyph, to render
//! with `glyphcast render`; `--summary` writes the extremes and averages that
//! `glyphcast_materials` computes (docs/guide/materials.md).
use clap::Args;
use glyphcast::demo::{RowGlyph, material_row_scene, stiffness_row_scene};
use glyphcast::error::quoted;
use glyphcast::glyph::stiffness::{ShearOrder, VoigtStiffness};
use glyphcast::io::stiffness::StiffnessFile;
use glyphcast::{Error, Result};
use glyphcast_materials::{Options, Rotation, Stiffness, Summary, Surface};
use std::path::{Path, PathBuf};

#[derive(Args)]
pub struct StiffnessArgs {
    /// 6 x 6 stiffness matrices in Voigt notation: CSV, whitespace-separated text (6
    /// lines of 6 numbers) or JSON. Several draw a row of glyphs on one scale.
    #[arg(value_name = "FILE", required = true, num_args = 1..)]
    inputs: Vec<PathBuf>,
    /// Output scene file (JSON): one glyph a material, in a row along x.
    #[arg(
        short = 'o',
        long = "output",
        value_name = "SCENE",
        required_unless_present = "summary"
    )]
    output: Option<PathBuf>,
    /// Write the elastic extremes and averages (JSON, the input's units) and print them
    /// as a table: Young's modulus with the directions of its extremes, linear
    /// compressibility, shear modulus, Poisson's ratio, Voigt/Reuss/Hill averages.
    #[arg(long, value_name = "FILE.json")]
    summary: Option<PathBuf>,
    /// The crystal's orientation as Bunge Euler angles in degrees (ZXZ, as MTEX and EBSD
    /// write them): g = Rz(phi2) Rx(Phi) Rz(phi1) maps sample to crystal coordinates;
    /// the glyphs and numbers are the sample frame's.
    #[arg(
        long,
        value_name = "PHI1,PHI,PHI2",
        conflicts_with = "rotation",
        value_parser = parse_euler,
        allow_hyphen_values = true
    )]
    euler: Option<EulerAngles>,
    /// The crystal's orientation as a 3 x 3 matrix g (3 lines of 3 numbers) with the
    /// meaning of --euler's: sample to crystal coordinates.
    #[arg(long, value_name = "R.csv")]
    rotation: Option<PathBuf>,
    /// Draw and summarise a matrix that is not positive definite (a mechanically
    /// unstable crystal, or a mistyped one), which is otherwise refused.
    #[arg(long)]
    allow_unstable: bool,
    /// Voigt shear order of the files: 23,13,12 (standard) or 12,13,23.
    #[arg(long, value_name = "ORDER")]
    shear_order: Option<String>,
    /// Write the fully symmetric part (15 coefficients) instead of all 81 C_ijkl
    /// (the Reynolds glyph: not with --surface).
    #[arg(long, conflicts_with = "surface")]
    symmetric_part: bool,
    /// The surface the scene draws, its radius in the input's units: reynolds
    /// (C_ijkl u_i u_j u_k u_l), young (Young's modulus E(u)) or compressibility (linear
    /// compressibility beta(u), in inverse units; negative where the crystal expands
    /// under pressure: render with --color sign), shear-min or shear-max (the smallest
    /// or largest shear modulus G(u, v) over the shear directions v ⊥ u), poisson-min or
    /// poisson-max (the smallest or largest Poisson's ratio nu(u, v) over the transverse
    /// directions v ⊥ u, dimensionless; negative ratios in --color sign). Default:
    /// reynolds.
    #[arg(long, value_name = "SURFACE", value_parser = parse_surface)]
    surface: Option<DrawnSurface>,
}

/// What `--surface` draws: the Reynolds glyph of C, or a surface of the materials crate.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum DrawnSurface {
    Reynolds,
    Modulus(Surface),
}

/// `--surface NAME`.
fn parse_surface(text: &str) -> std::result::Result<DrawnSurface, String> {
    match text {
        "reynolds" => Ok(DrawnSurface::Reynolds),
        _ => match Surface::from_name(text) {
            Some(surface) => Ok(DrawnSurface::Modulus(surface)),
            None => Err(
                "expected reynolds, young, compressibility, shear-min, shear-max, \
                         poisson-min or poisson-max"
                    .into(),
            ),
        },
    }
}

/// Bunge Euler angles in degrees (phi1, Phi, phi2), finite.
#[derive(Clone, Copy, Debug)]
pub struct EulerAngles([f64; 3]);

/// `--euler PHI1,PHI,PHI2`: three finite numbers, degrees.
fn parse_euler(text: &str) -> std::result::Result<EulerAngles, String> {
    let angles: Vec<Option<f64>> = text
        .split(',')
        .map(|v| v.trim().parse::<f64>().ok().filter(|a| a.is_finite()))
        .collect();
    match angles[..] {
        [Some(phi1), Some(phi), Some(phi2)] => Ok(EulerAngles([phi1, phi, phi2])),
        _ => Err("expected PHI1,PHI,PHI2: three finite angles in degrees".into()),
    }
}

/// One material: its file, its checked matrix (in the sample frame) and its units.
struct Material {
    file: String,
    stiffness: Stiffness,
    units: Option<String>,
}

pub fn run(args: StiffnessArgs) -> Result<()> {
    let shear = match &args.shear_order {
        Some(text) => Some(ShearOrder::parse(text).ok_or_else(|| Error::Flag {
            flag: "--shear-order",
            message: format!("'{}': expected 23,13,12 or 12,13,23", quoted(text)).into(),
        })?),
        None => None,
    };
    let outputs: Vec<&Path> = args
        .output
        .iter()
        .chain(&args.summary)
        .map(|p| p.as_path())
        .collect();
    let mut inputs: Vec<&Path> = args.inputs.iter().map(|p| p.as_path()).collect();
    inputs.extend(args.rotation.as_deref());
    glyphcast::io::atomic::check_outputs(&outputs, &inputs)?;
    if let Some(output) = &args.output {
        glyphcast::io::atomic::check_ending(output, "-o/--output", &[".json"])?;
    }
    if let Some(summary) = &args.summary {
        glyphcast::io::atomic::check_ending(summary, "--summary", &[".json"])?;
    }
    let rotation = orientation(&args)?;
    let materials = args
        .inputs
        .iter()
        .map(|path| material(path, shear, rotation.as_ref(), args.allow_unstable))
        .collect::<Result<Vec<_>>>()?;
    let summaries: Vec<Summary> = materials.iter().map(|m| m.stiffness.summary()).collect();
    let surface = args.surface.unwrap_or(DrawnSurface::Reynolds);
    let scene = match (&args.output, surface) {
        (None, _) => None,
        (Some(_), DrawnSurface::Reynolds) => {
            let drawn = materials
                .iter()
                .map(|m| {
                    VoigtStiffness::from_matrix(*m.stiffness.voigt(), ShearOrder::Standard, &m.file)
                })
                .collect::<Result<Vec<_>>>()?;
            Some(stiffness_row_scene(&drawn, args.symmetric_part)?)
        }
        (Some(_), DrawnSurface::Modulus(surface)) => {
            let glyphs = materials
                .iter()
                .map(|m| surface_glyph(m, surface))
                .collect::<Result<Vec<_>>>()?;
            Some(material_row_scene(&glyphs)?)
        }
    };
    for (material, summary) in materials.iter().zip(&summaries) {
        println!("{}", material.file);
        print!(
            "{}",
            summary.to_table(material.units.as_deref().unwrap_or("input units"))
        );
    }
    if let Some(path) = &args.summary {
        let json = summary_json(&materials, &summaries);
        glyphcast::io::atomic::write_atomic(path, json.as_bytes())?;
        eprintln!("wrote {}", path.display());
    }
    if let (Some(path), Some(scene)) = (&args.output, scene) {
        glyphcast::io::atomic::write_atomic(path, scene.to_json().as_bytes())?;
        eprintln!("wrote {}", path.display());
    }
    Ok(())
}

/// One material's glyph of `surface`; an error naming the file where the surface is
/// unbounded (Young's modulus of an unstable crystal whose 1/E vanishes somewhere).
fn surface_glyph(material: &Material, surface: Surface) -> Result<RowGlyph> {
    let refused = |message: String| Error::input(&material.file, "voigt", message);
    let largest = material.stiffness.largest_radius(surface);
    if let Some(f) = material.stiffness.ratio_forms(surface) {
        let forms = [&f.determinant[..], &f.trace, &f.denominator];
        return RowGlyph::of_ratio(forms, f.smaller_root, largest).map_err(|e| {
            refused(format!(
                "{}'s surface: {e} (a mechanically unstable crystal)",
                surface.name()
            ))
        });
    }
    if let Some(forms) = material.stiffness.plane_forms(surface) {
        return RowGlyph::of_plane(&forms.determinant, &forms.trace, forms.larger_root, largest)
            .map_err(|e| {
                refused(format!(
                    "{}'s surface: {e} (a mechanically unstable crystal)",
                    surface.name()
                ))
            });
    }
    let form = material
        .stiffness
        .surface_form(surface)
        .ok_or_else(|| refused(format!("{} is not drawn as a surface", surface.name())))?;
    RowGlyph::of_form(form.order, &form.tensor, form.reciprocal, largest).map_err(|e| {
        refused(format!(
            "{}'s surface: {e} (a mechanically unstable crystal)",
            surface.name()
        ))
    })
}

/// The summary file: the object of the one material, or a list of them (each with its
/// `file`) for several; `units` where the file states them.
fn summary_json(materials: &[Material], summaries: &[Summary]) -> String {
    let entries: Vec<serde_json::Value> = materials
        .iter()
        .zip(summaries)
        .map(|(material, summary)| {
            let mut value = serde_json::to_value(summary).unwrap_or_default();
            if let Some(object) = value.as_object_mut() {
                if let Some(units) = &material.units {
                    object.insert("units".into(), units.clone().into());
                }
                if materials.len() > 1 {
                    object.insert("file".into(), material.file.clone().into());
                }
            }
            value
        })
        .collect();
    let value = match <[_; 1]>::try_from(entries) {
        Ok([one]) => one,
        Err(all) => serde_json::Value::Array(all),
    };
    let mut text = serde_json::to_string_pretty(&value).unwrap_or_default();
    text.push('\n');
    text
}

/// One file's matrix, checked for stability and turned into the sample frame.
fn material(
    path: &Path,
    shear: Option<ShearOrder>,
    rotation: Option<&Rotation>,
    allow_unstable: bool,
) -> Result<Material> {
    let file = path.display().to_string();
    let read = StiffnessFile::load(path, shear)?;
    let crystal = read.stiffness.in_order(ShearOrder::Standard);
    let options = Options { allow_unstable };
    let stiffness = Stiffness::with_options(crystal, options).map_err(|e| refused(&file, e))?;
    let stiffness = match rotation {
        Some(g) => stiffness.rotated(g),
        None => stiffness,
    };
    Ok(Material {
        file,
        stiffness,
        units: read.units,
    })
}

/// A matrix the materials' code refuses, as an error naming the file.
fn refused(file: &str, error: glyphcast_materials::Error) -> Error {
    use glyphcast_materials::Error as E;
    match error {
        E::Unstable {
            smallest_eigenvalue,
        } => Error::input(
            file,
            "voigt",
            format!(
                "not positive definite (smallest eigenvalue {smallest_eigenvalue:.6e}): a \
                 mechanically unstable crystal, or a mistyped matrix; --allow-unstable draws \
                 it anyway"
            ),
        ),
        other => Error::input(file, "voigt", other.to_string()),
    }
}

/// The rotation of `--euler` or `--rotation`, if either is given.
fn orientation(args: &StiffnessArgs) -> Result<Option<Rotation>> {
    if let Some(EulerAngles([phi1, phi, phi2])) = args.euler {
        // Finite angles (parse_euler) always make a rotation.
        let rotation = Rotation::from_bunge_degrees(phi1, phi, phi2)
            .map_err(|e| Error::input("--euler", "angles", e.to_string()))?;
        return Ok(Some(rotation));
    }
    let Some(path) = &args.rotation else {
        return Ok(None);
    };
    let file = path.display().to_string();
    let text = std::fs::read_to_string(path).map_err(|e| Error::io(path, e))?;
    let mut rows = Vec::new();
    for (index, line) in text.lines().enumerate() {
        let content = line.split('#').next().unwrap_or("");
        let row = content
            .split(|c: char| c.is_whitespace() || c == ',')
            .filter(|t| !t.is_empty())
            .map(|t| {
                t.parse::<f64>()
                    .ok()
                    .filter(|v| v.is_finite())
                    .ok_or_else(|| {
                        Error::input(
                            &file,
                            format!("line {}", index + 1),
                            format!("'{}' is not a finite number", quoted(t)),
                        )
                    })
            })
            .collect::<Result<Vec<f64>>>()?;
        match row.len() {
            0 => continue,
            3 => rows.push([row[0], row[1], row[2]]),
            n => {
                return Err(Error::input(
                    &file,
                    format!("line {}", index + 1),
                    format!("{n} numbers, expected 3 (a 3 x 3 rotation)"),
                ));
            }
        }
    }
    let g: [[f64; 3]; 3] = rows.try_into().map_err(|rows: Vec<_>| {
        Error::input(
            &file,
            "rows",
            format!(
                "{} rows of numbers, expected 3 (a 3 x 3 rotation)",
                rows.len()
            ),
        )
    })?;
    Rotation::from_matrix(g)
        .map(Some)
        .map_err(|e| Error::input(&file, "rotation", e.to_string()))
}
