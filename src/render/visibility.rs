//! Hidden glyphs skipped: the step the paper leaves to future work ("reduce the number of
//! glyphs that are rendered even though they are occluded by other glyphs").
//!
//! With `--cull occluded` the headless renderer draws a frame's glyphs in several passes,
//! nearest first. The first pass is the usual one. A later pass must not launch the
//! fragments that an earlier pass hides (on lavapipe, whose shaders run branches as
//! masks, a fragment that ends early saves nothing: only a fragment never launched does),
//! so its pipelines test the depth attachment before the fragment shader runs
//! (EarlyFragmentTests): a fragment whose box face lies at or behind the depth already
//! drawn there is never launched. The box face is the nearest point of its glyph along the
//! ray, so such a fragment could only give a hit the depth test rejects.
//!
//! With early tests a fragment cannot write its own depth, so a later pass has two stages
//! over the same glyphs: the first keeps, per pixel, the nearest ray distance of the
//! pass's hits (blended by MIN into an image of its own); the second shades the hit whose
//! distance is that one and lies nearer than the depth drawn before
//! (glsl/raycast_common.glsl, `shows_hit`), writing its colour and ray distance, and its
//! depth into a copy of the depth buffer, which goes back into the depth attachment after
//! the pass. The image and the ray distances are those of a single pass, bit for bit
//! (tests/visibility.rs).
//!
//! The second stage launches only the fragments that can show the winner: its boxes are
//! tested against a gate, not against the depth drawn before. Each first-stage hit
//! nearer than that depth opens the gate at its pixel a little beyond itself (atomically,
//! in a buffer that is copied into the depth attachment between the stages, before the
//! nearest distances take its place); a pixel where the pass has no such hit keeps it
//! shut at the near plane. The winner's box face lies at least as near as its hit, so it
//! always passes; a pixel that the pass's glyphs miss (the gaps between lobes, most of a
//! block's later passes) launches nothing.
//!
//! A device that jumps over code that no lane of a batch of pixels runs (a GPU; lavapipe
//! of Mesa 25, measured; Mesa 22.3's runs such code masked) has a cheaper way, early outs
//! (`Culling::EarlyOut`, which `Culling::Occluded` takes there for the `exact` method):
//! the frame is one pass over the same clusters nearest first, with a known depth per
//! pixel that starts at the clear depth and that each hit raises (atomically). A fragment
//! whose box face lies behind its pixel's known depth (by more than the face's rounding)
//! skips the root isolation: its hit, at or behind the face, would fail the depth test.
//! Nothing is copied and nothing is drawn twice; the fragments still launch, and the
//! saving is the shader's code, so a device that runs every branch masked saves nothing
//! and keeps the passes. Whatever order the fragments run in, the known depth is always
//! that of a real hit, so the image is that of one pass without culling, bit for bit.
//!
//! The order of the passes comes from the CPU: the glyphs of a batch are taken in clusters
//! of [`CLUSTER_GLYPHS`] consecutive glyphs (a volume's voxels are consecutive in space),
//! the clusters are sorted by the view depth of their centre, and a pass takes clusters
//! until their glyphs' projected bounding discs add up to [`PASS_COVER`] times the screen
//! area the scene covers. A flat field is one pass, drawn as without culling; a block seen
//! head-on is one or two layers per pass.
//!
//! The work counters count, per frame, the fragment shader invocations of the glyphs' boxes
//! and the glyph evaluations (the exact method's root isolations, the other methods'
//! marched rays): `glyphcast bench` reports them per covered pixel.
use crate::error::Result;
use crate::render::Culling;
use crate::render::frame::FrameParams;
use crate::vk::{Buffer, BufferBinding, DescriptorPool, DeviceContext, buffer_binding};
use ash::vk;
use glam::DVec3;
use gpu_allocator::MemoryLocation;

/// Consecutive glyphs of a batch that are ordered and drawn together.
pub const CLUSTER_GLYPHS: usize = 64;

/// The most passes of one frame: each pass after the first costs a copy of the depth
/// attachment.
pub const MAX_PASSES: usize = 32;

