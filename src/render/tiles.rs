//! Screen tiles for the compute ray caster (`--path compute`): each glyph's oriented box
//! is projected to the screen on the CPU, the glyph is listed in every tile of
//! `TILE_SIZE` x `TILE_SIZE` pixels its projection may touch, and each tile's list is
//! sorted by a lower bound on the ray distance of any hit in the glyph (its nearest depth),
//! so that a pixel can walk its list front to back and stop at the first glyph that lies
//! behind its best hit.
//!
//! Conservative by construction, never tight: a box that reaches behind the eye plane is
//! listed in every tile (its projection is unbounded), the pixel rectangle is widened by
//! a pixel for the float32 rounding of the shader's rays, and the nearest depth is the
//! larger of two lower bounds (bounding sphere, box corners along the view axis) less a
//! relative margin. A walk longer than one dispatch allows goes on in the next (see
//! [`WALK_PER_DISPATCH`]).
use crate::camera::{Camera, Projection};
use crate::render::frame::FrameParams;
use glam::{DQuat, DVec3};

/// Tile edge in pixels; the compute shader's workgroup is one tile
/// (glsl/raycast_exact.comp, `local_size_x` and `local_size_y`).
pub(crate) const TILE_SIZE: u32 = 16;

/// Root isolations that a subgroup of pixels runs in one dispatch. lavapipe (llvmpipe)
/// ends a shader invocation after 65,535 loop iterations in total, counted for a SIMD
/// batch of pixels whenever any of its lanes iterates. One glyph's exact root isolation
/// iterates at most about 1,500 times (order 12: 2 x 65 pieces of the subdivision and its
/// rounds, 40 Newton steps for each of at most 27 roots, 2 x 72 samples and regula falsi
/// steps of the centre zone; typically a few dozen), so 32 of them and the box tests of
/// at most 8,192 entries (glsl/raycast_exact.comp `ENTRIES_PER_DISPATCH`) stay below the
/// limit. A walk that needs more goes on in the next dispatch from where it stopped; each
/// dispatch takes every unfinished walk at least 32 entries further, so a list of n
/// entries needs at most n / 32 dispatches, and the dispatches after the first launch
/// nothing once every walk is over.
pub const WALK_PER_DISPATCH: u32 = 32;

/// Relative margin taken off each nearest depth: the shader's hit distances are float32
/// numbers computed from float32 rays, so a bound within rounding of a hit must not stop
/// the walk before it.
const NEAR_MARGIN: f64 = 1e-5;

/// The camera as the shaders see it (pixel_ray.glsl), in float64: the ray through
/// normalised window position (sx, sy) (-1 to 1, y up) leaves the eye along
/// fwd + sx right + sy up in perspective, or leaves eye + sx right + sy up along fwd in
/// orthographic projection.
#[derive(Clone, Copy, Debug)]
pub(crate) struct ScreenView {
    eye: DVec3,
    fwd: DVec3,
    /// Half the view's width and height per unit of forward distance (perspective) or of
    /// world length (orthographic), along the view's right and up.
    right: DVec3,
    up: DVec3,
    orthographic: bool,
    width: u32,
    height: u32,
}

impl ScreenView {
    /// The view of `camera` on an image of `width` x `height` pixels.
    pub fn new(camera: &Camera, width: u32, height: u32) -> ScreenView {
        let f = camera.frame();
        let (scale, orthographic) = match camera.projection {
            Projection::Perspective { fov_y_deg } => ((fov_y_deg.to_radians() * 0.5).tan(), false),
            Projection::Orthographic { height } => (0.5 * height, true),
        };
        ScreenView {
            eye: camera.eye,
            fwd: f.fwd,
            right: f.right * (scale * width as f64 / height as f64),
            up: f.up * scale,
            orthographic,
            width,
            height,
        }
    }

