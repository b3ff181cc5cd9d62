//! Voigt stiffness files.
//!
//! - CSV: 6 lines of 6 numbers separated by commas and/or whitespace; `#` starts a
//!   comment; blank lines are skipped.
//! - JSON: `{"voigt": [[6 numbers] x 6], "shear_order": "23,13,12"}`; `shear_order` is
//!   optional, and no other key is allowed (a misspelt key would otherwise be ignored).
//!
//! A file whose first non-blank character is `{` is JSON, anything else CSV.
use serde_json::Value;
use std::path::Path;

use super::{ShearOrder, VoigtStiffness};
use crate::{Error, Result};

type Matrix = [[f64; 6]; 6];

impl VoigtStiffness {
    /// Reads a CSV or JSON Voigt file. The shear order is the file's `shear_order`, else
    /// `shear`, else standard; a file and a `shear` that disagree are an error.
    pub fn load(path: &Path, shear: Option<ShearOrder>) -> Result<Self> {
        let text = std::fs::read_to_string(path).map_err(|err| Error::io(path, err))?;
        Self::from_text(&text, &path.display().to_string(), shear)
    }

    /// Same as [`VoigtStiffness::load`], from text; `file` is the name used in errors.
    pub fn from_text(text: &str, file: &str, shear: Option<ShearOrder>) -> Result<Self> {
        let text = text.strip_prefix('\u{feff}').unwrap_or(text);
        let (matrix, written) = if text.trim_start().starts_with('{') {
            read_json(text, file)?
        } else {
            (read_csv(text, file)?, None)
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
        Self::from_matrix(matrix, order, file)
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
                t.parse::<f64>()
                    .map_err(|_| Error::input(file, field(), format!("'{t}' is not a number")))
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

fn read_json(text: &str, file: &str) -> Result<(Matrix, Option<ShearOrder>)> {
    let value: Value =
        serde_json::from_str(text).map_err(|err| Error::input(file, "JSON", err.to_string()))?;
    let Value::Object(object) = value else {
        return Err(Error::input(file, "JSON", "expected an object"));
    };
    if let Some(key) = object.keys().find(|k| *k != "voigt" && *k != "shear_order") {
        return Err(Error::input(
            file,
            key.as_str(),
            "unknown key (expected voigt and optionally shear_order)",
        ));
    }
    let shear = match object.get("shear_order") {
        None => None,
        Some(v) => Some(v.as_str().and_then(ShearOrder::parse).ok_or_else(|| {
            Error::input(
                file,
                "shear_order",
                format!("{v}: expected \"23,13,12\" or \"12,13,23\""),
            )
        })?),
    };
    let not_six = || Error::input(file, "voigt", "expected 6 rows of 6 numbers");
    let rows = object
        .get("voigt")
        .ok_or_else(|| Error::input(file, "voigt", "missing"))?
        .as_array()
        .ok_or_else(not_six)?;
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
                            format!("{v} is not a number"),
                        )
                    })
                })
                .collect::<Result<Vec<f64>>>()
        })
        .collect::<Result<Vec<_>>>()?;
    Ok((to_matrix(&rows).ok_or_else(not_six)?, shear))
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
