//! The float64 reference of shadow rays (`--shadows`, glsl/shadow.glsl): from a glyph hit,
//! rays towards the light start `SHADOW_RAY_OFFSET` bounding radii of the hit glyph
//! beyond the hit and are intersected exactly ([`first_hit`]) with every glyph given, the
//! hit glyph included; a ray that meets one is blocked. Rays that leave the surface into
//! the glyph (n . l <= 0, n the normal turned towards the viewer) are not cast, and the
//! lit share is that of the rays cast (1 when none is). The GPU walks a grid to find the
//! glyphs a ray may meet; this reference tests them all.
//!
//! A soft light's 16 rays and the 16 occlusion rays come from one stratified disc
//! pattern that each pixel turns by its own offset ([`SamplePattern`]: a hash of the
//! pixel's index, as glsl/shadow.glsl computes it), so that neighbouring pixels cast
//! different rays and a penumbra shows fine noise, not bands; the reference takes the
//! pixel's pattern and casts the same rays.
use crate::camera::Ray;
use crate::glyph::NegativeMode;
use crate::glyph::intersect::{WorldGlyph, first_hit};
use glam::DVec3;

/// Where a shadow ray starts beyond its hit, as a fraction of the hit glyph's bounding
/// radius: clear of the float32 rounding of the GPU's hit, so that the surface the ray
/// leaves does not block it. The frame block hands it to the shaders.
pub(crate) const SHADOW_RAY_OFFSET: f64 = 1e-3;

/// One pixel's turn of the disc pattern that soft shadows and ambient occlusion sample:
/// an offset on the torus of (r^2, angle / 2 pi), two 24-bit fractions hashed from the
/// pixel's index in the image (glsl/shadow.glsl `shadow_pixel_shift`). Hard shadows do
/// not use it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SamplePattern {
    shift: [u32; 2],
}

impl SamplePattern {
    /// The pattern of the image pixel in column `x` and row `y` (from the top left, as
    /// [`crate::camera::Camera::ray`] counts them).
    pub fn for_pixel(x: u32, y: u32) -> SamplePattern {
        let a = pcg_hash(x.wrapping_add(pcg_hash(y)));
        let b = pcg_hash(a);
        SamplePattern {
            shift: [a >> 8, b >> 8],
        }
    }
}

/// One round of the PCG hash (Jarzynski and Olano, "Hash Functions for GPU Rendering",
/// JCGT 2020), as glsl/shadow.glsl `shadow_hash`.
fn pcg_hash(v: u32) -> u32 {
    let state = v.wrapping_mul(747_796_405).wrapping_add(2_891_336_453);
    let word = ((state >> ((state >> 28) + 4)) ^ state).wrapping_mul(277_803_737);
    (word >> 22) ^ word
}

/// Sample `k` (0 to 15) of a soft light's disc for the pixel of `pattern`, as
/// glsl/shadow.glsl `shadow_disc_sample` places it: its offset from the disc's centre in
/// units of the disc's radius. Point k of the lattice (k / 16, 7 k / 16), one in each
/// sixteenth of each coordinate, shifted by the pixel's offset modulo 1 in 24-bit fixed
/// point (a Cranley-Patterson rotation), mapped to the disc by r = sqrt(x), angle 2 pi y
/// (equal areas).
pub(crate) fn soft_sample(k: u32, pattern: SamplePattern) -> [f64; 2] {
    const ONE: f64 = (1u32 << 24) as f64;
    let x = ((k << 20).wrapping_add(pattern.shift[0])) & 0xff_ffff;
    let y = (((7 * k) & 15) << 20).wrapping_add(pattern.shift[1]) & 0xff_ffff;
    let radius = (f64::from(x) / ONE).sqrt();
    let angle = std::f64::consts::TAU * (f64::from(y) / ONE);
    [radius * angle.cos(), radius * angle.sin()]
}

/// The outward unit normal of `glyph`'s surface at the world point `p` on it (a
/// polynomial glyph: the gradient of the radial function, as the shaders take it).
pub fn surface_normal(glyph: &WorldGlyph, p: DVec3) -> DVec3 {
    let q = (p - glyph.center) / glyph.scale;
    let len = q.length().max(1e-300);
    let q_dir = q / len;
    let (f, grad) = glyph.poly.eval_with_gradient(q_dir);
    let sgn = if glyph.negative == NegativeMode::Hide || f >= 0.0 {
        1.0
    } else {
        -1.0
    };
    let order = f64::from(glyph.poly.order);
    ((len + order * f.abs()) * q_dir - sgn * grad).normalize()
}

