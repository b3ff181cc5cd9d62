//! Voigt stiffness files, read into [`VoigtStiffness`] (the math lives in
//! `glyph::stiffness`).
//!
//! - CSV: 6 lines of 6 numbers separated by commas and/or whitespace; `#` starts a
//!   comment; blank lines are skipped.
//! - JSON: `{"voigt": [[6 numbers] x 6], "shear_order": "23,13,12", "units": "GPa"}`;
//!   the matrix may be named `C` instead of `voigt`; `shear_order`, `units` and the
//!   descriptive `material` and `source` are optional, and no other key is allowed (a
//!   misspelt key would otherwise be ignored); or the bare list `[[6 numbers] x 6]`.
//!
//! A file named `.json`, or whose first non-blank character is `{` or `[`, is JSON;
//! anything else CSV (so a JSON list is never misread as CSV lines).
use serde_json::Value;
use std::path::Path;

use crate::error::quoted;
use crate::glyph::stiffness::{ShearOrder, VoigtStiffness};
use crate::{Error, Result};

type Matrix = [[f64; 6]; 6];

/// A stiffness file's matrix and the units it states (JSON's `units`), if any.
pub struct StiffnessFile {
    /// The matrix, in the standard Voigt order.
    pub stiffness: VoigtStiffness,
    /// The units of the entries as the file states them (`GPa`), if it does.
    pub units: Option<String>,
}

impl VoigtStiffness {
    /// Reads a CSV or JSON Voigt file. The shear order is the file's `shear_order`, else
    /// `shear`, else standard; a file and a `shear` that disagree are an error.
    pub fn load(path: &Path, shear: Option<ShearOrder>) -> Result<Self> {
        Ok(StiffnessFile::load(path, shear)?.stiffness)
    }

    /// Same as [`VoigtStiffness::load`], from text; `file` is the name used in errors.
    pub fn from_text(text: &str, file: &str, shear: Option<ShearOrder>) -> Result<Self> {
        Ok(StiffnessFile::read(text, file, shear, false)?.stiffness)
    }
}

impl StiffnessFile {
    /// Reads a CSV or JSON Voigt file as [`VoigtStiffness::load`] does, with its units.
    pub fn load(path: &Path, shear: Option<ShearOrder>) -> Result<Self> {
        let text = std::fs::read_to_string(path).map_err(|err| Error::io(path, err))?;
        let named_json = path
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("json"));
        Self::read(&text, &path.display().to_string(), shear, named_json)
    }

    /// JSON when `named_json` or when the text opens with `{` or `[`, else CSV.
    fn read(text: &str, file: &str, shear: Option<ShearOrder>, named_json: bool) -> Result<Self> {
        let text = text.strip_prefix('\u{feff}').unwrap_or(text);
        let opening = text.trim_start().chars().next();
        let (matrix, written, units) = if named_json || matches!(opening, Some('{' | '[')) {
            read_json(text, file)?
        } else {
            (read_csv(text, file)?, None, None)
        };
        let order = match (written, shear) {
            (Some(a), Some(b)) if a != b => {
                return Err(Error::input(
                    file,
                    "shear_order",
                    format!("the file says {}, the command line {}", a.name(), b.name()),
                ));
            }
            (Some(order), _) | (None, Some(order)) => order,
            (None, None) => ShearOrder::Standard,
        };
        Ok(StiffnessFile {
            stiffness: VoigtStiffness::from_matrix(matrix, order, file)?,
            units,
        })
    }
}

fn read_csv(text: &str, file: &str) -> Result<Matrix> {
    let mut rows = Vec::new();
    for (index, line) in text.lines().enumerate() {
        let field = || format!("line {}", index + 1);
        let content = line.split('#').next().unwrap_or("");
        let row = content
            .split(|c: char| c.is_whitespace() || c == ',')
            .filter(|t| !t.is_empty())
            .map(|t| {
                t.parse::<f64>().map_err(|_| {
                    Error::input(file, field(), format!("'{}' is not a number", quoted(t)))
                })
            })
            .collect::<Result<Vec<f64>>>()?;
        if row.is_empty() {
            continue;
        }
        if row.len() != 6 {
            return Err(Error::input(
                file,
                field(),
                format!("{} numbers, expected 6 (a 6 x 6 Voigt matrix)", row.len()),
            ));
        }
        rows.push(row);
    }
    to_matrix(&rows).ok_or_else(|| {
        Error::input(
            file,
            "rows",
            format!(
                "{} rows of numbers, expected 6 (a 6 x 6 Voigt matrix)",
                rows.len()
            ),
        )
    })
}

