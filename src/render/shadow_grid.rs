//! The uniform grid over one glyph batch's boxes that shadow rays walk (`--shadows`,
//! glsl/shadow.glsl): each glyph is listed in every cell that the axis-aligned box around
//! its oriented box (enlarged as the exact method's chord is) overlaps, so a ray that
//! walks the cells it crosses meets every glyph whose box it enters. Built on the CPU at
//! upload, for every batch (the viewer can switch shadows on without uploading again).
use bytemuck::{Pod, Zeroable};
use glam::{DQuat, DVec3};

/// The grid's header, first in its buffer (glsl/shadow.glsl `ShadowCells`), then one
/// `[first entry, count]` per cell, x fastest.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub(crate) struct GridHeader {
    /// xyz: the grid's lowest corner, world units; w: the glyphs' mean bounding radius
    /// (what the underlay's shadow rays take for the hit glyph's).
    pub lo: [f32; 4],
    /// xyz: a cell's edges, world units.
    pub cell: [f32; 4],
    /// xyz: cells along each axis, at least 1.
    pub dims: [i32; 4],
}

/// A batch's grid: header, cell ranges and the glyph indices they point into.
#[derive(Clone, Debug)]
pub(crate) struct ShadowGrid {
    /// Where and how large the cells are.
    pub header: GridHeader,
    /// Per cell (x fastest): its first entry and its number of entries.
    pub cells: Vec<[u32; 2]>,
    /// Glyph indices of the batch, cell after cell.
    pub entries: Vec<u32>,
}

/// Cells along one axis at most.
const MAX_DIM: usize = 256;
/// Cells per glyph at most (the grid is coarsened until it has no more).
const CELLS_PER_GLYPH: usize = 4;
/// The chord radius of glsl/exact_root.glsl (`CHORD_RADIUS`): the shadow rays clip each
/// glyph's box scaled by it, so the grid lists the scaled box.
const CHORD_RADIUS: f64 = 1.0 + 1.0 / 1024.0;
/// Relative margin on each box for the float32 rounding of the rays that walk the grid.
const MARGIN: f64 = 1e-4;

impl ShadowGrid {
    /// The grid over glyphs of `instances` (centre, bounding radius) and `boxes` (unit
    /// quaternion box to world, half extents in units of the radius), as the ray-cast
    /// pass uploads them.
    pub fn new(instances: &[[f32; 4]], boxes: &[[f32; 8]]) -> ShadowGrid {
        // Glyphs whose bounds are not finite cannot block a ray the GPU can follow.
        let (indices, bounds): (Vec<u32>, Vec<(DVec3, DVec3)>) = instances
            .iter()
            .zip(boxes)
            .map(|(instance, b)| world_bounds(instance, b))
            .enumerate()
            .filter(|(_, (lo, hi))| lo.is_finite() && hi.is_finite())
            .map(|(k, bounds)| (k as u32, bounds))
            .unzip();
        if bounds.is_empty() {
            return ShadowGrid {
                header: GridHeader {
                    lo: [0.0; 4],
                    cell: [1.0, 1.0, 1.0, 0.0],
                    dims: [1, 1, 1, 0],
                },
                cells: vec![[0, 0]],
                entries: vec![0],
            };
        }
        let lo = bounds.iter().fold(DVec3::INFINITY, |a, b| a.min(b.0));
        let hi = bounds.iter().fold(DVec3::NEG_INFINITY, |a, b| a.max(b.1));
        // Cells about as large as a glyph's box, coarsened until there are at most
        // CELLS_PER_GLYPH per glyph.
        let mean = bounds
            .iter()
            .map(|(l, h)| (*h - *l).max_element())
            .sum::<f64>()
            / bounds.len() as f64;
        let extent = (hi - lo).max(DVec3::splat(mean * 1e-6));
        let mut edge = mean.max(extent.max_element() / MAX_DIM as f64);
        let dims_for = |edge: f64| {
            [extent.x, extent.y, extent.z].map(|e| ((e / edge).ceil() as usize).clamp(1, MAX_DIM))
        };
        let budget = CELLS_PER_GLYPH * bounds.len() + 64;
        let mut dims = dims_for(edge);
        while dims.iter().product::<usize>() > budget {
            edge *= 1.25;
            dims = dims_for(edge);
        }
        // Cells of equal edge; the grid covers [lo, lo + dims * cell].
        let cell = DVec3::new(
            extent.x / dims[0] as f64,
            extent.y / dims[1] as f64,
            extent.z / dims[2] as f64,
        );
        let index_of = |p: DVec3| {
            let rel = (p - lo) / cell;
            let at = |v: f64, d: usize| (v.floor().max(0.0) as usize).min(d - 1);
            [at(rel.x, dims[0]), at(rel.y, dims[1]), at(rel.z, dims[2])]
        };
        let count = dims.iter().product::<usize>();
        let mut lists: Vec<Vec<u32>> = vec![Vec::new(); count];
        for (&glyph, (l, h)) in indices.iter().zip(&bounds) {
            let (a, b) = (index_of(*l), index_of(*h));
            for z in a[2]..=b[2] {
                for y in a[1]..=b[1] {
                    for x in a[0]..=b[0] {
                        lists[(z * dims[1] + y) * dims[0] + x].push(glyph);
                    }
                }
            }
        }
        let mut cells = Vec::with_capacity(count);
        let mut entries = Vec::new();
        for list in lists {
            cells.push([entries.len() as u32, list.len() as u32]);
            entries.extend(list);
        }
        if entries.is_empty() {
            entries.push(0);
        }
        let v4 = |v: DVec3| [v.x as f32, v.y as f32, v.z as f32, 0.0];
        let mut lo = v4(lo);
        lo[3] = mean_radius(&indices, instances) as f32;
        ShadowGrid {
            header: GridHeader {
                lo,
                cell: v4(cell),
                dims: [dims[0] as i32, dims[1] as i32, dims[2] as i32, 0],
            },
            cells,
            entries,
        }
    }

