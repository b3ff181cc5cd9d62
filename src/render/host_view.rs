//! A host engine's camera as glyphcast's frame block: the host's own view and projection
//! matrices, its viewport (any sub-rectangle of its target) and its depth convention.
//!
//! The ray casters shade one ray per pixel (or per sample), built from an eye, a forward
//! axis and the right/up steps per unit of normalised device coordinates
//! (glsl/pixel_ray.glsl); the depth they write is the host's clip space divided by w
//! (`frame.view_proj`), so it lands in the host's convention, finite or infinite far
//! plane alike. What is read from the projection: the x and y scales (P00, P11), whether
//! it is perspective (w = +-z) or orthographic (w = 1), and where its near plane lies.
//! Off-centre and skewed projections (a lens shift, a jittered frustum) have no such
//! frame and are refused, as is a view matrix that is not a rotation and translation.
use crate::error::{Error, Result};
use crate::render::frame::{FrameParams, SceneExtent};
use crate::render::settings::RenderSettings;
use crate::render::shaders::DepthConvention;
use ash::vk;
use glam::{DMat4, DVec3};

/// The host's camera for one frame.
#[derive(Clone, Copy, Debug)]
pub struct HostView {
    /// World to view space: a rotation and a translation.
    pub view: DMat4,
    /// View to Vulkan clip space (y down, depth 0 to 1 in the renderer's convention),
    /// perspective or orthographic, centred.
    pub projection: DMat4,
    /// The viewport the frame is drawn in: any rectangle of the target, depth range 0 to
    /// 1; a negative height flips y as Vulkan defines.
    pub viewport: vk::Viewport,
    /// The scissor rectangle.
    pub scissor: vk::Rect2D,
}

impl HostView {
    /// The whole of a `width` x `height` target as viewport and scissor.
    pub fn whole(view: DMat4, projection: DMat4, width: u32, height: u32) -> HostView {
        let extent = vk::Extent2D { width, height };
        let (viewport, scissor) = crate::render::raycast::viewport_and_scissor(extent);
        HostView {
            view,
            projection,
            viewport,
            scissor,
        }
    }
}

/// A right-handed view matrix (the camera looks along -z, y up) from `eye` towards
/// `target`: what most engines' look-at gives.
pub fn look_at(eye: DVec3, target: DVec3, up: DVec3) -> DMat4 {
    let f = (target - eye).normalize();
    let s = f.cross(up).normalize();
    let u = s.cross(f);
    DMat4::from_cols(
        glam::DVec4::new(s.x, u.x, -f.x, 0.0),
        glam::DVec4::new(s.y, u.y, -f.y, 0.0),
        glam::DVec4::new(s.z, u.z, -f.z, 0.0),
        glam::DVec4::new(-s.dot(eye), -u.dot(eye), f.dot(eye), 1.0),
    )
}

/// A Vulkan perspective projection (y down, depth 0 to 1) for a right-handed view:
/// vertical field of view `fov_y` (radians), `aspect` = width / height, the near plane,
/// a far plane or none (infinite), in `depth`'s convention.
pub fn perspective(
    fov_y: f64,
    aspect: f64,
    near: f64,
    far: Option<f64>,
    depth: DepthConvention,
) -> DMat4 {
    let h = 1.0 / (0.5 * fov_y).tan();
    // Window depth = (P22 z + P32) / -z for view depth z < 0.
    let (p22, p32) = match (depth, far) {
        (DepthConvention::Standard, Some(f)) => (f / (near - f), near * f / (near - f)),
        (DepthConvention::Standard, None) => (-1.0, -near),
        (DepthConvention::Reversed, Some(f)) => (near / (f - near), near * f / (f - near)),
        (DepthConvention::Reversed, None) => (0.0, near),
    };
    DMat4::from_cols(
        glam::DVec4::new(h / aspect, 0.0, 0.0, 0.0),
        glam::DVec4::new(0.0, -h, 0.0, 0.0),
        glam::DVec4::new(0.0, 0.0, p22, -1.0),
        glam::DVec4::new(0.0, 0.0, p32, 0.0),
    )
}

/// Relative tolerance for the projection entries that must be zero.
const ZERO: f64 = 1e-9;

/// The host's view refused: an [`Error::Input`] of the "host view" naming `field`.
fn refuse(field: &str, what: impl Into<crate::error::Message>) -> Error {
    Error::input("host view", field, what)
}

