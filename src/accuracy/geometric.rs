//! Geometric error of a render in screen pixels: how far the surface it drew lies from the
//! true glyph surface, and how far its silhouettes lie from the float64 reference's. This
//! is the error a tessellation level is chosen by (a level is good enough when its error
//! is below half a pixel), and it applies unchanged to the ray caster and the impostor.
//!
//! - Surface: each drawn pixel's point p = ray(t) is attributed to the glyph it lies
//!   nearest to, and its distance from that glyph's surface is estimated from the radial
//!   form: with q = (p - c) / scale and u = q / |q|, the surface is at r(u) u, so p is
//!   |r(u) - |q|| from it along u, and |r(u) - |q|| |n . u| along the surface normal n
//!   (first order; exact for a sphere). Unlike a depth difference along the ray, this
//!   does not blow up where rays graze the surface. In pixels, each distance is divided by
//!   the world size of a pixel at p's depth.
//! - Silhouettes: the symmetric difference of the rendered and reference coverage masks
//!   (every pixel, the silhouette band included), divided by the length of the
//!   reference's silhouettes in pixels, is the mean distance between the two silhouettes
//!   in pixels. The length is the number of 4-neighbour pixel pairs across the reference's
//!   silhouette times pi/4 (Cauchy-Crofton: such counts overestimate the length of a
//!   curve of uniformly distributed orientation by 4/pi).
use crate::camera::{Camera, Projection};
use crate::glyph::intersect::WorldGlyph;
use crate::glyph::tessellate::surface_point;
use glam::DVec3;

/// The geometric error of one render against the reference.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct GeometricError {
    /// Largest distance of a drawn point from the true surface, world units.
    pub surface_max: f64,
    /// The same distances in pixels at the point's depth: the largest and the 99th
    /// percentile.
    pub surface_max_px: f64,
    /// The 99th percentile of those distances in pixels (see `surface_max_px`).
    pub surface_p99_px: f64,
    /// Pixels whose coverage differs from the reference.
    pub coverage_mismatch: usize,
    /// Length of the reference's silhouettes, pixels.
    pub silhouette_length_px: f64,
    /// Mean distance between the rendered and the reference silhouettes, pixels.
    pub silhouette_mean_px: f64,
}

impl GeometricError {
    /// One number per render: the larger of the largest surface distance and the mean
    /// silhouette distance, in pixels.
    pub fn pixels(&self) -> f64 {
        self.surface_max_px.max(self.silhouette_mean_px)
    }
}

impl std::fmt::Display for GeometricError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "surface error max {:.3e} ({:.3} px, p99 {:.3} px), silhouettes {:.3} px apart \
             ({} px differ over {:.0} px of silhouette)",
            self.surface_max,
            self.surface_max_px,
            self.surface_p99_px,
            self.silhouette_mean_px,
            self.coverage_mismatch,
            self.silhouette_length_px
        )
    }
}

/// Measures `rendered` (distances along the pixel rays, NaN = miss) against the glyphs
/// and their float64 reference depth map `reference` (NaN = miss), both row-major.
pub fn geometric_error(
    rendered: &[f32],
    reference: &[f64],
    glyphs: &[WorldGlyph],
    camera: &Camera,
    width: u32,
    height: u32,
) -> GeometricError {
    let mut distances = surface_distances(rendered, glyphs, camera, width, height);
    distances.sort_by(|a, b| a.0.total_cmp(&b.0));
    let surface_max = distances.iter().map(|d| d.1).fold(0.0, f64::max);
    let surface_max_px = distances.last().map_or(0.0, |d| d.0);
    let surface_p99_px = distances
        .get(((distances.len() as f64 - 1.0) * 0.99).round().max(0.0) as usize)
        .map_or(0.0, |d| d.0);

    let (w, h) = (width as usize, height as usize);
    let covered = |k: usize| !reference[k].is_nan();
    let coverage_mismatch = rendered
        .iter()
        .zip(reference)
        .filter(|(r, e)| r.is_nan() != e.is_nan())
        .count();
    let mut crossings = 0usize;
    for y in 0..h {
        for x in 0..w {
            let k = y * w + x;
            if x + 1 < w && covered(k) != covered(k + 1) {
                crossings += 1;
            }
            if y + 1 < h && covered(k) != covered(k + w) {
                crossings += 1;
            }
        }
    }
    let silhouette_length_px = crossings as f64 * std::f64::consts::FRAC_PI_4;
    let silhouette_mean_px = if silhouette_length_px > 0.0 {
        coverage_mismatch as f64 / silhouette_length_px
    } else if coverage_mismatch > 0 {
        f64::INFINITY
    } else {
        0.0
    };
    GeometricError {
        surface_max,
        surface_max_px,
        surface_p99_px,
        coverage_mismatch,
        silhouette_length_px,
        silhouette_mean_px,
    }
}

