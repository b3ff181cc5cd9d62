//! Fast guaranteed bounds of a glyph: its bounding radius and an oriented bounding box,
//! in a few microseconds per glyph, for preparing whole brain slices (10^4 to 10^6 glyphs).
//!
//! # The bound: band norms of the spherical-harmonic expansion
//!
//! On the unit sphere, a homogeneous polynomial f of degree d is a spherical-harmonic
//! series of the bands l = d, d - 2, ... (the parity of d): f = sum_l f_l with
//! f_l(u) = sum_m w_lm Y_lm(u) in a real orthonormal basis. By Cauchy-Schwarz and the
//! addition theorem, sum_m Y_lm(u)^2 = (2l + 1) / (4 pi) for every u, so
//!
//! ```text
//!   |f(u)| <= sum_l |f_l(u)| <= sum_l sqrt((2l + 1) / (4 pi)) ||w_l||_2 .
//! ```
//!
//! The bound is attained by a zonal function whose bands all have the same sign on its
//! axis, which is what a single-fibre ODF is, and it stays within a few tens of percent
//! for crossings. The coefficients w = P c come from the monomial coefficients c by one
//! matrix P per degree, built once in float64 by a quadrature that is exact for these
//! degrees (Gauss-Legendre in z times a uniform rule in the azimuth), so the cost per
//! glyph is one K x K product (K = (d + 1)(d + 2) / 2): about 2,000 multiplications at
//! order 8.
//!
//! # The oriented box
//!
//! The glyph is the star-shaped set { q : |q| <= |f(q / |q|)| } (its subset for
//! `negative: hide`), which is symmetric about its centre because |f(-u)| = |f(u)|. Its
//! extent along a unit axis a is max over u of |f(u)| |u . a| = max |g_a(u)| with
//! g_a(u) = f(u) (a . u), itself a homogeneous polynomial of degree d + 1: the same bound
//! applies. The axes are the eigenvectors of the second moment of f^2 over the sphere,
//! A = integral of f(u)^2 u u^T (exact, from the monomial moments), which line up with
//! the lobes: a fibre's axis for one fibre, the plane of a crossing for two. The axes
//! only decide how tight the box is; every extent is a guaranteed bound whatever they are.
//! The same bounds are taken along the box frame's ten diagonals ([`diagonal_directions`]),
//! which cut the box into a 26-sided polytope that the ray-casting pass outlines on the
//! screen (`--proxy hull`). Since g_n is linear in n, the band coefficients of g along
//! n = sum c_k a_k are the same combination of the three axes' (one projection per axis,
//! not per direction), and at each lattice node n . u is that combination of a_k . u.
//!
//! # Tighter where sampling proves it: Szegő's inequality
//!
//! The band bound of an extent is exact for a fibre's own axis, but across a fibre or a
//! crossing it runs 30 to 55 % above the true extent (measured on the 256-glyph fODF
//! benchmark field: the boxes held 2.2 times the volume of the tightest boxes on the same
//! axes), and every pixel of a box runs the ray caster. So each bound is also taken from
//! samples, with a proof that no value between them is larger. On a great circle
//! u(t) = cos t e1 + sin t e2, a homogeneous polynomial g of degree d is a trigonometric
//! polynomial of degree at most d, and Szegő's inequality T'^2 + d^2 T^2 <= d^2 max T^2
//! gives, at a maximum T(t0) = M, T(t0 + h) >= M cos(d h) while d |h| <= pi. The
//! circle through the maximiser of |g| over the sphere and any lattice node within the
//! lattice's covering radius theta of it (|g| is even, so nodes are needed on half the
//! sphere only) then shows
//!
//! ```text
//!   max |g| <= max over the nodes |g(v)| / cos(d theta)      (d theta < pi / 2).
//! ```
//!
//! The nodes are an equiangular grid on three faces of the cube (`SampleLattice`), whose
//! covering radius is bounded cell by cell: a point of a cell is within half the cell's
//! diagonal of a corner in the face's plane, and a segment of that plane seen from the
//! centre subtends at most its length over its least distance from the centre. With 32
//! cells a side, theta is about 0.041: a pad of 7 % on an order-8 glyph's extents (d = 9),
//! 16 % at order 12. Each bound is the smaller of the band bound and this one; the cost is
//! f at 3,267 nodes per glyph, one product with a per-order table of monomial values.
//!
//! Rounding: P is exact to about 1e-15 relative; the bound is padded by 1e-9 S (S, the
//! sum of the absolute monomial coefficients, bounds |f| on the sphere) and capped by S.
use std::sync::OnceLock;

use glam::DVec3;

use super::monomials::{Monomial, monomial_index, monomials, symmetric_count};
use super::polynomial::GlyphPolynomial;

/// Highest polynomial degree the tables are built for: orders up to 20
/// (`GlyphPolynomial`'s limit) and their products with a linear form.
const MAX_DEGREE: usize = 21;
/// Padding relative to the absolute coefficient sum (see the module notes).
const ROUNDING_SLACK: f64 = 1e-9;

/// A glyph's guaranteed bounds, in the units of its polynomial (before any scale).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GlyphBounds {
    /// Upper bound of |f(u)| over unit u: the radius of a sphere that holds the glyph.
    pub radius: f64,
    /// Orthonormal, right-handed box axes (columns of a rotation).
    pub axes: [DVec3; 3],
    /// Upper bounds of the glyph's extent along each axis (each at most `radius`): the
    /// glyph lies in the box `|q . axes[i]| <= extents[i]`.
    pub extents: [f64; 3],
    /// Upper bounds of the glyph's extent along the box frame's ten diagonals
    /// ([`diagonal_directions`]): with the three axes', a guaranteed 26-sided polytope
    /// (`|q . n_j| <= diagonals[j]`) that holds the glyph more tightly than the box.
    pub diagonals: [f64; 10],
}

/// The ten diagonal directions of a box frame, as coefficients on its axes: the six face
/// diagonals (a0 + a1, a0 - a1, a1 + a2, a1 - a2, a0 + a2, a0 - a2) / sqrt 2 and the four
/// corner diagonals (a0 + a1 + a2, a0 + a1 - a2, a0 - a1 + a2, a0 - a1 - a2) / sqrt 3, in
/// the order of [`GlyphBounds::diagonals`] (raycast.vert reads them in this order).
pub fn diagonal_directions() -> [DVec3; 10] {
    let s2 = std::f64::consts::FRAC_1_SQRT_2;
    let s3 = 1.0 / 3f64.sqrt();
    [
        DVec3::new(s2, s2, 0.0),
        DVec3::new(s2, -s2, 0.0),
        DVec3::new(0.0, s2, s2),
        DVec3::new(0.0, s2, -s2),
        DVec3::new(s2, 0.0, s2),
        DVec3::new(s2, 0.0, -s2),
        DVec3::new(s3, s3, s3),
        DVec3::new(s3, s3, -s3),
        DVec3::new(s3, -s3, s3),
        DVec3::new(s3, -s3, -s3),
    ]
}

