//! The camera that shows a slice face on, with the whole slice in view.
//!
//! The view looks along the world axis closest to the slice's normal (after the affine),
//! from a side set by the [`Orientation`] in world terms (scanner RAS+: +x the subject's
//! right, +y anterior, +z superior), whatever the voxel order of the file:
//! - z (axial), anterior up: radiological looks from inferior (+z), so the subject's
//!   right is on the image's left, as mrview shows it; neurological looks down from
//!   superior, right on the right;
//! - y (coronal), superior up: radiological looks from anterior (facing the subject,
//!   its right on the image's left); neurological from posterior;
//! - x (sagittal), superior up: both look from the subject's left, so that anterior is on
//!   the left of the image, as in mrview's and FSLeyes' sagittal panes (left and right do
//!   not appear in a sagittal image).
//!
//! The framed region is the slice's voxel boxes (centres +- half a voxel), so glyphs that
//! fill their voxel stay inside. Without a requested size the image takes the region's
//! aspect with its longer side 1024 pixels; with one side requested the other follows
//! the aspect; with both, the region is fitted inside (the rest is background).
//! `--perspective` puts a 30 degree camera on the same axis at the distance where the
//! region's front face fills the same view.
use glam::DVec3;

use super::selection::SliceRegion;
use crate::io::nifti::VoxelToWorld;
use glyphcast::camera::{Camera, Projection};
use glyphcast::scene::{ImageSize, MAX_IMAGE_SIDE};
use glyphcast::{Error, Result, Setting};

/// Longer image side when no size is requested.
pub const DEFAULT_LONG_SIDE: u32 = 1024;
/// Vertical field of view of `--perspective`.
pub const PERSPECTIVE_FOV_DEG: f64 = 30.0;

/// The camera a volume view is framed with.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum ViewProjection {
    /// Parallel rays along the slice's normal.
    #[default]
    Orthographic,
    /// A pinhole of [`PERSPECTIVE_FOV_DEG`] vertical field of view (`--perspective`).
    Perspective,
}

/// Which side of the image the subject's right is on (see the module notes).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Orientation {
    /// The subject's right on the image's left (mrview, radiology).
    #[default]
    Radiological,
    /// The subject's right on the image's right.
    Neurological,
}

impl Orientation {
    /// The name used by `--orientation` and in the viewer's title.
    pub fn name(self) -> &'static str {
        match self {
            Orientation::Radiological => "radiological",
            Orientation::Neurological => "neurological",
        }
    }
}

impl std::str::FromStr for Orientation {
    type Err = Error;

    /// `radiological` or `neurological`.
    fn from_str(text: &str) -> Result<Self> {
        match text {
            "radiological" => Ok(Orientation::Radiological),
            "neurological" => Ok(Orientation::Neurological),
            _ => Err(Error::setting_value(
                Setting::Orientation,
                format!("'{}'", glyphcast::error::quoted(text)),
                "expected radiological or neurological",
            )),
        }
    }
}

/// Image size asked for (the width and height settings); a missing side follows the
/// slice's aspect.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ImageRequest {
    /// Image width in pixels, if asked for.
    pub width: Option<u32>,
    /// Image height in pixels, if asked for.
    pub height: Option<u32>,
    /// Keep the band along each edge that edge labels and captions cover
    /// ([`edge_band`](glyphcast::render::compose::labels::edge_band)) free of glyphs:
    /// the view is framed a little wider.
    pub keep_edges: bool,
}

impl ImageRequest {
    /// The size asked for ([`Setting::Width`], [`Setting::Height`]), each side checked to be in
    /// 1..=[`MAX_IMAGE_SIDE`]; the device's own limit is checked when it is known
    /// (`HeadlessRenderer::render_view`).
    pub fn checked(width: Option<u32>, height: Option<u32>) -> glyphcast::Result<Self> {
        for (setting, value) in [(Setting::Width, width), (Setting::Height, height)] {
            if let Some(v) = value
                && (v == 0 || v > MAX_IMAGE_SIDE)
            {
                return Err(Error::setting_value(
                    setting,
                    v,
                    format!("must be in 1 to {MAX_IMAGE_SIDE}"),
                ));
            }
        }
        Ok(Self {
            width,
            height,
            keep_edges: false,
        })
    }
}

