//! Tight proxies: a glyph cut into eight convex pieces, one per octant of a frame turned
//! to its largest lobe, each bounded by guaranteed support planes.
//!
//! # The pieces
//!
//! The glyph is star-shaped about its centre: the surface is q = r(u) u over unit u. Take
//! an orthonormal frame (e0, e1, e2) and its eight octants R_s = { u : s_k (u . e_k) >= 0 }
//! (signs s). Piece s is the convex set
//!
//! ```text
//!   P_s = { x : s_k (x . e_k) >= 0 (k = 0, 1, 2),  (x . n_j) <= h_j (j = 0..7) }
//! ```
//!
//! with the seven directions n_j = s o D_j, where D_j are e0, e1, e2, the three edge
//! diagonals (e0 + e1) / sqrt 2, ... and the corner diagonal (e0 + e1 + e2) / sqrt 3 of the
//! positive octant, reflected into octant s. The three cone planes through the centre are
//! shared with the neighbouring pieces (the same plane, the other side). P_s holds every
//! surface point r(u) u with u in R_s, and the centre, exactly when h_j is at least the
//! support
//!
//! ```text
//!   h_j >= max over u in R_s of r(u) (u . n_j)    (and >= 0),
//! ```
//!
//! so the eight pieces together hold the glyph (its points t r(u) u, 0 <= t <= 1, lie on
//! the segment from the centre to the surface point of u, inside the convex piece of u).
//! Every n_j has (u . n_j) >= 0 on R_s, so with g_j(u) = f(u) (u . n_j), a homogeneous
//! polynomial of degree n + 1, the support is the maximum over R_s of |g_j| (of g_j for
//! `negative: hide`, where r = max(f, 0)).
//!
//! # The bound: branch and bound over the octant's cells
//!
//! R_s is exactly a quarter of three faces of the cube around the sphere in the frame, so
//! it is a union of the cube-sphere cells of [`super::bounds`]. Each support is bounded by
//! the same branch and bound as the glyph's radius there: on a cell of angular radius
//! theta around its centre v, along any great circle from v, g_j is a trigonometric
//! polynomial of degree d = n + 1, so by Bernstein's inequality and Taylor's theorem
//!
//! ```text
//!   |g(u)| <= |g(v)| + d M theta,    |g(u)| <= |g(v)| + |grad_t g(v)| theta + d^2 M theta^2 / 2,
//! ```
//!
//! with M an upper bound of max |g_j| over the whole sphere (not only the region: the
//! inequality is about the whole great circle), for which the glyph's guaranteed radius
//! serves (|u . n_j| <= 1). Cells whose bound is below the best sample are dropped; the
//! top cell is split until its bound is within `TOLERANCE` of the best sample, or a budget
//! of evaluations runs out (the top bound is still valid then, only looser). The result
//! is padded for rounding like the radius (1e-12 of the coefficient sum).
//!
//! # The frame
//!
//! The frame is the glyph's box frame (`proxy::glyph_bounds`) turned by the least rotation
//! that takes its corner diagonal (e0 + e1 + e2) / sqrt 3 onto the direction of the
//! largest sampled radius, so that the largest lobe (and its opposite) lies in the middle
//! of one piece (and of the opposite one) instead of across seams. Any frame gives valid
//! pieces; the frame only decides how tight they are.
//!
//! For r(-u) = r(u) (`negative: abs`, or `hide` at even orders) the glyph is symmetric
//! about its centre and piece s is piece -s mirrored: four octants are bounded.
//!
//! # On the GPU
//!
//! Seven planes that all face out of the octant cannot hold a thin lobe tightly: a lobe
//! along the corner diagonal fills the cube of its tip. So each piece also has the
//! twelve "mixed" directions of the 26-sided polytope (e0 - e1, e0 + e1 - e2, ...; in all
//! nineteen, [`piece_directions`]), whose supports are bounded the same way, where
//! r(u) (u . n) may be negative on part of the octant (a cell wholly on the negative side
//! bounds nothing). The renderer (`--proxy pieces`) draws each piece as an octagon around
//! its outline and clips each fragment's ray to its piece (glsl/pieces.glsl); the
//! supports travel as six-bit numbers, rounded up in 1/63 of the glyph's sphere radius
//! ([`GlyphPieces::gpu_words`]).
use glam::{DQuat, DVec3};

