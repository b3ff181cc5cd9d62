//! Generated workloads: square grids of fibre glyphs of one order, framed by a camera
//! that sees the whole grid, so glyph count, order and resolution can be swept alone.
use crate::camera::{Camera, Projection};
use crate::demo::{direction, fibre_tensor, glyph_set, symmetric};
use crate::io::scene::{ImageSize, Scene};
use crate::{Error, Result};
use glam::DVec3;

/// `count` glyphs of `order` (even, 2..=12) on a square grid of unit spacing, two or three
/// crossing populations each, turning across the grid; seen from above at an angle.
pub fn grid(count: usize, order: u32, width: u32, height: u32) -> Result<Scene> {
    if count == 0 || count > 4_000_000 {
        return Err(Error::Invalid(format!(
            "workload: {count} glyphs is not in 1..=4000000"
        )));
    }
    if !(1..=12).contains(&order) {
        return Err(Error::Invalid(format!(
            "workload: order {order} is not in 1..=12"
        )));
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
    let extent = side as f64;
    Ok(Scene {
        glyph_sets: vec![glyph_set(symmetric(order), centers, 0.48, coeffs)],
        camera: Camera {
            projection: Projection::Perspective { fov_y_deg: 30.0 },
            eye: DVec3::new(0.0, -1.2 * extent, 1.6 * extent + 2.0),
            target: DVec3::ZERO,
            up: DVec3::Z,
        },
        image: ImageSize { width, height },
    })
}

/// Parses `grid:COUNT:ORDER`.
pub fn parse(spec: &str, width: u32, height: u32) -> Result<Scene> {
    let parts: Vec<&str> = spec.split(':').collect();
    let bad = || Error::Invalid(format!("--workload: '{spec}' is not grid:COUNT:ORDER"));
    match parts.as_slice() {
        ["grid", count, order] => grid(
            count.parse().map_err(|_| bad())?,
            order.parse().map_err(|_| bad())?,
            width,
            height,
        ),
        _ => Err(bad()),
    }
}