/// A pass takes clusters until their glyphs' projected bounding discs cover this many
/// times the screen area of the whole scene (measured on blocks of band-8 fODFs: 0.5 to
/// 4 tried, 3 the fastest on lavapipe).
pub const PASS_COVER: f64 = 3.0;

/// Early outs are taken by `occluded` where the glyphs' projected bounding discs cover
/// more than this many times the screen area of the whole scene (measured on DIPY's
/// 10 x 10 x 10 CSD block, which they cover about 1.3 to 2 times: evaluations per
/// covered pixel 3.40 -> 3.01 with the default sizes, 4.63 -> 3.40 with `--norm
/// per-glyph`, whose frame on Mesa 25 is 8 % faster; a flat field covers it less than
/// once and is drawn as without culling).
pub(crate) const EARLY_OUT_COVER: f64 = 1.0;

/// Bytes before the known depths in their buffer (glsl/raycast_common.glsl `KnownDepth`:
/// the row length, the visibility word, the target's first pixel).
pub(crate) const KNOWN_DEPTH_HEADER: u64 = 16;

/// Whether the known depths of a target of `width` x `height` pixels fit in one storage
/// buffer of at most `limit` bytes (the device's maxStorageBufferRange, or a pass's cap):
/// culling needs them, and a larger target is drawn without culling.
pub(crate) fn known_depths_fit(limit: u64, width: u32, height: u32) -> bool {
    KNOWN_DEPTH_HEADER + 4 * u64::from(width) * u64::from(height) <= limit
}

/// The work counters of one frame (`WORK_*` of glsl/codes.glsl).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize)]
pub struct WorkCounts {
    /// Fragment shader invocations of the glyphs' boxes (the later passes' fragments
    /// behind the depth of the earlier ones never run, and are not counted).
    pub fragments: u64,
    /// Glyph evaluations: the exact method's root isolations, the other methods' rays
    /// marched through a glyph.
    pub evaluations: u64,
    /// Passes the frame was drawn in.
    pub passes: u64,
}

/// Consecutive glyphs of one batch: where they are, their bounding sphere, and the sum of
/// their bounding spheres' squared radii (the area their discs project to, up to
/// pi (pixels per world unit)^2).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Cluster {
    /// The first glyph (instance) of the batch in the cluster.
    pub first: u32,
    /// Glyphs in the cluster.
    pub count: u32,
    center: DVec3,
    radius: f64,
    squared_radii: f64,
}

/// The clusters of a batch's instances (centre and bounding radius per glyph).
pub(crate) fn clusters(instances: &[[f32; 4]]) -> Vec<Cluster> {
    let point = |i: &[f32; 4]| DVec3::new(f64::from(i[0]), f64::from(i[1]), f64::from(i[2]));
    instances
        .chunks(CLUSTER_GLYPHS)
        .enumerate()
        .map(|(k, chunk)| {
            let center = chunk.iter().map(point).sum::<DVec3>() / chunk.len() as f64;
            let radius = chunk
                .iter()
                .map(|i| (point(i) - center).length() + f64::from(i[3]))
                .fold(0.0, f64::max);
            Cluster {
                first: (k * CLUSTER_GLYPHS) as u32,
                count: chunk.len() as u32,
                center,
                radius,
                squared_radii: chunk.iter().map(|i| f64::from(i[3]).powi(2)).sum(),
            }
        })
        .collect()
}

/// The draws of one frame in passes: (batch, cluster) pairs in drawing order, and where
/// each pass begins among them.
#[derive(Clone, Debug, Default)]
pub struct PassPlan {
    draws: Vec<(u32, u32)>,
    starts: Vec<usize>,
    early_out: bool,
}

impl PassPlan {
    /// Passes of the frame (0 for no glyphs).
    pub fn passes(&self) -> usize {
        self.starts.len()
    }

    /// Whether the frame is one pass front to back with early outs (`Culling::EarlyOut`).
    pub fn early_out(&self) -> bool {
        self.early_out
    }

