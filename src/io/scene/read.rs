//! Validating a parsed tree into a [`Scene`]: glyph sets, camera and image, each field
//! checked against docs/scene-format.md with an error naming the field.
use glam::DVec3;
use std::path::Path;

use super::field::beyond_float32;
use super::field::{Field, Object};
use super::names::{KindName, ProjectionName};
use super::npy_array;
use super::{FORMAT_VERSION, GlyphKind, GlyphSet, ImageSize, Scene, ShBasis};
use crate::Result;
use crate::camera::{Camera, Projection};
use crate::glyph::PLANE_LAYOUT;
use crate::glyph::ellipsoid::ELLIPSOID_LAYOUT;
use crate::glyph::{GlyphShape, NegativeMode, Symmetry, TensorLayout};
use crate::scene::{MAX_IMAGE_SIDE, fits_float32};

use crate::catalog::{MAX_NONSYMMETRIC_ORDER, MAX_SH_BAND, MAX_SYMMETRIC_ORDER};
const DEFAULT_FOV_Y_DEG: f64 = 30.0;
const DEFAULT_UP: DVec3 = DVec3::Z;
/// Below this sine of the angle between `up` and the view direction the camera frame
/// (a normalised cross product) would be dominated by rounding.
const PARALLEL_SINE: f64 = 1e-6;

const SCENE_KEYS: &[&str] = &["version", "glyphs", "camera", "image"];
const GLYPH_SET_KEYS: &[&str] = &[
    "kind",
    "order",
    "symmetric",
    "basis",
    "legacy",
    "negative",
    "shape",
    "centers",
    "scale",
    "scales",
    "coeffs",
];
const CAMERA_KEYS: &[&str] = &["projection", "eye", "target", "up", "fov_y_deg", "height"];
const IMAGE_KEYS: &[&str] = &["width", "height"];

pub(super) fn read_scene(root: &Field) -> Result<Scene> {
    let scene = root.object()?;
    // The version comes first: keys unknown to version 1 may be fine in a later one.
    read_version(&scene.require("version")?)?;
    scene.deny_unknown(SCENE_KEYS)?;
    let glyph_sets = scene
        .require("glyphs")?
        .items()?
        .map(|set| read_glyph_set(&set))
        .collect::<Result<Vec<_>>>()?;
    let camera = read_camera(&scene.require("camera")?)?;
    let image = scene.optional("image", read_image)?.unwrap_or_default();
    Ok(Scene {
        glyph_sets,
        camera,
        image,
    })
}

/// The array file names a scene document gives in place of lists (see
/// `Scene::array_files`); nothing for a document that is no scene.
pub(super) fn array_names(root: &Field) -> Vec<String> {
    let Some(glyphs) = root.object().ok().and_then(|scene| scene.get("glyphs")) else {
        return Vec::new();
    };
    let Ok(sets) = glyphs.items() else {
        return Vec::new();
    };
    let mut names = Vec::new();
    for set in sets {
        let Ok(set) = set.object() else { continue };
        for key in ["centers", "coeffs", "scales"] {
            if let Some(name) = set.get(key).and_then(|field| field.text()) {
                names.push(name.to_owned());
            }
        }
    }
    names
}

fn read_version(field: &Field) -> Result<()> {
    match field.integer()? {
        FORMAT_VERSION => Ok(()),
        other => Err(field.error(format!(
            "unsupported version {other}; this reader supports version {FORMAT_VERSION}"
        ))),
    }
}

fn read_glyph_set(field: &Field) -> Result<GlyphSet> {
    let set = field.object()?;
    set.deny_unknown(GLYPH_SET_KEYS)?;
    let kind = read_glyph_kind(&set)?;
    let negative = set.optional("negative", Field::choice)?.unwrap_or_default();
    let shape = read_shape(&set, kind, negative)?;
    let centers_field = set.require("centers")?;
    let centers = match centers_field.text() {
        Some(name) => read_array(&centers_field, name, None, 3, "centers")?
            .into_iter()
            .map(|row| DVec3::new(row[0], row[1], row[2]))
            .collect(),
        None => centers_field
            .items()?
            .map(|center| center.vec3())
            .collect::<Result<Vec<_>>>()?,
    };
    let scales = read_scales(&set, centers.len())?;
    let coeffs = read_coeffs(&set.require("coeffs")?, kind, shape, centers.len())?;
    Ok(GlyphSet {
        kind,
        negative,
        shape,
        centers,
        scales,
        coeffs,
    })
}