/// Whether the projection is perspective (`Some(sign)`: w = sign * z_view) or
/// orthographic (`None`), after checking it is centred and unskewed.
fn projection_kind(p: &[[f64; 4]; 4]) -> Result<Option<f64>> {
    let scale = p[0][0].abs().max(p[1][1].abs());
    if !(scale.is_finite() && scale > 0.0 && p[0][0] != 0.0 && p[1][1] != 0.0) {
        return Err(refuse(
            "projection",
            "the projection has no x or y scale (P00, P11)",
        ));
    }
    let zero = |v: f64| v.abs() <= ZERO * scale;
    // p[column][row]: x and y rows read only x and y (and the centre offsets below).
    let skew = [p[1][0], p[0][1], p[0][2], p[1][2], p[0][3], p[1][3]];
    if !skew.iter().all(|&v| zero(v)) {
        return Err(refuse(
            "view",
            "the projection mixes axes (a rotated or skewed projection): put rotations in \
             the view matrix",
        ));
    }
    let (w_z, w_one) = (p[2][3], p[3][3]);
    let kind = if zero(w_one) && (w_z.abs() - 1.0).abs() <= 1e-9 {
        Some(w_z.signum())
    } else if zero(w_z) && (w_one - 1.0).abs() <= 1e-9 {
        None
    } else {
        return Err(refuse(
            "projection",
            "the projection is neither perspective (w = -z or z) nor orthographic (w = 1)",
        ));
    };
    // Perspective centre offsets sit in column 2, orthographic ones in column 3.
    let (cx, cy) = match kind {
        Some(_) => (p[2][0], p[2][1]),
        None => (p[3][0], p[3][1]),
    };
    if !(zero(cx) && zero(cy)) {
        return Err(refuse(
            "projection",
            "the projection is off-centre (a lens shift or jitter); glyphcast's rays start \
             from a centred frustum",
        ));
    }
    Ok(kind)
}

