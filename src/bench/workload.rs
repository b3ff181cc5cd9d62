//! Generated workloads: square grids of fibre glyphs of one order, framed by a camera
//! that sees the whole grid, so glyph count, order and resolution can be swept alone.
//!
//! - `grid:COUNT:ORDER`: symmetric fibre tensors (two or three crossing populations);
//! - `fodf:COUNT:BAND`: fibre ODFs as SH series (tournier07, MRtrix3's basis) with one to
//!   three random fibres each, the common case of real HARDI data.
use crate::camera::{Camera, Projection};
use crate::catalog::{MAX_SH_BAND, MAX_SYMMETRIC_ORDER};
use crate::demo::{direction, fibre_tensor, glyph_set, symmetric};
use crate::glyph::sh::{sh_basis_values, sh_orders};
use crate::rng::SplitMix64;
use crate::scene::{GlyphKind, GlyphSet, ImageSize, Scene, ShBasis};
use crate::{Error, Result, Setting};
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
    fodf_coefficients_tapered(band, &fodf_taper(band), fibres)
}

/// The taper k_l of [`fodf_coefficients`], one per coefficient (l, m).
fn fodf_taper(band: u32) -> Vec<f64> {
    let top = (band * (band + 1)).max(1) as f64;
    sh_orders(band)
        .map(|(l, _)| (-2.0 * (l * (l + 1)) as f64 / top).exp())
        .collect()
}

/// [`fodf_coefficients`] with the taper computed once.
fn fodf_coefficients_tapered(band: u32, taper: &[f64], fibres: &[(DVec3, f64)]) -> Vec<f64> {
    let mut coeffs = vec![0.0; taper.len()];
    for (d, w) in fibres {
        let y = sh_basis_values(band, ShBasis::Tournier07, false, *d);
        for ((c, k), y) in coeffs.iter_mut().zip(taper).zip(y) {
            *c += w * k * y;
        }
    }
    coeffs
}

/// `count` fibre ODFs of SH band `band` (even, 2..=12) on a square grid of unit spacing:
/// one to three fibres each (40 %, 40 %, 20 %) in random directions with weights 1 and
/// 0.4 to 0.9, each glyph scaled to a peak radius of about 0.45; seen as `grid` is.
pub fn fodf(count: usize, band: u32, width: u32, height: u32) -> Result<Scene> {
    if count == 0 || count > MAX_WORKLOAD_GLYPHS {
        return Err(glyph_count(count));
    }
    if !(2..=MAX_SH_BAND).contains(&band) || !band.is_multiple_of(2) {
        return Err(Error::setting_value(
            Setting::Workload,
            format!("SH band {band}"),
            format!("a workload's SH band is one of 2, 4, ..., {MAX_SH_BAND}"),
        ));
    }
    let side = (count as f64).sqrt().ceil() as usize;
    let mut rng = SplitMix64::new(0x5eed_f0df ^ (count as u64) << 8 ^ band as u64);
    let mut centers = Vec::with_capacity(count);
    let mut coeffs = Vec::with_capacity(count);
    let taper = fodf_taper(band);
    for k in 0..count {
        let (i, j) = (k % side, k / side);
        let draw = rng.unit();
        let fibre_count = if draw < 0.4 {
            1
        } else if draw < 0.8 {
            2
        } else {
            3
        };
        let fibres: Vec<(DVec3, f64)> = (0..fibre_count)
            .map(|f| {
                let weight = if f == 0 { 1.0 } else { 0.4 + 0.5 * rng.unit() };
                (rng.direction(), weight)
            })
            .collect();
        // The peak of the dominant fibre's kernel, for a size that does not depend on
        // how many fibres cross.
        let c = fodf_coefficients_tapered(band, &taper, &fibres);
        let peak = fibres
            .iter()
            .map(|(d, _)| crate::glyph::sh::sh_eval(band, ShBasis::Tournier07, false, &c, *d).abs())
            .fold(0.0, f64::max);
        centers.push(DVec3::new(
            i as f64 - 0.5 * (side - 1) as f64,
            j as f64 - 0.5 * (side - 1) as f64,
            0.0,
        ));
        coeffs.push(c.iter().map(|v| v * 0.45 / peak.max(1e-12)).collect());
    }
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

/// Parses `grid:COUNT:ORDER` or `fodf:COUNT:BAND`.
pub fn parse(spec: &str, width: u32, height: u32) -> Result<Scene> {
    let parts: Vec<&str> = spec.split(':').collect();
    let bad = || {
        Error::setting_value(
            Setting::Workload,
            format!("'{}'", crate::error::quoted(spec)),
            "not grid:COUNT:ORDER or fodf:COUNT:BAND",
        )
    };
    let number = |s: &str| s.parse::<usize>().map_err(|_| bad());
    match parts.as_slice() {
        ["grid", count, order] => grid(number(count)?, number(order)? as u32, width, height),
        ["fodf", count, band] => fodf(number(count)?, number(band)? as u32, width, height),
        _ => Err(bad()),
    }
}