/// `shape`: the ellipsoid is defined for order-2 symmetric tensors only; neither it nor
/// the reciprocal glyph has negative lobes to hide.
fn read_shape(set: &Object, kind: GlyphKind, negative: NegativeMode) -> Result<GlyphShape> {
    let Some(field) = set.get("shape") else {
        return Ok(GlyphShape::default());
    };
    let shape: GlyphShape = field.choice()?;
    if shape == GlyphShape::Ellipsoid {
        if kind != GlyphKind::Tensor(ELLIPSOID_LAYOUT) {
            return Err(field.error(format!(
                "\"ellipsoid\" applies only to symmetric tensors of order 2, not to a {kind}"
            )));
        }
        if !shape.takes(negative) {
            return Err(field
                .error("\"ellipsoid\" has no negative lobes to hide: use \"negative\": \"abs\""));
        }
    }
    if shape == GlyphShape::Reciprocal && !shape.takes(negative) {
        return Err(field.error(
            "\"reciprocal\" (r = 1/|f|) needs f without zeros, so it has no negative lobes to \
             hide: use \"negative\": \"abs\"",
        ));
    }
    if shape.is_pair() {
        if kind != GlyphKind::Tensor(PLANE_LAYOUT) {
            let (radius, rest) = if shape.is_plane() {
                ("r = 1/λ", "T")
            } else {
                ("r = |λ/Q|", "T and Q")
            };
            return Err(field.error(format!(
                "\"{}\" ({radius}, λ² − T λ + D = 0) takes D as a symmetric tensor of \
                 order 6 (then {rest} of order 4 in each glyph's coefficients), not a {kind}",
                shape.name()
            )));
        }
        if !shape.takes(negative) {
            return Err(field.error(format!(
                "\"{}\" has no negative lobes to hide: use \"negative\": \"abs\"",
                shape.name()
            )));
        }
    }
    Ok(shape)
}

fn read_glyph_kind(set: &Object) -> Result<GlyphKind> {
    let kind: KindName = set.require("kind")?.choice()?;
    let order_field = set.require("order")?;
    let order = order_field.integer()?;
    match kind {
        KindName::Tensor => read_tensor_layout(set, &order_field, order).map(GlyphKind::Tensor),
        KindName::Sh => read_sh_kind(set, &order_field, order),
    }
}

fn read_tensor_layout(set: &Object, order_field: &Field, order: i128) -> Result<TensorLayout> {
    set.forbid("basis", "applies only to kind \"sh\"")?;
    set.forbid("legacy", "applies only to kind \"sh\"")?;
    let symmetric = set.optional("symmetric", Field::boolean)?.unwrap_or(true);
    let (symmetry, max_order, limit) = if symmetric {
        let limit = format!("symmetric tensor order must be from 1 to {MAX_SYMMETRIC_ORDER}");
        (Symmetry::Symmetric, MAX_SYMMETRIC_ORDER, limit)
    } else {
        let limit = format!(
            "non-symmetric tensors are supported up to order {MAX_NONSYMMETRIC_ORDER} \
             (order 1 to {MAX_NONSYMMETRIC_ORDER})"
        );
        (Symmetry::NonSymmetric, MAX_NONSYMMETRIC_ORDER, limit)
    };
    let order = order_in(order, 1..=max_order, |_| true)
        .ok_or_else(|| order_field.error(format!("{limit}, found {order}")))?;
    Ok(TensorLayout { order, symmetry })
}

fn read_sh_kind(set: &Object, order_field: &Field, band: i128) -> Result<GlyphKind> {
    set.forbid(
        "symmetric",
        "applies only to kind \"tensor\" (an SH series is always symmetric)",
    )?;
    let band = order_in(band, 0..=MAX_SH_BAND, |b| b % 2 == 0).ok_or_else(|| {
        order_field.error(format!(
            "SH band must be even and from 0 to {MAX_SH_BAND}, found {band}"
        ))
    })?;
    let basis = set
        .optional("basis", Field::choice)?
        .unwrap_or(ShBasis::Tournier07);
    let legacy = set.optional("legacy", Field::boolean)?.unwrap_or(false);
    Ok(GlyphKind::Sh {
        band,
        basis,
        legacy,
    })
}