use super::NegativeMode;
use super::bounds::{Cell, fibonacci_sphere};
use super::polynomial::GlyphPolynomial;
use super::proxy::GlyphBounds;

/// The number of pieces of a glyph.
pub(crate) const PIECES: usize = 8;
/// The support planes of a piece besides its three cone planes.
pub(crate) const PIECE_PLANES: usize = 19;

/// The nineteen plane directions of the positive octant, as integer steps on the frame's
/// axes (normalised by [`piece_directions`]): the three axes, the three edge diagonals,
/// the corner diagonal (all facing out of the octant), then the six mixed edge diagonals
/// and the six mixed corner diagonals. glsl/pieces.glsl's `PIECE_SLOT` holds the same
/// order (a test compares them).
pub(crate) const PIECE_STEPS: [[i8; 3]; PIECE_PLANES] = [
    [1, 0, 0],
    [0, 1, 0],
    [0, 0, 1],
    [1, 1, 0],
    [0, 1, 1],
    [1, 0, 1],
    [1, 1, 1],
    [1, -1, 0],
    [-1, 1, 0],
    [0, 1, -1],
    [0, -1, 1],
    [1, 0, -1],
    [-1, 0, 1],
    [1, 1, -1],
    [1, -1, 1],
    [-1, 1, 1],
    [1, -1, -1],
    [-1, 1, -1],
    [-1, -1, 1],
];

/// The unit directions of [`PIECE_STEPS`], in frame coordinates.
pub(crate) fn piece_directions() -> [DVec3; PIECE_PLANES] {
    PIECE_STEPS.map(|m| DVec3::new(f64::from(m[0]), f64::from(m[1]), f64::from(m[2])).normalize())
}

/// 32-bit words a glyph's pieces take on the GPU: its frame's quaternion (4 floats), then
/// per piece its nineteen supports as six-bit numbers, five to a word (glsl/pieces.glsl).
pub(crate) const PIECE_WORDS: usize = 4 + 4 * PIECES;

/// Relative gap between a support's bound and its best sample at which refinement stops.
const TOLERANCE: f64 = 0.02;
/// Cell evaluations per octant at most; past it the open cells' bounds are taken (valid,
/// only looser).
const MAX_EVALUATIONS: usize = 6_000;
/// Rounding allowance relative to the absolute coefficient sum (as the radius's).
const ROUNDING_SLACK: f64 = 1e-12;
/// Directions sampled to find the largest lobe that the frame is turned to.
const LOBE_SAMPLES: usize = 400;

/// The GPU's step of a support: 1/63 of the glyph's sphere radius.
const SUPPORT_STEPS: f64 = 63.0;

/// Adds support `relative` (units of the sphere radius) of plane `j` of piece `piece` to
/// the GPU's words, rounded up to the next step (at least one, at most the sphere).
fn pack_support(words: &mut [u32; PIECE_WORDS], piece: usize, j: usize, relative: f64) {
    let steps = (relative * SUPPORT_STEPS).ceil().clamp(1.0, SUPPORT_STEPS) as u32;
    words[4 + 4 * piece + j / 5] |= steps << (6 * (j % 5));
}

/// The signs (+1 or -1 per frame axis) of octant `piece`: bit k set is negative along k.
pub(crate) fn octant_signs(piece: usize) -> DVec3 {
    let sign = |k: usize| if piece >> k & 1 == 1 { -1.0 } else { 1.0 };
    DVec3::new(sign(0), sign(1), sign(2))
}

/// A glyph's eight pieces, in the units of its polynomial (before any scale).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct GlyphPieces {
    /// The frame's orthonormal, right-handed axes (columns of a rotation, frame to glyph).
    pub(crate) axes: [DVec3; 3],
    /// Per piece (octant, [`octant_signs`]), the guaranteed supports along
    /// [`piece_directions`] reflected into the octant; all 0 for a piece that holds no
    /// part of the surface (a hidden negative lobe's octant).
    pub(crate) supports: [[f64; PIECE_PLANES]; PIECES],
}