/// The keys a JSON stiffness file may hold: the matrix (under one of two names), its
/// shear order, its units and two descriptive texts.
const JSON_KEYS: [&str; 6] = ["voigt", "C", "shear_order", "units", "material", "source"];

fn read_json(text: &str, file: &str) -> Result<(Matrix, Option<ShearOrder>, Option<String>)> {
    let value: Value =
        serde_json::from_str(text).map_err(|err| Error::input(file, "JSON", err.to_string()))?;
    let object = match value {
        Value::Object(object) => object,
        Value::Array(rows) => return Ok((voigt_rows(&Value::Array(rows), file)?, None, None)),
        _ => {
            return Err(Error::input(
                file,
                "JSON",
                "expected an object with \"voigt\" or a list of 6 rows of 6 numbers",
            ));
        }
    };
    if let Some(key) = object.keys().find(|k| !JSON_KEYS.contains(&k.as_str())) {
        return Err(Error::input(
            file,
            quoted(key),
            "unknown key (expected voigt or C, and optionally shear_order, units, material, \
             source)",
        ));
    }
    let text_of = |key: &str| match object.get(key) {
        None => Ok(None),
        Some(Value::String(text)) => Ok(Some(text.clone())),
        Some(other) => Err(Error::input(
            file,
            key,
            format!("{} is not a text", quoted(&other.to_string())),
        )),
    };
    let units = text_of("units")?;
    text_of("material")?;
    text_of("source")?;
    let shear = match object.get("shear_order") {
        None => None,
        Some(v) => Some(v.as_str().and_then(ShearOrder::parse).ok_or_else(|| {
            Error::input(
                file,
                "shear_order",
                format!(
                    "{}: expected \"23,13,12\" or \"12,13,23\"",
                    quoted(&v.to_string())
                ),
            )
        })?),
    };
    let voigt = match (object.get("voigt"), object.get("C")) {
        (Some(_), Some(_)) => {
            return Err(Error::input(
                file,
                "C",
                "the matrix is given twice (voigt and C)",
            ));
        }
        (Some(matrix), None) | (None, Some(matrix)) => matrix,
        (None, None) => return Err(Error::input(file, "voigt", "missing (or C)")),
    };
    Ok((voigt_rows(voigt, file)?, shear, units))
}

/// The 6 x 6 matrix of a JSON list of rows (the `voigt` value, or the whole file).
fn voigt_rows(voigt: &Value, file: &str) -> Result<Matrix> {
    let not_six = || Error::input(file, "voigt", "expected 6 rows of 6 numbers");
    let rows = voigt.as_array().ok_or_else(not_six)?;
    let rows = rows
        .iter()
        .enumerate()
        .map(|(p, row)| {
            let row = row
                .as_array()
                .filter(|r| r.len() == 6)
                .ok_or_else(not_six)?;
            row.iter()
                .enumerate()
                .map(|(q, v)| {
                    v.as_f64().ok_or_else(|| {
                        Error::input(
                            file,
                            format!("voigt[{p}][{q}]"),
                            format!("{} is not a number", quoted(&v.to_string())),
                        )
                    })
                })
                .collect::<Result<Vec<f64>>>()
        })
        .collect::<Result<Vec<_>>>()?;
    to_matrix(&rows).ok_or_else(not_six)
}

fn to_matrix(rows: &[Vec<f64>]) -> Option<Matrix> {
    if rows.len() != 6 || rows.iter().any(|r| r.len() != 6) {
        return None;
    }
    let mut matrix = [[0.0; 6]; 6];
    for (out, row) in matrix.iter_mut().zip(rows) {
        out.copy_from_slice(row);
    }
    Some(matrix)
}
