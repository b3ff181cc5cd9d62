//! The float64 reference depth map: what every GPU depth map is compared with.
//!
//! Each pixel's ray (the scene format's [`Camera::ray`]) is tested against every glyph's
//! world bounding sphere (center, scale * bound); the glyphs it passes through are sorted
//! by sphere entry distance and intersected exactly ([`first_hit`]) in that order, stopping
//! as soon as the next sphere starts beyond the nearest hit found. That is a linear scan
//! over the glyphs per pixel, fine for the test scenes (< 100 glyphs); a spatial grid can
//! replace the scan without changing the results.
//!
//! Rows are handed out one at a time to `available_parallelism` scoped threads through a
//! shared iterator, so slow rows (many glyphs) do not leave threads idle.
use std::sync::Mutex;

use glam::DVec3;

use super::intersect::{BOUND_PADDING, WorldGlyph, first_hit};
use crate::camera::{Camera, Ray};

/// Float64 reference depth map: for each pixel (row-major, height rows of width), the
/// distance along the camera ray ([`Camera::ray`]) to the nearest glyph hit over all
/// glyphs, NaN for a miss.
pub fn reference_depth(
    glyphs: &[WorldGlyph],
    camera: &Camera,
    width: u32,
    height: u32,
) -> Vec<f64> {
    let mut depth = vec![f64::NAN; width as usize * height as usize];
    if depth.is_empty() {
        return depth;
    }
    let spheres: Vec<BoundingSphere> = glyphs.iter().map(BoundingSphere::of).collect();
    let rows = Mutex::new(depth.chunks_mut(width as usize).enumerate());
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
    std::thread::scope(|scope| {
        for _ in 0..threads.min(height as usize) {
            scope.spawn(|| {
                let mut candidates = Vec::new();
                while let Some((j, row)) = next_row(&rows) {
                    for (i, pixel) in row.iter_mut().enumerate() {
                        let ray = camera.ray(i as u32, j as u32, width, height);
                        *pixel = nearest_hit(&ray, glyphs, &spheres, &mut candidates)
                            .unwrap_or(f64::NAN);
                    }
                }
            });
        }
    });
    depth
}

