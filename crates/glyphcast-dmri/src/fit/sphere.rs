//! Geodesic spheres: the icosahedron with each face cut into f^2 triangles, projected
//! onto the unit sphere (10 f^2 + 2 vertices). CSD enforces its constraint on one
//! (f = 6: 362 directions, as many as DIPY's default constraint sphere) and the peak
//! finder searches a denser one, walking its edges to find local maxima.
//!
//! The set is antipodally symmetric (the icosahedron is), so an antipodally symmetric
//! function has its maxima in pairs.
use glam::DVec3;
use glyphcast::glyph::tessellate::icosahedron;
use std::collections::HashMap;

/// Vertices of a geodesic sphere and which vertices share an edge.
#[derive(Clone, Debug)]
pub struct GeodesicSphere {
    /// Unit vectors, 10 f^2 + 2 of them.
    pub vertices: Vec<DVec3>,
    /// For each vertex, the indices of its 5 or 6 neighbours.
    pub neighbours: Vec<Vec<usize>>,
}

impl GeodesicSphere {
    /// The sphere of frequency `frequency` (at least 1): 10 f^2 + 2 vertices.
    pub fn new(frequency: usize) -> Self {
        let f = frequency.max(1);
        let (corners, faces) = icosahedron();
        let mut vertices = Vec::new();
        let mut index_of: HashMap<[i64; 3], usize> = HashMap::new();
        let mut edges: Vec<(usize, usize)> = Vec::new();
        // Points on shared face edges are generated twice; a quantised key merges them.
        let mut vertex = |p: DVec3| -> usize {
            let p = p.normalize();
            let key = [p.x, p.y, p.z].map(|c| (c * 1e9).round() as i64);
            *index_of.entry(key).or_insert_with(|| {
                vertices.push(p);
                vertices.len() - 1
            })
        };
        for [a, b, c] in faces {
            let (a, b, c) = (corners[a], corners[b], corners[c]);
            let mut grid = vec![vec![0usize; f + 1]; f + 1];
            for (i, row) in grid.iter_mut().enumerate() {
                for (j, slot) in row.iter_mut().enumerate().take(f + 1 - i) {
                    let (i, j) = (i as f64, j as f64);
                    let p = (a * (f as f64 - i - j) + b * i + c * j) / f as f64;
                    *slot = vertex(p);
                }
            }
            for i in 0..f {
                for j in 0..f - i {
                    let (p, q, r) = (grid[i][j], grid[i + 1][j], grid[i][j + 1]);
                    edges.extend([(p, q), (q, r), (r, p)]);
                }
            }
        }
        let mut neighbours = vec![Vec::new(); vertices.len()];
        for (p, q) in edges {
            if !neighbours[p].contains(&q) {
                neighbours[p].push(q);
                neighbours[q].push(p);
            }
        }
        Self {
            vertices,
            neighbours,
        }
    }

    /// One vertex of each antipodal pair: those with (z, y, x) above (0, 0, 0) in
    /// lexicographic order, 5 f^2 + 1 of them. An antipodally symmetric function (an
    /// fODF) is constrained or searched on these alone.
    pub fn hemisphere(frequency: usize) -> Vec<DVec3> {
        Self::new(frequency)
            .vertices
            .into_iter()
            .filter(|v| (v.z, v.y, v.x) > (0.0, 0.0, 0.0))
            .collect()
    }

    /// The largest angle (radians) between a vertex and its nearest neighbour: the
    /// resolution of a search over the vertices.
    pub fn spacing(&self) -> f64 {
        self.vertices
            .iter()
            .zip(&self.neighbours)
            .map(|(v, n)| {
                n.iter()
                    .map(|&i| v.dot(self.vertices[i]).clamp(-1.0, 1.0).acos())
                    .fold(f64::INFINITY, f64::min)
            })
            .fold(0.0, f64::max)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn geodesic_spheres_have_the_expected_counts_and_symmetry() {
        for (f, n) in [(1, 12), (6, 362), (16, 2562)] {
            let s = GeodesicSphere::new(f);
            assert_eq!(s.vertices.len(), n, "frequency {f}");
            // Euler: 30 f^2 edges, each counted from both ends.
            let degree: usize = s.neighbours.iter().map(Vec::len).sum();
            assert_eq!(degree, 60 * f * f);
            assert!(s.neighbours.iter().all(|v| v.len() == 5 || v.len() == 6));
            for v in &s.vertices {
                assert!((v.length() - 1.0).abs() < 1e-12);
                assert!(s.vertices.iter().any(|w| (*w + *v).length() < 1e-9));
            }
        }
        let spacing = GeodesicSphere::new(16).spacing().to_degrees();
        assert!(spacing < 5.0, "{spacing}");
    }
}
