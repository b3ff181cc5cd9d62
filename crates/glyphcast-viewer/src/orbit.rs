//! Mouse camera control on the scene format's [`Camera`]: orbit about the target, pan in
//! the view plane, zoom. Orbiting turns the eye and the up vector together about the
//! camera's own axes (a trackball), so there is no pole where the view flips.
use glam::{DQuat, DVec3};
use glyphcast::camera::{Camera, Projection};

/// A drag across the whole window height turns the view by half a turn.
const RADIANS_PER_HEIGHT: f64 = std::f64::consts::PI;

/// Turns the camera about its target by a drag of (dx, dy) pixels in a window
/// `height` pixels high: dragging right turns the scene right, dragging down tips it
/// towards the viewer.
pub fn orbit(camera: &mut Camera, dx: f64, dy: f64, height: u32) {
    let f = camera.frame();
    let scale = RADIANS_PER_HEIGHT / f64::from(height.max(1));
    let turn =
        DQuat::from_axis_angle(f.up, -dx * scale) * DQuat::from_axis_angle(f.right, -dy * scale);
    let offset = camera.eye - camera.target;
    camera.eye = camera.target + turn * offset;
    camera.up = (turn * f.up).normalize();
}

/// World units per pixel at the target's depth.
fn pixel_size(camera: &Camera, height: u32) -> f64 {
    let view_height = match camera.projection {
        Projection::Orthographic { height } => height,
        Projection::Perspective { fov_y_deg } => {
            2.0 * (fov_y_deg.to_radians() * 0.5).tan() * (camera.target - camera.eye).length()
        }
    };
    view_height / f64::from(height.max(1))
}

/// Slides eye and target so that the point under the cursor follows a drag of (dx, dy)
/// pixels (x right, y down).
pub fn pan(camera: &mut Camera, dx: f64, dy: f64, height: u32) {
    let f = camera.frame();
    let shift = pixel_size(camera, height) * (-dx * f.right + dy * f.up);
    camera.eye += shift;
    camera.target += shift;
}

/// Zooms in for `factor` < 1: the eye moves towards the target (perspective), or the
/// view height shrinks (orthographic).
pub fn zoom(camera: &mut Camera, factor: f64) {
    match &mut camera.projection {
        Projection::Orthographic { height } => *height = (*height * factor).max(1e-9),
        Projection::Perspective { .. } => {
            let offset: DVec3 = camera.eye - camera.target;
            let length = (offset.length() * factor).max(1e-6);
            camera.eye = camera.target + offset.normalize() * length;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn camera(projection: Projection) -> Camera {
        Camera {
            projection,
            eye: DVec3::new(0.0, -5.0, 0.0),
            target: DVec3::new(0.0, 0.0, 0.0),
            up: DVec3::Z,
        }
    }

    #[test]
    fn orbit_keeps_the_distance_and_a_valid_frame() {
        let mut c = camera(Projection::Perspective { fov_y_deg: 30.0 });
        // Over the pole and beyond: the frame stays orthonormal.
        for _ in 0..50 {
            orbit(&mut c, 13.0, 41.0, 400);
        }
        assert!(((c.eye - c.target).length() - 5.0).abs() < 1e-9);
        let f = c.frame();
        assert!(f.fwd.dot(f.up).abs() < 1e-9 && (f.up.length() - 1.0).abs() < 1e-9);
        // A drag of half the height to the right is a quarter turn about the up axis.
        let mut c = camera(Projection::Perspective { fov_y_deg: 30.0 });
        orbit(&mut c, 200.0, 0.0, 400);
        assert!(
            (c.eye - DVec3::new(-5.0, 0.0, 0.0)).length() < 1e-9,
            "{:?}",
            c.eye
        );
    }

    #[test]
    fn pan_moves_the_scene_with_the_cursor() {
        let mut c = camera(Projection::Orthographic { height: 4.0 });
        pan(&mut c, 100.0, 0.0, 400);
        // 4 world units over 400 pixels: 1 unit; dragging right moves the camera left.
        assert!((c.target - DVec3::new(-1.0, 0.0, 0.0)).length() < 1e-12);
        assert!((c.eye - DVec3::new(-1.0, -5.0, 0.0)).length() < 1e-12);
    }

    #[test]
    fn zoom_scales_the_view() {
        let mut c = camera(Projection::Orthographic { height: 4.0 });
        zoom(&mut c, 0.5);
        assert_eq!(c.projection, Projection::Orthographic { height: 2.0 });
        let mut c = camera(Projection::Perspective { fov_y_deg: 30.0 });
        zoom(&mut c, 0.5);
        assert!((c.eye - DVec3::new(0.0, -2.5, 0.0)).length() < 1e-12);
    }
}
