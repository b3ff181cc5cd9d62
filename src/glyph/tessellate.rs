//! Tessellated glyphs: the baseline that FURY/DIPY's `odf_slicer` and MRtrix's `mrview`
//! draw. A triangulated unit sphere (a subdivided icosahedron, or a latitude-longitude
//! grid) is shared by every glyph; each glyph moves the sphere's vertex u to its surface
//! point r(u) u, r = h(f(u)) + offset (h = |.|, or max(., 0) for `negative: hide`), and
//! takes the surface's analytic normal there, the same formula the ray caster shades with.
//!
//! Vertices are generated in float64 and stored in float32 as offsets from the glyph
//! centre in world units (scale * r(u) * u), so that far-away glyphs keep their precision;
//! glyphs are spread over scoped threads, since a level-6 icosphere is 40962 evaluations
//! of f and its gradient per glyph.
//!
//! Every vertex lies on the true surface, so the error of a tessellation is the deviation
//! of its flat triangles from the surface between them. For the sphere that has a closed
//! form ([`SphereMesh::max_radial_error`]), which the tests hold the renders to.
use std::collections::HashMap;

use glam::DVec3;

use super::NegativeMode;
use super::intersect::WorldGlyph;
use crate::{Error, Result, Setting};

/// Highest icosphere subdivision level: level 7 has 163842 vertices per glyph.
pub(crate) const MAX_ICOSPHERE_LEVEL: u32 = 7;
/// Latitude bands of a latitude-longitude sphere: 2 to this many.
pub(crate) const MAX_LAT_LONG_RINGS: u32 = 512;

/// Which triangulated sphere the glyphs are built on (`--method mesh:L`, `latlong:N`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum MeshKind {
    /// The icosahedron with every triangle split in four `level` times, vertices pushed
    /// onto the sphere: 10 * 4^L + 2 vertices, 20 * 4^L triangles (FURY's `repulsion` and
    /// DIPY's default spheres are of this family).
    Icosphere(u32),
    /// `rings` latitude bands and 2 * rings longitude segments, poles included (MRtrix's
    /// and VTK's `vtkSphereSource` layout).
    LatLong(u32),
}

impl MeshKind {
    /// An [`Error::Setting`] naming the method if the level or ring count is out of
    /// range.
    pub fn validate(self) -> Result<()> {
        match self {
            MeshKind::Icosphere(level) if level > MAX_ICOSPHERE_LEVEL => Err(Error::setting_value(
                Setting::Method,
                format!("mesh:{level}"),
                format!("the icosphere level must be in 0..={MAX_ICOSPHERE_LEVEL}"),
            )),
            MeshKind::LatLong(rings) if !(2..=MAX_LAT_LONG_RINGS).contains(&rings) => {
                Err(Error::setting_value(
                    Setting::Method,
                    format!("latlong:{rings}"),
                    format!("the number of latitude bands must be in 2..={MAX_LAT_LONG_RINGS}"),
                ))
            }
            _ => Ok(()),
        }
    }

    /// Vertices of the sphere mesh of this kind.
    pub fn vertex_count(self) -> usize {
        match self {
            MeshKind::Icosphere(level) => 10 * 4usize.pow(level) + 2,
            MeshKind::LatLong(rings) => 2 * rings as usize * (rings as usize - 1) + 2,
        }
    }

    /// Triangles of the sphere mesh of this kind.
    pub fn triangle_count(self) -> usize {
        match self {
            MeshKind::Icosphere(level) => 20 * 4usize.pow(level),
            MeshKind::LatLong(rings) => 4 * rings as usize * (rings as usize - 1),
        }
    }
}

impl std::fmt::Display for MeshKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            MeshKind::Icosphere(level) => write!(f, "mesh:{level}"),
            MeshKind::LatLong(rings) => write!(f, "latlong:{rings}"),
        }
    }
}

