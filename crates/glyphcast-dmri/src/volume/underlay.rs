//! The underlay of a volume view (`--underlay`): a 3D scalar image (FA, T1) or an RGB
//! one (colour-FA: a 4th axis of 3 values) read with the one image reader, and one plane
//! per slice of the view, out to the outer voxel edges of its region, placed in world
//! space by the glyph volume's affine. The underlay is sampled through its own affine
//! (`render::underlay`), so the two grids may differ; they must both be placed in world
//! space, and must overlap there.
//!
//! Where the plane lies along the slice's normal is [`UnderlayPlacement`]: by default
//! at the back of the glyph slab (as far behind the voxel centres, seen from the
//! camera, as the largest glyph reaches, and a little more), so that no glyph is cut by
//! it: a plane through the centres hides every glyph's far half, which makes symmetric
//! fODFs look one-sided and tilted ellipsoids thin. The plane still samples the
//! underlay on the slice itself: it is shifted, not resampled.
use std::path::Path;
use std::sync::Arc;

use std::str::FromStr;

use glam::DVec3;

use super::build::VolumeScene;
use super::input::{Volume, show_shape};
use super::selection::SliceRegion;
use crate::io::image::{Image, read_image};
use crate::io::nifti::{AffineSource, VoxelToWorld};
use glyphcast::camera::{Camera, Projection};
use glyphcast::render::underlay::{Underlay, UnderlayPlane, UnderlayVolume};
use glyphcast::{Error, Result, Setting};

/// How much further back than the largest glyph's radius a plane behind the glyphs lies:
/// a glyph that touches the plane would otherwise fight it for the depth of its tip.
const BEHIND_MARGIN: f64 = 0.02;

/// Where a slice's underlay plane lies ([`Setting::UnderlayPlane`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum UnderlayPlacement {
    /// Behind the glyphs: at the back of the glyph slab, seen from the camera.
    #[default]
    Back,
    /// Through the voxel centres of the slice (glyphs are cut in half by it).
    Centre,
}

impl FromStr for UnderlayPlacement {
    type Err = Error;

    fn from_str(text: &str) -> Result<Self> {
        match text {
            "back" => Ok(UnderlayPlacement::Back),
            "centre" | "center" => Ok(UnderlayPlacement::Centre),
            _ => Err(Error::setting_value(
                Setting::UnderlayPlane,
                format!("'{}'", glyphcast::error::quoted(text)),
                "expected back (behind the glyphs) or centre (through the voxel centres)",
            )),
        }
    }
}

/// Reads an underlay image: [x, y, z] (scalar) or [x, y, z, 3] (RGB), any other shape an
/// error naming the file and its dimensions; with the source of its affine, which
/// [`view_underlay`] checks.
pub fn load_underlay(path: &Path) -> Result<(UnderlayVolume, AffineSource)> {
    underlay_of_image(read_image(path)?)
}

/// The underlay volume of an image read with [`read_image`] (values as float32), and
/// the source of its affine.
pub fn underlay_of_image(image: Image) -> Result<(UnderlayVolume, AffineSource)> {
    let shape = image.shape(3);
    let channels = match shape.len() {
        3 => 1,
        4 if shape[3] == 3 => 3,
        _ => {
            return Err(Error::input(
                &image.file,
                "dim",
                format!(
                    "a {}D image ({}) where an underlay is 3D [x, y, z] (FA, T1) or RGB \
                     [x, y, z, 3] (colour-FA)",
                    shape.len(),
                    show_shape(&shape)
                ),
            ));
        }
    };
    let dims = [shape[0], shape[1], shape[2]];
    let mut values = Vec::new();
    values
        .try_reserve_exact(dims.iter().product::<usize>() * channels)
        .map_err(|_| Error::OutOfMemory {
            what: "the underlay's values",
            file: Some(image.file.clone()),
            bytes: Some((dims.iter().product::<usize>() * channels * size_of::<f32>()) as u64),
            settings: &[],
        })?;
    // The stored axes beyond the trimmed shape all have length 1: index 0 there.
    let mut index = vec![0usize; image.data.ndim()];
    for k in 0..dims[2] {
        for j in 0..dims[1] {
            for i in 0..dims[0] {
                for c in 0..channels {
                    for (axis, value) in [i, j, k, c].into_iter().enumerate() {
                        if let Some(slot) = index.get_mut(axis) {
                            *slot = value;
                        }
                    }
                    let value = image.data.get(index.as_slice()).copied().ok_or_else(|| {
                        Error::input(&image.file, "dim", "voxel index outside the data")
                    })?;
                    values.push(value as f32);
                }
            }
        }
    }
    let source = image.voxel_to_world.source;
    let volume = UnderlayVolume::new(
        image.file,
        dims,
        channels,
        values,
        image.voxel_to_world.affine,
    )?;
    Ok((volume, source))
}

