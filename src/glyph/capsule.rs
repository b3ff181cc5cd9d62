//! The capsule that draws one fibre peak (`render::peaks`): the points within `radius`
//! of the segment from `a` to `b`, intersected with a ray in closed form, in float64.
//! This is the reference the peaks pass's fragment shader (glsl/peaks.frag) is held to;
//! both work in the same frame and by the same steps.
//!
//! The ray is taken from its point closest to the capsule's midpoint m, q(s) = q0 + s d
//! with q0 = o + t_m d - m, so that the numbers stay of the capsule's size however far
//! the camera is (as the glyph ray casters do, `raycast_common.glsl`). Along it the
//! distance to the axis line (unit u, half length h) is a quadratic in s: the entry
//! into the infinite cylinder is its smaller root, and it is the capsule's entry where
//! its axial coordinate y lies in [-h, h]; beyond either end the entry is on that end's
//! hemisphere. A ray that misses the infinite cylinder misses the capsule (the capsule
//! lies inside it). A ray parallel to the axis (|d x u|^2 below `PARALLEL`) meets an
//! end cap or nothing.
use crate::camera::Ray;
use glam::DVec3;

/// |d x u|^2 below which a ray counts as parallel to the capsule's axis.
pub(crate) const PARALLEL: f64 = 1e-12;

/// The points within `radius` of the segment from `a` to `b`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Capsule {
    /// One end of the axis, world space.
    pub a: DVec3,
    /// The other end.
    pub b: DVec3,
    /// Distance of the surface from the axis, world units (> 0).
    pub radius: f64,
}

/// Where a ray enters a capsule.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CapsuleHit {
    /// Distance along the ray (unit direction) from its origin.
    pub t: f64,
    /// Unit outward normal there.
    pub normal: DVec3,
}

impl Capsule {
    /// The capsule of a segment through `center` along `half` (from center - half to
    /// center + half).
    pub fn through(center: DVec3, half: DVec3, radius: f64) -> Capsule {
        Capsule {
            a: center - half,
            b: center + half,
            radius,
        }
    }

    /// Midpoint of the axis.
    pub fn center(&self) -> DVec3 {
        0.5 * (self.a + self.b)
    }

    /// Radius of the smallest sphere about the midpoint that holds the capsule.
    pub fn bounding_radius(&self) -> f64 {
        0.5 * (self.b - self.a).length() + self.radius
    }

    /// The first point in front of the ray's origin where it enters the capsule, if any
    /// (a ray that starts inside gets none: cameras look at peaks from outside).
    pub fn intersect(&self, ray: &Ray) -> Option<CapsuleHit> {
        let m = self.center();
        let axis = 0.5 * (self.b - self.a);
        let h = axis.length();
        let u = if h > 0.0 { axis / h } else { DVec3::Z };
        let d = ray.dir;
        let t_mid = (m - ray.origin).dot(d);
        let q0 = ray.origin + t_mid * d - m;
        let r2 = self.radius * self.radius;
        // Components across the axis.
        let q_across = q0 - q0.dot(u) * u;
        let d_across = d - d.dot(u) * u;
        let a = d_across.dot(d_across);
        let b = q_across.dot(d_across);
        let c = q_across.dot(q_across) - r2;
        let end = if a < PARALLEL {
            if c > 0.0 {
                return None;
            }
            // Entering along the axis: through the end the ray comes from.
            if d.dot(u) > 0.0 { -h } else { h }
        } else {
            let disc = b * b - a * c;
            if disc < 0.0 {
                return None;
            }
            let s = (-b - disc.sqrt()) / a;
            let y = (q0 + s * d).dot(u);
            if y.abs() <= h {
                let p = q0 + s * d;
                return hit(t_mid + s, (p - y * u) / self.radius);
            }
            if y < 0.0 { -h } else { h }
        };
        // The hemisphere about the end at `end` along u.
        let qc = q0 - end * u;
        let bc = qc.dot(d);
        let cc = qc.dot(qc) - r2;
        let disc = bc * bc - cc;
        if disc < 0.0 {
            return None;
        }
        let s = -bc - disc.sqrt();
        hit(t_mid + s, (qc + s * d) / self.radius)
    }
}

