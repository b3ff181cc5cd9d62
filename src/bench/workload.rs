//! Generated workloads: square grids of fibre glyphs of one order, framed by a camera
//! that sees the whole grid, so glyph count, order and resolution can be swept alone.
//!
//! - `grid:COUNT:ORDER`: symmetric fibre tensors (two or three crossing populations);
//! - `fodf:COUNT:BAND`: fibre ODFs as SH series (tournier07, MRtrix3's basis) with one to
//!   three random fibres each, the common case of real HARDI data;
//! - `block:NX:NY:NZ:BAND[:front|:corner|:stacked]`: a dense 3D block of such fODFs
//!   filling their voxels, seen head-on through its layers or from a corner, or its first
//!   layer copied behind itself (what hidden glyphs cost);
//! - `tracks:COUNT:POINTS[:slab][:lines]`: a whole-brain tractogram's worth of synthetic
//!   streamlines drawn as tubes (or lines), whole in 3D or a 5 mm slab over an axial
//!   slice.
use crate::camera::{Camera, Projection};
use crate::catalog::{MAX_SH_BAND, MAX_SYMMETRIC_ORDER};
use crate::demo::{direction, fibre_tensor, glyph_set, symmetric};
use crate::glyph::sh::{ShEvaluator, sh_count, sh_orders};
use crate::rng::SplitMix64;
use crate::scene::{GlyphKind, GlyphSet, ImageSize, Scene, ShBasis};
use crate::{Error, Result, Setting, parallel};
use glam::DVec3;

/// `count` glyphs of `order` (even, 2..=12) on a square grid of unit spacing, two or three
/// crossing populations each, turning across the grid; seen from above at an angle.
pub fn grid(count: usize, order: u32, width: u32, height: u32) -> Result<Scene> {
    if count == 0 || count > MAX_WORKLOAD_GLYPHS {
        return Err(glyph_count(count));
    }
    if !(1..=MAX_SYMMETRIC_ORDER).contains(&order) {
        return Err(Error::setting_value(
            Setting::Workload,
            format!("order {order}"),
            format!("a workload's order is 1 to {MAX_SYMMETRIC_ORDER}"),
        ));
    }
    let side = (count as f64).sqrt().ceil() as usize;
    let mut centers = Vec::with_capacity(count);
    let mut coeffs = Vec::with_capacity(count);
    for k in 0..count {
        let (i, j) = (k % side, k / side);
        let turn = 360.0 * (i as f64 * 0.137 + j as f64 * 0.071);
        let mut fibres = vec![
            (direction(turn, 10.0), 1.0),
            (direction(turn + 75.0, -5.0), 0.8),
        ];
        if k % 3 == 0 {
            fibres.push((direction(turn + 140.0, 40.0), 0.6));
        }
        centers.push(DVec3::new(
            i as f64 - 0.5 * (side - 1) as f64,
            j as f64 - 0.5 * (side - 1) as f64,
            0.0,
        ));
        coeffs.push(fibre_tensor(order, &fibres));
    }
    let set = glyph_set(symmetric(order), centers, 0.48, coeffs);
    Ok(field_scene(set, side, width, height))
}

/// The largest generated workload, in glyphs.
const MAX_WORKLOAD_GLYPHS: usize = 4_000_000;

/// A glyph count outside 1..=[`MAX_WORKLOAD_GLYPHS`] refused.
fn glyph_count(count: usize) -> Error {
    Error::setting_value(
        Setting::Workload,
        format!("{count} glyphs"),
        format!("a workload has 1 to {MAX_WORKLOAD_GLYPHS} glyphs"),
    )
}

/// A square field of `side` x `side` glyphs at unit spacing, seen from above at an angle
/// by a camera that frames it whole.
fn field_scene(set: GlyphSet, side: usize, width: u32, height: u32) -> Scene {
    let extent = side as f64;
    Scene {
        glyph_sets: vec![set],
        camera: Camera {
            projection: Projection::Perspective { fov_y_deg: 30.0 },
            eye: DVec3::new(0.0, -1.2 * extent, 1.6 * extent + 2.0),
            target: DVec3::ZERO,
            up: DVec3::Z,
        },
        image: ImageSize { width, height },
    }
}