impl GlyphPieces {
    /// Whether the point `q` (glyph coordinates, the polynomial's units) lies in piece
    /// `piece`, with the planes moved out by `slack`.
    #[cfg(test)]
    pub(crate) fn piece_contains(&self, piece: usize, q: DVec3, slack: f64) -> bool {
        let signs = octant_signs(piece);
        let local = DVec3::new(
            q.dot(self.axes[0]),
            q.dot(self.axes[1]),
            q.dot(self.axes[2]),
        );
        let reflected = local * signs;
        if reflected.min_element() < -slack {
            return false;
        }
        piece_directions()
            .iter()
            .zip(&self.supports[piece])
            .all(|(d, h)| reflected.dot(*d) <= h + slack)
    }

    /// Whether some piece holds `q` (within `slack`).
    #[cfg(test)]
    pub(crate) fn contains(&self, q: DVec3, slack: f64) -> bool {
        (0..PIECES).any(|p| self.piece_contains(p, q, slack))
    }

    /// The GPU's words ([`PIECE_WORDS`]): the frame's unit quaternion (frame to glyph) as
    /// float bits, then per piece its supports in steps of 1/63 of `unit` (the glyph's
    /// sphere radius in the polynomial's units, before the offset), rounded up (the
    /// offset added as the box's extents add it: (h / unit + offset) / (1 + offset)),
    /// at most the sphere, padded as the box's extents are.
    pub(crate) fn gpu_words(&self, unit: f64, offset: f64, padding: f64) -> [u32; PIECE_WORDS] {
        let q = DQuat::from_mat3(&glam::DMat3::from_cols(
            self.axes[0],
            self.axes[1],
            self.axes[2],
        ))
        .normalize();
        let mut words = [0u32; PIECE_WORDS];
        for (w, c) in words.iter_mut().zip([q.x, q.y, q.z, q.w]) {
            *w = (c as f32).to_bits();
        }
        for (piece, supports) in self.supports.iter().enumerate() {
            for (j, &h) in supports.iter().enumerate() {
                let relative = (h / unit + offset) / (1.0 + offset) * (1.0 + padding);
                pack_support(&mut words, piece, j, relative);
            }
        }
        words
    }
}

/// The GPU's pieces of a glyph without its own ([`PIECE_WORDS`]): its 26-sided polytope
/// (its box cut across its ten diagonals) cut by the octants of its box frame, from its
/// GPU box (rotation x, y, z, w, then the half extents) and its GPU hull (the ten
/// diagonals' extents of [`super::proxy::diagonal_directions`]), in units of the sphere
/// radius. Valid wherever the polytope holds the glyph (ellipsoids, stiffness surfaces,
/// sets whose float64 glyphs were not kept); tighter than the box, looser than a glyph's
/// own pieces.
pub(crate) fn polytope_piece_words(gpu_box: &[f32; 8], hull: &[f32; 12]) -> [u32; PIECE_WORDS] {
    let mut words = [0u32; PIECE_WORDS];
    for (w, c) in words.iter_mut().zip(&gpu_box[..4]) {
        *w = c.to_bits();
    }
    for (piece, slots) in polytope_slots().iter().enumerate() {
        for (j, &k) in slots.iter().enumerate() {
            let extent = if k < 3 { gpu_box[4 + k] } else { hull[k - 3] };
            pack_support(&mut words, piece, j, f64::from(extent));
        }
    }
    words
}

/// For each piece and plane, which of the polytope's 13 directions (the box's three
/// axes, then the ten diagonals) is the plane's direction or its opposite: the same for
/// every glyph, so worked out once.
fn polytope_slots() -> &'static [[usize; PIECE_PLANES]; PIECES] {
    static SLOTS: std::sync::OnceLock<[[usize; PIECE_PLANES]; PIECES]> = std::sync::OnceLock::new();
    SLOTS.get_or_init(|| {
        let mut axes = vec![DVec3::X, DVec3::Y, DVec3::Z];
        axes.extend(super::proxy::diagonal_directions());
        let directions = piece_directions();
        std::array::from_fn(|piece| {
            let signs = octant_signs(piece);
            std::array::from_fn(|j| {
                let n = directions[j] * signs;
                axes.iter()
                    .position(|a| a.dot(n).abs() > 1.0 - 1e-9)
                    .expect("every piece direction is one of the polytope's")
            })
        })
    })
}