/// A triangulated unit sphere: vertex directions and triangles that wind
/// counter-clockwise seen from outside.
#[derive(Clone, Debug)]
pub struct SphereMesh {
    /// The tessellation it was built with.
    pub kind: MeshKind,
    /// Unit vertex directions.
    pub directions: Vec<DVec3>,
    /// Vertex indices into `directions`, counter-clockwise from outside.
    pub triangles: Vec<[u32; 3]>,
}

impl SphereMesh {
    /// The mesh of `kind`; an [`Error::Setting`] if its level or ring count is out of range.
    pub fn new(kind: MeshKind) -> Result<SphereMesh> {
        kind.validate()?;
        let (directions, mut triangles) = match kind {
            MeshKind::Icosphere(level) => icosphere(level),
            MeshKind::LatLong(rings) => lat_long(rings),
        };
        // Outward winding by construction is easy to get wrong; fix it by the sign of
        // det(a, b, c), which for a small triangle on the sphere is its orientation.
        for t in &mut triangles {
            let [a, b, c] = t.map(|i| directions[i as usize]);
            if a.dot(b.cross(c)) < 0.0 {
                t.swap(1, 2);
            }
        }
        Ok(SphereMesh {
            kind,
            directions,
            triangles,
        })
    }

    /// The largest radial distance between the unit sphere and its triangulation,
    /// 1 - min over triangles of the triangle's distance from the centre, in closed form
    /// from each triangle's edge chords a, b, c: the nearest point of the triangle's plane
    /// is its circumcentre, at sqrt(1 - R^2) with circumradius R = abc / (4 area); for an
    /// obtuse triangle the circumcentre lies outside and the nearest point is the middle
    /// of the longest edge, at sqrt(1 - c^2 / 4) (the edge's sagitta). The circumcentre of
    /// a near-equilateral triangle is deeper than its edges' midpoints (R^2 = c^2 / 3
    /// against c^2 / 4), so the edge sagitta alone would underestimate the error by a
    /// quarter.
    pub fn max_radial_error(&self) -> f64 {
        self.triangles
            .iter()
            .map(|t| {
                let [p, q, r] = t.map(|i| self.directions[i as usize]);
                let mut chords = [(q - r).length(), (r - p).length(), (p - q).length()];
                chords.sort_by(f64::total_cmp);
                let [a, b, c] = chords;
                let depth2 = if c * c < a * a + b * b {
                    let area = 0.5 * (q - p).cross(r - p).length();
                    let circumradius = a * b * c / (4.0 * area);
                    1.0 - circumradius * circumradius
                } else {
                    1.0 - 0.25 * c * c
                };
                1.0 - depth2.max(0.0).sqrt()
            })
            .fold(0.0, f64::max)
    }
}