/// SH coefficients (tournier07, band `band`) of a fibre ODF: a sum over fibres of a sharp
/// zonal kernel about each direction, sum_i w_i sum_l k_l sum_m Y_lm(d_i) Y_lm(u) (the
/// addition theorem), with a Gaussian taper k_l = exp(-2 l(l+1) / (L(L+1))) that keeps
/// the lobes as sharp as band L allows with little ringing.
pub fn fodf_coefficients(band: u32, fibres: &[(DVec3, f64)]) -> Vec<f64> {
    let taper = fodf_taper(band);
    let evaluator = ShEvaluator::new(band, ShBasis::Tournier07, false);
    let mut values = vec![0.0; taper.len()];
    let mut coeffs = vec![0.0; taper.len()];
    for (d, w) in fibres {
        evaluator.values_into(*d, &mut values);
        add_kernel(&mut coeffs, &taper, *w, &values);
    }
    coeffs
}

/// The taper k_l of [`fodf_coefficients`], one per coefficient (l, m).
fn fodf_taper(band: u32) -> Vec<f64> {
    let top = (band * (band + 1)).max(1) as f64;
    sh_orders(band)
        .map(|(l, _)| (-2.0 * (l * (l + 1)) as f64 / top).exp())
        .collect()
}

/// Adds one fibre's kernel, weight `weight`, from its basis values `values`.
fn add_kernel(coeffs: &mut [f64], taper: &[f64], weight: f64, values: &[f64]) {
    for ((c, k), y) in coeffs.iter_mut().zip(taper).zip(values) {
        *c += weight * k * y;
    }
}

/// Glyphs whose coefficients are computed at once, in parallel, into one flat buffer
/// (64k band-8 glyphs: 23 MB).
const FODF_BLOCK: usize = 1 << 16;

/// The most fibres of a generated fODF.
const MAX_FIBRES: usize = 3;

/// The random draws of one generated fODF: its fibres (direction, weight).
#[derive(Clone, Copy, Default)]
struct FibreDraw {
    fibres: [(DVec3, f64); MAX_FIBRES],
    count: usize,
}

impl FibreDraw {
    /// One to three fibres (40 %, 40 %, 20 %) in random directions, the first of
    /// weight 1, the others 0.4 to 0.9.
    fn draw(rng: &mut SplitMix64) -> Self {
        let draw = rng.unit();
        let count = if draw < 0.4 {
            1
        } else if draw < 0.8 {
            2
        } else {
            3
        };
        let mut fibres = [(DVec3::ZERO, 0.0); MAX_FIBRES];
        for (f, fibre) in fibres[..count].iter_mut().enumerate() {
            let weight = if f == 0 { 1.0 } else { 0.4 + 0.5 * rng.unit() };
            *fibre = (rng.direction(), weight);
        }
        Self { fibres, count }
    }

    fn fibres(&self) -> &[(DVec3, f64)] {
        &self.fibres[..self.count]
    }
}

/// What every generated fODF of one band shares.
struct FodfKernel {
    evaluator: ShEvaluator,
    taper: Vec<f64>,
}

impl FodfKernel {
    /// Basis values held on the stack: the workload's highest band.
    const VALUES: usize = sh_count(MAX_SH_BAND);

    /// Writes the coefficients of `draw` into `out`, scaled to a peak radius of 0.45:
    /// the largest |f| at a fibre's own direction, for a size that does not depend on
    /// how many fibres cross. Allocates nothing, so it can run on worker threads.
    fn coefficients(&self, draw: &FibreDraw, out: &mut [f64]) {
        let n = out.len().min(Self::VALUES);
        let mut values = [[0.0; Self::VALUES]; MAX_FIBRES];
        out.fill(0.0);
        for ((d, w), values) in draw.fibres().iter().zip(&mut values) {
            self.evaluator.values_into(*d, &mut values[..n]);
            add_kernel(out, &self.taper, *w, &values[..n]);
        }
        // f(d_i) = sum_j c_j Y_j(d_i), from the values already at hand.
        let peak = values[..draw.count]
            .iter()
            .map(|y| {
                y[..n]
                    .iter()
                    .zip(&*out)
                    .map(|(y, c)| y * c)
                    .sum::<f64>()
                    .abs()
            })
            .fold(0.0, f64::max);
        for c in out.iter_mut() {
            *c = *c * 0.45 / peak.max(1e-12);
        }
    }
}