fn hit(t: f64, normal: DVec3) -> Option<CapsuleHit> {
    (t >= 0.0).then(|| CapsuleHit {
        t,
        normal: normal.normalize(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ray(origin: [f64; 3], dir: [f64; 3]) -> Ray {
        Ray {
            origin: DVec3::from(origin),
            dir: DVec3::from(dir).normalize(),
        }
    }

    #[test]
    fn side_caps_and_misses() {
        let capsule = Capsule {
            a: DVec3::new(-1.0, 0.0, 0.0),
            b: DVec3::new(1.0, 0.0, 0.0),
            radius: 0.25,
        };
        // Down onto the side: the cylinder at z = 0.25.
        let side = capsule
            .intersect(&ray([0.3, 0.0, 5.0], [0.0, 0.0, -1.0]))
            .expect("side");
        assert!((side.t - 4.75).abs() < 1e-12);
        assert!((side.normal - DVec3::Z).length() < 1e-12);
        // Onto the cap beyond b: the sphere about (1, 0, 0) at x = 1.1.
        let cap = capsule
            .intersect(&ray([1.1, 0.0, 5.0], [0.0, 0.0, -1.0]))
            .expect("cap");
        let z = (0.0625f64 - 0.01).sqrt();
        assert!((cap.t - (5.0 - z)).abs() < 1e-12, "{}", cap.t);
        // Beyond the cap, and beside the side.
        assert!(
            capsule
                .intersect(&ray([1.3, 0.0, 5.0], [0.0, 0.0, -1.0]))
                .is_none()
        );
        assert!(
            capsule
                .intersect(&ray([0.0, 0.3, 5.0], [0.0, 0.0, -1.0]))
                .is_none()
        );
        // Along the axis: the tip of the cap at x = -1.25; behind the ray: nothing.
        let along = capsule
            .intersect(&ray([-5.0, 0.1, 0.0], [1.0, 0.0, 0.0]))
            .expect("along");
        let x = (0.0625f64 - 0.01).sqrt();
        assert!((along.t - (5.0 - 1.0 - x)).abs() < 1e-12);
        assert!(
            capsule
                .intersect(&ray([-5.0, 0.0, 0.0], [-1.0, 0.0, 0.0]))
                .is_none()
        );
    }

    #[test]
    fn entry_is_the_nearest_surface_point_on_the_ray() {
        // Against a dense march of the distance to the segment.
        let capsule = Capsule {
            a: DVec3::new(0.2, -0.4, 0.1),
            b: DVec3::new(-0.3, 0.5, 0.6),
            radius: 0.15,
        };
        let distance = |p: DVec3| {
            let ab = capsule.b - capsule.a;
            let f = ((p - capsule.a).dot(ab) / ab.dot(ab)).clamp(0.0, 1.0);
            (p - capsule.a - f * ab).length()
        };
        for k in 0..200 {
            let x = -0.6 + 1.2 * (k as f64) / 199.0;
            let r = ray([x, 0.05 * k as f64 % 1.0 - 0.5, 3.0], [0.1, 0.05, -1.0]);
            let marched = (0..60_000)
                .map(|n| n as f64 * 1e-4)
                .find(|&t| distance(r.origin + t * r.dir) <= capsule.radius);
            match (capsule.intersect(&r), marched) {
                (Some(hit), Some(t)) => assert!((hit.t - t).abs() < 2e-4, "{x}: {} {t}", hit.t),
                (None, None) => {}
                (hit, t) => {
                    // A graze within the march's step of the silhouette only.
                    let p = r.origin + hit.map_or(t.unwrap_or(0.0), |h| h.t) * r.dir;
                    assert!(
                        (distance(p) - capsule.radius).abs() < 1e-3,
                        "{x}: {hit:?} {t:?}"
                    );
                }
            }
        }
    }
}