/// The regular icosahedron on the unit sphere: 12 vertices and 20 faces, counter-clockwise
/// seen from outside (also the start of `fit::sphere`'s geodesic spheres).
pub fn icosahedron() -> ([DVec3; 12], [[usize; 3]; 20]) {
    let t = (1.0 + 5f64.sqrt()) / 2.0;
    let vertices = [
        (-1.0, t, 0.0),
        (1.0, t, 0.0),
        (-1.0, -t, 0.0),
        (1.0, -t, 0.0),
        (0.0, -1.0, t),
        (0.0, 1.0, t),
        (0.0, -1.0, -t),
        (0.0, 1.0, -t),
        (t, 0.0, -1.0),
        (t, 0.0, 1.0),
        (-t, 0.0, -1.0),
        (-t, 0.0, 1.0),
    ]
    .map(|(x, y, z)| DVec3::new(x, y, z).normalize());
    let faces = [
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    (vertices, faces)
}

/// Subdivides the icosahedron `level` times; shared edges share their midpoints.
fn icosphere(level: u32) -> (Vec<DVec3>, Vec<[u32; 3]>) {
    let (corners, faces) = icosahedron();
    let mut directions: Vec<DVec3> = corners.to_vec();
    let mut triangles: Vec<[u32; 3]> = faces.iter().map(|f| f.map(|i| i as u32)).collect();
    for _ in 0..level {
        let mut midpoints: HashMap<(u32, u32), u32> = HashMap::new();
        let mut midpoint = |a: u32, b: u32, directions: &mut Vec<DVec3>| {
            *midpoints.entry((a.min(b), a.max(b))).or_insert_with(|| {
                let m = (directions[a as usize] + directions[b as usize]).normalize();
                directions.push(m);
                (directions.len() - 1) as u32
            })
        };
        let mut finer = Vec::with_capacity(4 * triangles.len());
        for [a, b, c] in triangles {
            let ab = midpoint(a, b, &mut directions);
            let bc = midpoint(b, c, &mut directions);
            let ca = midpoint(c, a, &mut directions);
            finer.extend([[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]);
        }
        triangles = finer;
    }
    (directions, triangles)
}

/// Poles, `rings - 1` circles of latitude of 2 * rings points, fans at the poles and two
/// triangles per quad between the circles.
fn lat_long(rings: u32) -> (Vec<DVec3>, Vec<[u32; 3]>) {
    let segments = 2 * rings;
    let mut directions = vec![DVec3::Z];
    for k in 1..rings {
        let theta = std::f64::consts::PI * k as f64 / rings as f64;
        for j in 0..segments {
            let phi = std::f64::consts::TAU * j as f64 / segments as f64;
            directions.push(DVec3::new(
                theta.sin() * phi.cos(),
                theta.sin() * phi.sin(),
                theta.cos(),
            ));
        }
    }
    directions.push(-DVec3::Z);
    let south = directions.len() as u32 - 1;
    let at = |k: u32, j: u32| 1 + (k - 1) * segments + j % segments;
    let mut triangles = Vec::new();
    for j in 0..segments {
        triangles.push([0, at(1, j), at(1, j + 1)]);
        triangles.push([south, at(rings - 1, j + 1), at(rings - 1, j)]);
        for k in 1..rings - 1 {
            let (a, b) = (at(k, j), at(k, j + 1));
            let (c, d) = (at(k + 1, j), at(k + 1, j + 1));
            triangles.push([a, c, d]);
            triangles.push([a, d, b]);
        }
    }
    (directions, triangles)
}

/// One mesh vertex as the GPU reads it: the offset from the glyph centre and the unit
/// normal, world units, 24 bytes.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct MeshVertex {
    /// Position relative to the glyph centre, world units.
    pub offset: [f32; 3],
    /// Outward unit normal.
    pub normal: [f32; 3],
}

/// The local radius r(u) = h(f(u)) + offset of `glyph` in direction `u` (unit) and the
/// outward unit normal of its surface r(u) u there.
///
/// The surface is g(q) = h(f(q / |q|)) + offset - |q| = 0. With f homogeneous of degree n,
/// Euler's identity gives grad_q f(q / |q|) = (grad f(u) - n f(u) u) / |q|, so the outward
/// normal -grad g is along (|q| + n |f|) u - s grad f(u), s the sign of f (the formula of
/// raycast_fixed.frag). Where h is flat (f <= 0 with `hide`) the surface is the offset
/// sphere, with normal u.
pub(crate) fn surface_point(glyph: &WorldGlyph, u: DVec3) -> (f64, DVec3) {
    let (f, grad) = glyph.poly.eval_with_gradient(u);
    let (h, sign) = match glyph.negative {
        NegativeMode::Abs => (f.abs(), if f >= 0.0 { 1.0 } else { -1.0 }),
        NegativeMode::Hide if f > 0.0 => (f, 1.0),
        NegativeMode::Hide => (0.0, 0.0),
    };
    let radius = h + glyph.offset;
    let normal = (radius + glyph.poly.order as f64 * h) * u - sign * grad;
    let length = normal.length();
    let normal = if length > 0.0 && length.is_finite() {
        normal / length
    } else {
        u
    };
    (radius, normal)
}

/// Writes one glyph's vertices (one per direction of `sphere`) into `out`.
pub(crate) fn glyph_vertices(glyph: &WorldGlyph, sphere: &SphereMesh, out: &mut [MeshVertex]) {
    for (vertex, &u) in out.iter_mut().zip(&sphere.directions) {
        let (radius, normal) = surface_point(glyph, u);
        vertex.offset = (glyph.scale * radius * u).as_vec3().to_array();
        vertex.normal = normal.as_vec3().to_array();
    }
}

/// The vertices of every glyph, glyph-major (glyph i owns vertices i * V .. (i + 1) * V,
/// V = `sphere.directions.len()`), computed on `available_parallelism` scoped threads,
/// each taking a contiguous run of glyphs.
pub fn tessellate(glyphs: &[WorldGlyph], sphere: &SphereMesh) -> Vec<MeshVertex> {
    let per_glyph = sphere.directions.len();
    let mut vertices = vec![MeshVertex::default(); glyphs.len() * per_glyph];
    if vertices.is_empty() {
        return vertices;
    }
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
    let glyphs_per_thread = glyphs.len().div_ceil(threads);
    std::thread::scope(|scope| {
        let runs = glyphs
            .chunks(glyphs_per_thread)
            .zip(vertices.chunks_mut(glyphs_per_thread * per_glyph));
        for (run, out) in runs {
            scope.spawn(move || {
                for (glyph, vertices) in run.iter().zip(out.chunks_mut(per_glyph)) {
                    glyph_vertices(glyph, sphere, vertices);
                }
            });
        }
    });
    vertices
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::glyph::polynomial::GlyphPolynomial;
    use crate::glyph::{Symmetry, TensorLayout};

    fn layout(order: u32) -> TensorLayout {
        TensorLayout {
            order,
            symmetry: Symmetry::Symmetric,
        }
    }

    #[test]
    fn counts_match_the_closed_forms_and_the_sphere_is_closed() {
        for kind in [
            MeshKind::Icosphere(0),
            MeshKind::Icosphere(3),
            MeshKind::LatLong(2),
            MeshKind::LatLong(9),
        ] {
            let mesh = SphereMesh::new(kind).expect("valid kind");
            assert_eq!(mesh.directions.len(), kind.vertex_count(), "{kind}");
            assert_eq!(mesh.triangles.len(), kind.triangle_count(), "{kind}");
            // Closed and consistently wound: every directed edge appears once, and its
            // reverse once (Euler: V - E + F = 2 follows).
            let mut edges = HashMap::new();
            for t in &mesh.triangles {
                for k in 0..3 {
                    *edges.entry((t[k], t[(k + 1) % 3])).or_insert(0) += 1;
                }
            }
            for (&(a, b), &n) in &edges {
                assert_eq!(n, 1, "{kind}: edge {a}-{b} used {n} times in one direction");
                assert_eq!(edges.get(&(b, a)), Some(&1), "{kind}: edge {a}-{b} is open");
            }
            // The triangles tile the sphere: their solid angles sum to 4 pi.
            let solid: f64 = mesh
                .triangles
                .iter()
                .map(|t| {
                    let [a, b, c] = t.map(|i| mesh.directions[i as usize]);
                    2.0 * a
                        .dot(b.cross(c))
                        .atan2(1.0 + a.dot(b) + b.dot(c) + c.dot(a))
                })
                .sum();
            assert!((solid - 4.0 * std::f64::consts::PI).abs() < 1e-9, "{kind}");
        }
    }

    #[test]
    fn radial_error_of_the_icosahedron_and_its_levels() {
        // The icosahedron's inradius over its circumradius is known in closed form.
        let t = (1.0 + 5f64.sqrt()) / 2.0;
        let inradius = t * t / (3f64.sqrt() * (1.0 + t * t).sqrt());
        let level0 = SphereMesh::new(MeshKind::Icosphere(0)).expect("level 0");
        assert!((level0.max_radial_error() - (1.0 - inradius)).abs() < 1e-12);
        let mut previous = level0.max_radial_error();
        for level in 1..=5 {
            let e = SphereMesh::new(MeshKind::Icosphere(level))
                .expect("level")
                .max_radial_error();
            // Halving the edges quarters the error, up to the projection onto the sphere.
            assert!(e < previous && e > previous / 5.0, "level {level}: {e:.3e}");
            previous = e;
        }
    }

    #[test]
    fn vertices_lie_on_the_surface_with_the_normal_of_the_implicit_form() {
        // f = x^4 + 0.5 y^4 - 0.3 z^4 + x^2 y^2: positive and negative lobes.
        let mut coeffs = vec![0.0; layout(4).coefficient_count()];
        let index = |a, b, c| {
            crate::glyph::monomials::monomial_index(
                4,
                crate::glyph::monomials::Monomial { a, b, c },
            )
        };
        coeffs[index(4, 0, 0)] = 1.0;
        coeffs[index(0, 4, 0)] = 0.5;
        coeffs[index(0, 0, 4)] = -0.3;
        coeffs[index(2, 2, 0)] = 1.0 / 6.0;
        let poly = GlyphPolynomial::from_tensor(layout(4), &coeffs).expect("tensor");
        let glyph = WorldGlyph::new(DVec3::ONE, 2.0, poly, NegativeMode::Abs, 0.0);
        let sphere = SphereMesh::new(MeshKind::Icosphere(2)).expect("level 2");
        let vertices = tessellate(std::slice::from_ref(&glyph), &sphere);
        for (v, &u) in vertices.iter().zip(&sphere.directions) {
            let r = glyph.poly.eval(u).abs();
            let offset = DVec3::from_array(v.offset.map(f64::from));
            assert!((offset - 2.0 * r * u).length() < 1e-6, "{u}");
            // The normal is the normalised gradient of g(q) = |f(q / |q|)| - |q|, here
            // by central differences.
            let g = |q: DVec3| glyph.poly.eval(q / q.length()).abs() - q.length();
            let q = r * u;
            if r < 0.05 {
                continue;
            }
            let h = 1e-6;
            let grad = DVec3::new(
                g(q + h * DVec3::X) - g(q - h * DVec3::X),
                g(q + h * DVec3::Y) - g(q - h * DVec3::Y),
                g(q + h * DVec3::Z) - g(q - h * DVec3::Z),
            ) / (2.0 * h);
            let expected = -grad.normalize();
            let normal = DVec3::from_array(v.normal.map(f64::from));
            assert!(
                (normal - expected).length() < 1e-4,
                "{u}: {normal} vs {expected}"
            );
        }
    }

    #[test]
    fn parallel_generation_equals_one_glyph_at_a_time() {
        let sphere = SphereMesh::new(MeshKind::LatLong(6)).expect("latlong");
        let glyphs: Vec<WorldGlyph> = (0..7)
            .map(|k| {
                let mut coeffs = vec![0.0; 6];
                coeffs[0] = 1.0 + k as f64;
                coeffs[3] = 0.5;
                coeffs[5] = 0.25;
                let poly = GlyphPolynomial::from_tensor(layout(2), &coeffs).expect("tensor");
                WorldGlyph::new(DVec3::X * k as f64, 0.5, poly, NegativeMode::Abs, 0.0)
            })
            .collect();
        let all = tessellate(&glyphs, &sphere);
        let per_glyph = sphere.directions.len();
        for (k, glyph) in glyphs.iter().enumerate() {
            let mut one = vec![MeshVertex::default(); per_glyph];
            glyph_vertices(glyph, &sphere, &mut one);
            assert_eq!(&all[k * per_glyph..(k + 1) * per_glyph], &one[..]);
        }
    }
}