/// `count` fibre ODFs of SH band `band` (even, 2..=12) on a square grid of unit spacing:
/// one to three fibres each (40 %, 40 %, 20 %) in random directions with weights 1 and
/// 0.4 to 0.9, each glyph scaled to a peak radius of about 0.45; seen as `grid` is.
///
/// The draws are made on this thread in glyph order (a fixed sequence for a given count
/// and band); the coefficients are computed block by block on every core into one flat
/// buffer, and each glyph's own `Vec` is made here, so the workers allocate nothing.
pub fn fodf(count: usize, band: u32, width: u32, height: u32) -> Result<Scene> {
    if count == 0 || count > MAX_WORKLOAD_GLYPHS {
        return Err(glyph_count(count));
    }
    check_band(band)?;
    let side = (count as f64).sqrt().ceil() as usize;
    let centers = (0..count)
        .map(|k| {
            let (i, j) = (k % side, k / side);
            DVec3::new(
                i as f64 - 0.5 * (side - 1) as f64,
                j as f64 - 0.5 * (side - 1) as f64,
                0.0,
            )
        })
        .collect();
    let coeffs = fodf_coefficient_blocks(count, band, FODF_BLOCK)?;
    let kind = GlyphKind::Sh {
        band,
        basis: ShBasis::Tournier07,
        legacy: false,
    };
    Ok(field_scene(
        glyph_set(kind, centers, 1.0, coeffs),
        side,
        width,
        height,
    ))
}

/// The coefficients of [`fodf`]'s glyphs, `block` glyphs at a time.
fn fodf_coefficient_blocks(count: usize, band: u32, block: usize) -> Result<Vec<Vec<f64>>> {
    let seed = 0x5eed_f0df ^ (count as u64) << 8 ^ band as u64;
    seeded_fodf_coefficients(seed, count, band, block)
}

/// `count` fODFs of band `band` drawn from the sequence of `seed`, `block` at a time.
fn seeded_fodf_coefficients(
    seed: u64,
    count: usize,
    band: u32,
    block: usize,
) -> Result<Vec<Vec<f64>>> {
    let mut rng = SplitMix64::new(seed);
    let kernel = FodfKernel {
        evaluator: ShEvaluator::new(band, ShBasis::Tournier07, false),
        taper: fodf_taper(band),
    };
    let width = kernel.taper.len();
    let block = block.clamp(1, count.max(1));
    let mut draws = Vec::with_capacity(block);
    let mut flat = vec![0.0; block * width];
    let mut coeffs = Vec::with_capacity(count);
    while coeffs.len() < count {
        let n = block.min(count - coeffs.len());
        draws.clear();
        draws.extend((0..n).map(|_| FibreDraw::draw(&mut rng)));
        let flat = &mut flat[..n * width];
        parallel::fill_chunks(&draws, flat, width, "fODF workload", |draw, out| {
            kernel.coefficients(draw, out)
        })?;
        coeffs.extend(flat.chunks(width).map(<[f64]>::to_vec));
    }
    Ok(coeffs)
}

/// Which side a `block` workload is seen from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BlockView {
    /// Head-on: the camera on the block's axis in front of its first layer, looking
    /// through the layers.
    Front,
    /// From a corner: the camera along the block's diagonal, framing it whole.
    Corner,
    /// Head-on as `Front`, every layer a copy of the first: a glyph hides the ones
    /// behind it where it is drawn, and the gaps between its lobes stay gaps through
    /// the whole block (where no depth can hide anything).
    Stacked,
}