    /// The view of a frame block's camera (as pixel_ray.glsl reads it: a host's view,
    /// [`crate::render::host_view`]) on an image of `width` x `height` pixels.
    pub fn of_frame(frame: &FrameParams, width: u32, height: u32) -> ScreenView {
        let v = |a: [f32; 4]| DVec3::new(a[0] as f64, a[1] as f64, a[2] as f64);
        ScreenView {
            eye: v(frame.eye),
            fwd: v(frame.fwd).normalize(),
            right: v(frame.right) * frame.right[3] as f64,
            up: v(frame.up),
            orthographic: frame.eye[3] > 0.5,
            width,
            height,
        }
    }

    /// The image's width and height in pixels.
    pub fn size(&self) -> (u32, u32) {
        (self.width, self.height)
    }

    /// Tile columns: width / [`TILE_SIZE`], rounded up.
    pub fn tiles_x(&self) -> u32 {
        self.width.div_ceil(TILE_SIZE)
    }

    /// Tile rows: height / [`TILE_SIZE`], rounded up.
    pub fn tiles_y(&self) -> u32 {
        self.height.div_ceil(TILE_SIZE)
    }

    /// Window coordinates (pixels from the top-left corner) of a point in front of the
    /// eye plane; `None` for a point on or behind it in perspective.
    fn window(&self, p: DVec3) -> Option<(f64, f64)> {
        let v = p - self.eye;
        let depth = if self.orthographic {
            1.0
        } else {
            let z = v.dot(self.fwd);
            if z <= 1e-9 * v.length() {
                return None;
            }
            z
        };
        let (w, h) = (self.width as f64, self.height as f64);
        let sx = v.dot(self.right) / (depth * self.right.length_squared());
        let sy = v.dot(self.up) / (depth * self.up.length_squared());
        Some((0.5 * (sx + 1.0) * w, 0.5 * (1.0 - sy) * h))
    }
}

/// The tile lists of one glyph set (or part of one), as the compute shader reads them.
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct TileBins {
    /// Tile columns.
    pub tiles_x: u32,
    /// Tile rows.
    pub tiles_y: u32,
    /// Per tile (row-major from the top-left): the first entry of its list and its length.
    pub ranges: Vec<[u32; 2]>,
    /// Per entry: the glyph's index in its set (part) and the bits of its nearest depth
    /// (f32), each tile's entries sorted by nearest depth.
    pub entries: Vec<[u32; 2]>,
    /// Dispatches that walk the longest list in the worst case, [`WALK_PER_DISPATCH`]
    /// entries each.
    pub slices: u32,
}

/// A glyph's box on the screen: the tiles it may touch and its nearest depth.
struct Footprint {
    tiles: [u32; 4], // x0, y0, x1, y1, inclusive
    near: f32,
}

/// The corners of a glyph's oriented box in world space, from its instance (centre,
/// sphere radius) and box (rotation quaternion, half extents in units of the radius), as
/// raycast.vert builds them.
pub(crate) fn box_corners(instance: &[f32; 4], b: &[f32; 8]) -> [DVec3; 8] {
    let centre = DVec3::new(instance[0] as f64, instance[1] as f64, instance[2] as f64);
    let radius = instance[3] as f64;
    let q = DQuat::from_xyzw(b[0] as f64, b[1] as f64, b[2] as f64, b[3] as f64).normalize();
    let axes = [
        q * DVec3::X * (radius * b[4] as f64),
        q * DVec3::Y * (radius * b[5] as f64),
        q * DVec3::Z * (radius * b[6] as f64),
    ];
    std::array::from_fn(|corner| {
        let sign = |bit: usize| if corner >> bit & 1 == 1 { 1.0 } else { -1.0 };
        centre + sign(0) * axes[0] + sign(1) * axes[1] + sign(2) * axes[2]
    })
}

