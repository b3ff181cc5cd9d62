//! The anatomical underlay: a scalar (FA, T1) or RGB (colour-FA) volume drawn as textured
//! planes in the glyphs' depth buffer, so that glyphs in front of a plane hide it and
//! glyphs behind it are hidden.
//!
//! The volume is not resampled onto a texture on the CPU: its values go to the GPU as
//! they are (float32, channels interleaved), with the world-to-voxel map of its own
//! affine. Each plane is a world-space parallelogram; its vertex shader maps the corners
//! into the underlay's voxel coordinates and the fragment shader samples the volume
//! trilinearly there (glsl/underlay.frag). The underlay's grid and the glyphs' grid may
//! differ in size, resolution and orientation: they meet in world space. The same
//! sampling in float64 ([`UnderlayVolume::sample`]) is the reference the tests hold the
//! pixels to.
//!
//! A plane writes colour, depth, and "no glyph" (-1) as the ray distance: the depth map
//! (`--depth-out`) keeps its contract, the distance to the first *glyph* hit at the pixel
//! centre, NaN where none is seen (a glyph behind the plane is not seen).
//!
//! `crate::volume::underlay` reads an underlay from a NIfTI or MRtrix file and places the
//! planes on the slices of a volume view; an embedder builds an [`Underlay`] from its own
//! arrays and hands it to
//! [`HeadlessRenderer::render_view`](crate::render::headless::HeadlessRenderer::render_view)
//! or records [`UnderlayPass::record`] into its own frame.
use crate::camera::{Camera, Ray};
use crate::error::{Error, Result, Setting};
use crate::render::frame::{FRAME_DESCRIPTOR, FRAME_USAGE, SceneExtent};
use crate::render::raycast::{TargetFormats, viewport_and_scissor};
use crate::render::shaders::{UNDERLAY_FRAGMENT, UNDERLAY_VERTEX};
use crate::vk::recording::bind_graphics;
use crate::vk::{
    Buffer, BufferBinding, DescriptorPool, DeviceContext, GraphicsPipelineDesc, Pipeline,
    PipelineLayout, RasterTarget, ShaderModule, buffer_binding, graphics_pipeline,
    vertex_fragment_stages,
};
use ash::vk;
use bytemuck::{Pod, Zeroable};
use glam::{DMat4, DVec3, DVec4};
use std::sync::Arc;

/// The default window: from the 2nd to the 98th percentile of the finite values.
pub(crate) const DEFAULT_PERCENTILES: (f64, f64) = (2.0, 98.0);

/// An underlay volume: values on a voxel grid with its voxel-to-world affine, and the
/// window that maps them to grey levels (or, per channel, to RGB).
#[derive(Clone, Debug)]
pub struct UnderlayVolume {
    /// Where it came from, for messages.
    pub file: String,
    /// Voxels along i, j, k.
    pub dims: [usize; 3],
    /// 1 (scalar: grey) or 3 (RGB).
    pub channels: usize,
    /// Channels interleaved, i fastest, then j, then k; NaN where there is no value.
    values: Vec<f32>,
    world_to_voxel: DMat4,
    /// The values drawn black (low) and white (high).
    window: (f64, f64),
}

/// One plane of an underlay: the world-space parallelogram `origin + s u + t v` for s, t
/// in [0, 1], showing the volume at each of its points p at p - `sample_offset` (zero
/// for a plane on its slice; a plane moved behind a slab of glyphs still shows the
/// slice).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct UnderlayPlane {
    /// A corner, world space.
    pub origin: DVec3,
    /// The edge from `origin` along s.
    pub u: DVec3,
    /// The edge from `origin` along t.
    pub v: DVec3,
    /// What is subtracted from a point of the plane where the volume is sampled.
    pub sample_offset: DVec3,
}

/// An underlay ready to draw: the volume (shared, so that a viewer can move the planes
/// without copying it) and the planes it is drawn on.
#[derive(Clone, Debug)]
pub struct Underlay {
    /// The values and their window.
    pub volume: Arc<UnderlayVolume>,
    /// The planes drawn; typically the slices of the glyph view.
    pub planes: Vec<UnderlayPlane>,
}

