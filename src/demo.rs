//! Built-in scenes: the demo that `glyphcast demo` renders, and fibre-like glyphs that
//! tests and benchmarks build on.
//!
//! A fibre population with unit directions d_i and weights w_i gives the symmetric tensor
//! T = sum_i w_i d_i (x) ... (x) d_i, whose glyph function is f(u) = sum_i w_i (u . d_i)^n:
//! even orders give crossing lobes that sharpen as n grows and that touch the centre
//! wherever u is orthogonal to every d_i.
use crate::camera::{Camera, Projection};
use crate::glyph::monomials::monomials;
use crate::glyph::{NegativeMode, Symmetry, TensorLayout};
use crate::io::scene::{GlyphKind, GlyphSet, ImageSize, Scene};
use glam::DVec3;

/// Unique coefficients (scene order) of sum_i w_i d_i^(x)n.
pub fn fibre_tensor(order: u32, fibres: &[(DVec3, f64)]) -> Vec<f64> {
    monomials(order)
        .iter()
        .map(|m| {
            fibres
                .iter()
                .map(|(d, w)| {
                    let d = d.normalize();
                    w * d.x.powi(m.a as i32) * d.y.powi(m.b as i32) * d.z.powi(m.c as i32)
                })
                .sum()
        })
        .collect()
}

/// A direction in the xy-plane at `deg` degrees from x, tilted `elev` degrees towards z.
pub fn direction(deg: f64, elev: f64) -> DVec3 {
    let (a, e) = (deg.to_radians(), elev.to_radians());
    DVec3::new(a.cos() * e.cos(), a.sin() * e.cos(), e.sin())
}

pub fn symmetric(order: u32) -> GlyphKind {
    GlyphKind::Tensor(TensorLayout {
        order,
        symmetry: Symmetry::Symmetric,
    })
}

/// A glyph set of one kind at the given centres, one scale for all.
pub fn glyph_set(
    kind: GlyphKind,
    centers: Vec<DVec3>,
    scale: f64,
    coeffs: Vec<Vec<f64>>,
) -> GlyphSet {
    GlyphSet {
        kind,
        negative: NegativeMode::Abs,
        scales: vec![scale; centers.len()],
        centers,
        coeffs,
    }
}

/// The demo: a 6 x 4 field of fibre glyphs of orders 4, 6 and 8 with one, two and three
/// crossing populations that turn across the field, seen from above at an angle.
pub fn demo_scene() -> Scene {
    let mut sets = Vec::new();
    for (row, order) in [4u32, 6, 8, 8].into_iter().enumerate() {
        let mut centers = Vec::new();
        let mut coeffs = Vec::new();
        for col in 0..6 {
            let turn = 15.0 * col as f64;
            let fibres: Vec<(DVec3, f64)> = match row {
                0 => vec![(direction(turn, 10.0), 1.0)],
                1 => vec![
                    (direction(turn, 0.0), 1.0),
                    (direction(turn + 70.0, 20.0), 0.8),
                ],
                2 => vec![
                    (direction(turn, 0.0), 1.0),
                    (direction(turn + 90.0, 0.0), 0.9),
                ],
                _ => vec![
                    (direction(turn, 0.0), 1.0),
                    (direction(turn + 60.0, 0.0), 0.9),
                    (direction(turn + 120.0, 35.0), 0.8),
                ],
            };
            centers.push(DVec3::new(col as f64 - 2.5, row as f64 - 1.5, 0.0));
            coeffs.push(fibre_tensor(order, &fibres));
        }
        sets.push(glyph_set(symmetric(order), centers, 0.48, coeffs));
    }
    Scene {
        glyph_sets: sets,
        camera: Camera {
            projection: Projection::Perspective { fov_y_deg: 30.0 },
            eye: DVec3::new(0.0, -7.4, 6.4),
            target: DVec3::new(0.0, 0.0, 0.0),
            up: DVec3::Z,
        },
        image: ImageSize {
            width: 800,
            height: 600,
        },
    }
}