/// The frame block for the host's view: its camera, the magnitude range from
/// `max_radius` (the largest glyph radius) and the march, colour and lighting of
/// `settings`, glyph depth written in `depth`.
pub(crate) fn host_frame(
    view: &HostView,
    depth: DepthConvention,
    max_radius: f64,
    settings: &RenderSettings,
) -> Result<FrameParams> {
    let vp = &view.viewport;
    if !(vp.width > 0.0 && vp.height != 0.0 && vp.width.is_finite() && vp.height.is_finite()) {
        return Err(refuse(
            "viewport",
            format!(
                "the viewport is {} x {} pixels; it needs a positive width and a height",
                vp.width, vp.height
            ),
        ));
    }
    if (vp.min_depth, vp.max_depth) != (0.0, 1.0) {
        return Err(refuse(
            "viewport",
            format!(
                "the viewport's depth range is {} to {}; glyphs write depth for 0 to 1",
                vp.min_depth, vp.max_depth
            ),
        ));
    }
    let p = view.projection.to_cols_array_2d();
    let perspective = projection_kind(&p)?;
    let to_world = view.view.inverse();
    let axis = |k: usize| to_world.col(k).truncate();
    let (x, y, z) = (axis(0), axis(1), axis(2));
    let rigid = [x.length(), y.length(), z.length()]
        .iter()
        .all(|l| (l - 1.0).abs() < 1e-6)
        && x.dot(y).abs() < 1e-6
        && x.dot(z).abs() < 1e-6
        && y.dot(z).abs() < 1e-6;
    if !rigid || !to_world.is_finite() {
        return Err(refuse(
            "view",
            "the view matrix is not a rotation and a translation (no scale or shear)",
        ));
    }
    let eye = to_world.col(3).truncate();
    let near_depth = f64::from(depth.near_depth());
    let (fwd, near) = match perspective {
        Some(sign) => {
            // Window depth at view depth d in front (z = sign d): P22 sign + P32 / d. It
            // falls with distance under reversed depth (P32 > 0), rises under standard.
            let falls = p[3][2] > 0.0;
            if falls != (depth == DepthConvention::Reversed) || p[3][2] == 0.0 {
                return Err(refuse(
                    "projection",
                    format!(
                        "the projection's depth does not follow {depth:?} depth (near at {})",
                        near_depth
                    ),
                ));
            }
            // The near plane: the view depth whose window depth is the near end.
            let z_near = p[3][2] / (near_depth * sign - p[2][2]);
            (z * sign, z_near * sign)
        }
        None => {
            // Window depth p22 z + p32: forward is where it moves towards the far end.
            let towards_far = if depth == DepthConvention::Reversed {
                -1.0
            } else {
                1.0
            };
            (z * (p[2][2].signum() * towards_far), 0.0)
        }
    };
    // A window position's NDC x times right (and NDC y times -up) is the ray's offset per
    // unit of forward distance (perspective) or of world length (orthographic).
    let right = x / p[0][0];
    let up = -y / p[1][1];
    let screen_up = up * f64::from(vp.height.signum());
    let lighting = &settings.lighting;
    let [lx, ly, lz] = lighting.unit_direction().map(f64::from);
    let light = (lx * right.normalize() + ly * screen_up.normalize() - lz * fwd).normalize();
    let v4 = |v: DVec3, w: f32| [v.x as f32, v.y as f32, v.z as f32, w];
    let extent = SceneExtent {
        near: near.max(0.0),
        far: f64::INFINITY,
        max_radius,
    };
    // One pixel spans 2 / (|P11| |height|) at unit distance (world units if orthographic).
    let pixel = 2.0 / (p[1][1].abs() * f64::from(vp.height.abs()));
    Ok(FrameParams {
        view_proj: (view.projection * view.view).as_mat4().to_cols_array_2d(),
        eye: v4(eye, if perspective.is_some() { 0.0 } else { 1.0 }),
        // w: the aspect factor of pixel_ray.glsl, folded into `right` here.
        right: v4(right, 1.0),
        up: v4(up, 0.0),
        fwd: v4(fwd, 0.0),
        viewport: [1.0 / vp.width, 1.0 / vp.height, extent.near as f32, 0.0],
        light: v4(light, 0.0),
        robust: [settings.precision_px * pixel as f32, 0.0, 0.0, 0.0],
        window: [vp.x, vp.y, depth.near_depth(), 0.0],
        ..FrameParams::of_settings(&extent, settings)
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::camera::{Camera, Projection};

    fn camera() -> Camera {
        Camera {
            projection: Projection::Perspective { fov_y_deg: 40.0 },
            eye: DVec3::new(1.0, -3.0, 2.0),
            target: DVec3::new(0.2, 0.1, -0.3),
            up: DVec3::Z,
        }
    }

    /// A Vulkan perspective (y down) of the camera's in the given convention.
    fn host(depth: DepthConvention, infinite: bool) -> HostView {
        let c = camera();
        let view = look_at(c.eye, c.target, c.up);
        let far = (!infinite).then_some(30.0);
        let projection = perspective(40f64.to_radians(), 1.6, 0.5, far, depth);
        HostView::whole(view, projection, 160, 100)
    }

    /// The host's matrices give the rays of the scene format's camera they were made
    /// from, and the near plane at 0.5, in all four depth conventions.
    #[test]
    fn host_matrices_give_the_cameras_rays() {
        let settings = RenderSettings::default();
        let c = camera();
        let extent = SceneExtent {
            near: 0.5,
            far: 30.0,
            max_radius: 1.0,
        };
        let own = FrameParams::new(&c, 160, 100, &extent, &settings);
        for depth in [DepthConvention::Standard, DepthConvention::Reversed] {
            for infinite in [false, true] {
                let f = host_frame(&host(depth, infinite), depth, 1.0, &settings).unwrap();
                let close =
                    |a: [f32; 4], b: [f32; 4], n: usize| (0..n).all(|k| (a[k] - b[k]).abs() < 1e-5);
                assert!(close(f.eye, own.eye, 4));
                assert!(close(f.fwd, own.fwd, 3));
                assert!(close(f.up, own.up, 3));
                // The host folds the aspect into `right`.
                let aspect_right = own.right.map(|v| v * own.right[3]);
                assert!(
                    close(f.right, aspect_right, 3),
                    "{:?} {:?}",
                    f.right,
                    own.right
                );
                assert!(close(f.light, own.light, 3));
                assert!((f.viewport[2] - 0.5).abs() < 1e-5, "{depth:?} {infinite}");
                assert!((f.robust[0] - own.robust[0]).abs() < 1e-9);
                assert_eq!(f.window[2], depth.near_depth());
            }
        }
    }

    /// The helpers' matrices are those of the scene format's camera: their reversed
    /// infinite view-projection equals `Camera::view_projection`'s.
    #[test]
    fn helper_matrices_match_the_camera() {
        let c = camera();
        let ours = c.view_projection(160, 100, 0.5, 30.0);
        let view = look_at(c.eye, c.target, c.up);
        let projection = perspective(
            40f64.to_radians(),
            1.6,
            0.5,
            None,
            DepthConvention::Reversed,
        );
        let host = projection * view;
        let diff = (ours - host)
            .to_cols_array()
            .iter()
            .map(|v| v.abs())
            .fold(0.0, f64::max);
        assert!(diff < 1e-12, "{ours:?} {host:?}");
    }

    /// Projections that do not fit the convention, or have no centred frustum, are refused.
    #[test]
    fn mismatched_or_off_centre_projections_are_refused() {
        let settings = RenderSettings::default();
        let standard = host(DepthConvention::Standard, false);
        let err = host_frame(&standard, DepthConvention::Reversed, 1.0, &settings);
        assert!(err.unwrap_err().to_string().contains("Reversed"));
        let mut shifted = standard;
        shifted.projection.z_axis.x = 0.1;
        let err = host_frame(&shifted, DepthConvention::Standard, 1.0, &settings);
        assert!(err.unwrap_err().to_string().contains("off-centre"));
        let mut scaled = standard;
        scaled.view = DMat4::from_scale(DVec3::splat(2.0)) * scaled.view;
        let err = host_frame(&scaled, DepthConvention::Standard, 1.0, &settings);
        assert!(err.unwrap_err().to_string().contains("rotation"));
    }
}