impl UnderlayVolume {
    /// A volume of `dims` voxels with `channels` (1 or 3) values each, interleaved, i
    /// fastest; `voxel_to_world` maps voxel indices (centres) to world points. The window
    /// starts at `DEFAULT_PERCENTILES`. `file` names errors.
    pub fn new(
        file: impl Into<String>,
        dims: [usize; 3],
        channels: usize,
        values: Vec<f32>,
        voxel_to_world: DMat4,
    ) -> Result<Self> {
        let file = file.into();
        if !matches!(channels, 1 | 3) {
            return Err(Error::input(
                &file,
                "dim",
                format!("an underlay has 1 (scalar) or 3 (RGB) values per voxel, not {channels}"),
            ));
        }
        let voxels = dims.iter().product::<usize>();
        if voxels == 0 || values.len() != voxels * channels {
            return Err(Error::input(
                &file,
                "dim",
                format!(
                    "{} values for {}x{}x{} voxels of {channels} channel(s)",
                    values.len(),
                    dims[0],
                    dims[1],
                    dims[2]
                ),
            ));
        }
        if dims.iter().any(|&n| n > i32::MAX as usize) || values.len() > u32::MAX as usize {
            return Err(Error::input(
                &file,
                "dim",
                "the underlay is too large to draw",
            ));
        }
        let invertible = voxel_to_world.is_finite()
            && voxel_to_world.row(3) == DVec4::new(0.0, 0.0, 0.0, 1.0)
            && voxel_to_world.determinant().abs() > 0.0;
        let world_to_voxel = voxel_to_world.inverse();
        if !(invertible && world_to_voxel.is_finite()) {
            return Err(Error::input(
                &file,
                "affine",
                "the voxel-to-world affine is not finite and invertible",
            ));
        }
        let mut volume = UnderlayVolume {
            file,
            dims,
            channels,
            values,
            world_to_voxel,
            window: (0.0, 1.0),
        };
        volume.window = volume.percentile_window(DEFAULT_PERCENTILES)?;
        Ok(volume)
    }

    /// The window (low, high): values at or below `low` are drawn black, at or above
    /// `high` white, linearly in between (in the PNG's 8-bit values).
    pub fn window(&self) -> (f64, f64) {
        self.window
    }

    /// Sets the window; `low < high`, both finite (`--underlay-range`).
    pub fn set_window(&mut self, low: f64, high: f64) -> Result<()> {
        if !(low.is_finite() && high.is_finite() && low < high) {
            return Err(Error::setting_value(
                Setting::UnderlayRange,
                format!("{low}:{high}"),
                "needs finite LOW < HIGH",
            ));
        }
        self.window = (low, high);
        Ok(())
    }

    /// The window from the `(low, high)` percentiles (0 to 100) of the finite values
    /// (every channel together), by the nearest-rank method. A constant volume gets the
    /// window (v, v + 1): it is drawn black. No finite value at all is an error.
    pub fn percentile_window(&self, (low, high): (f64, f64)) -> Result<(f64, f64)> {
        let mut finite: Vec<f32> = self
            .values
            .iter()
            .copied()
            .filter(|v| v.is_finite())
            .collect();
        if finite.is_empty() {
            return Err(Error::input(
                &self.file,
                "data",
                "the underlay has no finite value to draw",
            ));
        }
        let mut rank = |p: f64| -> f64 {
            let n = finite.len();
            let index = ((p / 100.0 * n as f64).ceil() as usize).clamp(1, n) - 1;
            let (_, value, _) = finite.select_nth_unstable_by(index, f32::total_cmp);
            *value as f64
        };
        let (lo, hi) = (rank(low), rank(high));
        Ok(if hi > lo { (lo, hi) } else { (lo, lo + 1.0) })
    }

    /// World point to the underlay's voxel coordinates (voxel centres at integers).
    pub fn voxel_of(&self, world: DVec3) -> DVec3 {
        self.world_to_voxel.transform_point3(world)
    }

    /// The world-to-voxel map (the inverse of the affine given to [`UnderlayVolume::new`]).
    pub fn world_to_voxel(&self) -> DMat4 {
        self.world_to_voxel
    }

    /// The raw values, channels interleaved, i fastest.
    pub fn values(&self) -> &[f32] {
        &self.values
    }