/// Whether any of `glyphs` blocks the ray from `origin` along the unit `dir`.
pub fn blocked(origin: DVec3, dir: DVec3, glyphs: &[WorldGlyph]) -> bool {
    let ray = Ray { origin, dir };
    glyphs.iter().any(|g| first_hit(&ray, g).is_some())
}

/// The share of the light (`light`: its unit direction, rays, and the tangent of its
/// angular radius: a disc around the direction, sampled by the rays in the pattern of
/// `pattern`'s pixel, when rays > 1) that reaches the point `hit` of `glyph`, seen along
/// the unit direction `view_dir` (from the eye), among `glyphs`.
pub fn visibility(
    glyph: &WorldGlyph,
    hit: DVec3,
    view_dir: DVec3,
    light: (DVec3, u32, f64),
    pattern: SamplePattern,
    glyphs: &[WorldGlyph],
) -> f64 {
    let n = facing_normal(glyph, hit, view_dir);
    let offset = SHADOW_RAY_OFFSET * glyph.world_radius();
    visibility_at(hit, n, offset, light, pattern, glyphs)
}

/// The share of the light (`light`: unit direction towards it, rays, tan of its angular
/// radius, as in [`visibility`]) that reaches the point `hit` whose unit normal, turned
/// towards the viewer, is `n`, its rays starting `offset` beyond it.
fn visibility_at(
    hit: DVec3,
    n: DVec3,
    offset: f64,
    (light, rays, tan_radius): (DVec3, u32, f64),
    pattern: SamplePattern,
    glyphs: &[WorldGlyph],
) -> f64 {
    let (u, v) = perpendiculars(light);
    let (mut cast, mut lit) = (0u32, 0u32);
    for k in 0..rays {
        let dir = if rays > 1 {
            let [x, y] = soft_sample(k, pattern);
            (light + tan_radius * (x * u + y * v)).normalize()
        } else {
            light
        };
        if n.dot(dir) <= 0.0 {
            continue;
        }
        cast += 1;
        if !blocked(hit + offset * dir, dir, glyphs) {
            lit += 1;
        }
    }
    if cast == 0 {
        1.0
    } else {
        f64::from(lit) / f64::from(cast)
    }
}

/// The mean bounding radius of `glyphs`: what the underlay's rays take for the hit
/// glyph's radius (where they start, how far occlusion reaches).
pub fn mean_radius(glyphs: &[WorldGlyph]) -> f64 {
    glyphs.iter().map(WorldGlyph::world_radius).sum::<f64>() / glyphs.len().max(1) as f64
}

/// The light a point of an underlay plane receives among `glyphs`, as a share of the
/// underlay's colour: ambient * (occlusion share) + (1 - ambient) * (lit share), the
/// plane a matte surface facing the light. `point` lies on the plane of unit normal
/// `normal` (either side), seen along the unit `view_dir` by the pixel of `pattern`;
/// `light` is the light's unit direction, rays and tan of its angular radius (as in
/// [`visibility`]); `reach` is the occlusion rays' reach in units of [`mean_radius`]
/// (None: no occlusion), `ambient` the ambient term. The rays start and reach as from a
/// glyph of the mean radius.
pub fn plane_share(
    (point, normal, view_dir): (DVec3, DVec3, DVec3),
    light: (DVec3, u32, f64),
    pattern: SamplePattern,
    reach: Option<f64>,
    ambient: f64,
    glyphs: &[WorldGlyph],
) -> f64 {
    let n = if normal.dot(-view_dir) < 0.0 {
        -normal
    } else {
        normal
    };
    let radius = mean_radius(glyphs);
    let lit = visibility_at(point, n, SHADOW_RAY_OFFSET * radius, light, pattern, glyphs);
    let open = reach.map_or(1.0, |reach| {
        ambient_share_at(point, n, (radius, reach), pattern, glyphs)
    });
    ambient * open + (1.0 - ambient) * lit
}

/// Occlusion rays per hit (`--ambient-occlusion`): the soft light's 16 disc samples lifted
/// onto the hemisphere (glsl/shadow.glsl `AMBIENT_RAYS`).
pub const AMBIENT_OCCLUSION_RAYS: u32 = 16;