    /// The (batch, cluster) pairs of pass `k`.
    pub(crate) fn pass(&self, k: usize) -> &[(u32, u32)] {
        let end = self.starts.get(k + 1).copied().unwrap_or(self.draws.len());
        &self.draws[self.starts[k]..end]
    }
}

/// The camera of a frame block, as far as ordering needs it.
struct View {
    eye: DVec3,
    fwd: DVec3,
    right: DVec3,
    up: DVec3,
    orthographic: bool,
    width: f64,
    height: f64,
}

impl View {
    fn of(frame: &FrameParams) -> View {
        let v = |a: [f32; 4]| DVec3::new(f64::from(a[0]), f64::from(a[1]), f64::from(a[2]));
        View {
            eye: v(frame.eye),
            fwd: v(frame.fwd),
            right: v(frame.right),
            up: v(frame.up),
            orthographic: frame.eye[3] > 0.5,
            width: 1.0 / f64::from(frame.viewport[0]).max(1e-9),
            height: 1.0 / f64::from(frame.viewport[1]).max(1e-9),
        }
    }

    /// The view depth of a point, and the pixels per world unit there (`None` where the
    /// point lies at or behind the eye plane).
    fn depth_and_scale(&self, point: DVec3) -> (f64, Option<f64>) {
        let depth = (point - self.eye).dot(self.fwd);
        let half_height = self.up.length().max(1e-12);
        let pixels = 0.5 * self.height / half_height;
        if self.orthographic {
            return (depth, Some(pixels));
        }
        (depth, (depth > 1e-9).then(|| pixels / depth))
    }

    /// A cluster's screen rectangle (pixels, unclamped), or `None` where it reaches the
    /// eye plane.
    fn rectangle(&self, c: &Cluster) -> Option<[f64; 4]> {
        let (depth, scale) = self.depth_and_scale(c.center);
        if !self.orthographic && depth - c.radius <= 1e-9 {
            return None;
        }
        let scale = scale?;
        let d = c.center - self.eye;
        let perspective = if self.orthographic { 1.0 } else { depth };
        let x = d.dot(self.right) / self.right.length_squared().max(1e-24) / perspective;
        let y = d.dot(self.up) / self.up.length_squared().max(1e-24) / perspective;
        let (cx, cy) = (0.5 * (x + 1.0) * self.width, 0.5 * (1.0 - y) * self.height);
        let r = c.radius * scale;
        Some([cx - r, cy - r, cx + r, cy + r])
    }
}