    /// The volume at world point `world`, trilinearly interpolated between the eight
    /// voxel centres around it, in float64 (the shader's sampling, the tests' reference).
    /// `None` outside the volume (more than half a voxel beyond the outer centres) or
    /// where one of the eight values is NaN. A scalar volume gives its value three times.
    pub fn sample(&self, world: DVec3) -> Option<[f64; 3]> {
        let p = self.voxel_of(world).to_array();
        let mut lo = [0usize; 3];
        let mut hi = [0usize; 3];
        let mut f = [0.0; 3];
        for a in 0..3 {
            let last = self.dims[a] - 1;
            if !(p[a] >= -0.5 && p[a] <= last as f64 + 0.5) {
                return None;
            }
            let q = p[a].clamp(0.0, last as f64);
            lo[a] = (q.floor() as usize).min(last);
            hi[a] = (lo[a] + 1).min(last);
            f[a] = q - lo[a] as f64;
        }
        let mut out = [0.0; 3];
        for (c, value) in out.iter_mut().enumerate().take(self.channels) {
            let at = |i: usize, j: usize, k: usize| -> f64 {
                let index = ((k * self.dims[1] + j) * self.dims[0] + i) * self.channels + c;
                self.values[index] as f64
            };
            let lerp = |a: f64, b: f64, t: f64| a + (b - a) * t;
            let corners = [
                at(lo[0], lo[1], lo[2]),
                at(hi[0], lo[1], lo[2]),
                at(lo[0], hi[1], lo[2]),
                at(hi[0], hi[1], lo[2]),
                at(lo[0], lo[1], hi[2]),
                at(hi[0], lo[1], hi[2]),
                at(lo[0], hi[1], hi[2]),
                at(hi[0], hi[1], hi[2]),
            ];
            if corners.iter().any(|v| v.is_nan()) {
                return None;
            }
            let x = [0, 2, 4, 6].map(|n| lerp(corners[n], corners[n + 1], f[0]));
            *value = lerp(lerp(x[0], x[1], f[1]), lerp(x[2], x[3], f[1]), f[2]);
        }
        if self.channels == 1 {
            out = [out[0]; 3];
        }
        Some(out)
    }

    /// The windowed colour at `world`: each channel mapped to [0, 1] by the window (the
    /// PNG stores round(255 g)); `None` where [`UnderlayVolume::sample`] has no value.
    pub fn shade(&self, world: DVec3) -> Option<[f64; 3]> {
        let (lo, hi) = self.window;
        self.sample(world)
            .map(|v| v.map(|x| ((x - lo) / (hi - lo)).clamp(0.0, 1.0)))
    }
}

impl UnderlayPlane {
    /// The four corners, world space.
    pub fn corners(&self) -> [DVec3; 4] {
        let o = self.origin;
        [o, o + self.u, o + self.u + self.v, o + self.v]
    }

    /// The distance along `ray` to the plane, if the ray crosses it inside the
    /// parallelogram (in float64: the analytic plane the tests compare with).
    pub fn intersect(&self, ray: &Ray) -> Option<f64> {
        let normal = self.u.cross(self.v);
        let denominator = normal.dot(ray.dir);
        if denominator == 0.0 {
            return None;
        }
        let t = normal.dot(self.origin - ray.origin) / denominator;
        let p = ray.origin + t * ray.dir - self.origin;
        // Coordinates of p in the (u, v) basis: solve the 2x2 Gram system.
        let (uu, uv, vv) = (self.u.dot(self.u), self.u.dot(self.v), self.v.dot(self.v));
        let (pu, pv) = (p.dot(self.u), p.dot(self.v));
        let det = uu * vv - uv * uv;
        let s = (pu * vv - pv * uv) / det;
        let r = (pv * uu - pu * uv) / det;
        ((0.0..=1.0).contains(&s) && (0.0..=1.0).contains(&r) && t >= 0.0).then_some(t)
    }
}