impl GlyphBounds {
    /// Bounds whose diagonal extents are the box's own (its support along each
    /// diagonal): what a glyph without a tighter bound along them gets.
    pub fn from_box(radius: f64, axes: [DVec3; 3], extents: [f64; 3]) -> GlyphBounds {
        let extent = DVec3::from_array(extents);
        GlyphBounds {
            radius,
            axes,
            extents,
            diagonals: diagonal_directions().map(|n| (n.abs() * extent).element_sum().min(radius)),
        }
    }

    /// The box's rotation as a unit quaternion (x, y, z, w), box frame to glyph frame.
    pub fn rotation(&self) -> glam::DQuat {
        glam::DQuat::from_mat3(&glam::DMat3::from_cols(
            self.axes[0],
            self.axes[1],
            self.axes[2],
        ))
        .normalize()
    }
}

/// The projection of degree-d monomial coefficients onto the bands of their parity.
///
/// P is three-quarters zeros: Y_lm has one parity in x and one in y (m >= 0: the real
/// part of (x + i y)^|m|, even in y and of x-parity |m|; m < 0: the imaginary part, odd
/// in y and of x-parity |m| + 1), and x^a y^b z^c integrates to zero against it unless
/// a and b have those parities. Each row is therefore stored over the columns of its
/// parity class only, and a glyph's coefficients are gathered by class once per bound:
/// a quarter of the multiplications of the dense product. (The quadrature's values at
/// the other entries are rounding noise about 1e-16; `new` checks they are below 1e-12 of
/// P's largest entry and leaves them out, which is the exact value; a row that failed the check
/// would keep all its entries, as class `DENSE`.)
struct BandProjector {
    /// The bands l = d % 2, d % 2 + 2, ..., d, each with its 2l + 1 rows.
    bands: Vec<u32>,
    /// Per row, in (l, m) order: its parity class and where its entries start in
    /// `packed` (each row has as many entries as its class has columns).
    rows: Vec<(u8, u32)>,
    /// The rows' entries over their class's columns, in `class_columns` order.
    packed: Vec<f64>,
    /// The monomial indices of each parity class (a % 2 + 2 (b % 2)), in order, and of
    /// `DENSE` (every monomial) if a row is kept whole.
    class_columns: [Vec<u16>; 5],
}

/// Monomials of the highest degree a glyph's product with a linear form has.
const MAX_MONOMIALS: usize = GATHERED / 2;
/// Monomials of the highest degree of f^2 the moment tables hold (2 (MAX_DEGREE - 1)).
const MAX_SQUARE_MONOMIALS: usize = (2 * MAX_DEGREE) * (2 * MAX_DEGREE + 1) / 2;

/// The class of a row kept over every column.
const DENSE: u8 = 4;

/// Room for a glyph's gathered coefficients: every class (the monomials of the highest
/// degree the tables hold, d + 1 for d = MAX_DEGREE) and the dense class again.
const GATHERED: usize = (MAX_DEGREE + 2) * (MAX_DEGREE + 3);

/// The parity class of x^a y^b z^c: a % 2 + 2 (b % 2).
fn parity_class(m: Monomial) -> u8 {
    (m.a % 2 + 2 * (m.b % 2)) as u8
}

impl BandProjector {
    fn new(degree: u32) -> Self {
        let monos = monomials(degree);
        let bands: Vec<u32> = (degree % 2..=degree).step_by(2).collect();
        let rows: usize = bands.iter().map(|l| 2 * *l as usize + 1).sum();
        let columns = monos.len();
        let mut matrix = vec![0.0; rows * columns];
        // Exact for polynomials of degree <= 2d + 1 on the sphere (see module notes).
        let (nodes, weights) = gauss_legendre(degree as usize + 1);
        let azimuths = 2 * degree as usize + 2;
        let azimuth_weight = 2.0 * std::f64::consts::PI / azimuths as f64;
        let mut sh = Vec::with_capacity(rows);
        let mut powers = Vec::with_capacity(columns);
        for (z, wz) in nodes.iter().zip(&weights) {
            let r = (1.0 - z * z).max(0.0).sqrt();
            for j in 0..azimuths {
                let phi = 2.0 * std::f64::consts::PI * (j as f64 + 0.5) / azimuths as f64;
                let u = DVec3::new(r * phi.cos(), r * phi.sin(), *z);
                real_sh_values(degree, &bands, u, &mut sh);
                powers.clear();
                powers.extend(monos.iter().map(|m| monomial_value(*m, u)));
                let w = wz * azimuth_weight;
                for (row, y) in sh.iter().enumerate() {
                    let line = &mut matrix[row * columns..(row + 1) * columns];
                    for (entry, p) in line.iter_mut().zip(&powers) {
                        *entry += w * y * p;
                    }
                }
            }
        }
        let mut class_columns: [Vec<u16>; 5] = Default::default();
        for (i, m) in monos.iter().enumerate() {
            class_columns[parity_class(*m) as usize].push(i as u16);
        }
        let row_classes = bands.iter().flat_map(|&l| {
            (-(l as i32)..=l as i32).map(|m| {
                let k = m.unsigned_abs();
                if m >= 0 {
                    (k % 2) as u8
                } else {
                    ((k + 1) % 2 + 2) as u8
                }
            })
        });
        let mut packed_rows = Vec::with_capacity(rows);
        let mut packed = Vec::with_capacity(rows * columns / 4 + columns);
        // The rounding noise of the quadrature's sums is relative to the terms summed, of
        // the size of P's largest entries, not to a row's own (some rows are 1e-4 of it).
        let largest = matrix.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        for (line, class) in matrix.chunks_exact(columns).zip(row_classes) {
            let outside = monos
                .iter()
                .zip(line)
                .filter(|(m, _)| parity_class(**m) != class)
                .fold(0.0f64, |a, (_, v)| a.max(v.abs()));
            let class = if outside <= 1e-12 * largest {
                class
            } else {
                if class_columns[DENSE as usize].is_empty() {
                    class_columns[DENSE as usize] = (0..columns as u16).collect();
                }
                DENSE
            };
            packed_rows.push((class, packed.len() as u32));
            packed.extend(
                class_columns[class as usize]
                    .iter()
                    .map(|&i| line[i as usize]),
            );
        }
        Self {
            bands,
            rows: packed_rows,
            packed,
            class_columns,
        }
    }

