//! Walking the JSON tree with paths. Every value on the walk is a [`Field`] that knows
//! its file and `JsonPath`, so each error names the exact field (`glyphs[0].coeffs[3]`).
//! A path is a chain of borrowed stack frames, rendered only when an error is reported.
use std::fmt;

use glam::DVec3;

use super::json::Json;
use super::names::Named;
use crate::error::quoted;
use crate::scene::fits_float32;
use crate::{Error, Result};

/// One step from a value to a child: a key of an object or an index into a list.
#[derive(Clone, Copy, Debug)]
enum Step<'p> {
    Key(&'p str),
    Index(usize),
}

/// Where a value sits in the document, as borrowed links to its parent.
#[derive(Clone, Copy, Debug)]
struct JsonPath<'p> {
    up: Option<(&'p JsonPath<'p>, Step<'p>)>,
}

impl fmt::Display for JsonPath<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let Some((parent, step)) = self.up else {
            return f.write_str("(top level)");
        };
        let under_root = parent.up.is_none();
        if !under_root {
            write!(f, "{parent}")?;
        }
        match step {
            Step::Key(key) if under_root => f.write_str(&quoted(key)),
            Step::Key(key) => write!(f, ".{}", quoted(key)),
            Step::Index(index) => write!(f, "[{index}]"),
        }
    }
}

/// A value of the document, with the file and path to name in errors.
#[derive(Clone, Copy, Debug)]
pub(super) struct Field<'a> {
    file: &'a str,
    path: JsonPath<'a>,
    value: &'a Json,
}

impl<'a> Field<'a> {
    pub(super) fn root(file: &'a str, value: &'a Json) -> Self {
        Field {
            file,
            path: JsonPath { up: None },
            value,
        }
    }

    fn child<'b>(&'b self, step: Step<'b>, value: &'b Json) -> Field<'b> {
        Field {
            file: self.file,
            path: JsonPath {
                up: Some((&self.path, step)),
            },
            value,
        }
    }

    pub(super) fn error(&self, message: impl Into<String>) -> Error {
        Error::input(self.file, self.path.to_string(), message.into())
    }

    fn mismatch(&self, expected: &str) -> Error {
        self.error(format!(
            "expected {expected}, found {}",
            self.value.describe()
        ))
    }

    pub(super) fn object(&self) -> Result<Object<'_>> {
        match self.value {
            Json::Object(entries) => Ok(Object {
                field: self,
                entries,
            }),
            _ => Err(self.mismatch("an object")),
        }
    }

    pub(super) fn list(&self) -> Result<&'a [Json]> {
        match self.value {
            Json::Array(items) => Ok(items),
            _ => Err(self.mismatch("a list")),
        }
    }

    pub(super) fn items(&self) -> Result<impl Iterator<Item = Field<'_>>> {
        let items = self.list()?;
        Ok(items
            .iter()
            .enumerate()
            .map(move |(index, item)| self.child(Step::Index(index), item)))
    }

    /// A finite number within float32's range (the GPU draws in float32:
    /// [`crate::scene::MAX_SCENE_MAGNITUDE`]); JSON integers are numbers too.
    pub(super) fn number(&self) -> Result<f64> {
        let value = match self.value {
            Json::Integer(i) => *i as f64,
            Json::Float(x) => *x,
            _ => return Err(self.mismatch("a number")),
        };
        if !value.is_finite() {
            Err(self.error(format!("expected a finite number, found {value:?}")))
        } else if !fits_float32(value) {
            Err(self.error(beyond_float32(value)))
        } else {
            Ok(value)
        }
    }

    pub(super) fn positive(&self) -> Result<f64> {
        let value = self.number()?;
        if value > 0.0 {
            Ok(value)
        } else {
            Err(self.error(format!("must be positive, found {value:?}")))
        }
    }

    pub(super) fn integer(&self) -> Result<i128> {
        match self.value {
            Json::Integer(i) => Ok(*i),
            _ => Err(self.mismatch("an integer")),
        }
    }

    pub(super) fn boolean(&self) -> Result<bool> {
        match self.value {
            Json::Bool(b) => Ok(*b),
            _ => Err(self.mismatch("true or false")),
        }
    }

    /// One of the format's names for `T`.
    pub(super) fn choice<T: Named>(&self) -> Result<T> {
        let Json::String(name) = self.value else {
            return Err(self.mismatch(&format!("one of {}", quoted_names::<T>())));
        };
        T::ALL
            .iter()
            .copied()
            .find(|value| value.name() == name)
            .ok_or_else(|| {
                self.error(format!(
                    "unknown value \"{}\"; expected one of {}",
                    quoted(name),
                    quoted_names::<T>()
                ))
            })
    }

    /// The text of a string value, or `None` for any other value.
    pub(super) fn text(&self) -> Option<&'a str> {
        match self.value {
            Json::String(text) => Some(text),
            _ => None,
        }
    }

    /// The name of the file being read, as errors show it.
    pub(super) fn file(&self) -> &'a str {
        self.file
    }

    /// A point or direction: a list of three finite numbers.
    pub(super) fn vec3(&self) -> Result<DVec3> {
        let xyz = self
            .items()?
            .map(|c| c.number())
            .collect::<Result<Vec<_>>>()?;
        match xyz[..] {
            [x, y, z] => Ok(DVec3::new(x, y, z)),
            _ => Err(self.error(format!(
                "expected [x, y, z] (3 numbers), found {} items",
                xyz.len()
            ))),
        }
    }

    /// A list of exactly `count` finite numbers; `what` describes them for the message.
    pub(super) fn numbers(&self, count: usize, what: &str) -> Result<Vec<f64>> {
        let found = self.list()?.len();
        if found != count {
            return Err(self.error(format!("expected {count} {what}, found {found}")));
        }
        self.items()?.map(|item| item.number()).collect()
    }
}