/// The extent of the glyphs widened to the underlay's plane corners, so that no plane is
/// cut by the near or far plane; the magnitude range stays the glyphs'.
pub fn extent_with_planes(
    camera: &Camera,
    glyphs: SceneExtent,
    planes: &[UnderlayPlane],
) -> SceneExtent {
    let corners = planes
        .iter()
        .flat_map(|p| p.corners())
        .map(|c| (c.to_array(), 0.0));
    let fwd = camera.frame().fwd;
    let seen = planes
        .iter()
        .flat_map(|p| p.corners())
        .any(|c| fwd.dot(c - camera.eye) > 0.0);
    if !seen {
        return glyphs;
    }
    let planes = SceneExtent::of_spheres(camera, corners);
    SceneExtent {
        near: glyphs.near.min(planes.near),
        far: glyphs.far.max(planes.far),
        max_radius: glyphs.max_radius,
    }
}

/// The parameter block of glsl/underlay.vert/.frag (`UnderlayParams`; a storage buffer, as the frame block).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub(crate) struct UnderlayParams {
    pub(crate) world_to_voxel: [[f32; 4]; 4],
    pub(crate) dims: [i32; 4],
    pub(crate) window: [f32; 4],
}

/// The push constants of glsl/underlay.vert (`Plane`): 112 bytes, within the 128 every
/// device offers.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub(crate) struct PlanePush {
    pub(crate) view_proj: [[f32; 4]; 4],
    pub(crate) origin: [f32; 4],
    pub(crate) u: [f32; 4],
    pub(crate) v: [f32; 4],
}

/// Binding of the underlay's parameter block (`UnderlayParams`).
pub(crate) const PARAMS_BINDING: u32 = 0;
/// Binding of the underlay's values (`UnderlayValues`).
pub(crate) const VALUES_BINDING: u32 = 1;

/// The bindings of an underlay's descriptor set: its parameter block and its values.
pub(crate) fn underlay_bindings() -> [vk::DescriptorSetLayoutBinding<'static>; 2] {
    [
        buffer_binding(
            PARAMS_BINDING,
            FRAME_DESCRIPTOR,
            vk::ShaderStageFlags::VERTEX | vk::ShaderStageFlags::FRAGMENT,
        ),
        buffer_binding(
            VALUES_BINDING,
            vk::DescriptorType::STORAGE_BUFFER,
            vk::ShaderStageFlags::FRAGMENT,
        ),
    ]
}

impl PlanePush {
    /// The push constants that draw `plane` with the glyph pass's `view_proj`; the w
    /// components carry the sample offset (glsl/underlay.vert).
    pub(crate) fn new(plane: &UnderlayPlane, view_proj: [[f32; 4]; 4]) -> PlanePush {
        let v4 = |v: DVec3, w: f64| [v.x as f32, v.y as f32, v.z as f32, w as f32];
        PlanePush {
            view_proj,
            origin: v4(plane.origin, plane.sample_offset.x),
            u: v4(plane.u, plane.sample_offset.y),
            v: v4(plane.v, plane.sample_offset.z),
        }
    }
}

/// The underlay's pipeline, for attachments of given formats; created once per device.
pub struct UnderlayPass {
    ctx: DeviceContext,
    // Fields drop in order: the pipelines go before the modules and the layout they were
    // made with, the order the validation layer expects.
    pipeline: Pipeline,
    layout: PipelineLayout,
}

/// An underlay volume on the GPU: its values and its parameter block.
pub struct UnderlayGpu {
    _params: Buffer,
    _values: Buffer,
    _pool: DescriptorPool,
    pub(crate) descriptor_set: vk::DescriptorSet,
}

impl UnderlayPass {
    /// The pipeline for attachments of `formats`: colour and depth written (reversed
    /// depth, tested GREATER, as the glyphs), -1 (no glyph) into the distance
    /// attachment, if any; both faces drawn.
    pub fn new(ctx: &DeviceContext, formats: TargetFormats) -> Result<UnderlayPass> {
        let bindings = underlay_bindings();
        let push = std::mem::size_of::<PlanePush>() as u32;
        let layout = PipelineLayout::new(ctx, &bindings, vk::ShaderStageFlags::VERTEX, push)?;
        let pipeline = create_pipeline(ctx, formats, layout.handle())?;
        Ok(UnderlayPass {
            ctx: ctx.clone(),
            layout,
            pipeline,
        })
    }