/// A dense 3D block of `nx` x `ny` x `nz` fibre ODFs of SH band `band`, one per voxel of
/// unit size, each scaled to a peak radius of about one voxel, so that the lobes of
/// neighbours reach each other's centres and cross (a dense crossing region drawn with
/// large glyphs): a glyph's fibres are drawn at random as [`fodf`]'s are. Layer k (k = 0 .. nz) lies at z = -k, so that the first layer faces
/// a camera on +z; its glyphs are the same whatever `nz` (the draws depend on `nx`, `ny`
/// and `band` only, layer after layer), so `block:NX:NY:1:BAND` is the front layer of every
/// deeper block and their frames compare directly. `Front` looks at the first layer's
/// centre from +z, framing that layer; `Corner` looks at the block's centre along the
/// diagonal (1, 1, 1), framing its bounding sphere; `Stacked` is `Front`'s view of the
/// first layer copied into every layer.
pub fn block(
    (nx, ny, nz): (usize, usize, usize),
    band: u32,
    view: BlockView,
    width: u32,
    height: u32,
) -> Result<Scene> {
    let count = nx
        .checked_mul(ny)
        .and_then(|c| c.checked_mul(nz))
        .unwrap_or(usize::MAX);
    if nx == 0 || ny == 0 || nz == 0 || count > MAX_WORKLOAD_GLYPHS {
        return Err(glyph_count(count));
    }
    check_band(band)?;
    let seed = 0xb10c_f0df ^ (nx as u64) << 32 ^ (ny as u64) << 8 ^ band as u64;
    let coeffs = match view {
        BlockView::Stacked => {
            let layer = seeded_fodf_coefficients(seed, nx * ny, band, FODF_BLOCK)?;
            (0..nz).flat_map(|_| layer.iter().cloned()).collect()
        }
        _ => seeded_fodf_coefficients(seed, count, band, FODF_BLOCK)?,
    };
    let half = |n: usize| 0.5 * (n - 1) as f64;
    let centers = (0..count)
        .map(|v| {
            let (i, j, k) = (v % nx, (v / nx) % ny, v / (nx * ny));
            DVec3::new(i as f64 - half(nx), j as f64 - half(ny), 0.0 - k as f64)
        })
        .collect();
    let kind = GlyphKind::Sh {
        band,
        basis: ShBasis::Tournier07,
        legacy: false,
    };
    let fov_y_deg = 30.0_f64;
    let tan = (0.5 * fov_y_deg.to_radians()).tan();
    let aspect = f64::from(width) / f64::from(height.max(1));
    let camera = match view {
        BlockView::Front | BlockView::Stacked => {
            // The first layer's face (its glyphs reach about 1 beyond their centres)
            // fills 90 % of the image's height or width, whichever is tighter.
            let reach = (0.5 * ny as f64 + 0.5).max((0.5 * nx as f64 + 0.5) / aspect) / 0.9;
            Camera {
                projection: Projection::Perspective { fov_y_deg },
                eye: DVec3::new(0.0, 0.0, 1.0 + reach / tan),
                target: DVec3::ZERO,
                up: DVec3::Y,
            }
        }
        BlockView::Corner => {
            let centre = DVec3::new(0.0, 0.0, -half(nz));
            let radius = 0.5 * ((nx * nx + ny * ny + nz * nz) as f64).sqrt() + 1.0;
            let distance = radius / (tan.min(tan * aspect) * 0.95);
            Camera {
                projection: Projection::Perspective { fov_y_deg },
                eye: centre + DVec3::new(1.0, 1.0, 1.0).normalize() * distance.max(radius + 1.0),
                target: centre,
                up: DVec3::Y,
            }
        }
    };
    Ok(Scene {
        glyph_sets: vec![glyph_set(kind, centers, 1.0 / 0.45, coeffs)],
        camera,
        image: ImageSize { width, height },
    })
}

/// An SH band outside the workloads' (even, 2 to [`MAX_SH_BAND`]) refused.
fn check_band(band: u32) -> Result<()> {
    if !(2..=MAX_SH_BAND).contains(&band) || !band.is_multiple_of(2) {
        return Err(Error::setting_value(
            Setting::Workload,
            format!("SH band {band}"),
            format!("a workload's SH band is one of 2, 4, ..., {MAX_SH_BAND}"),
        ));
    }
    Ok(())
}

/// The most capsules (streamline segments) a tracks workload draws.
const MAX_WORKLOAD_SEGMENTS: usize = 50_000_000;

/// The tubes' radius of a tracks workload, millimetres.
const TRACKS_RADIUS_MM: f64 = 0.2;

/// The half width of the slab of `tracks:COUNT:POINTS:slab`, millimetres (a 5 mm slab).
const TRACKS_SLAB_HALF_MM: f64 = 2.5;