/// Camera and image size of a slice view.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Framing {
    /// A camera that shows the whole slice (or slices).
    pub camera: Camera,
    /// The image size, the requested sides with the other following the slice's aspect.
    pub image: ImageSize,
}

/// Forward and up directions of the view along world axis `axis` (0 = x, 1 = y, 2 = z)
/// in `orientation`.
pub fn view_directions(axis: usize, orientation: Orientation) -> (DVec3, DVec3) {
    let radiological = orientation == Orientation::Radiological;
    match axis {
        0 => (DVec3::X, DVec3::Z),
        1 if radiological => (DVec3::NEG_Y, DVec3::Z),
        1 => (DVec3::Y, DVec3::Z),
        _ if radiological => (DVec3::Z, DVec3::Y),
        _ => (DVec3::NEG_Z, DVec3::Y),
    }
}

/// The world axis closest to the normal of `region`'s slice plane.
pub fn view_axis(region: &SliceRegion, map: &VoxelToWorld) -> usize {
    let a = map.linear();
    let normal = match region.slice.voxel_axis() {
        0 => a.y_axis.cross(a.z_axis),
        1 => a.z_axis.cross(a.x_axis),
        _ => a.x_axis.cross(a.y_axis),
    };
    normal.abs().max_position()
}

/// Frames `region` of a volume mapped by `map`.
pub fn frame_region(
    region: &SliceRegion,
    map: &VoxelToWorld,
    projection: ViewProjection,
    orientation: Orientation,
    request: ImageRequest,
) -> Result<Framing> {
    let (fwd, up) = view_directions(view_axis(region, map), orientation);
    let right = fwd.cross(up);
    let (mut lo, mut hi) = (DVec3::INFINITY, DVec3::NEG_INFINITY);
    for corner in 0..8 {
        let voxel = DVec3::from_array(std::array::from_fn(|axis| {
            let range = &region.ranges[axis];
            let end = if corner & (1 << axis) == 0 {
                range.start
            } else {
                range.end
            };
            end as f64 - 0.5
        }));
        let p = map.voxel_center(voxel);
        let view = DVec3::new(right.dot(p), up.dot(p), fwd.dot(p));
        lo = lo.min(view);
        hi = hi.max(view);
    }
    let extent = hi - lo;
    let image = image_size(extent.x, extent.y, request)?;
    let aspect = f64::from(image.width) / f64::from(image.height);
    // The share of each side that glyphs may take: all of it, or what the edge bands
    // of labels and captions leave.
    let (free_w, free_h) = free_shares(image, request.keep_edges);
    let view_height = (extent.y / free_h).max(extent.x / free_w / aspect);
    let middle = 0.5 * (lo + hi);
    let front = right * middle.x + up * middle.y + fwd * lo.z;
    let target = front + fwd * (0.5 * extent.z);
    let (eye, projection) = match projection {
        ViewProjection::Orthographic => (
            front - fwd * view_height.max(extent.z),
            Projection::Orthographic {
                height: view_height,
            },
        ),
        ViewProjection::Perspective => {
            let half_fov = (0.5 * PERSPECTIVE_FOV_DEG).to_radians();
            (
                front - fwd * (0.5 * view_height / half_fov.tan()),
                Projection::Perspective {
                    fov_y_deg: PERSPECTIVE_FOV_DEG,
                },
            )
        }
    };
    Ok(Framing {
        camera: Camera {
            projection,
            eye,
            target,
            up,
        },
        image,
    })
}