/// The glyph's pieces, from its polynomial and its bounds (the frame starts from the
/// box's axes; the radius bounds the Bernstein terms). None for a zero or non-finite
/// polynomial.
pub(crate) fn glyph_pieces(
    poly: &GlyphPolynomial,
    negative: NegativeMode,
    bounds: &GlyphBounds,
) -> Option<GlyphPieces> {
    let s = poly.abs_coefficient_sum();
    if !s.is_finite() || s <= 0.0 || !bounds.radius.is_finite() {
        return None;
    }
    let axes = turned_frame(poly, negative, bounds.axes);
    let symmetric = negative == NegativeMode::Abs || poly.order.is_multiple_of(2);
    let mut supports = [[0.0; PIECE_PLANES]; PIECES];
    let directions = piece_directions();
    let slack = ROUNDING_SLACK * s;
    for piece in 0..PIECES {
        if symmetric && piece >= PIECES / 2 {
            // The mirror image of the octant with every sign flipped (bits 0..2 all
            // inverted): the same supports.
            supports[piece] = supports[PIECES - 1 - piece];
            continue;
        }
        let signs = octant_signs(piece);
        let normals = directions.map(|d| {
            axes[0] * (signs.x * d.x) + axes[1] * (signs.y * d.y) + axes[2] * (signs.z * d.z)
        });
        let mut search = OctantSearch {
            poly,
            negative,
            normals,
            axes,
            m_known: bounds.radius,
            best: [0.0; PIECE_PLANES],
            evaluations: 0,
        };
        let bounded = search.run(signs, s);
        for (h, b) in supports[piece].iter_mut().zip(bounded) {
            // No support exceeds the sphere's radius.
            *h = (b.max(0.0) + slack).min(bounds.radius);
        }
    }
    Some(GlyphPieces { axes, supports })
}

/// The box's frame turned so that its corner diagonal points along the largest sampled
/// radius (module notes).
fn turned_frame(poly: &GlyphPolynomial, negative: NegativeMode, axes: [DVec3; 3]) -> [DVec3; 3] {
    let radius = |u: DVec3| match negative {
        NegativeMode::Abs => poly.eval(u).abs(),
        NegativeMode::Hide => poly.eval(u).max(0.0),
    };
    let (_, lobe) = fibonacci_sphere(LOBE_SAMPLES).map(|u| (radius(u), u)).fold(
        (f64::NEG_INFINITY, DVec3::X),
        |a, b| if b.0 > a.0 { b } else { a },
    );
    let diagonal = (axes[0] + axes[1] + axes[2]).normalize();
    // The lobe's direction or its opposite, whichever is nearer the diagonal (both are
    // lobes of a symmetric glyph; for an asymmetric one, the sampled one).
    let target = if negative == NegativeMode::Abs || poly.order.is_multiple_of(2) {
        if lobe.dot(diagonal) < 0.0 {
            -lobe
        } else {
            lobe
        }
    } else {
        lobe
    };
    let turn = DQuat::from_rotation_arc(diagonal, target);
    axes.map(|a| (turn * a).normalize())
}

/// The branch and bound of one octant's seven supports at once (module notes): each
/// cell's f and gradient serve all seven, level by level; a cell is split while one of
/// its seven bounds may exceed that support's best sample by more than `TOLERANCE`.
struct OctantSearch<'a> {
    poly: &'a GlyphPolynomial,
    negative: NegativeMode,
    /// The seven planes' unit normals, in glyph coordinates.
    normals: [DVec3; PIECE_PLANES],
    /// The frame whose octant is searched (cells are in frame coordinates).
    axes: [DVec3; 3],
    /// An upper bound of max |f| over the sphere (hence of every max |g_j|).
    m_known: f64,
    /// The best sampled value of each target (a lower bound of its support).
    best: [f64; PIECE_PLANES],
    evaluations: usize,
}