fn footprint(view: &ScreenView, instance: &[f32; 4], b: &[f32; 8]) -> Option<Footprint> {
    let corners = box_corners(instance, b);
    let centre = DVec3::new(instance[0] as f64, instance[1] as f64, instance[2] as f64);
    // Rays start on the eye plane (s_start >= -t_mid in glyph_ray_clip): a box wholly
    // behind it is never hit.
    let depths = corners.map(|c| (c - view.eye).dot(view.fwd));
    let nearest_z = depths.iter().copied().fold(f64::INFINITY, f64::min);
    let farthest_z = depths.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    if farthest_z <= 0.0 {
        return None;
    }
    // Along a unit ray from the eye (perspective) t >= eye depth, and t >= the distance
    // to the bounding sphere; orthographic rays have t = depth exactly.
    let mut near = nearest_z.max(0.0);
    let distance = (centre - view.eye).length();
    if !view.orthographic {
        near = near.max(distance - instance[3] as f64);
    }
    let near = (near - NEAR_MARGIN * (distance + instance[3] as f64)).max(0.0);
    let (tx, ty) = (view.tiles_x(), view.tiles_y());
    let whole = [0, 0, tx - 1, ty - 1];
    let mut lo = (f64::INFINITY, f64::INFINITY);
    let mut hi = (f64::NEG_INFINITY, f64::NEG_INFINITY);
    let mut bounded = true;
    for c in corners {
        match view.window(c) {
            Some((x, y)) => {
                lo = (lo.0.min(x), lo.1.min(y));
                hi = (hi.0.max(x), hi.1.max(y));
            }
            None => bounded = false,
        }
    }
    let tiles = if bounded {
        // Pixel i's ray passes through x = i + 0.5; one pixel more on each side.
        let (w, h) = (view.width as f64, view.height as f64);
        if hi.0 < -1.0 || hi.1 < -1.0 || lo.0 > w + 1.0 || lo.1 > h + 1.0 {
            return None;
        }
        let tile =
            |v: f64, limit: u32| ((v.max(0.0) / TILE_SIZE as f64).floor() as u32).min(limit - 1);
        [
            tile(lo.0 - 1.0, tx),
            tile(lo.1 - 1.0, ty),
            tile(hi.0 + 1.0, tx),
            tile(hi.1 + 1.0, ty),
        ]
    } else {
        whole
    };
    Some(Footprint {
        tiles,
        near: near as f32,
    })
}