/// `order` as a u32 when it lies in `range` and passes `accept`.
fn order_in(
    order: i128,
    range: std::ops::RangeInclusive<u32>,
    accept: impl Fn(u32) -> bool,
) -> Option<u32> {
    u32::try_from(order)
        .ok()
        .filter(|order| range.contains(order) && accept(*order))
}

/// One scale per glyph, from `scale` or `scales` (exactly one of them).
fn read_scales(set: &Object, count: usize) -> Result<Vec<f64>> {
    match (set.get("scale"), set.get("scales")) {
        (Some(scale), None) => Ok(vec![scale.positive()?; count]),
        (None, Some(scales)) if scales.text().is_some() => {
            let name = scales.text().unwrap_or_default();
            let rows = read_array(&scales, name, Some(count), 1, "scales")?;
            rows.into_iter()
                .enumerate()
                .map(|(glyph, row)| match row[0] {
                    scale if scale > 0.0 => Ok(scale),
                    scale => Err(scales.error(format!(
                        "{name}: the scale of glyph {glyph} must be positive, found {scale:?}"
                    ))),
                })
                .collect()
        }
        (None, Some(scales)) => {
            let found = scales.list()?.len();
            if found != count {
                return Err(scales.error(format!(
                    "expected {count} scales (one per center), found {found}"
                )));
            }
            scales.items()?.map(|scale| scale.positive()).collect()
        }
        (Some(_), Some(_)) => {
            Err(set.error_at("scales", "give either `scale` or `scales`, not both"))
        }
        (None, None) => Err(set.error_at(
            "scale",
            "missing required field (give `scale` for all glyphs or `scales`, one per glyph)",
        )),
    }
}

fn read_coeffs(
    field: &Field,
    kind: GlyphKind,
    shape: GlyphShape,
    count: usize,
) -> Result<Vec<Vec<f64>>> {
    let per_glyph = shape.coefficient_count(kind.coefficient_count());
    let what = if shape.is_plane() {
        format!("coefficients (D: {kind}, then T: symmetric tensor of order 4)")
    } else if shape.is_ratio() {
        format!("coefficients (D: {kind}, then T and Q: symmetric tensors of order 4)")
    } else {
        format!("coefficients ({kind})")
    };
    if let Some(name) = field.text() {
        return read_array(field, name, Some(count), per_glyph, &what);
    }
    let found = field.list()?.len();
    if found != count {
        return Err(field.error(format!(
            "expected {count} coefficient lists (one per center), found {found}"
        )));
    }
    field
        .items()?
        .map(|glyph| glyph.numbers(per_glyph, &what))
        .collect()
}

pub(super) fn read_camera(field: &Field) -> Result<Camera> {
    let camera = field.object()?;
    camera.deny_unknown(CAMERA_KEYS)?;
    let projection = read_projection(&camera)?;
    let eye = camera.require("eye")?.vec3()?;
    let target = camera.require("target")?.vec3()?;
    let up = camera.optional("up", Field::vec3)?.unwrap_or(DEFAULT_UP);
    check_view(&camera, eye, target, up)?;
    Ok(Camera {
        projection,
        eye,
        target,
        up,
    })
}

fn read_projection(camera: &Object) -> Result<Projection> {
    let name = camera
        .optional("projection", Field::choice)?
        .unwrap_or(ProjectionName::Perspective);
    match name {
        ProjectionName::Perspective => {
            camera.forbid(
                "height",
                "applies only to orthographic cameras (perspective uses `fov_y_deg`)",
            )?;
            let fov_y_deg = camera
                .optional("fov_y_deg", read_fov)?
                .unwrap_or(DEFAULT_FOV_Y_DEG);
            Ok(Projection::Perspective { fov_y_deg })
        }
        ProjectionName::Orthographic => {
            camera.forbid(
                "fov_y_deg",
                "applies only to perspective cameras (orthographic uses `height`)",
            )?;
            let height = camera.require("height")?.positive()?;
            Ok(Projection::Orthographic { height })
        }
    }
}