/// `count` synthetic streamlines of `points` points each, 1 mm apart, drawn as tubes of
/// [`TRACKS_RADIUS_MM`]: smooth random curves (each step turns a little from the last)
/// starting inside a brain-sized ellipsoid (half axes 70, 85 and 60 mm), as a
/// whole-brain tractogram has them. Seen whole in 3D from the front and above, or with
/// `slab` only their parts within [`TRACKS_SLAB_HALF_MM`] of the axial plane z = 0, seen
/// from above (a slab over an axial slice). With `lines` the segments are the set's lines
/// (flat ribbons, `PeakSet::lines`), not its exact tubes. No glyphs: the scene's glyph
/// sets are empty.
fn tracks(
    count: usize,
    points: usize,
    (slab, lines): (bool, bool),
    width: u32,
    height: u32,
) -> Result<(Scene, crate::render::peaks::PeakSet)> {
    use crate::glyph::capsule::Capsule;
    use crate::render::peaks::{PeakSegment, PeakSet};
    let segments = count.saturating_mul(points.saturating_sub(1));
    if count == 0 || points < 2 || segments > MAX_WORKLOAD_SEGMENTS {
        return Err(Error::setting_value(
            Setting::Workload,
            format!("{count} streamlines of {points} points"),
            format!(
                "a tracks workload has at least one streamline of 2 points or more, and at \
                 most {MAX_WORKLOAD_SEGMENTS} segments"
            ),
        ));
    }
    let half = DVec3::new(70.0, 85.0, 60.0);
    let mut rng = SplitMix64::new(0x7ac5 ^ (count as u64) << 16 ^ points as u64);
    let mut tubes = Vec::with_capacity(if slab { segments / 20 } else { segments });
    for _ in 0..count {
        let mut p = loop {
            let q = DVec3::new(rng.unit(), rng.unit(), rng.unit()) * 2.0 - DVec3::ONE;
            if q.length_squared() <= 1.0 {
                break q * half;
            }
        };
        let mut d = rng.direction();
        for _ in 1..points {
            d = (d + 0.15 * rng.direction()).normalize();
            let next = p + d;
            let kept =
                !slab || (p.z.abs() <= TRACKS_SLAB_HALF_MM && next.z.abs() <= TRACKS_SLAB_HALF_MM);
            if kept {
                tubes.push(PeakSegment {
                    capsule: Capsule {
                        a: p,
                        b: next,
                        radius: TRACKS_RADIUS_MM,
                    },
                    color: d.abs().to_array(),
                });
            }
            p = next;
        }
    }
    let camera = if slab {
        Camera {
            projection: Projection::Orthographic {
                height: 2.3 * half.y,
            },
            eye: DVec3::new(0.0, 0.0, 400.0),
            target: DVec3::ZERO,
            up: DVec3::Y,
        }
    } else {
        Camera {
            projection: Projection::Perspective { fov_y_deg: 30.0 },
            eye: DVec3::new(0.0, -420.0, 260.0),
            target: DVec3::ZERO,
            up: DVec3::Z,
        }
    };
    let scene = Scene {
        glyph_sets: Vec::new(),
        camera,
        image: ImageSize { width, height },
    };
    let tubes = match lines {
        false => PeakSet {
            segments: tubes,
            lines: Vec::new(),
        },
        true => PeakSet {
            segments: Vec::new(),
            lines: tubes,
        },
    };
    Ok((scene, tubes))
}

/// `tracks:COUNT:POINTS[:slab][:lines]` ([`tracks`]): the scene and its tubes; `None`
/// for any other workload.
fn parse_tracks(
    spec: &str,
    width: u32,
    height: u32,
) -> Option<Result<(Scene, crate::render::peaks::PeakSet)>> {
    let parts: Vec<&str> = spec.split(':').collect();
    if parts.first() != Some(&"tracks") {
        return None;
    }
    let bad = || {
        Error::setting_value(
            Setting::Workload,
            format!("'{}'", crate::error::quoted(spec)),
            "not tracks:COUNT:POINTS[:slab][:lines]",
        )
    };
    let number = |s: &str| s.parse::<usize>().map_err(|_| bad());
    Some(match parts.as_slice() {
        ["tracks", count, points, rest @ ..] => {
            let shape = match rest {
                [] => Ok((false, false)),
                ["slab"] => Ok((true, false)),
                ["lines"] => Ok((false, true)),
                ["slab", "lines"] => Ok((true, true)),
                _ => Err(bad()),
            };
            shape.and_then(|shape| tracks(number(count)?, number(points)?, shape, width, height))
        }
        _ => Err(bad()),
    })
}

/// Parses `grid:COUNT:ORDER`, `fodf:COUNT:BAND`,
/// `block:NX:NY:NZ:BAND[:front|:corner|:stacked]` or `tracks:COUNT:POINTS[:slab][:lines]`: the
/// scene, and the tubes drawn with it (a tracks workload's; its scene has no glyphs).
pub fn parse(
    spec: &str,
    width: u32,
    height: u32,
) -> Result<(Scene, Option<crate::render::peaks::PeakSet>)> {
    if let Some(tracks) = parse_tracks(spec, width, height) {
        return tracks.map(|(scene, tubes)| (scene, Some(tubes)));
    }
    parse_glyphs(spec, width, height).map(|scene| (scene, None))
}

