//! Writing a [`Scene`]: the same JSON tree the reader walks, printed with one center or
//! coefficient list per line.
use std::fmt;

use super::json::Json;
use super::names::{KindName, Named, ProjectionName};
use super::npy_array::encode_f64;
use super::{FORMAT_VERSION, GlyphKind, GlyphSet, Scene};
use crate::camera::{Camera, Projection};
use crate::glyph::{GlyphShape, Symmetry};

/// The text of [`Scene::to_json`].
pub(super) fn to_json(scene: &Scene) -> String {
    let document = scene_json(scene, None);
    format!("{}\n", Pretty::new(&document))
}

/// The text of [`Scene::to_json_with_arrays`] and its array files (name, bytes).
pub(super) fn to_json_with_arrays(scene: &Scene, stem: &str) -> (String, Vec<(String, Vec<u8>)>) {
    let mut arrays = Vec::new();
    let document = scene_json(scene, Some((stem, &mut arrays)));
    (format!("{}\n", Pretty::new(&document)), arrays)
}

/// Where a set's arrays go when they are written beside the scene: the file names'
/// stem and the list of files written so far.
type ArrayFiles<'a> = Option<(&'a str, &'a mut Vec<(String, Vec<u8>)>)>;

fn object(entries: Vec<(&str, Json)>) -> Json {
    Json::Object(
        entries
            .into_iter()
            .map(|(k, v)| (k.to_string(), v))
            .collect(),
    )
}

fn name<T: Named>(value: T) -> Json {
    Json::String(value.name().to_string())
}

fn floats(values: &[f64]) -> Json {
    Json::Array(values.iter().map(|&x| Json::Float(x)).collect())
}

fn scene_json(scene: &Scene, mut arrays: ArrayFiles) -> Json {
    let sets = scene
        .glyph_sets
        .iter()
        .enumerate()
        .map(|(index, set)| {
            let files = arrays.as_mut().map(|(stem, files)| (*stem, &mut **files));
            glyph_set_json(set, index, files)
        })
        .collect();
    object(vec![
        ("version", Json::Integer(FORMAT_VERSION)),
        ("glyphs", Json::Array(sets)),
        ("camera", camera_json(&scene.camera)),
        (
            "image",
            object(vec![
                ("width", Json::Integer(scene.image.width.into())),
                ("height", Json::Integer(scene.image.height.into())),
            ]),
        ),
    ])
}

fn glyph_set_json(set: &GlyphSet, index: usize, arrays: ArrayFiles) -> Json {
    let mut entries = kind_entries(set.kind);
    entries.push(("negative", name(set.negative)));
    if set.shape != GlyphShape::default() {
        entries.push(("shape", name(set.shape)));
    }
    let n = set.centers.len();
    let one_scale = match set.scales.split_first() {
        Some((first, rest)) if rest.iter().all(|s| s == first) => Some(*first),
        _ => None,
    };
    let Some((stem, files)) = arrays else {
        let centers = set.centers.iter().map(|c| floats(&c.to_array())).collect();
        entries.push(("centers", Json::Array(centers)));
        match one_scale {
            Some(scale) => entries.push(("scale", Json::Float(scale))),
            None => entries.push(("scales", floats(&set.scales))),
        }
        let coeffs = set.coeffs.iter().map(|c| floats(c)).collect();
        entries.push(("coeffs", Json::Array(coeffs)));
        return object(entries);
    };
    let mut file = |field: &str, shape: &[usize], values: &mut dyn Iterator<Item = f64>| {
        let name = format!("{stem}.{index}.{field}.npy");
        files.push((name.clone(), encode_f64(shape, values)));
        Json::String(name)
    };
    let centers = file(
        "centers",
        &[n, 3],
        &mut set.centers.iter().flat_map(|c| c.to_array()),
    );
    entries.push(("centers", centers));
    match one_scale {
        Some(scale) => entries.push(("scale", Json::Float(scale))),
        None => {
            let scales = file("scales", &[n], &mut set.scales.iter().copied());
            entries.push(("scales", scales));
        }
    }
    let count = set.shape.coefficient_count(set.kind.coefficient_count());
    let coeffs = file(
        "coeffs",
        &[n, count],
        &mut set.coeffs.iter().flatten().copied(),
    );
    entries.push(("coeffs", coeffs));
    object(entries)
}