/// Direction from the volume's centre to the camera of a three-slice view, superior and
/// from the subject's left, so that all three planes are seen obliquely, anterior on the
/// left as in the sagittal view: radiological from anterior (the subject's right on the
/// image's left, as in the coronal view), neurological from posterior.
fn oblique_from(orientation: Orientation) -> DVec3 {
    match orientation {
        Orientation::Radiological => DVec3::new(-1.0, 1.0, 1.0),
        Orientation::Neurological => DVec3::new(-1.0, -1.0, 1.0),
    }
}

/// Frames the voxel box `ranges` (index ranges along i, j, k) for three orthogonal
/// slices: a perspective camera looking at the box's centre from `oblique_from`, at the
/// distance where the box's bounding sphere fills the view. Without a requested size the
/// image is square, 1024 pixels.
pub fn frame_volume(
    ranges: &[std::ops::Range<usize>; 3],
    map: &VoxelToWorld,
    orientation: Orientation,
    request: ImageRequest,
) -> Result<Framing> {
    frame_oblique(ranges, map, orientation, request, Fit::Sphere)
}

/// Frames the voxel box `ranges` for a block view: the camera of [`frame_volume`]'s
/// direction, moved sideways and to the nearest distance where the box's eight corners
/// (the outer faces of its voxels) fall inside the view, so that the block is framed
/// whole, centred and as large as that allows. Without a requested size the image takes the box's aspect seen from
/// afar, its longer side 1024 pixels.
pub fn frame_block(
    ranges: &[std::ops::Range<usize>; 3],
    map: &VoxelToWorld,
    orientation: Orientation,
    request: ImageRequest,
) -> Result<Framing> {
    frame_oblique(ranges, map, orientation, request, Fit::Corners)
}

/// What an oblique view of a voxel box keeps inside its field of view.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Fit {
    /// The box's bounding sphere: the box stays in view from every direction (the
    /// viewer's orbit around three slices).
    Sphere,
    /// The box's corners, seen from the framing direction.
    Corners,
}

/// The world positions of the eight corners of the voxel box `ranges` (voxel centres
/// +- half a voxel).
fn box_corners(ranges: &[std::ops::Range<usize>; 3], map: &VoxelToWorld) -> [DVec3; 8] {
    std::array::from_fn(|corner| {
        let voxel = DVec3::from_array(std::array::from_fn(|axis| {
            let range = &ranges[axis];
            let end = if corner & (1 << axis) == 0 {
                range.start
            } else {
                range.end
            };
            end as f64 - 0.5
        }));
        map.voxel_center(voxel)
    })
}

/// The perspective camera that looks at the centre of the voxel box `ranges` from
/// `oblique_from`, at the distance where `fit` is in view.
fn frame_oblique(
    ranges: &[std::ops::Range<usize>; 3],
    map: &VoxelToWorld,
    orientation: Orientation,
    request: ImageRequest,
    fit: Fit,
) -> Result<Framing> {
    let corners = box_corners(ranges, map);
    let (mut lo, mut hi) = (DVec3::INFINITY, DVec3::NEG_INFINITY);
    for p in corners {
        lo = lo.min(p);
        hi = hi.max(p);
    }
    let target = 0.5 * (lo + hi);
    let from = oblique_from(orientation).normalize();
    let up = (DVec3::Z - from * from.z).normalize();
    let right = up.cross(from);
    // The sphere's view is square; the corners' has the aspect of the box seen from
    // afar (a missing side follows it).
    let (across, high) = match fit {
        Fit::Sphere => (1.0, 1.0),
        Fit::Corners => corners.iter().fold((0.0f64, 0.0f64), |(x, y), &p| {
            let offset = p - target;
            (x.max(offset.dot(right).abs()), y.max(offset.dot(up).abs()))
        }),
    };
    let image = image_size(across, high, request)?;
    let aspect = f64::from(image.width) / f64::from(image.height);
    let radius = (0.5 * (hi - lo).length()).max(f64::MIN_POSITIVE);
    let half_fov = (0.5 * PERSPECTIVE_FOV_DEG).to_radians();
    let (free_w, free_h) = free_shares(image, request.keep_edges);
    let (target, distance) = match fit {
        Fit::Sphere => {
            // The narrower of the two fields of view must hold the sphere.
            let half = (half_fov.tan() * free_h)
                .min(half_fov.tan() * aspect * free_w)
                .atan();
            (target, radius / half.sin())
        }
        Fit::Corners => {
            let (tan_x, tan_y) = (half_fov.tan() * aspect * free_w, half_fov.tan() * free_h);
            let seen: Vec<(f64, f64, f64)> = corners
                .iter()
                .map(|&p| {
                    let offset = p - target;
                    (offset.dot(right), offset.dot(up), offset.dot(from))
                })
                .collect();
            let x: Vec<(f64, f64)> = seen.iter().map(|&(x, _, z)| (x, z)).collect();
            let y: Vec<(f64, f64)> = seen.iter().map(|&(_, y, z)| (y, z)).collect();
            let distance = nearest_fit(&x, tan_x).max(nearest_fit(&y, tan_y));
            let shift = right * centred_shift(&x, tan_x, distance)
                + up * centred_shift(&y, tan_y, distance);
            (target + shift, distance)
        }
    };
    let eye = target + from * distance;
    Ok(Framing {
        camera: Camera {
            projection: Projection::Perspective {
                fov_y_deg: PERSPECTIVE_FOV_DEG,
            },
            eye,
            target,
            up,
        },
        image,
    })
}