    /// w = P coeffs, into `w` (one value per row, in (l, m) order), with `gathered` as
    /// working room (every entry read is written first).
    fn project(&self, coeffs: &[f64], gathered: &mut [f64; GATHERED], w: &mut [f64]) {
        // The coefficients gathered class by class, so each row's product is one dot
        // product over a contiguous run.
        let mut starts = [0usize; 6];
        let mut n = 0;
        for (class, columns) in self.class_columns.iter().enumerate() {
            starts[class] = n;
            for &i in columns {
                gathered[n] = coeffs.get(i as usize).copied().unwrap_or(0.0);
                n += 1;
            }
        }
        starts[5] = n;
        for (value, &(class, offset)) in w.iter_mut().zip(&self.rows) {
            let (c0, c1) = (starts[class as usize], starts[class as usize + 1]);
            let row = &self.packed[offset as usize..offset as usize + (c1 - c0)];
            *value = dot(row, &gathered[c0..c1]);
        }
    }

    /// sum_l sqrt((2l + 1) / (4 pi)) ||w_l|| for w = P coeffs.
    fn band_bound(&self, coeffs: &[f64], scratch: &mut Scratch) -> f64 {
        let Scratch { gathered, w } = scratch;
        self.project(coeffs, gathered, w);
        self.band_norm(w)
    }

    /// sum_l sqrt((2l + 1) / (4 pi)) ||w_l|| for band coefficients w (in (l, m) order).
    fn band_norm(&self, w: &[f64]) -> f64 {
        let mut w = w.iter();
        let mut total = 0.0;
        for l in &self.bands {
            let norm2: f64 = w.by_ref().take(2 * *l as usize + 1).map(|v| v * v).sum();
            total += ((2 * l + 1) as f64 / (4.0 * std::f64::consts::PI)).sqrt() * norm2.sqrt();
        }
        total
    }
}

/// Working room of [`BandProjector::band_bound`], made once per glyph: zeroing these
/// arrays (5 kB) anew for each of a glyph's four bounds was 5 % of bounding a million
/// glyphs. Nothing is carried from one bound to the next: `project` writes every entry
/// it reads.
struct Scratch {
    gathered: [f64; GATHERED],
    w: [f64; MAX_MONOMIALS],
}

impl Scratch {
    fn new() -> Self {
        Self {
            gathered: [0.0; GATHERED],
            w: [0.0; MAX_MONOMIALS],
        }
    }
}

/// sum_i a_i b_i over the shorter length, in four interleaved partial sums: a single
/// running sum is a chain of dependent additions, and these dot products are most of the
/// cost of bounding a glyph. (The rounding allowance of the bounds does not depend on
/// the order of the additions.)
fn dot(a: &[f64], b: &[f64]) -> f64 {
    let n = a.len().min(b.len());
    let (a, b) = (&a[..n], &b[..n]);
    let mut partial = [0.0f64; 4];
    let mut a4 = a.chunks_exact(4);
    let mut b4 = b.chunks_exact(4);
    for (x, y) in a4.by_ref().zip(b4.by_ref()) {
        for ((p, x), y) in partial.iter_mut().zip(x).zip(y) {
            *p += x * y;
        }
    }
    let tail: f64 = a4
        .remainder()
        .iter()
        .zip(b4.remainder())
        .map(|(x, y)| x * y)
        .sum();
    (partial[0] + partial[1]) + (partial[2] + partial[3]) + tail
}

/// The products c_i c_j, j = `j`..`j + len`, of f^2's coefficients, which add to the
/// coefficients `k`..`k + len` of f^2 (twice over where i != j). Along a run of j with one
/// power of x, m_i m_j steps through consecutive monomials too, so the pairs (i, j) fall
/// into runs (at order 8, 194 runs of 1,035 pairs), each one slice operation. The runs
/// keep the pairs' order, (i, j) ascending, so each coefficient of f^2 sums its terms in
/// the same order as pair by pair.
#[derive(Clone, Copy, Debug)]
struct SquareRun {
    i: u16,
    j: u16,
    k: u16,
    len: u16,
    twice: bool,
}

/// Per degree d: the projector of degree d, the monomial index of x m, y m and z m in
/// degree d + 1 for every monomial m, and what the second moment of f^2 needs.
struct DegreeTables {
    projector: BandProjector,
    times_axis: Vec<[u16; 3]>,
    /// The products m_i m_j (i <= j) of f^2, in runs (module `SquareRun`).
    square_runs: Vec<SquareRun>,
    /// Per monomial g of degree 2d: the integrals of g u_a u_b over the sphere, for
    /// (a, b) = xx, xy, xz, yy, yz, zz.
    moments: Vec<[f64; 6]>,
}

impl DegreeTables {
    fn new(degree: u32) -> Self {
        let monos = monomials(degree);
        let times_axis = monos
            .iter()
            .map(|m| {
                let up = |m: Monomial| monomial_index(degree + 1, m) as u16;
                [
                    up(Monomial { a: m.a + 1, ..*m }),
                    up(Monomial { b: m.b + 1, ..*m }),
                    up(Monomial { c: m.c + 1, ..*m }),
                ]
            })
            .collect();
        let mut square_runs: Vec<SquareRun> = Vec::new();
        for (i, mi) in monos.iter().enumerate() {
            for (j, mj) in monos.iter().enumerate().skip(i) {
                let product = Monomial {
                    a: mi.a + mj.a,
                    b: mi.b + mj.b,
                    c: mi.c + mj.c,
                };
                let k = monomial_index(2 * degree, product) as u16;
                let (i, j, twice) = (i as u16, j as u16, i != j);
                match square_runs.last_mut() {
                    Some(run)
                        if run.i == i
                            && run.twice == twice
                            && run.j + run.len == j
                            && run.k + run.len == k =>
                    {
                        run.len += 1
                    }
                    _ => square_runs.push(SquareRun {
                        i,
                        j,
                        k,
                        len: 1,
                        twice,
                    }),
                }
            }
        }
        let moments = monomials(2 * degree)
            .iter()
            .map(|g| {
                let m = |da: u32, db: u32, dc: u32| sphere_moment(g.a + da, g.b + db, g.c + dc);
                [
                    m(2, 0, 0),
                    m(1, 1, 0),
                    m(1, 0, 1),
                    m(0, 2, 0),
                    m(0, 1, 1),
                    m(0, 0, 2),
                ]
            })
            .collect();
        Self {
            projector: BandProjector::new(degree),
            times_axis,
            square_runs,
            moments,
        }
    }
}