fn kind_entries(kind: GlyphKind) -> Vec<(&'static str, Json)> {
    match kind {
        GlyphKind::Tensor(layout) => vec![
            ("kind", name(KindName::Tensor)),
            ("order", Json::Integer(layout.order.into())),
            (
                "symmetric",
                Json::Bool(layout.symmetry == Symmetry::Symmetric),
            ),
        ],
        GlyphKind::Sh {
            band,
            basis,
            legacy,
        } => vec![
            ("kind", name(KindName::Sh)),
            ("order", Json::Integer(band.into())),
            ("basis", name(basis)),
            ("legacy", Json::Bool(legacy)),
        ],
    }
}

fn camera_json(camera: &Camera) -> Json {
    let (projection, parameter) = match camera.projection {
        Projection::Perspective { fov_y_deg } => (
            ProjectionName::Perspective,
            ("fov_y_deg", Json::Float(fov_y_deg)),
        ),
        Projection::Orthographic { height } => (
            ProjectionName::Orthographic,
            ("height", Json::Float(height)),
        ),
    };
    object(vec![
        ("projection", name(projection)),
        ("eye", floats(&camera.eye.to_array())),
        ("target", floats(&camera.target.to_array())),
        ("up", floats(&camera.up.to_array())),
        parameter,
    ])
}

/// Indented JSON with every list of plain values on one line, so a glyph's
/// coefficients read as one row.
struct Pretty<'j> {
    json: &'j Json,
    indent: usize,
}

impl<'j> Pretty<'j> {
    fn new(json: &'j Json) -> Self {
        Pretty { json, indent: 0 }
    }

    fn block<'c>(
        &self,
        f: &mut fmt::Formatter<'_>,
        (open, close): (char, char),
        children: impl ExactSizeIterator<Item = (Option<&'c str>, &'c Json)>,
    ) -> fmt::Result {
        if children.len() == 0 {
            return write!(f, "{open}{close}");
        }
        let inner = self.indent + 2;
        write!(f, "{open}")?;
        for (index, (key, json)) in children.enumerate() {
            let separator = if index == 0 { "" } else { "," };
            write!(f, "{separator}\n{:inner$}", "")?;
            if let Some(key) = key {
                write!(f, "{}: ", serde_json::Value::from(key))?;
            }
            write!(
                f,
                "{}",
                Pretty {
                    json,
                    indent: inner
                }
            )?;
        }
        write!(f, "\n{:indent$}{close}", "", indent = self.indent)
    }
}

impl fmt::Display for Pretty<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.json {
            Json::Array(items) if items.iter().all(Json::is_scalar) => {
                f.write_str("[")?;
                for (index, item) in items.iter().enumerate() {
                    let separator = if index == 0 { "" } else { ", " };
                    write!(f, "{separator}{}", Pretty::new(item))?;
                }
                f.write_str("]")
            }
            Json::Array(items) => self.block(f, ('[', ']'), items.iter().map(|item| (None, item))),
            Json::Object(entries) => self.block(
                f,
                ('{', '}'),
                entries.iter().map(|(key, json)| (Some(key.as_str()), json)),
            ),
            Json::Null => f.write_str("null"),
            Json::Bool(b) => write!(f, "{b}"),
            Json::Integer(i) => write!(f, "{i}"),
            // The shortest text that identifies the f64 (ryu). A non-finite value, only
            // possible in a scene built in code, becomes null and fails to load.
            Json::Float(x) => match serde_json::Number::from_f64(*x) {
                Some(number) => write!(f, "{number}"),
                None => f.write_str("null"),
            },
            Json::String(s) => write!(f, "{}", serde_json::Value::from(s.as_str())),
        }
    }
}