    /// Uploads `volume`'s values and window. A volume larger than one storage buffer
    /// (maxStorageBufferRange) is an error naming its file.
    pub fn upload(&self, ctx: &DeviceContext, volume: &UnderlayVolume) -> Result<UnderlayGpu> {
        let bytes = 4 * volume.values.len() as u64;
        if bytes > ctx.max_storage_buffer_range() {
            return Err(Error::input(
                &volume.file,
                "dim",
                format!(
                    "the underlay's {} MiB of float32 values exceed this device's largest \
                     storage buffer ({} MiB); crop or downsample it",
                    bytes >> 20,
                    ctx.max_storage_buffer_range() >> 20
                ),
            ));
        }
        let m = volume.world_to_voxel.as_mat4().to_cols_array_2d();
        let (lo, hi) = volume.window;
        let params = UnderlayParams {
            world_to_voxel: m,
            dims: [
                volume.dims[0] as i32,
                volume.dims[1] as i32,
                volume.dims[2] as i32,
                volume.channels as i32,
            ],
            window: [lo as f32, (1.0 / (hi - lo)) as f32, 0.0, 0.0],
        };
        let params = Buffer::with_data(
            ctx,
            "underlay parameters",
            std::slice::from_ref(&params),
            FRAME_USAGE,
        )?;
        let values = Buffer::with_data(
            ctx,
            "underlay values",
            &volume.values,
            vk::BufferUsageFlags::STORAGE_BUFFER,
        )?;
        let pool = DescriptorPool::new(ctx, 1, 0, 2)?;
        let descriptor_set = pool.buffer_set(
            self.layout.set_layout(),
            &[
                BufferBinding::storage(PARAMS_BINDING, &params),
                BufferBinding::storage(VALUES_BINDING, &values),
            ],
        )?;
        Ok(UnderlayGpu {
            _params: params,
            _values: values,
            _pool: pool,
            descriptor_set,
        })
    }

    /// Records one draw per plane. The caller has begun dynamic rendering with
    /// attachments of this pass's formats, of size `extent`; `view_proj` is the glyph
    /// pass's (`FrameParams::view_proj`), so that planes and glyphs share the depth scale.
    pub fn record(
        &self,
        cmd: vk::CommandBuffer,
        volume: &UnderlayGpu,
        planes: &[UnderlayPlane],
        view_proj: [[f32; 4]; 4],
        extent: vk::Extent2D,
    ) {
        let (viewport, scissor) = viewport_and_scissor(extent);
        let d = self.ctx.device();
        // SAFETY: recording state is the caller's; every handle is alive.
        unsafe {
            let pipeline = (self.pipeline.handle(), self.layout.handle());
            bind_graphics(d, cmd, pipeline, volume.descriptor_set, (viewport, scissor));
        }
        for plane in planes {
            let push = PlanePush::new(plane, view_proj);
            // SAFETY: as above; the push range covers the whole block.
            unsafe {
                d.cmd_push_constants(
                    cmd,
                    self.layout.handle(),
                    vk::ShaderStageFlags::VERTEX,
                    0,
                    bytemuck::bytes_of(&push),
                );
                d.cmd_draw(cmd, 6, 1, 0, 0);
            }
        }
    }
}

