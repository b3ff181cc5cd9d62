//! The JSON tree and its parser. serde_json parses, but into this tree rather than its
//! `Value`: key order is kept, a duplicate key is an error instead of silently keeping
//! the last one, and integers stay apart from numbers with a fraction or exponent.
use std::collections::HashSet;
use std::fmt;

use serde::de::{self, Deserialize, Deserializer, MapAccess, SeqAccess, Visitor};

use crate::error::quoted;
use crate::{Error, Result};

/// A parsed JSON document: key order kept, duplicate keys refused, integers kept apart
/// from numbers with a fraction or exponent (so `order: 4.0` can be refused).
#[derive(Clone, Debug, PartialEq)]
pub(super) enum Json {
    Null,
    Bool(bool),
    Integer(i128),
    Float(f64),
    String(String),
    Array(Vec<Json>),
    Object(Vec<(String, Json)>),
}

impl Json {
    /// What a value is, for "expected X, found Y" messages.
    pub(super) fn describe(&self) -> String {
        match self {
            Json::Null => "null".into(),
            Json::Bool(b) => format!("the boolean {b}"),
            Json::Integer(i) => format!("the number {i}"),
            Json::Float(x) => format!("the number {x:?}"),
            Json::String(s) => format!("the string \"{}\"", quoted(s)),
            Json::Array(items) => format!("a list of {} items", items.len()),
            Json::Object(_) => "an object".into(),
        }
    }

    pub(super) fn is_scalar(&self) -> bool {
        !matches!(self, Json::Array(_) | Json::Object(_))
    }
}

impl<'de> Deserialize<'de> for Json {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> std::result::Result<Self, D::Error> {
        deserializer.deserialize_any(JsonVisitor)
    }
}

struct JsonVisitor;

impl<'de> Visitor<'de> for JsonVisitor {
    type Value = Json;

    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("a JSON value")
    }

    fn visit_unit<E>(self) -> std::result::Result<Json, E> {
        Ok(Json::Null)
    }

    fn visit_bool<E>(self, value: bool) -> std::result::Result<Json, E> {
        Ok(Json::Bool(value))
    }

    fn visit_i64<E>(self, value: i64) -> std::result::Result<Json, E> {
        Ok(Json::Integer(value.into()))
    }

    fn visit_u64<E>(self, value: u64) -> std::result::Result<Json, E> {
        Ok(Json::Integer(value.into()))
    }

    fn visit_f64<E>(self, value: f64) -> std::result::Result<Json, E> {
        Ok(Json::Float(value))
    }

    fn visit_str<E>(self, value: &str) -> std::result::Result<Json, E> {
        Ok(Json::String(value.to_owned()))
    }

    fn visit_string<E>(self, value: String) -> std::result::Result<Json, E> {
        Ok(Json::String(value))
    }

    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> std::result::Result<Json, A::Error> {
        let mut items = Vec::new();
        while let Some(item) = seq.next_element()? {
            items.push(item);
        }
        // Glyph lists are most of a large scene: no spare capacity kept.
        items.shrink_to_fit();
        Ok(Json::Array(items))
    }

    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> std::result::Result<Json, A::Error> {
        let mut entries = Vec::new();
        let mut seen = HashSet::new();
        while let Some(key) = map.next_key::<String>()? {
            if !seen.insert(key.clone()) {
                return Err(de::Error::custom(format!(
                    "duplicate key \"{}\"",
                    quoted(&key)
                )));
            }
            let value = map.next_value()?;
            entries.push((key, value));
        }
        Ok(Json::Object(entries))
    }
}

/// Parses a document as it is read; None on any error (the caller reads the text and
/// parses it with [`parse_document`] for the message).
pub(super) fn parse_reader(reader: impl std::io::Read) -> Option<Json> {
    serde_json::from_reader(reader).ok()
}

/// Parses the text; a syntax error names its line and column as the field.
pub(super) fn parse_document(text: &str, file: &str) -> Result<Json> {
    serde_json::from_str(text).map_err(|err| {
        let (line, column) = (err.line(), err.column());
        let full = err.to_string();
        let suffix = format!(" at line {line} column {column}");
        let what = full.strip_suffix(&suffix).unwrap_or(&full);
        let message = match err.classify() {
            serde_json::error::Category::Syntax | serde_json::error::Category::Eof => {
                let hint = non_finite_hint(text, line, column).unwrap_or_default();
                let range = if what == "number out of range" {
                    " (every number must fit a 64-bit float, magnitude below about 1.8e308)"
                } else {
                    ""
                };
                format!("malformed JSON: {what}{hint}{range}")
            }
            _ => what.to_string(),
        };
        Error::input(file, format!("line {line}, column {column}"), message)
    })
}

/// serde_json reports `NaN` or `Infinity` only as "expected value"; say what is wrong.
fn non_finite_hint(text: &str, line: usize, column: usize) -> Option<String> {
    let source_line = text.lines().nth(line.checked_sub(1)?)?;
    let rest = source_line
        .get(column.checked_sub(1)?..)?
        .to_ascii_lowercase();
    let rest = rest.trim_start_matches(['-', '+']);
    let token = if rest.starts_with("nan") {
        "NaN"
    } else if rest.starts_with("inf") {
        "Infinity"
    } else {
        return None;
    };
    Some(format!(
        " ({token} is not a valid JSON number; every number must be finite)"
    ))
}