/// The passes of a frame seen as `frame` says, over batches whose clusters are
/// `batches`: none where `cull` is off (one pass, one draw per batch), else the clusters
/// nearest first, cut into passes as the module says (every [`PASS_COVER`] times the
/// scene's area, or every time when `asked` names the passes); with early outs, one
/// pass nearest first where the discs cover the scene's area more than
/// [`EARLY_OUT_COVER`] times (at all when `asked` names the early outs). `asked` is
/// the `--cull` the frame was asked for, `cull` what the device takes for it
/// ([`culling`]).
pub(crate) fn plan<'a>(
    batches: impl Iterator<Item = &'a [Cluster]> + Clone,
    frame: &FrameParams,
    (cull, asked): (Culling, Culling),
) -> PassPlan {
    let mut draws: Vec<(u32, u32)> = batches
        .clone()
        .enumerate()
        .flat_map(|(b, clusters)| (0..clusters.len() as u32).map(move |c| (b as u32, c)))
        .collect();
    if draws.is_empty() {
        return PassPlan::default();
    }
    if !matches!(cull, Culling::Passes | Culling::EarlyOut) {
        // One draw per batch, as engines record it.
        return PassPlan::default();
    }
    let all: Vec<&[Cluster]> = batches.collect();
    let cluster = |&(b, c): &(u32, u32)| &all[b as usize][c as usize];
    let view = View::of(frame);
    // The screen area the scene covers: the clusters' rectangles' bounds, on the image.
    let mut bounds = [
        f64::INFINITY,
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::NEG_INFINITY,
    ];
    let mut whole_screen = false;
    for draw in &draws {
        match view.rectangle(cluster(draw)) {
            Some([x0, y0, x1, y1]) => {
                bounds = [
                    bounds[0].min(x0),
                    bounds[1].min(y0),
                    bounds[2].max(x1),
                    bounds[3].max(y1),
                ];
            }
            None => whole_screen = true,
        }
    }
    if whole_screen {
        bounds = [0.0, 0.0, view.width, view.height];
    }
    let clamp = |v: f64, hi: f64| v.clamp(0.0, hi);
    let area = (clamp(bounds[2], view.width) - clamp(bounds[0], view.width))
        * (clamp(bounds[3], view.height) - clamp(bounds[1], view.height));
    let depth = |draw: &(u32, u32)| view.depth_and_scale(cluster(draw).center).0;
    // The screen area of a cluster's glyphs' bounding discs.
    let disc_cover = |c: &Cluster| match view.depth_and_scale(c.center).1 {
        Some(scale) if view.rectangle(c).is_some() => {
            std::f64::consts::PI * c.squared_radii * scale * scale
        }
        // A cluster at the eye may cover the screen.
        _ => area,
    };
    draws.sort_by(|a, b| depth(a).total_cmp(&depth(b)).then(a.cmp(b)));
    if cull == Culling::EarlyOut {
        // Early outs cost a draw per cluster and an atomic per hit: taken where the
        // glyphs' discs cover the scene's area more than once (hidden work is likely),
        // or wherever there is more than one cluster when asked for by name.
        let needed = if asked == Culling::EarlyOut {
            0.0
        } else {
            EARLY_OUT_COVER
        };
        let total: f64 = draws.iter().map(|d| disc_cover(cluster(d))).sum();
        if draws.len() < 2 || total < needed * area {
            return PassPlan::default();
        }
        return PassPlan {
            draws,
            starts: vec![0],
            early_out: true,
        };
    }
    // An explicit `passes` splits wherever the discs overlap.
    let pass_cover = if asked == Culling::Passes {
        1.0
    } else {
        PASS_COVER
    };
    let mut starts = vec![0];
    let mut covered = 0.0;
    for (k, draw) in draws.iter().enumerate() {
        if covered >= pass_cover * area && starts.len() < MAX_PASSES {
            starts.push(k);
            covered = 0.0;
        }
        covered += disc_cover(cluster(draw));
    }
    if starts.len() == 1 {
        // One pass: one draw per batch, as without culling.
        return PassPlan::default();
    }
    PassPlan {
        draws,
        starts,
        early_out: false,
    }
}

/// The bindings of the ray-casting pass's visibility set (set 1): the work counters and
/// the known depths (glsl/raycast_common.glsl).
pub(crate) fn visibility_bindings() -> [vk::DescriptorSetLayoutBinding<'static>; 3] {
    let storage = vk::DescriptorType::STORAGE_BUFFER;
    let fragment = vk::ShaderStageFlags::FRAGMENT;
    [
        buffer_binding(0, storage, fragment),
        buffer_binding(1, storage, fragment),
        buffer_binding(2, storage, fragment),
    ]
}

/// How frames drawn with `settings` on this device are culled: not at all for the
/// impostor and the meshes (their shaders do not take part) and on the compute path;
/// in passes where the device blends the float32 ray distance (the first stage of the
/// later passes keeps the smaller one); with early outs for the `exact` method, whose
/// shader has them. `Occluded` takes the early outs on a device that jumps over code
/// no lane runs (on the others they save nothing), else the passes. Not at all on a
/// device without `fragmentStoresAndAtomics` (a host's that did not enable it), whose
/// fragment shaders may not write the known depths.
pub(crate) fn culling(ctx: &DeviceContext, settings: &crate::render::RenderSettings) -> Culling {
    use crate::render::{Method, RenderPath};
    let method = !matches!(settings.method, Method::Impostor | Method::Mesh(_));
    if !method || settings.path == RenderPath::Compute || !ctx.fragment_stores() {
        return Culling::Off;
    }
    let passes = ctx.blends_float32();
    let early_out = settings.method == Method::Exact;
    match settings.cull {
        Culling::Passes if passes => Culling::Passes,
        Culling::EarlyOut if early_out => Culling::EarlyOut,
        Culling::Occluded if early_out && ctx.skips_idle_branches() => Culling::EarlyOut,
        Culling::Occluded if passes => Culling::Passes,
        _ => Culling::Off,
    }
}