/// Corners seen along one image axis: each its offset `u` across the view and `z` towards
/// the camera, from the box's centre. A camera moved sideways by `s` at distance `d` has
/// corner (u, z) in view when |u - s| <= tan (d - z): some `s` holds every corner when
/// u_i - u_j <= tan (2 d - z_i - z_j) for each pair, so the nearest distance is the
/// largest ((u_i - u_j) / tan + z_i + z_j) / 2.
fn nearest_fit(corners: &[(f64, f64)], tan: f64) -> f64 {
    corners
        .iter()
        .flat_map(|&(ui, zi)| {
            corners
                .iter()
                .map(move |&(uj, zj)| 0.5 * ((ui - uj) / tan + zi + zj))
        })
        .fold(f64::MIN_POSITIVE, f64::max)
}

/// The sideways shift that centres the images of `corners` (as in [`nearest_fit`]) in
/// the view from `distance`: among the shifts that hold every corner, the one where the
/// outermost images on either side are equally far from the middle (found by bisection:
/// moving the camera one way moves every image the other way).
fn centred_shift(corners: &[(f64, f64)], tan: f64, distance: f64) -> f64 {
    let mut lowest = corners
        .iter()
        .map(|&(u, z)| u - tan * (distance - z))
        .fold(f64::NEG_INFINITY, f64::max);
    let mut highest = corners
        .iter()
        .map(|&(u, z)| u + tan * (distance - z))
        .fold(f64::INFINITY, f64::min);
    // Where the images lie from shift s, in -1..1 across the view.
    let imbalance = |s: f64| {
        let (lo, hi) = corners
            .iter()
            .map(|&(u, z)| (u - s) / (tan * (distance - z)))
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
                (lo.min(v), hi.max(v))
            });
        lo + hi
    };
    for _ in 0..64 {
        let middle = 0.5 * (lowest + highest);
        if imbalance(middle) > 0.0 {
            lowest = middle;
        } else {
            highest = middle;
        }
    }
    0.5 * (lowest + highest)
}

/// The image size for a view `width` x `height` world units wide and high.
/// The shares of the image's width and height that glyphs may fill: 1, or what is left
/// between the edge bands of labels and captions (at least a tenth).
fn free_shares(image: ImageSize, keep_edges: bool) -> (f64, f64) {
    if !keep_edges {
        return (1.0, 1.0);
    }
    let band = glyphcast::render::compose::labels::edge_band(image.width, image.height);
    let share = |side: u32| (1.0 - 2.0 * band / f64::from(side)).max(0.1);
    (share(image.width), share(image.height))
}