/// The underlay's pipeline: both faces of the planes drawn, no vertex input (the vertex
/// shader makes the quad's corners), the glyphs' attachments and depth test.
fn create_pipeline(
    ctx: &DeviceContext,
    formats: TargetFormats,
    layout: vk::PipelineLayout,
) -> Result<Pipeline> {
    // SAFETY: the SPIR-V comes from build.rs and was validated by glslang.
    let vertex = unsafe { ShaderModule::new(ctx, UNDERLAY_VERTEX)? };
    // SAFETY: as above.
    let fragment = unsafe { ShaderModule::fragment(ctx, UNDERLAY_FRAGMENT)? };
    let stages = vertex_fragment_stages(vertex.handle(), fragment.handle(), None);
    let mut color_formats = vec![formats.color];
    color_formats.extend(formats.distance);
    let desc = GraphicsPipelineDesc {
        stages: &stages,
        vertex_bindings: &[],
        vertex_attributes: &[],
        cull: vk::CullModeFlags::NONE,
        color_formats: &color_formats,
        depth_format: formats.depth,
        layout,
        raster: RasterTarget::default(),
        darken: None,
        stage: crate::vk::DrawStage::Normal,
    };
    // SAFETY: the modules are alive until the call returns; their SPIR-V declares the
    // blocks of `layout` (render::interface checks them).
    unsafe { graphics_pipeline(ctx, &desc) }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ramp() -> UnderlayVolume {
        // 4 x 3 x 2 voxels, value = i + 10 j + 100 k, voxel size 2, shifted by (1, 2, 3).
        let mut values = Vec::new();
        for k in 0..2 {
            for j in 0..3 {
                for i in 0..4 {
                    values.push((i + 10 * j + 100 * k) as f32);
                }
            }
        }
        let affine = DMat4::from_cols_array_2d(&[
            [2.0, 0.0, 0.0, 0.0],
            [0.0, 2.0, 0.0, 0.0],
            [0.0, 0.0, 2.0, 0.0],
            [1.0, 2.0, 3.0, 1.0],
        ]);
        UnderlayVolume::new("ramp", [4, 3, 2], 1, values, affine).expect("volume")
    }

    #[test]
    fn trilinear_sampling_reproduces_a_linear_field() {
        let volume = ramp();
        // Voxel (1.5, 0.25, 0.5) is world (4, 2.5, 4).
        let v = volume.sample(DVec3::new(4.0, 2.5, 4.0)).expect("inside");
        assert!((v[0] - (1.5 + 2.5 + 50.0)).abs() < 1e-12, "{v:?}");
        // Half a voxel beyond the last centre along i is inside (clamped), further is not.
        assert_eq!(
            volume
                .sample(DVec3::new(1.0 + 2.0 * 3.49, 2.0, 3.0))
                .map(|v| v[0]),
            Some(3.0)
        );
        assert!(
            volume
                .sample(DVec3::new(1.0 + 2.0 * 3.51, 2.0, 3.0))
                .is_none()
        );
        assert!(
            volume
                .sample(DVec3::new(1.0 - 2.0 * 0.51, 2.0, 3.0))
                .is_none()
        );
    }

    #[test]
    fn percentile_window_and_its_errors() {
        let volume = ramp();
        // 24 values: the 2nd percentile is the smallest (rank 1), the 98th the largest.
        assert_eq!(volume.window(), (0.0, 123.0));
        // The median is rank 12, 23 (the largest of slice k = 0); a window of one value
        // is widened to (v, v + 1).
        assert_eq!(
            volume.percentile_window((50.0, 50.0)).ok(),
            Some((23.0, 24.0))
        );
        let mut v = volume.clone();
        assert!(v.set_window(f64::NAN, 1.0).is_err());
        assert!(v.set_window(2.0, 1.0).is_err());
        assert!(v.set_window(1.0, 2.0).is_ok());
        let nan = UnderlayVolume::new("nan", [1, 1, 1], 1, vec![f32::NAN], DMat4::IDENTITY);
        assert!(
            nan.expect_err("no finite value")
                .to_string()
                .contains("nan")
        );
        let singular = UnderlayVolume::new("flat", [1, 1, 1], 1, vec![1.0], DMat4::ZERO);
        assert!(
            singular
                .expect_err("singular")
                .to_string()
                .contains("affine")
        );
        let two = UnderlayVolume::new("two", [1, 1, 1], 2, vec![1.0, 2.0], DMat4::IDENTITY);
        assert!(two.is_err());
    }

    #[test]
    fn a_ray_meets_the_plane_inside_its_parallelogram_only() {
        let plane = UnderlayPlane {
            origin: DVec3::new(-1.0, -1.0, 0.0),
            u: DVec3::new(2.0, 0.0, 0.0),
            v: DVec3::new(0.0, 2.0, 0.0),
            sample_offset: DVec3::ZERO,
        };
        let ray = |x: f64| Ray {
            origin: DVec3::new(x, 0.5, 5.0),
            dir: DVec3::new(0.0, 0.0, -1.0),
        };
        assert_eq!(plane.intersect(&ray(0.0)), Some(5.0));
        assert_eq!(plane.intersect(&ray(1.5)), None);
    }
}