fn projector(degree: u32) -> &'static BandProjector {
    static TABLES: [OnceLock<BandProjector>; MAX_DEGREE + 1] =
        [const { OnceLock::new() }; MAX_DEGREE + 1];
    let index = (degree as usize).min(MAX_DEGREE);
    TABLES[index].get_or_init(|| BandProjector::new(index as u32))
}

fn degree_tables(degree: u32) -> &'static DegreeTables {
    static TABLES: [OnceLock<DegreeTables>; MAX_DEGREE] = [const { OnceLock::new() }; MAX_DEGREE];
    let index = (degree as usize).min(MAX_DEGREE - 1);
    TABLES[index].get_or_init(|| DegreeTables::new(index as u32))
}

/// Cells along each side of a cube face of the sampling lattice (module notes).
const LATTICE_CELLS: usize = 32;

/// Nodes on three faces of the cube (x, y or z = 1), projected onto the sphere: every unit
/// vector or its opposite lies within `covering` of one (module notes).
struct SampleLattice {
    nodes: Vec<DVec3>,
    /// An upper bound of the geodesic distance from any unit vector, or its opposite, to
    /// the nearest node.
    covering: f64,
}

impl SampleLattice {
    fn new(cells: usize) -> Self {
        // Equiangular coordinates on the face: tan of evenly spaced angles in [-pi/4, pi/4].
        let coordinate =
            |i: usize| (std::f64::consts::FRAC_PI_4 * (2.0 * i as f64 / cells as f64 - 1.0)).tan();
        let grid: Vec<f64> = (0..=cells).map(coordinate).collect();
        let mut nodes = Vec::with_capacity(3 * grid.len() * grid.len());
        for face in 0..3 {
            for &s in &grid {
                for &t in &grid {
                    let v = match face {
                        0 => DVec3::new(1.0, s, t),
                        1 => DVec3::new(t, 1.0, s),
                        _ => DVec3::new(s, t, 1.0),
                    };
                    nodes.push(v.normalize());
                }
            }
        }
        // Per cell [s0, s1] x [t0, t1] of the plane at distance 1: a point is within half
        // the diagonal of a corner, and that segment, no nearer to the plane's foot than
        // the cell is (r_min), subtends at most its length over sqrt(1 + r_min^2).
        let nearest = |a: f64, b: f64| {
            if a <= 0.0 && b >= 0.0 {
                0.0
            } else {
                a.abs().min(b.abs())
            }
        };
        let mut covering = 0.0f64;
        for s in grid.windows(2) {
            for t in grid.windows(2) {
                let half_diagonal = 0.5 * (s[1] - s[0]).hypot(t[1] - t[0]);
                let r_min = nearest(s[0], s[1]).hypot(nearest(t[0], t[1]));
                covering = covering.max(half_diagonal / (1.0 + r_min * r_min).sqrt());
            }
        }
        // Allowance for the rounding of the coordinates above (about 1e-16 relative).
        Self {
            nodes,
            covering: covering * (1.0 + 1e-9),
        }
    }
}

fn sample_lattice() -> &'static SampleLattice {
    static LATTICE: OnceLock<SampleLattice> = OnceLock::new();
    LATTICE.get_or_init(|| SampleLattice::new(LATTICE_CELLS))
}

/// The monomial values of one degree at the lattice's nodes, row-major (a row per node).
fn lattice_values(degree: u32) -> &'static [f64] {
    static TABLES: [OnceLock<Vec<f64>>; MAX_DEGREE + 1] =
        [const { OnceLock::new() }; MAX_DEGREE + 1];
    let index = (degree as usize).min(MAX_DEGREE);
    TABLES[index].get_or_init(|| {
        let monos = monomials(index as u32);
        sample_lattice()
            .nodes
            .iter()
            .flat_map(|u| monos.iter().map(|m| monomial_value(*m, *u)))
            .collect()
    })
}

/// Szegő's bound (module notes) of max |g| over the sphere for g homogeneous of degree
/// `degree`, from its largest absolute value `sampled` at the lattice's nodes; infinite
/// where the lattice is too coarse for the degree.
fn sampled_bound(sampled: f64, degree: u32) -> f64 {
    let angle = degree as f64 * sample_lattice().covering;
    if angle >= 0.5 * std::f64::consts::PI {
        return f64::INFINITY;
    }
    sampled / angle.cos()
}

/// The glyph's radius bound and oriented box, each bound the smaller of the band bound
/// and the sampled one (module notes). None for a zero or non-finite polynomial.
pub fn glyph_bounds(poly: &GlyphPolynomial) -> Option<GlyphBounds> {
    glyph_bounds_with(poly, Sampling::Lattice)
}

/// Whether a glyph's bounds also take the sampled bound (module notes).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Sampling {
    /// The band bounds alone: about 5 microseconds a glyph at order 8.
    None,
    /// Also f at the lattice's 3,267 nodes: boxes of about half the volume on fibre
    /// ODFs, at about 45 microseconds a glyph more (order 8), which pays where a glyph
    /// covers thousands of pixels, not for a million small ones.
    Lattice,
}

