//! The scene format's camera: one ray per pixel centre, and the matching Vulkan
//! view-projection so that the rasterised bounding boxes cover exactly those rays.
use glam::{DMat4, DVec3, DVec4, Mat4};

/// How the camera maps pixels to rays.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Projection {
    /// Rays from the eye through a view plane.
    Perspective {
        /// Full vertical field of view, in degrees.
        fov_y_deg: f64,
    },
    /// Parallel rays along the forward axis, from a rectangle centred on the eye.
    Orthographic {
        /// Height of the visible rectangle, in world units (its width follows the aspect).
        height: f64,
    },
}

/// A camera as the scene format gives it, in world coordinates.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    /// Perspective or orthographic, with its extent.
    pub projection: Projection,
    /// Eye position: the ray origin in perspective, the view centre in orthographic.
    pub eye: DVec3,
    /// A point the camera looks at; the forward axis is `target - eye`.
    pub target: DVec3,
    /// Approximate up direction; [`Camera::frame`] makes it orthogonal to forward.
    pub up: DVec3,
}

/// A ray with unit direction; points are origin + t * dir.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ray {
    /// Start point of the ray.
    pub origin: DVec3,
    /// Unit direction.
    pub dir: DVec3,
}

/// Orthonormal camera frame: forward, right and the corrected up (scene format).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CameraFrame {
    /// Unit vector from the eye towards the target.
    pub fwd: DVec3,
    /// Unit vector `fwd x up`: screen x grows along it.
    pub right: DVec3,
    /// Unit vector `right x fwd`: screen y grows along it.
    pub up: DVec3,
}

impl Camera {
    /// The orthonormal frame of this camera (forward, right, corrected up).
    pub fn frame(&self) -> CameraFrame {
        let fwd = (self.target - self.eye).normalize();
        let right = fwd.cross(self.up).normalize();
        CameraFrame {
            fwd,
            right,
            up: right.cross(fwd),
        }
    }

    /// Screen coordinates (sx, sy) of the centre of pixel (i, j), as the format defines.
    pub fn screen(i: u32, j: u32, width: u32, height: u32) -> (f64, f64) {
        let (w, h) = (width as f64, height as f64);
        let sx = (2.0 * (i as f64 + 0.5) / w - 1.0) * w / h;
        let sy = 1.0 - 2.0 * (j as f64 + 0.5) / h;
        (sx, sy)
    }

    /// The ray through the centre of pixel (i, j): column i from the left, row j from the top.
    pub fn ray(&self, i: u32, j: u32, width: u32, height: u32) -> Ray {
        let f = self.frame();
        let (sx, sy) = Self::screen(i, j, width, height);
        match self.projection {
            Projection::Perspective { fov_y_deg } => {
                let k = (fov_y_deg.to_radians() * 0.5).tan();
                Ray {
                    origin: self.eye,
                    dir: (f.fwd + k * (sx * f.right + sy * f.up)).normalize(),
                }
            }
            Projection::Orthographic { height } => Ray {
                origin: self.eye + 0.5 * height * (sx * f.right + sy * f.up),
                dir: f.fwd,
            },
        }
    }

    /// World to Vulkan clip space (y down), written from the ray definition above so that
    /// pixel centres see exactly the rays of [`Camera::ray`]. Depth is reversed: 1 at
    /// `near` along the forward axis, falling towards 0 far away. In perspective it is
    /// near / e for eye depth e, with no far plane, so float32 depth keeps the same
    /// relative precision at every distance (scenes whose sizes and distances span 10^6
    /// and more); orthographic depth falls linearly from 1 at `near` to 0 at `far`.
    pub fn view_projection(&self, width: u32, height: u32, near: f64, far: f64) -> DMat4 {
        let f = self.frame();
        let aspect = width as f64 / height as f64;
        // Eye-space rows: ex = right.(p - eye), ey = up.(p - eye), ez = fwd.(p - eye).
        let row = |axis: DVec3| DVec4::new(axis.x, axis.y, axis.z, -axis.dot(self.eye));
        let (ex, ey, ez) = (row(f.right), row(f.up), row(f.fwd));
        let rows = match self.projection {
            Projection::Perspective { fov_y_deg } => {
                let k = (fov_y_deg.to_radians() * 0.5).tan();
                [ex / (k * aspect), -ey / k, DVec4::W * near, ez]
            }
            Projection::Orthographic { height } => {
                let half = 0.5 * height;
                [
                    ex / (half * aspect),
                    -ey / half,
                    (DVec4::W * far - ez) / (far - near),
                    DVec4::W,
                ]
            }
        };
        DMat4::from_cols(rows[0], rows[1], rows[2], rows[3]).transpose()
    }

    /// Single-precision view-projection for the GPU.
    pub fn view_projection_f32(&self, width: u32, height: u32, near: f64, far: f64) -> Mat4 {
        self.view_projection(width, height, near, far).as_mat4()
    }
}