/// The plane of `region`'s slice: through the voxel centres of its index along the
/// slice axis, spanning its ranges along the two other axes out to the voxel edges, in
/// world space by `map`.
pub fn slice_plane(region: &SliceRegion, map: &VoxelToWorld) -> UnderlayPlane {
    let axis = region.slice.voxel_axis();
    let (b, c) = ((axis + 1) % 3, (axis + 2) % 3);
    let mut origin = [0.0; 3];
    origin[axis] = region.index as f64;
    origin[b] = region.ranges[b].start as f64 - 0.5;
    origin[c] = region.ranges[c].start as f64 - 0.5;
    let mut u = [0.0; 3];
    u[b] = region.ranges[b].len() as f64;
    let mut v = [0.0; 3];
    v[c] = region.ranges[c].len() as f64;
    UnderlayPlane {
        origin: map.affine.transform_point3(DVec3::from(origin)),
        u: map.affine.transform_vector3(DVec3::from(u)),
        v: map.affine.transform_vector3(DVec3::from(v)),
        sample_offset: DVec3::ZERO,
    }
}

/// `plane` moved along its normal by `depth`, away from `camera`: to the back of a slab
/// of glyphs that reach `depth` out of it.
pub fn plane_behind(plane: UnderlayPlane, camera: &Camera, depth: f64) -> UnderlayPlane {
    let normal = plane.u.cross(plane.v).normalize_or_zero();
    let shift = away_from(camera, &plane, normal) * depth * (1.0 + BEHIND_MARGIN);
    UnderlayPlane {
        origin: plane.origin + shift,
        sample_offset: plane.sample_offset + shift,
        ..plane
    }
}

/// `plane` with its shift off its slice (`sample_offset`, from [`plane_behind`]) turned
/// to the slice's side away from `camera`, so that a plane behind the glyphs stays behind
/// them when a viewer's camera orbits to the other side of the slice. A plane through its
/// slice (no shift) comes back as it is.
pub fn turned_away(plane: &UnderlayPlane, camera: &Camera) -> UnderlayPlane {
    let shift = plane.sample_offset;
    let on_slice = UnderlayPlane {
        origin: plane.origin - shift,
        sample_offset: DVec3::ZERO,
        ..*plane
    };
    let shift = away_from(camera, &on_slice, shift);
    UnderlayPlane {
        origin: on_slice.origin + shift,
        sample_offset: shift,
        ..*plane
    }
}

/// `direction` or its opposite, whichever points away from `camera` at the centre of
/// `plane` (along the view direction there).
fn away_from(camera: &Camera, plane: &UnderlayPlane, direction: DVec3) -> DVec3 {
    let centre = plane.origin + 0.5 * (plane.u + plane.v);
    let towards = match camera.projection {
        Projection::Orthographic { .. } => camera.target - camera.eye,
        Projection::Perspective { .. } => centre - camera.eye,
    };
    if direction.dot(towards) < 0.0 {
        -direction
    } else {
        direction
    }
}

/// The planes of the slices `regions` of `volume`, placed by `placement` for glyphs
/// seen by `camera` that reach `glyph_radius` out of their plane.
pub fn slice_planes(
    regions: &[SliceRegion],
    volume: &Volume,
    camera: &Camera,
    glyph_radius: f64,
    placement: UnderlayPlacement,
) -> Vec<UnderlayPlane> {
    regions
        .iter()
        .map(|r| {
            let plane = slice_plane(r, &volume.voxel_to_world);
            match placement {
                UnderlayPlacement::Back => plane_behind(plane, camera, glyph_radius),
                UnderlayPlacement::Centre => plane,
            }
        })
        .collect()
}