/// What the passes of one target share: its work counters and the buffer its depth is
/// copied into between passes, with their descriptor set.
pub struct VisibilityBuffers {
    pub(crate) counters: Buffer,
    pub(crate) known: Buffer,
    /// Per pixel, the gate of a later pass's second stage during its first stage, then
    /// the nearest ray distance of the pass's glyphs (the first stage's).
    pub(crate) nearest: Buffer,
    /// The row length of the known depths, pixels.
    pub(crate) width: u32,
    /// Pixels of the target: the count of the known depths, of the gate and of the
    /// nearest distances.
    pub(crate) pixels: u32,
    _pool: DescriptorPool,
    pub(crate) set: vk::DescriptorSet,
}

impl VisibilityBuffers {
    /// The buffers of a target of `width` x `height` pixels and their set of `layout`
    /// (the ray-casting pass's set 1); the counters and the known depths' header alone
    /// where the target's known depths would not fit in a storage buffer of `limit`
    /// bytes (its frames are then drawn without culling). The nearest distances are
    /// per pixel only for frames culled in `passes`.
    pub(crate) fn new(
        ctx: &DeviceContext,
        layout: vk::DescriptorSetLayout,
        (width, height): (u32, u32),
        (limit, passes): (u64, bool),
    ) -> Result<VisibilityBuffers> {
        let storage = vk::BufferUsageFlags::STORAGE_BUFFER
            | vk::BufferUsageFlags::TRANSFER_DST
            | vk::BufferUsageFlags::TRANSFER_SRC;
        let counters = Buffer::new(ctx, "work counters", 16, storage, MemoryLocation::GpuToCpu)?;
        if !known_depths_fit(limit, width, height) {
            // The header alone (frame_start writes it), no known depth.
            let known = Buffer::new(ctx, "known depth", 32, storage, MemoryLocation::GpuOnly)?;
            let nearest = Buffer::with_data(ctx, "nearest distance", &[0u32; 4], storage)?;
            return VisibilityBuffers::with_set(ctx, layout, [counters, known, nearest], (1, 1));
        }
        let pixels = u64::from(width) * u64::from(height);
        let known = Buffer::new(
            ctx,
            "known depth",
            KNOWN_DEPTH_HEADER + 4 * pixels,
            storage,
            MemoryLocation::GpuOnly,
        )?;
        let nearest = Buffer::new(
            ctx,
            "nearest distance",
            if passes { 4 * pixels } else { 16 },
            storage,
            MemoryLocation::GpuOnly,
        )?;
        VisibilityBuffers::with_set(ctx, layout, [counters, known, nearest], (width, height))
    }

    /// The buffers of a host's frames drawn with early outs over a scissor of `width` x
    /// `height` pixels: the known depths of its pixels (no gate or nearest distance, no
    /// counting).
    pub(crate) fn for_early_outs(
        ctx: &DeviceContext,
        layout: vk::DescriptorSetLayout,
        width: u32,
        height: u32,
    ) -> Result<VisibilityBuffers> {
        let storage = vk::BufferUsageFlags::STORAGE_BUFFER;
        let counters = Buffer::with_data(ctx, "work counters", &[0u32; 4], storage)?;
        let pixels = u64::from(width) * u64::from(height);
        let known = Buffer::new(
            ctx,
            "known depth",
            KNOWN_DEPTH_HEADER + 4 * pixels,
            storage | vk::BufferUsageFlags::TRANSFER_DST,
            MemoryLocation::GpuOnly,
        )?;
        let nearest = Buffer::with_data(ctx, "nearest distance", &[0u32; 4], storage)?;
        VisibilityBuffers::with_set(ctx, layout, [counters, known, nearest], (width, height))
    }