fn image_size(width: f64, height: f64, request: ImageRequest) -> Result<ImageSize> {
    ImageRequest::checked(request.width, request.height)?;
    let aspect = width / height;
    let side = |value: f64| (value.round() as u32).clamp(1, MAX_IMAGE_SIDE);
    let long = f64::from(DEFAULT_LONG_SIDE);
    let (w, h) = match (request.width, request.height) {
        (Some(w), Some(h)) => (w, h),
        (Some(w), None) => (w, side(f64::from(w) / aspect)),
        (None, Some(h)) => (side(f64::from(h) * aspect), h),
        (None, None) if aspect >= 1.0 => (DEFAULT_LONG_SIDE, side(long / aspect)),
        (None, None) => (side(long * aspect), DEFAULT_LONG_SIDE),
    };
    Ok(ImageSize {
        width: w,
        height: h,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A block's corners all project into the image, the outermost onto its edge, for a
    /// flat box on a rotated, anisotropic grid; the sphere's framing is farther.
    #[test]
    fn a_block_is_framed_by_its_corners() {
        let linear = glam::DMat3::from_axis_angle(DVec3::new(1.0, 2.0, 0.5).normalize(), 0.4)
            * glam::DMat3::from_diagonal(DVec3::new(2.0, 2.0, 2.5));
        let affine = glam::DMat4::from_mat3_translation(linear, DVec3::new(-9.0, 4.0, 1.0));
        let map = VoxelToWorld::new(affine, crate::io::nifti::AffineSource::Sform, "v", "affine")
            .expect("an affine");
        let ranges = [2..12, 0..10, 3..9];
        for (width, height) in [(None, None), (Some(300), Some(200)), (Some(120), Some(400))] {
            let request = ImageRequest {
                width,
                height,
                ..Default::default()
            };
            let block = frame_block(&ranges, &map, Orientation::Radiological, request).unwrap();
            let (w, h) = (block.image.width, block.image.height);
            let clip = block.camera.view_projection(w, h, 1e-3, 1e3);
            let (mut lo, mut hi) = (glam::DVec2::INFINITY, glam::DVec2::NEG_INFINITY);
            for p in box_corners(&ranges, &map) {
                let ndc = clip.project_point3(p).truncate();
                assert!(
                    ndc.x.abs() <= 1.0 + 1e-9 && ndc.y.abs() <= 1.0 + 1e-9,
                    "{ndc}"
                );
                (lo, hi) = (lo.min(ndc), hi.max(ndc));
            }
            // Centred along both axes, and touching both edges along one of them.
            assert!((lo + hi).abs().max_element() < 1e-9, "{lo} {hi}");
            assert!(
                hi.max_element() > 1.0 - 1e-9,
                "{lo} {hi}: not framed tightly"
            );
            let sphere = frame_volume(&ranges, &map, Orientation::Radiological, request).unwrap();
            let direction = |c: &Camera| (c.eye - c.target).normalize();
            assert!((direction(&sphere.camera) - direction(&block.camera)).length() < 1e-12);
            let distance = |c: &Camera| (c.eye - c.target).length();
            assert!(distance(&block.camera) < distance(&sphere.camera));
        }
    }

    #[test]
    fn image_follows_the_aspect_unless_both_sides_are_given() {
        let size = |w, h, request| {
            let s = image_size(w, h, request).unwrap();
            (s.width, s.height)
        };
        assert_eq!(size(20.0, 10.0, ImageRequest::default()), (1024, 512));
        assert_eq!(size(10.0, 40.0, ImageRequest::default()), (256, 1024));
        let width = ImageRequest {
            width: Some(100),
            height: None,
            ..Default::default()
        };
        assert_eq!(size(20.0, 10.0, width), (100, 50));
        let both = ImageRequest {
            width: Some(32),
            height: Some(32),
            ..Default::default()
        };
        assert_eq!(size(20.0, 10.0, both), (32, 32));
        let zero = ImageRequest {
            width: Some(0),
            height: None,
            ..Default::default()
        };
        assert!(image_size(1.0, 1.0, zero).is_err());
    }
}
