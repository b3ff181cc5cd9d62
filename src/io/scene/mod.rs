//! Scene files (docs/scene-format.md, version 1): reading with full validation, and
//! writing. The scene itself ([`Scene`], [`GlyphSet`], ...) is the domain model of
//! `crate::scene`; this module only reads and writes it.
//!
//! The reader does not deserialise into serde structs. It parses into a small JSON tree
//! of its own (`Json`), which keeps key order and refuses duplicate keys (serde_json
//! would keep the last one silently), and then walks that tree by hand. Every value on
//! the walk is a `Field` that knows its `JsonPath`, so each error names the file and
//! the exact field (`glyphs[0].coeffs[3]`). A path is a chain of borrowed stack frames
//! rendered only when an error is reported: a file of a million coefficients builds no
//! strings. The writer builds the same tree and prints one center or coefficient list
//! per line.
//!
//! `json` holds the tree and its parser, `field` the path-tracking walk over it, `names`
//! the format's names for enumerated values; `read` validates a tree into a [`Scene`],
//! `write` turns a [`Scene`] back into text.
use std::path::{Path, PathBuf};

use crate::{Error, Result};

use field::Field;

mod field;
mod json;
mod names;
mod npy_array;
mod read;
mod write;

#[cfg(test)]
mod tests;

use crate::camera::Camera;
use crate::scene::{GlyphKind, GlyphSet, ImageSize, Scene, ShBasis};

const FORMAT_VERSION: i128 = 1;

impl Scene {
    /// Reads and validates a scene file. Every problem with the content is an
    /// [`Error::Input`] naming the file and the JSON path of the field; a file that
    /// cannot be read is an [`Error::Io`].
    pub fn load(path: &Path) -> Result<Scene> {
        use std::io::BufRead as _;
        // Parsed as it is read, so that a large scene (10^6 glyphs is a 1 GB file) is
        // never held as text beside its tree; on an error the text is read after all,
        // for the message that names the line and what is wrong there.
        let name = path.display().to_string();
        let file = std::fs::File::open(path).map_err(|err| Error::io(path, err))?;
        let mut reader = std::io::BufReader::with_capacity(1 << 20, file);
        let bom = reader.fill_buf().map_err(|err| Error::io(path, err))?;
        if bom.starts_with("\u{feff}".as_bytes()) {
            reader.consume(3);
        }
        match json::parse_reader(reader) {
            Some(document) => read::read_scene(&Field::root(&name, &document)),
            None => {
                let text = std::fs::read_to_string(path).map_err(|err| Error::io(path, err))?;
                Self::from_json_str(&text, &name)
            }
        }
    }

    /// The `.npy` files a scene file names in place of lists (`centers`, `coeffs`,
    /// `scales` of each glyph set), as [`Scene::load`] would read them: relative to the
    /// scene file's folder. For checks before any work (an output must not name one);
    /// a file that cannot be read or parsed names none (loading it reports why).
    pub fn array_files(path: &Path) -> Vec<PathBuf> {
        let Ok(file) = std::fs::File::open(path) else {
            return Vec::new();
        };
        let Some(document) = json::parse_reader(std::io::BufReader::new(file)) else {
            return Vec::new();
        };
        let name = path.display().to_string();
        read::array_names(&Field::root(&name, &document))
            .into_iter()
            .map(|array| path.parent().unwrap_or(Path::new("")).join(array))
            .collect()
    }

    /// Same as [`Scene::load`], from text; `file` is the name used in errors.
    pub fn from_json_str(text: &str, file: &str) -> Result<Scene> {
        // Editors on Windows may start a UTF-8 file with a byte order mark.
        let text = text.strip_prefix('\u{feff}').unwrap_or(text);
        let document = json::parse_document(text, file)?;
        read::read_scene(&Field::root(file, &document))
    }

    /// A scene's `camera` object alone, from text, validated as in a scene file;
    /// `file` is the name used in errors.
    pub fn camera_from_json_str(text: &str, file: &str) -> Result<Camera> {
        let document = json::parse_document(text, file)?;
        read::read_camera(&Field::root(file, &document))
    }

    /// Serialises to the scene format, version 1; [`Scene::from_json_str`] reads it
    /// back to an equal scene. A set whose glyphs all share one scale is written with
    /// `scale`, any other with `scales`. Numbers are written as the shortest decimal
    /// that identifies each f64; reading them back is bit-exact only when serde_json's
    /// `float_roundtrip` feature is on (without it, about one value in ten comes back
    /// one ulp off).
    pub fn to_json(&self) -> String {
        write::to_json(self)
    }

    /// The scene file with each set's `centers`, `coeffs` (and `scales`, unless one scale
    /// serves every glyph) written as float64 `.npy` files beside it instead of JSON
    /// lists: the JSON text and the arrays' (file name, bytes). The file names are
    /// `<stem>.<set index>.<field>.npy`, relative to the scene file's folder, so `stem`
    /// is usually the scene file's own stem. [`Scene::load`] reads the set back equal.
    pub fn to_json_with_arrays(&self, stem: &str) -> (String, Vec<(String, Vec<u8>)>) {
        write::to_json_with_arrays(self, stem)
    }

    /// The array files [`Scene::save`] writes beside `path` with `arrays` on
    /// (`<stem>.<set>.<field>.npy`), without encoding them: for the checks of outputs
    /// before any work.
    pub fn array_paths(&self, path: &Path) -> Result<Vec<PathBuf>> {
        let stem = array_stem(path)?;
        let folder = path.parent().unwrap_or(Path::new(""));
        let mut paths = Vec::new();
        for (index, set) in self.glyph_sets.iter().enumerate() {
            let one_scale = set.scales.windows(2).all(|pair| pair[0] == pair[1]);
            let fields: &[&str] = if one_scale && !set.scales.is_empty() {
                &["centers", "coeffs"]
            } else {
                &["centers", "scales", "coeffs"]
            };
            for field in fields {
                paths.push(folder.join(format!("{stem}.{index}.{field}.npy")));
            }
        }
        Ok(paths)
    }

    /// Writes the scene to `path`, with its arrays beside it when `arrays` is true
    /// ([`Scene::to_json_with_arrays`]), all files or none ([`crate::io::atomic`]).
    pub fn save(&self, path: &Path, arrays: bool) -> Result<()> {
        if !arrays {
            return crate::io::atomic::write_atomic(path, self.to_json().as_bytes());
        }
        let stem = array_stem(path)?;
        let (json, files) = self.to_json_with_arrays(stem);
        let folder = path.parent().unwrap_or(Path::new(""));
        let paths: Vec<_> = files.iter().map(|(name, _)| folder.join(name)).collect();
        let mut outputs: Vec<(&Path, &[u8])> = vec![(path, json.as_bytes())];
        outputs.extend(
            paths
                .iter()
                .zip(&files)
                .map(|(p, (_, b))| (p.as_path(), b.as_slice())),
        );
        crate::io::atomic::write_all_atomic(&outputs)
    }
}

/// The stem of a scene file's array names: the file's own stem, in UTF-8.
fn array_stem(path: &Path) -> Result<&str> {
    path.file_stem()
        .and_then(|s| s.to_str())
        .filter(|s| !s.is_empty())
        .ok_or_else(|| Error::io(path, "the scene file needs a UTF-8 name for its arrays"))
}