/// [`glyph_bounds`], with or without the sampled bound.
pub(crate) fn glyph_bounds_with(poly: &GlyphPolynomial, sampling: Sampling) -> Option<GlyphBounds> {
    let s = poly.abs_coefficient_sum();
    if !s.is_finite() || s <= 0.0 {
        return None;
    }
    let tables = degree_tables(poly.order);
    let slack = ROUNDING_SLACK * s;
    // f at the lattice's nodes (none without sampling).
    let lattice = sample_lattice();
    let values: Vec<f64> = match sampling {
        Sampling::Lattice => lattice_values(poly.order)
            .chunks_exact(poly.coeffs.len())
            .map(|row| dot(row, &poly.coeffs))
            .collect(),
        Sampling::None => Vec::new(),
    };
    let sampled_or_band = |sampled: f64, degree: u32| match sampling {
        Sampling::Lattice => sampled_bound(sampled, degree),
        Sampling::None => f64::INFINITY,
    };
    let sampled_radius = values.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let mut scratch = Scratch::new();
    let radius = (tables.projector.band_bound(&poly.coeffs, &mut scratch) + slack)
        .min(sampled_or_band(sampled_radius, poly.order) + slack)
        .min(s);
    let axes = moment_axes(tables, &poly.coeffs);
    let higher = projector(poly.order + 1);
    let monomials = symmetric_count(poly.order + 1).min(MAX_MONOMIALS);
    // g_a = f (a . u) has degree n + 1 and is linear in a: its band coefficients along
    // any combination of the axes are that combination of the axes' (module notes).
    let mut bands = [[0.0; MAX_MONOMIALS]; 3];
    let mut sums = [0.0; 3];
    let mut product = [0.0; MAX_MONOMIALS];
    for ((a, w), sum) in axes.iter().zip(&mut bands).zip(&mut sums) {
        let product = &mut product[..monomials];
        product.iter_mut().for_each(|v| *v = 0.0);
        for (c, up) in poly.coeffs.iter().zip(&tables.times_axis) {
            product[up[0] as usize] += c * a.x;
            product[up[1] as usize] += c * a.y;
            product[up[2] as usize] += c * a.z;
        }
        *sum = product.iter().map(|v| v.abs()).sum();
        higher.project(product, &mut scratch.gathered, &mut w[..monomials]);
    }
    // |f(u)| |n . u| at the nodes, for the axes and the diagonals (n = sum c_k a_k, so
    // n . u = sum c_k (a_k . u)).
    let diagonal = diagonal_directions();
    let directions: [DVec3; 13] = std::array::from_fn(|k| match k {
        0 => DVec3::X,
        1 => DVec3::Y,
        2 => DVec3::Z,
        _ => diagonal[k - 3],
    });
    let mut sampled = [0.0f64; 13];
    for (f, u) in values.iter().zip(&lattice.nodes) {
        let along = DVec3::new(axes[0].dot(*u), axes[1].dot(*u), axes[2].dot(*u));
        for (m, n) in sampled.iter_mut().zip(&directions) {
            *m = m.max((f * n.dot(along)).abs());
        }
    }
    let mut combined = [0.0; MAX_MONOMIALS];
    let mut extent_along = |k: usize| {
        let n = directions[k];
        let w = &mut combined[..monomials];
        for (i, v) in w.iter_mut().enumerate() {
            *v = n.x * bands[0][i] + n.y * bands[1][i] + n.z * bands[2][i];
        }
        // The combined product's absolute sum is at most that of the axes' products.
        let s_product = n.x.abs() * sums[0] + n.y.abs() * sums[1] + n.z.abs() * sums[2];
        let slack = ROUNDING_SLACK * s_product.max(s);
        (higher.band_norm(w) + slack)
            .min(sampled_or_band(sampled[k], poly.order + 1) + slack)
            .min(radius)
    };
    let extents = [0, 1, 2].map(&mut extent_along);
    // Each diagonal also bound by the box's support along it.
    let from_box = GlyphBounds::from_box(radius, axes, extents);
    let mut diagonals = from_box.diagonals;
    for (j, bound) in diagonals.iter_mut().enumerate() {
        *bound = bound.min(extent_along(3 + j));
    }
    Some(GlyphBounds {
        radius,
        axes,
        extents,
        diagonals,
    })
}

/// Below this ratio of the largest to the smallest eigenvalue of the second moment, a
/// glyph counts as round: its moment axes say little (they are as good as random), and
/// the world axes are taken instead, which views along an axis (slices, the common case)
/// see face on: a box turned at random shows up to sqrt(3) times the area of one face.
const ROUND_GLYPH_RATIO: f64 = 1.5;

/// The box axes: eigenvectors of A = integral of f^2 u u^T over the sphere as a
/// right-handed frame, or the world axes for a round glyph (see ROUND_GLYPH_RATIO).
fn moment_axes(tables: &DegreeTables, coeffs: &[f64]) -> [DVec3; 3] {
    let mut square = [0.0; MAX_SQUARE_MONOMIALS];
    let square = &mut square[..tables.moments.len().min(MAX_SQUARE_MONOMIALS)];
    add_square(tables, coeffs, square);
    let mut a = [0.0; 6];
    for (g, moment) in square.iter().zip(&tables.moments) {
        for (entry, m) in a.iter_mut().zip(moment) {
            *entry += g * m;
        }
    }
    let matrix = nalgebra::Matrix3::new(a[0], a[1], a[2], a[1], a[3], a[4], a[2], a[4], a[5]);
    if !matrix.iter().all(|v| v.is_finite()) {
        return [DVec3::X, DVec3::Y, DVec3::Z];
    }
    let eigen = nalgebra::SymmetricEigen::new(matrix);
    let (smallest, largest) = eigen
        .eigenvalues
        .iter()
        .fold((f64::INFINITY, 0.0f64), |(lo, hi), v| {
            (lo.min(*v), hi.max(*v))
        });
    // NaN eigenvalues (never seen; rounding of huge coefficients) count as round too.
    let anisotropic = largest > ROUND_GLYPH_RATIO * smallest;
    if !anisotropic {
        return [DVec3::X, DVec3::Y, DVec3::Z];
    }
    let column = |k: usize| {
        let v = eigen.eigenvectors.column(k);
        DVec3::new(v[0], v[1], v[2]).normalize_or_zero()
    };
    let (x, y) = (column(0), column(1));
    // Re-orthonormalise (the solver's vectors are orthonormal to rounding) and make the
    // frame right-handed, so the box's faces keep their winding.
    let x = if x == DVec3::ZERO { DVec3::X } else { x };
    let y = (y - x * x.dot(y)).normalize_or(x.any_orthonormal_vector());
    let z = x.cross(y);
    [x, y, z]
}

/// Adds the monomial coefficients of f^2 to `square` (zeros: then it holds f^2).
fn add_square(tables: &DegreeTables, coeffs: &[f64], square: &mut [f64]) {
    for run in &tables.square_runs {
        let ci = coeffs[run.i as usize];
        let (j, k, len) = (run.j as usize, run.k as usize, run.len as usize);
        let targets = square[k..k + len].iter_mut().zip(&coeffs[j..j + len]);
        if run.twice {
            targets.for_each(|(s, cj)| *s += 2.0 * (ci * cj));
        } else {
            targets.for_each(|(s, cj)| *s += ci * cj);
        }
    }
}