/// Bins the glyphs of one set (part) into the tiles of `view`.
pub(crate) fn bin_glyphs(
    view: &ScreenView,
    instances: &[[f32; 4]],
    boxes: &[[f32; 8]],
) -> TileBins {
    let (tx, ty) = (view.tiles_x(), view.tiles_y());
    let tiles = (tx * ty) as usize;
    let footprints: Vec<Option<Footprint>> = instances
        .iter()
        .zip(boxes)
        .map(|(i, b)| footprint(view, i, b))
        .collect();
    let mut counts = vec![0u32; tiles];
    let each_tile = |f: &Footprint, visit: &mut dyn FnMut(usize)| {
        for y in f.tiles[1]..=f.tiles[3] {
            for x in f.tiles[0]..=f.tiles[2] {
                visit((y * tx + x) as usize);
            }
        }
    };
    for f in footprints.iter().flatten() {
        each_tile(f, &mut |t| counts[t] += 1);
    }
    let mut ranges = Vec::with_capacity(tiles);
    let mut total = 0u32;
    for &count in &counts {
        ranges.push([total, count]);
        total += count;
    }
    let mut fill: Vec<u32> = ranges.iter().map(|r| r[0]).collect();
    let mut entries = vec![[0u32; 2]; total as usize];
    for (glyph, f) in footprints.iter().enumerate() {
        if let Some(f) = f {
            each_tile(f, &mut |t| {
                entries[fill[t] as usize] = [glyph as u32, f.near.to_bits()];
                fill[t] += 1;
            });
        }
    }
    for r in &ranges {
        let list = &mut entries[r[0] as usize..(r[0] + r[1]) as usize];
        list.sort_by(|a, b| {
            f32::from_bits(a[1])
                .total_cmp(&f32::from_bits(b[1]))
                .then(a[0].cmp(&b[0]))
        });
    }
    let longest = counts.iter().copied().max().unwrap_or(0);
    TileBins {
        tiles_x: tx,
        tiles_y: ty,
        ranges,
        entries,
        slices: longest.div_ceil(WALK_PER_DISPATCH),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::SplitMix64 as Rng;

    fn camera(projection: Projection) -> Camera {
        Camera {
            projection,
            eye: DVec3::new(0.3, -4.0, 1.0),
            target: DVec3::new(0.0, 0.0, 0.1),
            up: DVec3::Z,
        }
    }

    /// The view read back from a frame block (a host's camera) puts points where the
    /// camera's own view does, within float32 rounding of the block.
    #[test]
    fn a_frame_blocks_view_is_the_cameras() {
        use crate::render::frame::SceneExtent;
        let extent = SceneExtent {
            near: 0.1,
            far: 100.0,
            max_radius: 1.0,
        };
        let mut rng = Rng::new(7);
        for projection in [
            Projection::Perspective { fov_y_deg: 35.0 },
            Projection::Orthographic { height: 3.0 },
        ] {
            let camera = camera(projection);
            let (w, h) = (160, 90);
            let frame = FrameParams::new(&camera, w, h, &extent, &Default::default());
            let (ours, theirs) = (
                ScreenView::new(&camera, w, h),
                ScreenView::of_frame(&frame, w, h),
            );
            assert_eq!(ours.orthographic, theirs.orthographic);
            for _ in 0..100 {
                let p = 2.0 * rng.unit() * rng.direction();
                let (a, b) = (ours.window(p).unwrap(), theirs.window(p).unwrap());
                assert!(
                    (a.0 - b.0).abs() < 1e-3 && (a.1 - b.1).abs() < 1e-3,
                    "{a:?} {b:?}"
                );
            }
        }
    }

    /// Where a ray enters the part of a glyph's box inside its bounding sphere (where
    /// the shader looks for hits), float64; `None` if it misses that part.
    fn hits_box(origin: DVec3, dir: DVec3, instance: &[f32; 4], b: &[f32; 8]) -> Option<f64> {
        let centre = DVec3::new(instance[0] as f64, instance[1] as f64, instance[2] as f64);
        let radius = instance[3] as f64;
        let t_mid = (centre - origin).dot(dir);
        let miss2 = (origin + t_mid * dir - centre).length_squared();
        let half_chord = (radius * radius - miss2).max(0.0).sqrt();
        let q = DQuat::from_xyzw(b[0] as f64, b[1] as f64, b[2] as f64, b[3] as f64).normalize();
        let (o, d) = (q.inverse() * (origin - centre), q.inverse() * dir);
        let (mut lo, mut hi) = ((t_mid - half_chord).max(0.0), t_mid + half_chord);
        for i in 0..3 {
            let e = radius * b[4 + i] as f64;
            let (a, c) = ((-e - o[i]) / d[i], (e - o[i]) / d[i]);
            lo = lo.max(a.min(c));
            hi = hi.min(a.max(c));
        }
        (miss2 < radius * radius && lo < hi).then_some(lo)
    }

    fn uniform(rng: &mut Rng, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * rng.unit()
    }

    fn random_glyphs(rng: &mut Rng, count: usize) -> (Vec<[f32; 4]>, Vec<[f32; 8]>) {
        let mut instances = Vec::new();
        let mut boxes = Vec::new();
        for _ in 0..count {
            let p = |rng: &mut Rng| uniform(rng, -1.5, 1.5) as f32;
            instances.push([p(rng), p(rng), p(rng), uniform(rng, 0.05, 0.6) as f32]);
            let q = DQuat::from_xyzw(
                uniform(rng, -1.0, 1.0),
                uniform(rng, -1.0, 1.0),
                uniform(rng, -1.0, 1.0),
                uniform(rng, -1.0, 1.0),
            )
            .normalize();
            let e = |rng: &mut Rng| uniform(rng, 0.05, 1.0) as f32;
            boxes.push([
                q.x as f32,
                q.y as f32,
                q.z as f32,
                q.w as f32,
                e(rng),
                e(rng),
                e(rng),
                0.0,
            ]);
        }
        (instances, boxes)
    }

    /// Every pixel whose ray meets a glyph's box finds the glyph in its tile's list, with
    /// a nearest depth no farther than where the ray enters the box; lists are sorted.
    #[test]
    fn every_ray_that_meets_a_box_finds_it_in_its_tile() {
        let mut rng = Rng::new(7);
        let (instances, boxes) = random_glyphs(&mut rng, 60);
        for projection in [
            Projection::Perspective { fov_y_deg: 50.0 },
            Projection::Orthographic { height: 3.5 },
        ] {
            let camera = camera(projection);
            let (w, h) = (75, 43);
            let view = ScreenView::new(&camera, w, h);
            let bins = bin_glyphs(&view, &instances, &boxes);
            assert_eq!((bins.tiles_x, bins.tiles_y), (5, 3));
            for r in &bins.ranges {
                let list = &bins.entries[r[0] as usize..(r[0] + r[1]) as usize];
                assert!(
                    list.windows(2)
                        .all(|p| f32::from_bits(p[0][1]) <= f32::from_bits(p[1][1]))
                );
            }
            for j in 0..h {
                for i in 0..w {
                    let ray = camera.ray(i, j, w, h);
                    let r = bins.ranges[((j / TILE_SIZE) * bins.tiles_x + i / TILE_SIZE) as usize];
                    let list = &bins.entries[r[0] as usize..(r[0] + r[1]) as usize];
                    for (g, (inst, b)) in instances.iter().zip(&boxes).enumerate() {
                        let Some(entry) = hits_box(ray.origin, ray.dir, inst, b) else {
                            continue;
                        };
                        let listed = list.iter().find(|e| e[0] == g as u32);
                        let listed = listed.unwrap_or_else(|| {
                            panic!("{projection:?}: pixel ({i}, {j}) misses glyph {g}")
                        });
                        assert!(f32::from_bits(listed[1]) as f64 <= entry + 1e-9, "{g}");
                    }
                }
            }
        }
    }

    /// A box around the eye is listed everywhere with nearest depth 0; one behind it nowhere.
    #[test]
    fn boxes_around_and_behind_the_eye() {
        let camera = camera(Projection::Perspective { fov_y_deg: 60.0 });
        let view = ScreenView::new(&camera, 40, 40);
        let e = camera.eye.as_vec3();
        let behind = camera.eye - 3.0 * camera.frame().fwd;
        let instances = [
            [e.x, e.y + 0.1, e.z, 0.5],
            [behind.x as f32, behind.y as f32, behind.z as f32, 0.5],
        ];
        let boxes = [[0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0, 0.0]; 2];
        let bins = bin_glyphs(&view, &instances, &boxes);
        assert_eq!(bins.entries.len(), 9);
        assert!(bins.entries.iter().all(|e| *e == [0, 0.0f32.to_bits()]));
        assert_eq!(bins.slices, 1);
    }

    #[test]
    fn long_lists_take_several_slices() {
        let camera = camera(Projection::Orthographic { height: 2.0 });
        let view = ScreenView::new(&camera, 16, 16);
        let n = WALK_PER_DISPATCH as usize + 5;
        let fwd = camera.frame().fwd;
        let instances: Vec<[f32; 4]> = (0..n)
            .map(|k| {
                let c = camera.target + fwd * (k as f64 * 0.1);
                [c.x as f32, c.y as f32, c.z as f32, 0.1]
            })
            .collect();
        let boxes = vec![[0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0, 0.0]; n];
        let bins = bin_glyphs(&view, &instances, &boxes);
        assert_eq!(bins.slices, 2);
        let order: Vec<u32> = bins.entries.iter().map(|e| e[0]).collect();
        assert_eq!(order, (0..n as u32).collect::<Vec<_>>());
    }
}