    /// Records, outside any rendering, the start of a frame: the known depths' header
    /// (the row length, the visibility `word`, the target's first pixel `origin`), with
    /// `clear` every known depth at that value (early outs: the clear depth, no hit
    /// yet), and with `count` the work counters at zero; with the barriers from and to
    /// the fragment shaders.
    pub(crate) fn record_frame_start(
        &self,
        d: &ash::Device,
        cmd: vk::CommandBuffer,
        (word, origin): (u32, [u32; 2]),
        (clear, count): (Option<f32>, bool),
    ) {
        use crate::vk::recording::{FRAGMENT_STORAGE, TRANSFER_WRITES, memory_barrier};
        let known = self.known.handle;
        // SAFETY: `cmd` is recording outside rendering (the caller's promise); the buffers
        // are alive until the submission completes.
        unsafe {
            d.cmd_pipeline_barrier2(
                cmd,
                &vk::DependencyInfo::default()
                    .memory_barriers(&[memory_barrier(FRAGMENT_STORAGE, TRANSFER_WRITES)]),
            );
            for (k, value) in [self.width, word, origin[0], origin[1]]
                .into_iter()
                .enumerate()
            {
                d.cmd_fill_buffer(cmd, known, 4 * k as u64, 4, value);
            }
            if let Some(clear) = clear {
                let bytes = 4 * u64::from(self.pixels);
                d.cmd_fill_buffer(cmd, known, KNOWN_DEPTH_HEADER, bytes, clear.to_bits());
            }
            if count {
                d.cmd_fill_buffer(cmd, self.counters.handle, 0, vk::WHOLE_SIZE, 0);
            }
            d.cmd_pipeline_barrier2(
                cmd,
                &vk::DependencyInfo::default()
                    .memory_barriers(&[memory_barrier(TRANSFER_WRITES, FRAGMENT_STORAGE)]),
            );
        }
    }

    /// The buffers of frames drawn in one pass: a header of zeros (no known depth, no
    /// counting), never written.
    pub(crate) fn without_passes(
        ctx: &DeviceContext,
        layout: vk::DescriptorSetLayout,
    ) -> Result<VisibilityBuffers> {
        let storage = vk::BufferUsageFlags::STORAGE_BUFFER;
        let counters = Buffer::with_data(ctx, "work counters", &[0u32; 4], storage)?;
        let known = Buffer::with_data(ctx, "known depth", &[0u32; 8], storage)?;
        let nearest = Buffer::with_data(ctx, "nearest distance", &[0u32; 4], storage)?;
        VisibilityBuffers::with_set(ctx, layout, [counters, known, nearest], (1, 1))
    }

    /// The buffers (counters, known depths, nearest distances) and their set of `layout`.
    fn with_set(
        ctx: &DeviceContext,
        layout: vk::DescriptorSetLayout,
        [counters, known, nearest]: [Buffer; 3],
        (width, height): (u32, u32),
    ) -> Result<VisibilityBuffers> {
        let pool = DescriptorPool::new(ctx, 1, 0, 3)?;
        let set = pool.buffer_set(
            layout,
            &[
                BufferBinding::storage(0, &counters),
                BufferBinding::storage(1, &known),
                BufferBinding::storage(2, &nearest),
            ],
        )?;
        Ok(VisibilityBuffers {
            counters,
            known,
            nearest,
            width,
            pixels: width * height,
            _pool: pool,
            set,
        })
    }

    /// The counters of the last frame that counted (after its submission completed).
    pub(crate) fn counts(&self, passes: usize) -> Result<WorkCounts> {
        let bytes = self.counters.read()?;
        let word = |k: usize| {
            u64::from(u32::from_ne_bytes(
                bytes[4 * k..4 * k + 4].try_into().unwrap_or([0; 4]),
            ))
        };
        Ok(WorkCounts {
            fragments: word(crate::catalog::codes::WORK_FRAGMENTS as usize),
            evaluations: word(crate::catalog::codes::WORK_EVALUATIONS as usize),
            passes: passes as u64,
        })
    }
}