/// Integral of x^a y^b z^c over the unit sphere: 0 unless all powers are even, else
/// 4 pi (a-1)!! (b-1)!! (c-1)!! / (a+b+c+1)!!.
fn sphere_moment(a: u32, b: u32, c: u32) -> f64 {
    if a % 2 == 1 || b % 2 == 1 || c % 2 == 1 {
        return 0.0;
    }
    // Divide factor by factor to stay in range for high degrees.
    let mut numerators: Vec<f64> = [a, b, c]
        .iter()
        .flat_map(|&p| (1..p).step_by(2).map(|k| k as f64))
        .collect();
    let denominators: Vec<f64> = (1..=a + b + c + 1).step_by(2).map(|k| k as f64).collect();
    numerators.resize(denominators.len().max(numerators.len()), 1.0);
    let ratio: f64 = numerators
        .iter()
        .zip(denominators.iter().chain(std::iter::repeat(&1.0)))
        .map(|(n, d)| n / d)
        .product();
    4.0 * std::f64::consts::PI * ratio
}

fn monomial_value(m: Monomial, u: DVec3) -> f64 {
    u.x.powi(m.a as i32) * u.y.powi(m.b as i32) * u.z.powi(m.c as i32)
}

/// Real orthonormal spherical harmonics of the given bands at unit u, in (l, m) order
/// (m = -l..l): Y_l0 = Q_l^0, Y_lm = sqrt 2 Q_l^|m| Re (m > 0) or Im (m < 0) of
/// (x + i y)^|m|, with Q_l^m of `sh::legendre` (every l, odd ones included).
fn real_sh_values(degree: u32, bands: &[u32], u: DVec3, out: &mut Vec<f64>) {
    out.clear();
    let q = super::sh::legendre_table(degree, u.z);
    let mut powers = Vec::with_capacity(degree as usize + 1);
    let (mut re, mut im) = (1.0, 0.0);
    for _ in 0..=degree {
        powers.push((re, im));
        (re, im) = (re * u.x - im * u.y, re * u.y + im * u.x);
    }
    let sqrt2 = std::f64::consts::SQRT_2;
    for &l in bands {
        for m in -(l as i32)..=l as i32 {
            let k = m.unsigned_abs();
            let base = q[super::sh::legendre_index(l, k)];
            let (re, im) = powers[k as usize];
            out.push(match m.cmp(&0) {
                std::cmp::Ordering::Equal => base,
                std::cmp::Ordering::Greater => sqrt2 * base * re,
                std::cmp::Ordering::Less => sqrt2 * base * im,
            });
        }
    }
}

