//! Reading a 6x6 stiffness matrix from the text forms users have.
//!
//! - Whitespace-separated, as ELATE takes it: 6 lines of 6 numbers.
//! - CSV: 6 lines of 6 comma-separated numbers (chosen when any line has a comma). A
//!   header line is refused like any other non-number: write it as a `#` comment.
//! - JSON (text starting with `[` or `{`): a 6x6 array of arrays of numbers, or an
//!   object `{"C": [[...], ...], "units": "GPa"}`; `units` is optional, other keys
//!   (a source, a note) are ignored.
//!
//! In the first two forms blank lines and everything after a `#` are ignored. Anything
//! that is not exactly 6 rows of 6 finite numbers is refused with the row and column
//! (and the text line) at fault. Symmetry and stability are checked later, by
//! [`Stiffness::new`](crate::Stiffness::new).

use serde_json::Value;

use crate::error::{Error, ParseError};
use crate::voigt::Voigt;

/// A parsed matrix with the units the text declared, if any.
#[derive(Debug, Clone, PartialEq)]
pub struct ParsedMatrix {
    /// The 6x6 Voigt matrix as written.
    pub c: Voigt,
    /// The `units` field of a JSON object (e.g. `"GPa"`); `None` for the other forms.
    pub units: Option<String>,
}

/// Reads a 6x6 matrix from whitespace-separated text, CSV or JSON (see the module notes).
pub fn parse_matrix(text: &str) -> Result<Voigt, Error> {
    parse_matrix_with_units(text).map(|parsed| parsed.c)
}

/// As [`parse_matrix`], also returning the units a JSON object declares.
pub fn parse_matrix_with_units(text: &str) -> Result<ParsedMatrix, Error> {
    let trimmed = text.trim_start();
    if trimmed.starts_with('[') || trimmed.starts_with('{') {
        parse_json(trimmed).map_err(Error::from)
    } else {
        let c = parse_rows(text)?;
        Ok(ParsedMatrix { c, units: None })
    }
}

/// One numeric row of the text: its 1-based line number and its fields.
struct Row<'a> {
    line: usize,
    fields: Vec<&'a str>,
}

/// Reads the whitespace-separated or CSV form.
fn parse_rows(text: &str) -> Result<Voigt, ParseError> {
    let rows = content_rows(text);
    let mut c = [[0.0; 6]; 6];
    for (index, row) in rows.iter().enumerate() {
        if row.fields.len() != 6 {
            return Err(ParseError::WrongColumnCount {
                row: index + 1,
                line: row.line,
                found: row.fields.len(),
            });
        }
        for (column, field) in row.fields.iter().enumerate() {
            let value = parse_number(field).ok_or_else(|| ParseError::NotANumber {
                row: index + 1,
                column: column + 1,
                line: row.line,
                found: field.to_string(),
            })?;
            if let Some(slot) = c.get_mut(index) {
                slot[column] = value;
            }
        }
    }
    if rows.len() != 6 {
        return Err(ParseError::WrongRowCount { found: rows.len() });
    }
    Ok(c)
}

/// The non-blank lines with comments removed, split on commas if any line has one
/// and on whitespace otherwise.
fn content_rows(text: &str) -> Vec<Row<'_>> {
    let lines: Vec<(usize, &str)> = text
        .lines()
        .enumerate()
        .map(|(i, line)| (i + 1, line.split('#').next().unwrap_or("").trim()))
        .filter(|(_, line)| !line.is_empty())
        .collect();
    let csv = lines.iter().any(|(_, line)| line.contains(','));
    lines
        .into_iter()
        .map(|(line, content)| Row {
            line,
            fields: if csv {
                content.split(',').map(str::trim).collect()
            } else {
                content.split_whitespace().collect()
            },
        })
        .collect()
}

/// A finite number, or `None` (Rust's parser takes "inf" and "NaN": refused here).
fn parse_number(field: &str) -> Option<f64> {
    field.parse::<f64>().ok().filter(|x| x.is_finite())
}

/// Reads the JSON form.
fn parse_json(text: &str) -> Result<ParsedMatrix, ParseError> {
    let value: Value = serde_json::from_str(text).map_err(|error| ParseError::Json {
        message: error.to_string(),
    })?;
    match value {
        Value::Array(rows) => Ok(ParsedMatrix {
            c: json_matrix(&rows)?,
            units: None,
        }),
        Value::Object(object) => {
            let rows = match object.get("C") {
                Some(Value::Array(rows)) => rows,
                Some(_) => return Err(shape("\"C\" must be an array of 6 rows")),
                None => return Err(shape("the object has no \"C\" key with the matrix")),
            };
            let units = match object.get("units") {
                None => None,
                Some(Value::String(units)) => Some(units.clone()),
                Some(_) => return Err(shape("\"units\" must be a string")),
            };
            Ok(ParsedMatrix {
                c: json_matrix(rows)?,
                units,
            })
        }
        _ => Err(shape(
            "expected a 6x6 array of arrays or an object {\"C\": [[...]], \"units\": ...}",
        )),
    }
}

/// A [`ParseError::JsonShape`] with `message`.
fn shape(message: &str) -> ParseError {
    ParseError::JsonShape {
        message: message.to_string(),
    }
}