/// The next unclaimed row; a poisoned lock (another thread panicked) still hands out rows,
/// the panic itself resurfaces when the scope joins.
fn next_row<'a, I>(rows: &Mutex<I>) -> Option<(usize, &'a mut [f64])>
where
    I: Iterator<Item = (usize, &'a mut [f64])>,
{
    rows.lock().unwrap_or_else(|e| e.into_inner()).next()
}

/// A glyph's world bounding sphere.
#[derive(Clone, Copy)]
struct BoundingSphere {
    center: DVec3,
    radius_squared: f64,
}

impl BoundingSphere {
    fn of(glyph: &WorldGlyph) -> Self {
        let radius = glyph.world_radius() * (1.0 + BOUND_PADDING);
        Self {
            center: glyph.center,
            radius_squared: if radius > 0.0 { radius * radius } else { -1.0 },
        }
    }

    /// Distance along the (unit-direction) ray at which it enters the sphere, 0 if it
    /// starts inside, or None if it misses the sphere or the sphere is behind it.
    fn entry(&self, ray: &Ray) -> Option<f64> {
        let a = ray.origin - self.center;
        let mid = -a.dot(ray.dir);
        let disc = self.radius_squared - (a + mid * ray.dir).length_squared();
        if disc.is_nan() || disc <= 0.0 {
            return None;
        }
        let half = disc.sqrt();
        (mid + half > 0.0).then_some((mid - half).max(0.0))
    }
}

/// Nearest `first_hit` over the glyphs whose bounding spheres the ray crosses.
fn nearest_hit(
    ray: &Ray,
    glyphs: &[WorldGlyph],
    spheres: &[BoundingSphere],
    candidates: &mut Vec<(f64, usize)>,
) -> Option<f64> {
    candidates.clear();
    candidates.extend(
        spheres
            .iter()
            .enumerate()
            .filter_map(|(k, s)| s.entry(ray).map(|t| (t, k))),
    );
    candidates.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut nearest: Option<f64> = None;
    for &(entry, k) in candidates.iter() {
        if nearest.is_some_and(|t| entry > t) {
            break;
        }
        if let Some(t) = first_hit(ray, &glyphs[k]) {
            nearest = Some(nearest.map_or(t, |n| n.min(t)));
        }
    }
    nearest
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::camera::Projection;
    use crate::glyph::NegativeMode;
    use crate::glyph::polynomial::GlyphPolynomial;

    fn sphere_glyph(center: DVec3, radius: f64) -> WorldGlyph {
        let poly = GlyphPolynomial {
            order: 2,
            coeffs: vec![1.0, 0.0, 0.0, 1.0, 0.0, 1.0],
        };
        WorldGlyph::new(center, radius, poly, NegativeMode::Abs, 0.0)
    }

    /// Nearest intersection with t > 0 over analytic spheres, None for a miss.
    fn analytic(ray: &Ray, spheres: &[(DVec3, f64)]) -> Option<f64> {
        spheres
            .iter()
            .filter_map(|&(c, r)| {
                let a = ray.origin - c;
                let mid = -a.dot(ray.dir);
                let disc = mid * mid - (a.length_squared() - r * r);
                (disc > 0.0).then(|| [mid - disc.sqrt(), mid + disc.sqrt()])
            })
            .flatten()
            .filter(|t| *t > 0.0)
            .min_by(f64::total_cmp)
    }

    fn check(camera: Camera, spheres: &[(DVec3, f64)], width: u32, height: u32) {
        let glyphs: Vec<_> = spheres.iter().map(|&(c, r)| sphere_glyph(c, r)).collect();
        let depth = reference_depth(&glyphs, &camera, width, height);
        assert_eq!(depth.len(), (width * height) as usize);
        let mut hits = 0;
        for j in 0..height {
            for i in 0..width {
                let got = depth[(j * width + i) as usize];
                let want = analytic(&camera.ray(i, j, width, height), spheres);
                match want {
                    Some(t) => {
                        assert!(
                            (got - t).abs() <= 1e-12 * t.max(1.0),
                            "({i}, {j}): {got} vs {t}"
                        );
                        hits += 1;
                    }
                    None => assert!(got.is_nan(), "({i}, {j}): {got} vs miss"),
                }
            }
        }
        let total = (width * height) as usize;
        assert!(
            hits > total / 10 && hits < total,
            "{hits} of {total} pixels hit"
        );
    }

    #[test]
    fn sphere_under_perspective_matches_analytic_depth() {
        let camera = Camera {
            projection: Projection::Perspective { fov_y_deg: 30.0 },
            eye: DVec3::new(0.5, -6.0, 2.0),
            target: DVec3::ZERO,
            up: DVec3::Z,
        };
        check(camera, &[(DVec3::new(0.3, -0.2, 0.1), 0.8)], 40, 30);
    }

    #[test]
    fn sphere_under_orthographic_matches_analytic_depth() {
        let camera = Camera {
            projection: Projection::Orthographic { height: 3.0 },
            eye: DVec3::new(-4.0, -3.0, 1.0),
            target: DVec3::new(0.0, 0.0, 0.5),
            up: DVec3::Z,
        };
        check(camera, &[(DVec3::new(0.3, -0.2, 0.1), 0.8)], 36, 28);
    }

    #[test]
    fn nearest_of_overlapping_spheres_wins() {
        let camera = Camera {
            projection: Projection::Perspective { fov_y_deg: 40.0 },
            eye: DVec3::new(0.0, -5.0, 0.0),
            target: DVec3::ZERO,
            up: DVec3::Z,
        };
        let spheres = [
            (DVec3::new(0.0, 0.5, 0.0), 1.0),
            (DVec3::new(0.6, -0.6, 0.2), 0.5),
            (DVec3::new(-0.8, -1.5, -0.4), 0.3),
        ];
        check(camera, &spheres, 32, 32);
    }

    /// A small sphere inside the bounding sphere of a glyph with thin lobes: rays enter the
    /// big bounding sphere first but may hit the small sphere first, so the scan must not
    /// stop at the first glyph hit. Compared with the minimum of `first_hit` over all
    /// glyphs without any culling.
    #[test]
    fn culling_and_ordering_keep_the_nearest_hit() {
        let lobes = GlyphPolynomial {
            order: 8,
            coeffs: crate::glyph::monomials::monomials(8)
                .iter()
                .map(|m| if m.a == 8 || m.b == 8 { 1.0 } else { 0.0 })
                .collect(),
        };
        let glyphs = vec![
            WorldGlyph::new(DVec3::ZERO, 1.0, lobes, NegativeMode::Abs, 0.0),
            sphere_glyph(DVec3::new(0.45, 0.45, 0.0), 0.2),
            sphere_glyph(DVec3::new(-0.5, 0.4, 0.3), 0.15),
        ];
        let camera = Camera {
            projection: Projection::Perspective { fov_y_deg: 35.0 },
            eye: DVec3::new(2.5, -1.5, 2.0),
            target: DVec3::ZERO,
            up: DVec3::Z,
        };
        let (width, height) = (32, 32);
        let depth = reference_depth(&glyphs, &camera, width, height);
        let mut reordered = 0;
        for j in 0..height {
            for i in 0..width {
                let ray = camera.ray(i, j, width, height);
                let hits: Vec<f64> = glyphs.iter().filter_map(|g| first_hit(&ray, g)).collect();
                let want = hits.iter().copied().reduce(f64::min);
                let got = depth[(j * width + i) as usize];
                match want {
                    Some(t) => assert_eq!(got, t, "({i}, {j})"),
                    None => assert!(got.is_nan(), "({i}, {j}): {got} vs miss"),
                }
                // Pixels where the lobe glyph is hit but is not the nearest.
                let lobe_hit = first_hit(&ray, &glyphs[0]);
                reordered += usize::from(lobe_hit.is_some_and(|t| want.is_some_and(|w| w < t)));
            }
        }
        assert!(
            reordered >= 3,
            "only {reordered} pixels exercise the ordering"
        );
    }

    #[test]
    fn empty_scene_and_empty_image() {
        let camera = Camera {
            projection: Projection::Perspective { fov_y_deg: 30.0 },
            eye: DVec3::new(0.0, -5.0, 0.0),
            target: DVec3::ZERO,
            up: DVec3::Z,
        };
        assert!(
            reference_depth(&[], &camera, 4, 3)
                .iter()
                .all(|d| d.is_nan())
        );
        assert!(reference_depth(&[], &camera, 0, 3).is_empty());
    }
}