fn read_fov(field: &Field) -> Result<f64> {
    let fov = field.number()?;
    if fov > 0.0 && fov < 180.0 {
        Ok(fov)
    } else {
        Err(field.error(format!(
            "must lie strictly between 0 and 180 degrees, found {fov:?}"
        )))
    }
}

/// The camera frame of docs/scene-format.md needs a view direction and an `up` not parallel
/// to it.
fn check_view(camera: &Object, eye: DVec3, target: DVec3, up: DVec3) -> Result<()> {
    let Some(forward) = (target - eye).try_normalize() else {
        return Err(camera.error_at(
            "target",
            format!(
                "must differ from eye {} by a finite, nonzero vector, found {}",
                show(eye),
                show(target)
            ),
        ));
    };
    let Some(up_direction) = up.try_normalize() else {
        return Err(camera.error_at(
            "up",
            format!("must be a nonzero vector, found {}", show(up)),
        ));
    };
    if forward.cross(up_direction).length() < PARALLEL_SINE {
        let given = if camera.get("up").is_some() {
            show(up)
        } else {
            format!("the default {}", show(up))
        };
        return Err(camera.error_at(
            "up",
            format!(
                "{given} is parallel to the view direction {}; give an `up` across it",
                show(forward)
            ),
        ));
    }
    Ok(())
}

/// A vector as the file writes it, with every digit that matters and no more.
fn show(v: DVec3) -> String {
    format!("[{:?}, {:?}, {:?}]", v.x, v.y, v.z)
}

fn read_image(field: &Field) -> Result<ImageSize> {
    let image = field.object()?;
    image.deny_unknown(IMAGE_KEYS)?;
    Ok(ImageSize {
        width: read_image_side(&image.require("width")?)?,
        height: read_image_side(&image.require("height")?)?,
    })
}

fn read_image_side(field: &Field) -> Result<u32> {
    let pixels = field.integer()?;
    u32::try_from(pixels)
        .ok()
        .filter(|pixels| (1..=MAX_IMAGE_SIDE).contains(pixels))
        .ok_or_else(|| {
            field.error(format!(
                "must be from 1 to {MAX_IMAGE_SIDE} pixels, found {pixels}"
            ))
        })
}

/// The rows of the `.npy` file `name` (relative to the scene file's folder) that `field`
/// gives in place of a list: a float32 or float64 array of shape (rows, columns), or
/// (rows,) for one column, in C or Fortran order; `rows` when the glyph count is known.
/// Every value must be finite and within float32's range. Errors name the scene file, the field and the array file.
fn read_array(
    field: &Field,
    name: &str,
    rows: Option<usize>,
    columns: usize,
    what: &str,
) -> Result<Vec<Vec<f64>>> {
    let folder = Path::new(field.file()).parent().unwrap_or(Path::new(""));
    let path = folder.join(name);
    let fail = |message: String| field.error(format!("{name}: {message}"));
    let array = npy_array::read_rows(&path, columns).map_err(|e| fail(e.to_string()))?;
    let shape_ok = match array.shape[..] {
        [n, k] => k == columns && rows.is_none_or(|rows| rows == n),
        [n] => columns == 1 && rows.is_none_or(|rows| rows == n),
        _ => false,
    };
    if !shape_ok {
        let expected = match (rows, columns) {
            (Some(rows), 1) => format!("({rows},) or ({rows}, 1)"),
            (Some(rows), columns) => format!("({rows}, {columns})"),
            (None, columns) => format!("(N, {columns})"),
        };
        return Err(fail(format!(
            "expected {what} of shape {expected}, found shape {:?}",
            array.shape
        )));
    }
    for (row, values) in array.rows.iter().enumerate() {
        if let Some(column) = values.iter().position(|v| !v.is_finite()) {
            return Err(fail(format!(
                "{what}: row {row}, column {column} is {:?}; every value must be finite",
                values[column]
            )));
        }
        if let Some(column) = values.iter().position(|v| !fits_float32(*v)) {
            return Err(fail(format!(
                "{what}: row {row} (glyph {row}), column {column}: {}",
                beyond_float32(values[column])
            )));
        }
    }
    Ok(array.rows)
}