/// Why a finite value beyond float32's range is refused.
pub(super) fn beyond_float32(value: f64) -> String {
    format!(
        "{value:?} is beyond float32's range (magnitude at most {:e}), \
         in which the GPU draws",
        f32::MAX
    )
}

fn quoted_names<T: Named>() -> String {
    let names: Vec<String> = T::ALL.iter().map(|v| format!("\"{}\"", v.name())).collect();
    names.join(", ")
}

/// A JSON object being read, with the path of the object for errors about its keys.
pub(super) struct Object<'b> {
    field: &'b Field<'b>,
    entries: &'b [(String, Json)],
}

impl<'b> Object<'b> {
    pub(super) fn get(&self, key: &str) -> Option<Field<'b>> {
        let (key, value) = self.entries.iter().find(|(k, _)| k == key)?;
        Some(self.field.child(Step::Key(key), value))
    }

    /// An error about `key` of this object, present or not.
    pub(super) fn error_at(&self, key: &str, message: impl Into<String>) -> Error {
        self.field.child(Step::Key(key), &Json::Null).error(message)
    }

    pub(super) fn require(&self, key: &str) -> Result<Field<'b>> {
        self.get(key)
            .ok_or_else(|| self.error_at(key, "missing required field"))
    }

    /// Reads `key` with `read` when it is present.
    pub(super) fn optional<T>(
        &self,
        key: &str,
        read: impl FnOnce(&Field<'b>) -> Result<T>,
    ) -> Result<Option<T>> {
        self.get(key).map(|field| read(&field)).transpose()
    }

    /// A key that does not apply here (`symmetric` on SH, `basis` on tensors).
    pub(super) fn forbid(&self, key: &str, reason: &str) -> Result<()> {
        match self.get(key) {
            Some(_) => Err(self.error_at(key, format!("`{key}` {reason}"))),
            None => Ok(()),
        }
    }

    /// Typos must not be ignored: any key outside `allowed` is an error.
    pub(super) fn deny_unknown(&self, allowed: &[&str]) -> Result<()> {
        match self
            .entries
            .iter()
            .find(|(k, _)| !allowed.contains(&k.as_str()))
        {
            Some((key, _)) => Err(self.error_at(
                key,
                format!(
                    "unknown key \"{}\"; expected one of: {}",
                    quoted(key),
                    allowed.join(", ")
                ),
            )),
            None => Ok(()),
        }
    }
}