impl OctantSearch<'_> {
    /// Upper bounds of the seven supports over octant `signs` (`s`: the coefficient sum).
    fn run(&mut self, signs: DVec3, s: f64) -> [f64; PIECE_PLANES] {
        let absolute = 1e-6 * s;
        let mut cells: Vec<(Cell, [f64; PIECE_PLANES])> =
            octant_cells(signs).map(|c| self.bound(c)).collect();
        // What the retired cells may reach beyond the final best samples is within the
        // tolerance; the cells still open at the budget's end keep their own bounds.
        let mut open_bound = [0.0f64; PIECE_PLANES];
        while !cells.is_empty() {
            let mut next = Vec::with_capacity(4 * cells.len());
            let over_budget = self.evaluations + 4 * cells.len() > MAX_EVALUATIONS;
            for (cell, bounds) in cells {
                let open = (0..PIECE_PLANES)
                    .any(|j| bounds[j] > self.best[j] * (1.0 + TOLERANCE) + absolute);
                if !open {
                    continue;
                }
                if over_budget {
                    for j in 0..PIECE_PLANES {
                        open_bound[j] = open_bound[j].max(bounds[j]);
                    }
                    continue;
                }
                for child in cell.children() {
                    next.push(self.bound(child));
                }
            }
            cells = next;
        }
        std::array::from_fn(|j| open_bound[j].max(self.best[j] * (1.0 + TOLERANCE) + absolute))
    }

    /// A cell's seven bounds, the best samples updated with its centre's values.
    fn bound(&mut self, cell: Cell) -> (Cell, [f64; PIECE_PLANES]) {
        self.evaluations += 1;
        let center = cell.center();
        let theta = cell.angular_radius(center);
        let u = self.axes[0] * center.x + self.axes[1] * center.y + self.axes[2] * center.z;
        let (f, grad) = self.poly.eval_with_gradient(u);
        let d = f64::from(self.poly.order + 1);
        let m = self.m_known;
        let first = d * theta * m;
        let second = 0.5 * d * d * theta * theta * m;
        let mut bounds = [0.0; PIECE_PLANES];
        let shaped = match self.negative {
            NegativeMode::Abs => f.abs(),
            NegativeMode::Hide => f.max(0.0),
        };
        for (j, normal) in self.normals.iter().enumerate() {
            let along = normal.dot(u);
            // A point of the surface: r(u) (u . n) is a lower bound of the support.
            self.best[j] = self.best[j].max(shaped * along);
            // |u . n - v . n| <= |u - v| <= theta: a cell wholly on the negative side of
            // a mixed direction holds no point beyond the centre's plane.
            if along + theta <= 0.0 {
                continue;
            }
            // Elsewhere r(u) (u . n) <= |g(u)| (abs), or <= max(g(u), 0) (hide, where
            // r = max(f, 0)): the bounds of g's Taylor terms hold for it.
            let g = f * along;
            let grad_g = grad * along + *normal * f;
            let tangential = (grad_g - grad_g.dot(u) * u).length();
            let value = match self.negative {
                NegativeMode::Abs => g.abs(),
                NegativeMode::Hide => g,
            };
            bounds[j] = (value + first).min(value + tangential * theta + second);
        }
        (cell, bounds)
    }
}