/// The 6x6 matrix of a JSON array of rows.
fn json_matrix(rows: &[Value]) -> Result<Voigt, ParseError> {
    if rows.len() != 6 {
        return Err(ParseError::WrongRowCount { found: rows.len() });
    }
    let mut c = [[0.0; 6]; 6];
    for (i, row) in rows.iter().enumerate() {
        let Value::Array(entries) = row else {
            return Err(ParseError::JsonShape {
                message: format!("row {} is not an array", i + 1),
            });
        };
        if entries.len() != 6 {
            return Err(ParseError::WrongColumnCount {
                row: i + 1,
                line: 0,
                found: entries.len(),
            });
        }
        for (j, entry) in entries.iter().enumerate() {
            c[i][j] =
                entry
                    .as_f64()
                    .filter(|x| x.is_finite())
                    .ok_or_else(|| ParseError::NotANumber {
                        row: i + 1,
                        column: j + 1,
                        line: 0,
                        found: entry.to_string(),
                    })?;
        }
    }
    Ok(c)
}

#[cfg(test)]
mod tests {
    use super::*;

    const ROWS: [&str; 6] = [
        "1 2 3 4 5 6",
        "2 7 8 9 10 11",
        "3 8 12 13 14 15",
        "4 9 13 16 17 18",
        "5 10 14 17 19 20",
        "6 11 15 18 20 21",
    ];

    /// The matrix the rows above hold, built independently of any parsing.
    fn expected() -> Voigt {
        // Entry (a, b), a ≤ b, is its 1-based place in the row-major upper triangle.
        std::array::from_fn(|i| {
            std::array::from_fn(|j| {
                let (a, b) = (i.min(j), i.max(j));
                (a * 6 - a * a.saturating_sub(1) / 2 + (b - a) + 1) as f64
            })
        })
    }

    #[test]
    fn whitespace_form_with_comments_and_blanks() {
        let text = format!("# copper\n\n{}\n  # end\n", ROWS.join("   # row\n\t"));
        assert_eq!(parse_matrix(&text).unwrap(), expected());
    }

    #[test]
    fn csv_form() {
        let text = ROWS
            .map(|row| row.split(' ').collect::<Vec<_>>().join(", "))
            .join("\n");
        assert_eq!(
            parse_matrix(&format!("# C11,C12...\n{text}\n")).unwrap(),
            expected()
        );
    }

    #[test]
    fn json_forms() {
        let array = serde_json::to_string(&expected()).unwrap();
        assert_eq!(parse_matrix(&array).unwrap(), expected());
        let object = format!("{{\"source\": \"x\", \"units\": \"GPa\", \"C\": {array}}}");
        let parsed = parse_matrix_with_units(&object).unwrap();
        assert_eq!(parsed.c, expected());
        assert_eq!(parsed.units.as_deref(), Some("GPa"));
    }

    #[test]
    fn errors_name_row_column_and_line() {
        let mut rows = ROWS.map(String::from);
        rows[2] = "3 8 12 x 14 15".into();
        assert_eq!(
            parse_matrix(&format!("# header\n{}", rows.join("\n"))),
            Err(Error::Parse(ParseError::NotANumber {
                row: 3,
                column: 4,
                line: 4,
                found: "x".into()
            }))
        );
        let mut rows = ROWS.map(String::from);
        rows[4] = "5 10 14 17 19".into();
        assert_eq!(
            parse_matrix(&rows.join("\n")),
            Err(Error::Parse(ParseError::WrongColumnCount {
                row: 5,
                line: 5,
                found: 5
            }))
        );
        assert_eq!(
            parse_matrix(&ROWS[..5].join("\n")),
            Err(Error::Parse(ParseError::WrongRowCount { found: 5 }))
        );
        // A CSV header of names is refused at row 1, column 1.
        let csv = format!("C1,C2,C3,C4,C5,C6\n{}", ROWS.join("\n").replace(' ', ","));
        let error = parse_matrix(&csv).unwrap_err();
        assert!(error.to_string().contains("row 1, column 1"), "{error}");
        // inf and NaN parse as f64 in Rust but are refused.
        let mut rows = ROWS.map(String::from);
        rows[0] = "1 2 3 4 5 inf".into();
        assert!(matches!(
            parse_matrix(&rows.join("\n")),
            Err(Error::Parse(ParseError::NotANumber {
                row: 1,
                column: 6,
                ..
            }))
        ));
        // A trailing comma is an empty seventh field.
        let mut rows = ROWS.map(|row| row.replace(' ', ","));
        rows[1].push(',');
        assert!(matches!(
            parse_matrix(&rows.join("\n")),
            Err(Error::Parse(ParseError::WrongColumnCount {
                row: 2,
                found: 7,
                ..
            }))
        ));
    }

    #[test]
    fn json_errors() {
        let mut c = serde_json::to_value(expected()).unwrap();
        c[3][2] = Value::String("12".into());
        assert_eq!(
            parse_matrix(&c.to_string()),
            Err(Error::Parse(ParseError::NotANumber {
                row: 4,
                column: 3,
                line: 0,
                found: "\"12\"".into()
            }))
        );
        assert!(matches!(
            parse_matrix("{\"units\": \"GPa\"}"),
            Err(Error::Parse(ParseError::JsonShape { .. }))
        ));
        assert!(matches!(
            parse_matrix("[[1, 2], "),
            Err(Error::Parse(ParseError::Json { .. }))
        ));
        assert!(matches!(
            parse_matrix("[[1,2,3,4,5,6]]"),
            Err(Error::Parse(ParseError::WrongRowCount { found: 1 }))
        ));
        let units = format!(
            "{{\"C\": {}, \"units\": 1}}",
            serde_json::to_string(&expected()).unwrap()
        );
        assert!(
            parse_matrix(&units)
                .unwrap_err()
                .to_string()
                .contains("units")
        );
    }
}