    /// The bytes of the cells' buffer: the header, then the cell ranges.
    pub fn cell_bytes(&self) -> Vec<u8> {
        let mut bytes = bytemuck::bytes_of(&self.header).to_vec();
        bytes.extend_from_slice(bytemuck::cast_slice(&self.cells));
        bytes
    }
}

/// The mean bounding radius of the glyphs `indices` of `instances` (centre, radius), as
/// the underlay's shadow rays take it ([`crate::glyph::shadow::mean_radius`] of the
/// float64 glyphs).
fn mean_radius(indices: &[u32], instances: &[[f32; 4]]) -> f64 {
    let sum: f64 = indices
        .iter()
        .map(|&k| f64::from(instances[k as usize][3]))
        .sum();
    sum / indices.len() as f64
}

/// The world axis-aligned bounds of a glyph's oriented box, scaled by the chord radius
/// and a margin.
fn world_bounds(instance: &[f32; 4], b: &[f32; 8]) -> (DVec3, DVec3) {
    let center = DVec3::new(instance[0].into(), instance[1].into(), instance[2].into());
    let radius = f64::from(instance[3]) * CHORD_RADIUS * (1.0 + MARGIN);
    let rotation = DQuat::from_xyzw(b[0].into(), b[1].into(), b[2].into(), b[3].into()).normalize();
    let extent = DVec3::new(b[4].into(), b[5].into(), b[6].into()) * radius;
    let half = (rotation * DVec3::X * extent.x).abs()
        + (rotation * DVec3::Y * extent.y).abs()
        + (rotation * DVec3::Z * extent.z).abs();
    (center - half, center + half)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn unit_box() -> [f32; 8] {
        [0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0, 0.0]
    }

    /// Every glyph is listed in every cell its box overlaps, and in no other: checked
    /// against a direct overlap test of each cell with each box.
    #[test]
    fn every_glyph_is_in_the_cells_its_box_overlaps() {
        let mut instances = Vec::new();
        let mut boxes = Vec::new();
        for k in 0..40 {
            let t = k as f32;
            instances.push([
                (t * 0.37).sin() * 3.0,
                (t * 0.91).cos() * 2.0,
                t * 0.05,
                0.2 + 0.01 * t,
            ]);
            let angle = t * 0.3;
            let (s, c) = (0.5 * angle).sin_cos();
            boxes.push([s, 0.0, 0.0, c, 1.0, 0.5, 0.3, 0.0]);
        }
        let grid = ShadowGrid::new(&instances, &boxes);
        let h = grid.header;
        let dims = [h.dims[0] as usize, h.dims[1] as usize, h.dims[2] as usize];
        assert_eq!(grid.cells.len(), dims.iter().product::<usize>());
        assert!(grid.cells.len() <= CELLS_PER_GLYPH * 40 + 64);
        let lo = DVec3::new(h.lo[0].into(), h.lo[1].into(), h.lo[2].into());
        let cell = DVec3::new(h.cell[0].into(), h.cell[1].into(), h.cell[2].into());
        for (glyph, (instance, b)) in instances.iter().zip(&boxes).enumerate() {
            let (l, u) = world_bounds(instance, b);
            for z in 0..dims[2] {
                for y in 0..dims[1] {
                    for x in 0..dims[0] {
                        let c0 = lo + cell * DVec3::new(x as f64, y as f64, z as f64);
                        let c1 = c0 + cell;
                        // Strictly overlapping (a shared face may go either way).
                        let overlaps =
                            (c0 - u).max_element() < -1e-6 && (l - c1).max_element() < -1e-6;
                        let [first, count] = grid.cells[(z * dims[1] + y) * dims[0] + x];
                        let listed = grid.entries[first as usize..(first + count) as usize]
                            .contains(&(glyph as u32));
                        if overlaps {
                            assert!(listed, "glyph {glyph} missing from cell {x},{y},{z}");
                        }
                    }
                }
            }
        }
    }

    /// No glyphs: one empty cell, and buffers that are not empty.
    #[test]
    fn an_empty_batch_has_one_empty_cell() {
        let grid = ShadowGrid::new(&[], &[]);
        assert_eq!(grid.cells, vec![[0, 0]]);
        assert!(!grid.entries.is_empty());
        assert_eq!(grid.cell_bytes().len(), 48 + 8);
        let one = ShadowGrid::new(&[[0.0, 0.0, 0.0, 1.0]], &[unit_box()]);
        assert_eq!(one.cells.iter().map(|c| c[1]).sum::<u32>(), 1);
    }
}