/// The underlay of the view `scene` of `volume`: one plane per slice, placed by
/// `placement`. Errors name the underlay's file: an image placed by pixdim alone (no
/// sform or qform) beside a volume that has an affine, and an underlay that reaches none
/// of the planes in world space (a mismatched affine, or an image of another subject or
/// space).
pub fn view_underlay(
    underlay: Arc<UnderlayVolume>,
    source: AffineSource,
    volume: &Volume,
    scene: &VolumeScene,
    placement: UnderlayPlacement,
) -> Result<Underlay> {
    let glyph_source = volume.voxel_to_world.source;
    if source == AffineSource::Pixdim && glyph_source != AffineSource::Pixdim {
        return Err(Error::input(
            &underlay.file,
            "sform_code/qform_code",
            format!(
                "the underlay has no sform or qform, so its place in world space is unknown, \
                 while {} has one; give it the affine of the volume it was computed from",
                volume.file
            ),
        ));
    }
    let camera = &scene.scene.camera;
    let planes = slice_planes(
        &scene.regions,
        volume,
        camera,
        scene.glyph_radius,
        placement,
    );
    if !planes.iter().any(|p| reaches(&underlay, p)) {
        return Err(Error::input(
            &underlay.file,
            "affine",
            format!(
                "the underlay ({} voxels) does not reach the slice plane(s) of {} in world \
                 space: are both images of the same subject and space?",
                show_shape(&underlay.dims),
                volume.file
            ),
        ));
    }
    Ok(Underlay {
        volume: underlay,
        planes,
    })
}

/// Whether the box of the plane's corners, in the underlay's voxel coordinates, meets
/// the underlay's box (a necessary condition for any pixel of the plane to show it).
fn reaches(underlay: &UnderlayVolume, plane: &UnderlayPlane) -> bool {
    let corners = plane
        .corners()
        .map(|c| underlay.voxel_of(c - plane.sample_offset));
    (0..3).all(|a| {
        let lo = corners.iter().map(|c| c[a]).fold(f64::INFINITY, f64::min);
        let hi = corners
            .iter()
            .map(|c| c[a])
            .fold(f64::NEG_INFINITY, f64::max);
        hi >= -0.5 && lo <= underlay.dims[a] as f64 - 0.5
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn camera(eye: DVec3, projection: Projection) -> Camera {
        Camera {
            projection,
            eye,
            target: DVec3::new(2.0, 1.5, 0.0),
            up: DVec3::Y,
        }
    }

    /// A plane placed behind the glyphs for one camera and turned for a camera on the
    /// slice's other side is the plane placed behind them for that camera; a plane
    /// through its slice does not move.
    #[test]
    fn turned_away_is_placing_behind_for_the_new_camera() {
        let slice = UnderlayPlane {
            origin: DVec3::new(0.0, 0.0, 0.0),
            u: DVec3::new(4.0, 0.0, 0.0),
            v: DVec3::new(0.0, 3.0, 0.0),
            sample_offset: DVec3::ZERO,
        };
        for projection in [
            Projection::Orthographic { height: 5.0 },
            Projection::Perspective { fov_y_deg: 30.0 },
        ] {
            let above = camera(DVec3::new(2.0, 1.0, 9.0), projection);
            let below = camera(DVec3::new(1.0, 2.0, -9.0), projection);
            for (first, second) in [(&above, &below), (&below, &above), (&above, &above)] {
                let placed = plane_behind(slice, first, 0.7);
                let turned = turned_away(&placed, second);
                let expected = plane_behind(slice, second, 0.7);
                assert!((turned.origin - expected.origin).length() < 1e-12);
                assert!((turned.sample_offset - expected.sample_offset).length() < 1e-12);
                assert_eq!((turned.u, turned.v), (slice.u, slice.v));
                // Behind: on the far side of the slice from the eye.
                let side = (turned.origin.z - slice.origin.z) * (second.eye.z - slice.origin.z);
                assert!(side < 0.0, "the plane is on the eye's side");
            }
            assert_eq!(turned_away(&slice, &below), slice);
        }
    }
}