/// (pixels, world units) from each drawn point to the nearest glyph surface; rows are
/// shared out to scoped threads in contiguous runs.
fn surface_distances(
    rendered: &[f32],
    glyphs: &[WorldGlyph],
    camera: &Camera,
    width: u32,
    height: u32,
) -> Vec<(f64, f64)> {
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
    let rows_per_thread = (height as usize).div_ceil(threads).max(1);
    let row_len = width as usize;
    std::thread::scope(|scope| {
        let handles: Vec<_> = rendered
            .chunks(rows_per_thread * row_len)
            .enumerate()
            .map(|(run, pixels)| {
                scope.spawn(move || {
                    let first_row = run * rows_per_thread;
                    let mut out = Vec::new();
                    for (k, &t) in pixels.iter().enumerate() {
                        if t.is_nan() {
                            continue;
                        }
                        let (i, j) = ((k % row_len) as u32, (first_row + k / row_len) as u32);
                        let ray = camera.ray(i, j, width, height);
                        let p = ray.origin + t as f64 * ray.dir;
                        let world = distance_to_surface(glyphs, p);
                        out.push((world / pixel_size(camera, height, p), world));
                    }
                    out
                })
            })
            .collect();
        handles
            .into_iter()
            .flat_map(|h| h.join().unwrap_or_else(|e| std::panic::resume_unwind(e)))
            .collect()
    })
}

/// The distance (first order, along the normal) from `p` to the surface of the glyph
/// whose bounding sphere holds it and whose surface is nearest; a point outside every
/// bounding sphere gets its distance to the nearest sphere, a lower bound.
fn distance_to_surface(glyphs: &[WorldGlyph], p: DVec3) -> f64 {
    let mut best = f64::INFINITY;
    let mut outside = f64::INFINITY;
    for glyph in glyphs {
        let radius = glyph.world_radius();
        let from_centre = (p - glyph.center).length();
        // A drawn point may sit a float32 rounding outside its own bounding sphere.
        if from_centre > radius * (1.0 + 1e-4) + 1e-9 {
            outside = outside.min(from_centre - radius);
            continue;
        }
        let local = from_centre / glyph.scale;
        if local == 0.0 {
            best = best.min(glyph.offset * glyph.scale);
            continue;
        }
        let u = (p - glyph.center) / from_centre;
        let (r, normal) = surface_point(glyph, u);
        best = best.min((r - local).abs() * normal.dot(u).abs() * glyph.scale);
    }
    if best.is_finite() { best } else { outside }
}

/// World size of one pixel on a plane facing the camera through `p`.
pub fn pixel_size(camera: &Camera, height: u32, p: DVec3) -> f64 {
    match camera.projection {
        Projection::Perspective { fov_y_deg } => {
            let depth = (p - camera.eye).dot(camera.frame().fwd);
            2.0 * depth * (fov_y_deg.to_radians() * 0.5).tan() / height as f64
        }
        Projection::Orthographic { height: h } => h / height as f64,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn silhouettes_of_a_shifted_disc_are_the_shift_apart() {
        // A disc of radius r = 40 px and the same disc moved right by d = 2 px: their
        // symmetric difference is about 4 r d, the silhouette 2 pi r long, so the mean
        // distance is 2 d / pi, the shift's normal component d |cos| averaged over the
        // circle.
        let (w, h) = (128usize, 128usize);
        let disc = |cx: f64| -> Vec<f64> {
            (0..w * h)
                .map(|k| {
                    let (x, y) = ((k % w) as f64 + 0.5, (k / w) as f64 + 0.5);
                    if (x - cx).hypot(y - 64.0) < 40.0 {
                        1.0
                    } else {
                        f64::NAN
                    }
                })
                .collect()
        };
        let reference = disc(64.0);
        let moved: Vec<f32> = disc(66.0).iter().map(|&v| v as f32).collect();
        let camera = Camera {
            projection: Projection::Orthographic { height: 1.0 },
            eye: DVec3::new(0.0, -5.0, 0.0),
            target: DVec3::ZERO,
            up: DVec3::Z,
        };
        let e = geometric_error(&moved, &reference, &[], &camera, w as u32, h as u32);
        let length = 2.0 * std::f64::consts::PI * 40.0;
        assert!(
            (e.silhouette_length_px - length).abs() < 0.05 * length,
            "{e}"
        );
        let expected = 2.0 * 2.0 / std::f64::consts::PI;
        assert!((e.silhouette_mean_px - expected).abs() < 0.1, "{e}");
    }
}