/// The unit normal of `glyph` at its surface point `hit`, turned towards the viewer who
/// looks along the unit direction `view_dir`.
fn facing_normal(glyph: &WorldGlyph, hit: DVec3, view_dir: DVec3) -> DVec3 {
    let normal = surface_normal(glyph, hit);
    if normal.dot(-view_dir) < 0.0 {
        -normal
    } else {
        normal
    }
}

/// Occlusion ray `k` (0 to 15) of `--ambient-occlusion` from a point of unit normal `n`
/// (turned towards the viewer) seen by the pixel of `pattern`, as glsl/shadow.glsl casts
/// it: the soft light's disc sample `k` lifted onto the hemisphere around `n` (Malley's
/// method), so that the rays are cosine-weighted.
pub(crate) fn ambient_direction(n: DVec3, k: u32, pattern: SamplePattern) -> DVec3 {
    let [x, y] = soft_sample(k, pattern);
    let (u, v) = perpendiculars(n);
    (x * u + y * v + (1.0 - x * x - y * y).max(0.0).sqrt() * n).normalize()
}

/// The share of the ambient light that reaches the point `hit` of `glyph`, seen along the
/// unit direction `view_dir` by the pixel of `pattern`, among `glyphs`: of the 16
/// occlusion rays (`ambient_direction`), each starting `SHADOW_RAY_OFFSET` bounding radii
/// beyond the hit, those that no glyph meets within `reach` bounding radii of `glyph`
/// from their start.
pub fn ambient_share(
    glyph: &WorldGlyph,
    hit: DVec3,
    view_dir: DVec3,
    reach: f64,
    pattern: SamplePattern,
    glyphs: &[WorldGlyph],
) -> f64 {
    let n = facing_normal(glyph, hit, view_dir);
    ambient_share_at(hit, n, (glyph.world_radius(), reach), pattern, glyphs)
}

/// [`ambient_share`] of the point `hit` whose unit normal, turned towards the viewer, is
/// `n`, with `radius` for the hit glyph's bounding radius.
fn ambient_share_at(
    hit: DVec3,
    n: DVec3,
    (radius, reach): (f64, f64),
    pattern: SamplePattern,
    glyphs: &[WorldGlyph],
) -> f64 {
    let rays = AMBIENT_OCCLUSION_RAYS;
    let open = (0..rays)
        .filter(|&k| {
            let dir = ambient_direction(n, k, pattern);
            let ray = Ray {
                origin: hit + SHADOW_RAY_OFFSET * radius * dir,
                dir,
            };
            !glyphs
                .iter()
                .any(|g| first_hit(&ray, g).is_some_and(|t| t <= reach * radius))
        })
        .count();
    open as f64 / f64::from(rays)
}