/// The cube-sphere cells (frame coordinates) that tile octant `signs`: a quarter of each
/// of the three faces the octant meets, two by two cells each.
fn octant_cells(signs: DVec3) -> impl Iterator<Item = Cell> {
    let sign = signs.to_array();
    (0..3usize).flat_map(move |axis| {
        let face = 2 * axis as u8 + u8::from(sign[axis] < 0.0);
        let (s_sign, t_sign) = (sign[(axis + 1) % 3], sign[(axis + 2) % 3]);
        (0..4usize).map(move |k| {
            // Quarter [0, 1] or [-1, 0] per coordinate, halved.
            let start = |sign: f64, half: usize| {
                if sign > 0.0 {
                    0.5 * half as f64
                } else {
                    -1.0 + 0.5 * half as f64
                }
            };
            Cell {
                face,
                s0: start(s_sign, k % 2),
                t0: start(t_sign, k / 2),
                size: 0.5,
            }
        })
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::glyph::monomials::symmetric_count;
    use crate::glyph::polynomial::test_support::Rng;
    use crate::glyph::proxy::glyph_bounds;
    use crate::glyph::{Symmetry, TensorLayout};

    fn symmetric(order: u32, t: &[f64]) -> GlyphPolynomial {
        let layout = TensorLayout {
            order,
            symmetry: Symmetry::Symmetric,
        };
        GlyphPolynomial::from_tensor(layout, t).unwrap()
    }

    /// Every sampled surface point of random glyphs lies in its pieces.
    #[test]
    fn pieces_hold_random_glyphs() {
        let mut rng = Rng::new(5);
        for order in [2u32, 4, 6, 8] {
            for _ in 0..4 {
                let t = rng.values(symmetric_count(order), -1.0, 1.0);
                let poly = symmetric(order, &t);
                let bounds = glyph_bounds(&poly).unwrap();
                for negative in [NegativeMode::Abs, NegativeMode::Hide] {
                    let pieces = glyph_pieces(&poly, negative, &bounds).unwrap();
                    for u in fibonacci_sphere(20_000) {
                        let f = poly.eval(u);
                        let r = match negative {
                            NegativeMode::Abs => f.abs(),
                            NegativeMode::Hide => f.max(0.0),
                        };
                        assert!(pieces.contains(u * r, 0.0), "order {order} {negative:?}");
                    }
                }
            }
        }
    }

    /// glsl/pieces.glsl's slot table names the directions of PIECE_STEPS in their order.
    #[test]
    fn the_shader_slot_table_follows_the_steps() {
        let glsl = include_str!("../../glsl/pieces.glsl");
        let start = glsl.find("PIECE_SLOT[27] = int[27](").unwrap() + 25;
        let end = start + glsl[start..].find(')').unwrap();
        let slots: Vec<i32> = glsl[start..end]
            .split(',')
            .map(|v| v.trim().parse().unwrap())
            .collect();
        for (code, slot) in slots.iter().enumerate() {
            let r = [code % 3, code / 3 % 3, code / 9].map(|c| c as i8 - 1);
            let expected = PIECE_STEPS
                .iter()
                .position(|m| *m == r)
                .map_or(-1, |j| j as i32);
            assert_eq!(*slot, expected, "code {code} ({r:?})");
        }
    }

    /// The GPU's words decode (as glsl/pieces.glsl reads them) to supports at least the
    /// bounds', within one step above them.
    #[test]
    fn gpu_words_round_supports_up() {
        let mut rng = Rng::new(11);
        let poly = symmetric(6, &rng.values(symmetric_count(6), -1.0, 1.0));
        let bounds = glyph_bounds(&poly).unwrap();
        let pieces = glyph_pieces(&poly, NegativeMode::Abs, &bounds).unwrap();
        let words = pieces.gpu_words(bounds.radius, 0.0, 0.0);
        for piece in 0..PIECES {
            for j in 0..PIECE_PLANES {
                let bits = words[4 + 4 * piece + j / 5] >> (6 * (j % 5)) & 63;
                let gpu = f64::from(bits) / 63.0;
                let relative = pieces.supports[piece][j] / bounds.radius;
                assert!(gpu >= relative && gpu <= relative.max(1.0 / 63.0) + 1.0 / 63.0);
            }
            // The twentieth number is left for the piece's index.
            assert_eq!(words[4 + 4 * piece + 3] >> 24, 0);
        }
    }

    /// How long bounding a glyph's pieces takes (printed, not asserted).
    #[test]
    #[ignore]
    fn pieces_timing() {
        let mut rng = Rng::new(7);
        let order = 8;
        let polys: Vec<_> = (0..50)
            .map(|_| symmetric(order, &rng.values(symmetric_count(order), -1.0, 1.0)))
            .collect();
        let start = std::time::Instant::now();
        for p in &polys {
            let b = glyph_bounds(p).unwrap();
            glyph_pieces(p, NegativeMode::Abs, &b).unwrap();
        }
        eprintln!("{:?} per glyph", start.elapsed() / polys.len() as u32);
    }
}