fn parse_glyphs(spec: &str, width: u32, height: u32) -> Result<Scene> {
    let parts: Vec<&str> = spec.split(':').collect();
    let bad = || {
        Error::setting_value(
            Setting::Workload,
            format!("'{}'", crate::error::quoted(spec)),
            "not grid:COUNT:ORDER, fodf:COUNT:BAND, block:NX:NY:NZ:BAND[:front|:corner|:stacked] \
             or tracks:COUNT:POINTS[:slab][:lines]",
        )
    };
    let number = |s: &str| s.parse::<usize>().map_err(|_| bad());
    match parts.as_slice() {
        ["grid", count, order] => grid(number(count)?, number(order)? as u32, width, height),
        ["fodf", count, band] => fodf(number(count)?, number(band)? as u32, width, height),
        ["block", nx, ny, nz, band, view @ ..] => {
            let view = match view {
                [] | ["front"] => BlockView::Front,
                ["corner"] => BlockView::Corner,
                ["stacked"] => BlockView::Stacked,
                _ => return Err(bad()),
            };
            let dims = (number(nx)?, number(ny)?, number(nz)?);
            block(dims, number(band)? as u32, view, width, height)
        }
        _ => Err(bad()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tracks_workloads_make_their_segments() {
        let (scene, whole) = tracks(10, 5, (false, false), 64, 48).expect("tracks");
        assert!(scene.glyph_sets.is_empty());
        assert_eq!(whole.segments.len(), 40);
        for s in &whole.segments {
            let step = (s.capsule.b - s.capsule.a).length();
            assert!((step - 1.0).abs() < 1e-9 && s.capsule.radius == TRACKS_RADIUS_MM);
        }
        // The slab keeps the segments within 2.5 mm of z = 0, and only those.
        let (_, slab) = tracks(2000, 50, (true, false), 64, 48).expect("slab");
        assert!(!slab.segments.is_empty() && slab.segments.len() < 2000 * 49 / 5);
        assert!(slab.segments.iter().all(|s| {
            s.capsule.a.z.abs() <= TRACKS_SLAB_HALF_MM && s.capsule.b.z.abs() <= TRACKS_SLAB_HALF_MM
        }));
        assert!(parse_tracks("fodf:10:8", 64, 48).is_none());
        assert!(parse_tracks("tracks:10:5:slab", 64, 48).is_some_and(|r| r.is_ok()));
        let (_, lines) = parse_tracks("tracks:10:5:lines", 64, 48).unwrap().unwrap();
        assert!(lines.segments.is_empty() && !lines.lines.is_empty());
        for bad in [
            "tracks:10",
            "tracks:10:1",
            "tracks:0:5",
            "tracks:10:5:thick",
            "tracks:10:5:lines:slab",
            "tracks:x:5",
        ] {
            let err = parse_tracks(bad, 64, 48).expect("a tracks spec").err();
            assert!(err.is_some(), "{bad} was taken");
        }
    }
    use crate::glyph::sh::{sh_basis_values, sh_eval};

    /// The glyphs of `fodf(count, band)` as the workload first made them: one glyph at a
    /// time, basis values and series through the plain `sh` functions.
    fn serial_fodf(count: usize, band: u32) -> Vec<Vec<f64>> {
        let mut rng = SplitMix64::new(0x5eed_f0df ^ (count as u64) << 8 ^ band as u64);
        let taper = fodf_taper(band);
        (0..count)
            .map(|_| {
                let draw = rng.unit();
                let n = 1 + usize::from(draw >= 0.4) + usize::from(draw >= 0.8);
                let fibres: Vec<(DVec3, f64)> = (0..n)
                    .map(|f| {
                        let weight = if f == 0 { 1.0 } else { 0.4 + 0.5 * rng.unit() };
                        (rng.direction(), weight)
                    })
                    .collect();
                let mut c = vec![0.0; taper.len()];
                for (d, w) in &fibres {
                    let y = sh_basis_values(band, ShBasis::Tournier07, false, *d);
                    for ((c, k), y) in c.iter_mut().zip(&taper).zip(y) {
                        *c += w * k * y;
                    }
                }
                let peak = fibres
                    .iter()
                    .map(|(d, _)| sh_eval(band, ShBasis::Tournier07, false, &c, *d).abs())
                    .fold(0.0, f64::max);
                c.iter().map(|v| v * 0.45 / peak.max(1e-12)).collect()
            })
            .collect()
    }

    #[test]
    fn a_stacked_block_copies_the_front_layer_into_every_layer() {
        let (dims, layer) = ((3, 2, 4), 6);
        let front = parse("block:3:2:4:4", 64, 48).unwrap().0;
        let stacked = parse("block:3:2:4:4:stacked", 64, 48).unwrap().0;
        let (f, s) = (&front.glyph_sets[0], &stacked.glyph_sets[0]);
        assert_eq!(f.centers, s.centers);
        assert_eq!(f.scales, s.scales);
        assert_eq!(front.camera, stacked.camera, "seen as the front view is");
        assert_eq!(s.coeffs.len(), dims.0 * dims.1 * dims.2);
        for (k, glyph) in s.coeffs.iter().enumerate() {
            assert_eq!(
                glyph,
                &f.coeffs[k % layer],
                "glyph {k}: a copy of the first layer's"
            );
        }
        // The front block's deeper layers are glyphs of their own.
        assert_ne!(f.coeffs[layer], f.coeffs[0]);
    }

    #[test]
    fn fodf_blocks_on_every_core_give_the_serial_glyphs() {
        for band in [2, 8, 12] {
            let want = serial_fodf(300, band);
            // Blocks that end mid-list and blocks past the inline size of `fill_chunks`.
            for block in [7, 64, FODF_BLOCK] {
                let got = fodf_coefficient_blocks(300, band, block).unwrap();
                assert_eq!(got.len(), want.len());
                for (k, (g, w)) in got.iter().zip(&want).enumerate() {
                    assert_eq!(g.len(), sh_count(band));
                    for (a, b) in g.iter().zip(w) {
                        assert!(
                            (a - b).abs() <= 1e-12 * b.abs().max(1e-3),
                            "band {band}, block {block}, glyph {k}: {a} vs {b}"
                        );
                    }
                }
            }
        }
        let scene = fodf(300, 8, 64, 48).unwrap();
        assert_eq!(scene.glyph_sets[0].coeffs, serial_fodf(300, 8));
        assert_eq!(scene.glyph_sets[0].centers.len(), 300);
    }

    /// The Legendre polynomial P_l(t) (Bonnet's recurrence).
    fn legendre(l: u32, t: f64) -> f64 {
        let (mut prev, mut cur) = (1.0, t);
        if l == 0 {
            return prev;
        }
        for n in 1..l {
            let n = n as f64;
            (prev, cur) = (cur, ((2.0 * n + 1.0) * t * cur - n * prev) / (n + 1.0));
        }
        cur
    }

    #[test]
    fn fodf_kernels_follow_the_addition_theorem() {
        // sum_m Y_lm(d) Y_lm(u) = (2l + 1) / (4 pi) P_l(d . u) in the orthonormal basis,
        // so the series is sum_i w_i sum_l k_l (2l + 1) / (4 pi) P_l(d_i . u).
        let fibres = [
            (DVec3::new(0.2, 0.5, 0.8).normalize(), 1.0),
            (DVec3::X, 0.6),
        ];
        let mut rng = SplitMix64::new(5);
        for band in [2, 8, 12] {
            let c = fodf_coefficients(band, &fibres);
            let taper = fodf_taper(band);
            let closed = |u: DVec3| -> f64 {
                let zonal = |t: f64| -> f64 {
                    (0..=band)
                        .step_by(2)
                        .map(|l| {
                            let k = taper[crate::glyph::sh::sh_index(l, 0)];
                            k * (2 * l + 1) as f64 / (4.0 * std::f64::consts::PI) * legendre(l, t)
                        })
                        .sum()
                };
                fibres.iter().map(|(d, w)| w * zonal(d.dot(u))).sum()
            };
            let dirs = (0..200).map(|_| rng.direction()).chain(fibres.map(|f| f.0));
            for u in dirs {
                let got = sh_eval(band, ShBasis::Tournier07, false, &c, u);
                let want = closed(u);
                assert!(
                    (got - want).abs() < 1e-12,
                    "band {band} at {u}: {got} vs {want}"
                );
            }
        }
    }
}