/// Two unit vectors that make a right-handed frame with the unit `v` (glsl/shadow.glsl
/// `shadow_perpendicular`, then v x u).
fn perpendiculars(v: DVec3) -> (DVec3, DVec3) {
    let other = if v.x.abs() < 0.6 { DVec3::X } else { DVec3::Y };
    let u = v.cross(other).normalize();
    (u, v.cross(u))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::glyph::polynomial::GlyphPolynomial;

    fn sphere(center: DVec3, radius: f64) -> WorldGlyph {
        let poly = GlyphPolynomial {
            order: 2,
            coeffs: vec![1.0, 0.0, 0.0, 1.0, 0.0, 1.0],
        };
        WorldGlyph::new(center, radius, poly, NegativeMode::Abs, 0.0)
    }

    /// Each pixel's samples lie inside the unit disc, one in each sixteenth of its area
    /// (a ring of equal area) and one in each sixteenth of its turn; neighbouring pixels
    /// get different samples, the same pixel always the same; over many pixels the
    /// samples fill the disc evenly (their mean distance squared is 1/2, as a uniform
    /// disc's, and their mean offset is near the centre).
    #[test]
    fn soft_samples_are_stratified_and_turned_per_pixel() {
        let (mut mean, mut r2_mean, mut count) = ([0.0, 0.0], 0.0, 0.0);
        for (x, y) in (0..32).flat_map(|x| (0..32).map(move |y| (x, y))) {
            let pattern = SamplePattern::for_pixel(x, y);
            assert_eq!(pattern, SamplePattern::for_pixel(x, y));
            assert_ne!(pattern, SamplePattern::for_pixel(x + 1, y));
            assert_ne!(pattern, SamplePattern::for_pixel(x, y + 1));
            let samples: Vec<[f64; 2]> = (0..16).map(|k| soft_sample(k, pattern)).collect();
            let mut rings: Vec<usize> = samples
                .iter()
                .map(|s| ((s[0] * s[0] + s[1] * s[1]) * 16.0) as usize)
                .collect();
            let mut turns: Vec<usize> = samples
                .iter()
                .map(|s| {
                    (s[1].atan2(s[0]).rem_euclid(std::f64::consts::TAU) * 16.0
                        / std::f64::consts::TAU) as usize
                })
                .collect();
            rings.sort_unstable();
            turns.sort_unstable();
            assert_eq!(rings, (0..16).collect::<Vec<_>>(), "{x}, {y}");
            // One per sixteenth of the turn, up to rounding at a boundary.
            turns.dedup();
            assert!(turns.len() >= 15, "{x}, {y}: {turns:?}");
            for s in samples {
                mean = [mean[0] + s[0], mean[1] + s[1]];
                r2_mean += s[0] * s[0] + s[1] * s[1];
                count += 1.0;
            }
        }
        let (mx, my, r2) = (mean[0] / count, mean[1] / count, r2_mean / count);
        assert!(mx.abs() < 0.02 && my.abs() < 0.02, "{mx}, {my}");
        assert!((r2 - 0.5).abs() < 0.01, "{r2}");
    }

    /// The occlusion rays leave the surface, average near the normal as cosine-weighted
    /// rays do (their mean cosine is 2/3 for a continuous cosine lobe), and a sphere
    /// covering the hemisphere within reach blocks every one, one out of reach none.
    #[test]
    fn occlusion_rays_are_cosine_weighted_and_limited_in_reach() {
        let n = DVec3::new(0.3, -0.2, 0.9).normalize();
        let pattern = SamplePattern::for_pixel(3, 5);
        let cosine = |k| ambient_direction(n, k, pattern).dot(n);
        let mean: f64 = (0..16).map(cosine).sum::<f64>() / 16.0;
        assert!((0..16).all(|k| cosine(k) > 0.0));
        assert!((mean - 2.0 / 3.0).abs() < 0.03, "{mean}");
        let floor = sphere(DVec3::ZERO, 1.0);
        let hit = DVec3::new(0.0, 0.0, 1.0);
        let lid = |distance: f64| sphere(DVec3::new(0.0, 0.0, 1.0 + distance), 10.0);
        // A sphere of radius 10 whose surface passes 0.01 above the hit covers its whole
        // hemisphere; moved 20 radii up, it is out of a reach of 2.
        let near = [floor.clone(), lid(10.01)];
        let far = [floor.clone(), lid(30.0)];
        assert_eq!(
            ambient_share(&floor, hit, -DVec3::Z, 2.0, pattern, &near),
            0.0
        );
        assert_eq!(
            ambient_share(&floor, hit, -DVec3::Z, 2.0, pattern, &far),
            1.0
        );
        let alone = std::slice::from_ref(&floor);
        assert_eq!(
            ambient_share(&floor, hit, -DVec3::Z, 2.0, pattern, alone),
            1.0
        );
    }

    /// A sphere's normal is radial; a sphere between a point and the light blocks it, one
    /// beside the ray does not.
    #[test]
    fn a_sphere_between_the_point_and_the_light_blocks_it() {
        let s = sphere(DVec3::new(1.0, 2.0, 3.0), 0.5);
        let p = DVec3::new(1.0, 2.0, 3.5);
        assert!((surface_normal(&s, p) - DVec3::Z).length() < 1e-12);
        let floor = sphere(DVec3::ZERO, 1.0);
        let blocker = sphere(DVec3::new(0.0, 0.0, 3.0), 0.5);
        let beside = sphere(DVec3::new(2.0, 0.0, 3.0), 0.5);
        let top = DVec3::new(0.0, 0.0, 1.0);
        let down = -DVec3::Z;
        let pattern = SamplePattern::for_pixel(0, 0);
        let glyphs = [floor.clone(), blocker];
        let hard = (DVec3::Z, 1, 0.0);
        assert_eq!(visibility(&floor, top, down, hard, pattern, &glyphs), 0.0);
        let glyphs = [floor.clone(), beside];
        assert_eq!(visibility(&floor, top, down, hard, pattern, &glyphs), 1.0);
        // The light behind the surface: no ray is cast, the light's share stays 1.
        let behind = (-DVec3::Z, 1, 0.0);
        assert_eq!(visibility(&floor, top, down, behind, pattern, &glyphs), 1.0);
    }
}