/// Nodes and weights of the n-point Gauss-Legendre rule on [-1, 1] (Newton on P_n).
fn gauss_legendre(n: usize) -> (Vec<f64>, Vec<f64>) {
    let mut nodes = Vec::with_capacity(n);
    let mut weights = Vec::with_capacity(n);
    for i in 0..n {
        let mut x = (std::f64::consts::PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
        let mut derivative = 1.0;
        for _ in 0..100 {
            let (mut p0, mut p1) = (1.0, x);
            for k in 2..=n {
                let k = k as f64;
                (p0, p1) = (p1, ((2.0 * k - 1.0) * x * p1 - (k - 1.0) * p0) / k);
            }
            let pn = if n == 0 { 1.0 } else { p1 };
            let pn_1 = if n <= 1 { 1.0 } else { p0 };
            derivative = n as f64 * (x * pn - pn_1) / (x * x - 1.0);
            let step = pn / derivative;
            x -= step;
            if step.abs() < 1e-16 {
                break;
            }
        }
        nodes.push(x);
        weights.push(2.0 / ((1.0 - x * x) * derivative * derivative));
    }
    (nodes, weights)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::glyph::monomials::multiplicity;

    /// A deterministic pseudo-random sequence in [-1, 1).
    fn noise(seed: u64) -> impl FnMut() -> f64 {
        let mut state = seed;
        move || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((state >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
        }
    }

    fn fibonacci(count: usize) -> Vec<DVec3> {
        crate::glyph::bounds::fibonacci_sphere(count).collect()
    }

    /// The box frame's diagonals ([`diagonal_directions`]) in the glyph's frame.
    fn world_diagonals(bounds: &GlyphBounds) -> [DVec3; 10] {
        let a = bounds.axes;
        diagonal_directions().map(|n| a[0] * n.x + a[1] * n.y + a[2] * n.z)
    }

    fn fibre_poly(order: u32, fibres: &[(DVec3, f64)]) -> GlyphPolynomial {
        let coeffs = monomials(order)
            .iter()
            .map(|m| {
                let t: f64 = fibres
                    .iter()
                    .map(|(d, w)| w * monomial_value(*m, d.normalize()))
                    .sum();
                t * multiplicity(*m) as f64
            })
            .collect();
        GlyphPolynomial { order, coeffs }
    }

    #[test]
    fn gauss_legendre_integrates_polynomials_exactly() {
        let (x, w) = gauss_legendre(6);
        for k in 0..12 {
            let sum: f64 = x.iter().zip(&w).map(|(x, w)| w * x.powi(k)).sum();
            let exact = if k % 2 == 1 {
                0.0
            } else {
                2.0 / (k as f64 + 1.0)
            };
            assert!((sum - exact).abs() < 1e-14, "x^{k}: {sum} vs {exact}");
        }
    }

    #[test]
    fn sphere_moments_match_closed_forms() {
        let four_pi = 4.0 * std::f64::consts::PI;
        assert!((sphere_moment(0, 0, 0) - four_pi).abs() < 1e-14);
        assert!((sphere_moment(2, 0, 0) - four_pi / 3.0).abs() < 1e-14);
        assert!((sphere_moment(2, 2, 0) - four_pi / 15.0).abs() < 1e-14);
        assert!((sphere_moment(4, 0, 0) - four_pi / 5.0).abs() < 1e-14);
        assert_eq!(sphere_moment(1, 1, 0), 0.0);
    }

    /// The projector reproduces f: sum of the band parts equals f at random points, so
    /// the band norms are those of f itself.
    #[test]
    fn projection_reconstructs_the_polynomial() {
        for order in [1, 2, 3, 4, 7, 8, 12] {
            let mut rand = noise(order as u64);
            let coeffs: Vec<f64> = (0..symmetric_count(order)).map(|_| rand()).collect();
            let poly = GlyphPolynomial {
                order,
                coeffs: coeffs.clone(),
            };
            let p = projector(order);
            let mut w = vec![0.0; p.rows.len()];
            p.project(&coeffs, &mut [0.0; GATHERED], &mut w);
            let mut sh = Vec::new();
            for u in fibonacci(50) {
                real_sh_values(order, &p.bands, u, &mut sh);
                let series: f64 = sh.iter().zip(&w).map(|(y, w)| y * w).sum();
                let direct = poly.eval(u);
                assert!(
                    (series - direct).abs() < 1e-10 * poly.abs_coefficient_sum(),
                    "order {order}: {series} vs {direct}"
                );
            }
        }
    }

    /// Every row of every degree's projector lies in its parity class: the sparse
    /// product skips only exact zeros, and no row falls back to the dense class.
    #[test]
    fn projector_rows_keep_to_their_parity_class() {
        for degree in 0..=MAX_DEGREE as u32 {
            let p = projector(degree);
            assert!(
                p.rows.iter().all(|&(class, _)| class < DENSE),
                "degree {degree}"
            );
            assert!(p.class_columns[DENSE as usize].is_empty());
            let kept: usize = p
                .rows
                .iter()
                .map(|&(class, _)| p.class_columns[class as usize].len())
                .sum();
            let dense = p.rows.len() * symmetric_count(degree);
            assert!(
                degree < 2 || 2 * kept < dense,
                "degree {degree}: {kept} of {dense}"
            );
        }
    }

    /// The radius and every box extent hold the glyph: no sampled surface point lies
    /// outside, for random tensors of every order and for fibre glyphs.
    #[test]
    fn bounds_hold_every_sampled_surface_point() {
        let dirs = fibonacci(4000);
        let mut cases = Vec::new();
        for order in 1..=12 {
            let mut rand = noise(100 + order as u64);
            for _ in 0..4 {
                let coeffs = (0..symmetric_count(order)).map(|_| rand()).collect();
                cases.push(GlyphPolynomial { order, coeffs });
            }
        }
        for order in [2, 4, 6, 8, 10, 12] {
            cases.push(fibre_poly(order, &[(DVec3::new(1.0, 0.2, 0.1), 1.0)]));
            cases.push(fibre_poly(
                order,
                &[(DVec3::X, 1.0), (DVec3::new(0.3, 1.0, -0.2), 0.7)],
            ));
        }
        let samplings = [Sampling::Lattice, Sampling::None];
        for (poly, sampling) in cases.iter().flat_map(|p| samplings.map(|s| (p, s))) {
            let bounds = glyph_bounds_with(poly, sampling).expect("non-zero glyph");
            let mut max = 0.0f64;
            let mut extent = [0.0f64; 3];
            let diagonals = world_diagonals(&bounds);
            let mut diagonal = [0.0f64; 10];
            for u in &dirs {
                let r = poly.eval(*u).abs();
                max = max.max(r);
                for (e, a) in extent.iter_mut().zip(&bounds.axes) {
                    *e = e.max(r * u.dot(*a).abs());
                }
                for (e, n) in diagonal.iter_mut().zip(&diagonals) {
                    *e = e.max(r * u.dot(*n).abs());
                }
            }
            for (j, (sampled, bound)) in diagonal.iter().zip(&bounds.diagonals).enumerate() {
                assert!(
                    sampled <= bound,
                    "order {} diagonal {j}: {sampled} > {bound}",
                    poly.order,
                );
            }
            assert!(
                max <= bounds.radius,
                "order {}: {max} > {}",
                poly.order,
                bounds.radius
            );
            for (i, (sampled, bound)) in extent.iter().zip(&bounds.extents).enumerate() {
                assert!(
                    sampled <= bound,
                    "order {} axis {i}: {sampled} > {bound}",
                    poly.order,
                );
            }
            let frame = bounds.axes[0].cross(bounds.axes[1]).dot(bounds.axes[2]);
            assert!((frame - 1.0).abs() < 1e-9, "left-handed or skewed axes");
        }
    }

    /// A single fibre is zonal: the radius bound is exact, the long axis of the box
    /// follows the fibre, and no extent is more than the sampled bound's pad above the
    /// sampled one (7 % at order 8, 16 % at order 12).
    #[test]
    fn single_fibre_bounds_are_tight() {
        let axis = DVec3::new(0.3, -0.5, 0.8).normalize();
        let dirs = fibonacci(20000);
        for order in [4, 6, 8, 10, 12] {
            let poly = fibre_poly(order, &[(axis, 2.0)]);
            let bounds = glyph_bounds(&poly).expect("non-zero glyph");
            assert!((bounds.radius - 2.0).abs() < 1e-6, "{}", bounds.radius);
            assert!(bounds.axes.iter().any(|a| a.dot(axis).abs() > 0.999));
            for (a, e) in bounds.axes.iter().zip(&bounds.extents) {
                let sampled = dirs
                    .iter()
                    .map(|u| poly.eval(*u).abs() * u.dot(*a).abs())
                    .fold(0.0, f64::max);
                let pad = 1.0 / ((order + 1) as f64 * sample_lattice().covering).cos();
                assert!(
                    *e <= pad * sampled + 1e-9,
                    "order {order}: extent {e} against sampled {sampled}"
                );
            }
        }
    }

    /// Every unit vector, or its opposite, lies within the lattice's covering radius of a
    /// node (checked at 20,000 directions), and the radius is small enough for order 20.
    #[test]
    fn lattice_covers_the_sphere_within_its_radius() {
        let lattice = sample_lattice();
        assert!(lattice.covering < 0.045, "{}", lattice.covering);
        assert!(21.0 * lattice.covering < 0.5 * std::f64::consts::PI);
        let mut worst = 0.0f64;
        for u in fibonacci(20000) {
            let nearest = lattice
                .nodes
                .iter()
                .map(|v| u.dot(*v).abs().min(1.0).acos())
                .fold(f64::INFINITY, f64::min);
            worst = worst.max(nearest);
        }
        assert!(worst <= lattice.covering, "{worst} > {}", lattice.covering);
        // The bound is not far above what is seen (it is a bound, not an estimate).
        assert!(
            lattice.covering < 1.5 * worst,
            "{} vs {worst}",
            lattice.covering
        );
    }

    /// Fibre ODF-like glyphs of one to three fibres: every extent is within 10 % of the
    /// largest sampled one at order 8 (the band bound alone was up to 55 % above).
    #[test]
    fn fibre_glyph_extents_are_within_ten_percent() {
        let dirs = fibonacci(20000);
        let mut rand = noise(7);
        let mut direction = || DVec3::new(rand(), rand(), rand()).normalize();
        for fibres in 1..=3 {
            for _ in 0..4 {
                let spec: Vec<(DVec3, f64)> = (0..fibres)
                    .map(|k| (direction(), if k == 0 { 1.0 } else { 0.6 }))
                    .collect();
                let poly = fibre_poly(8, &spec);
                let bounds = glyph_bounds(&poly).expect("non-zero glyph");
                for (a, e) in bounds.axes.iter().zip(&bounds.extents) {
                    let sampled = dirs
                        .iter()
                        .map(|u| poly.eval(*u).abs() * u.dot(*a).abs())
                        .fold(0.0, f64::max);
                    assert!(sampled <= *e, "{sampled} > {e}");
                    assert!(
                        *e <= 1.1 * sampled,
                        "{fibres} fibres: {e} against {sampled}"
                    );
                }
            }
        }
    }

    /// The bounds hold against a far denser sampling than the lattice's, refined by
    /// gradient ascent on |g| from the best samples, for random tensors of every order
    /// (the hardest case for the sampled bound: no structure, highest degrees).
    #[test]
    fn bounds_hold_against_refined_maxima() {
        let dirs = fibonacci(60000);
        for order in 1..=12 {
            let mut rand = noise(500 + order as u64);
            for _ in 0..3 {
                let coeffs = (0..symmetric_count(order)).map(|_| rand()).collect();
                let poly = GlyphPolynomial { order, coeffs };
                let bounds = glyph_bounds(&poly).expect("non-zero glyph");
                let band_only = glyph_bounds_with(&poly, Sampling::None).expect("non-zero");
                // The band bounds hold alone, and the sampled ones only tighten them.
                assert!(bounds.radius <= band_only.radius);
                assert_eq!(bounds.axes, band_only.axes);
                for (tight, band) in bounds.extents.iter().zip(&band_only.extents) {
                    assert!(tight <= band);
                }
                for (tight, band) in bounds.diagonals.iter().zip(&band_only.diagonals) {
                    assert!(tight <= band);
                }
                let mut targets: Vec<(Option<DVec3>, f64)> = vec![(None, bounds.radius)];
                targets.extend(
                    bounds
                        .axes
                        .iter()
                        .zip(&bounds.extents)
                        .map(|(a, e)| (Some(*a), *e)),
                );
                targets.extend(
                    world_diagonals(&bounds)
                        .iter()
                        .zip(&bounds.diagonals)
                        .map(|(n, e)| (Some(*n), *e)),
                );
                for (axis, bound) in targets {
                    let g = |u: DVec3| {
                        let u = u.normalize();
                        poly.eval(u).abs() * axis.map_or(1.0, |a| u.dot(a).abs())
                    };
                    let mut best: Vec<(f64, DVec3)> = dirs.iter().map(|u| (g(*u), *u)).collect();
                    best.sort_by(|x, y| y.0.total_cmp(&x.0));
                    for (value, start) in best.iter().take(8) {
                        // Coordinate search on the sphere with shrinking steps.
                        let (mut u, mut v, mut step) = (*start, *value, 0.02);
                        while step > 1e-9 {
                            let basis = [
                                u.any_orthonormal_vector(),
                                u.cross(u.any_orthonormal_vector()),
                            ];
                            let moved = basis.iter().flat_map(|b| [*b, -*b]).find_map(|b| {
                                let w = (u + step * b).normalize();
                                let gw = g(w);
                                (gw > v).then_some((w, gw))
                            });
                            match moved {
                                Some((w, gw)) => (u, v) = (w, gw),
                                None => step *= 0.5,
                            }
                        }
                        assert!(v <= bound, "order {order}: {v} > {bound} (axis {axis:?})");
                    }
                }
            }
        }
    }

    /// A round glyph (three equal orthogonal fibres, second moment nearly isotropic) gets
    /// the world axes; a crossing of two fibres keeps its moment axes (one along the
    /// normal of its plane).
    /// The runs of f^2 hold every pair (i <= j) once, and give f^2 bit for bit as the
    /// pair-by-pair sum in (i, j) order.
    #[test]
    fn square_runs_give_the_pairwise_square() {
        for order in [1, 2, 4, 8, 12, 20] {
            let tables = degree_tables(order);
            let n = symmetric_count(order);
            let pairs: usize = tables.square_runs.iter().map(|r| r.len as usize).sum();
            assert_eq!(pairs, n * (n + 1) / 2, "order {order}");
            if order == 8 {
                assert_eq!(tables.square_runs.len(), 194);
            }
            let mut rand = noise(order as u64 + 7);
            let coeffs: Vec<f64> = (0..n).map(|_| rand()).collect();
            let monos = monomials(order);
            let mut want = vec![0.0; symmetric_count(2 * order)];
            for i in 0..n {
                for j in i..n {
                    let (mi, mj) = (monos[i], monos[j]);
                    let product = Monomial {
                        a: mi.a + mj.a,
                        b: mi.b + mj.b,
                        c: mi.c + mj.c,
                    };
                    let p = coeffs[i] * coeffs[j];
                    want[monomial_index(2 * order, product)] += if i == j { p } else { 2.0 * p };
                }
            }
            let mut got = vec![0.0; want.len()];
            add_square(tables, &coeffs, &mut got);
            assert_eq!(got, want, "order {order}");
        }
    }

    #[test]
    fn round_glyphs_take_the_world_axes() {
        let round = fibre_poly(4, &[(DVec3::X, 1.0), (DVec3::Y, 1.0), (DVec3::Z, 1.0)]);
        let bounds = glyph_bounds(&round).expect("non-zero glyph");
        assert_eq!(bounds.axes, [DVec3::X, DVec3::Y, DVec3::Z]);
        let a = DVec3::new(1.0, 1.0, 0.2).normalize();
        let b = DVec3::new(-1.0, 1.0, 0.3).normalize();
        let crossing = fibre_poly(8, &[(a, 1.0), (b, 1.0)]);
        let bounds = glyph_bounds(&crossing).expect("non-zero glyph");
        let normal = a.cross(b).normalize();
        assert!(
            bounds.axes.iter().any(|axis| axis.dot(normal).abs() > 0.99),
            "{:?}",
            bounds.axes
        );
    }
}
