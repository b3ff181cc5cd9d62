//! Scene files (SCENE-FORMAT.md, version 1): reading with full validation, and writing.
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
use std::fmt;
use std::path::Path;

use glam::DVec3;

use crate::camera::Camera;
use crate::glyph::monomials::symmetric_count;
use crate::glyph::{NegativeMode, Symmetry, TensorLayout};
use crate::{Error, Result};

use field::Field;
use names::Named;

mod field;
mod json;
mod names;
mod read;
mod write;

#[cfg(test)]
mod tests;

/// The real SH basis convention of a coefficient list (SCENE-FORMAT.md).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ShBasis {
    /// MRtrix3's basis.
    Tournier07,
    /// DIPY's default basis.
    Descoteaux07,
}

/// What the coefficients of a glyph set describe.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum GlyphKind {
    Tensor(TensorLayout),
    /// Even bands 0, 2, ..., `band`; `legacy` is DIPY's `legacy=True` variant.
    Sh {
        band: u32,
        basis: ShBasis,
        legacy: bool,
    },
}

/// Glyphs sharing kind, order and options; one center, scale and coefficient list each.
#[derive(Clone, Debug, PartialEq)]
pub struct GlyphSet {
    pub kind: GlyphKind,
    pub negative: NegativeMode,
    pub centers: Vec<DVec3>,
    /// One per glyph, expanded from `scale` when the file gives a single value.
    pub scales: Vec<f64>,
    pub coeffs: Vec<Vec<f64>>,
}

/// Output image size in pixels.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ImageSize {
    pub width: u32,
    pub height: u32,
}

/// A validated scene file.
#[derive(Clone, Debug, PartialEq)]
pub struct Scene {
    pub glyph_sets: Vec<GlyphSet>,
    pub camera: Camera,
    pub image: ImageSize,
}
const FORMAT_VERSION: i128 = 1;
const DEFAULT_IMAGE_SIDE: u32 = 512;

impl GlyphKind {
    /// Coefficients per glyph: (n+1)(n+2)/2 symmetric, 3^n non-symmetric, and for SH
    /// up to band L the same (L+1)(L+2)/2 as a symmetric tensor of order L.
    pub fn coefficient_count(&self) -> usize {
        match self {
            GlyphKind::Tensor(layout) => layout.coefficient_count(),
            GlyphKind::Sh { band, .. } => symmetric_count(*band),
        }
    }
}

impl fmt::Display for GlyphKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            GlyphKind::Tensor(TensorLayout { order, symmetry }) => {
                let symmetry = match symmetry {
                    Symmetry::Symmetric => "symmetric",
                    Symmetry::NonSymmetric => "non-symmetric",
                };
                write!(f, "{symmetry} tensor of order {order}")
            }
            GlyphKind::Sh {
                band,
                basis,
                legacy,
            } => {
                let legacy = if *legacy { "legacy " } else { "" };
                write!(f, "SH up to band {band}, {legacy}{} basis", basis.name())
            }
        }
    }
}

impl GlyphSet {
    /// Number of glyphs.
    pub fn len(&self) -> usize {
        self.centers.len()
    }

    pub fn is_empty(&self) -> bool {
        self.centers.is_empty()
    }
}

impl Default for ImageSize {
    /// The format's default, 512 x 512.
    fn default() -> Self {
        ImageSize {
            width: DEFAULT_IMAGE_SIDE,
            height: DEFAULT_IMAGE_SIDE,
        }
    }
}

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

    /// Same as [`Scene::load`], from text; `file` is the name used in errors.
    pub fn from_json_str(text: &str, file: &str) -> Result<Scene> {
        // Editors on Windows may start a UTF-8 file with a byte order mark.
        let text = text.strip_prefix('\u{feff}').unwrap_or(text);
        let document = json::parse_document(text, file)?;
        read::read_scene(&Field::root(file, &document))
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
}
