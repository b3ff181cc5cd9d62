//! Embedding glyphcast in an engine that owns its Vulkan objects.
//!
//! The engine (`engine.rs`, plain ash and gpu-allocator) has its own instance, device,
//! allocator and dynamic rendering, and draws its own geometry: a ground plane
//! (`plane.rs`) that cuts through the glyphs. glyphcast is handed the engine's device and
//! allocator as a [`DeviceContext`], and its [`RayCastPass`] is recorded into the same
//! command buffer, inside the same rendering, with the same depth buffer, after the plane:
//! the glyph shaders write `gl_FragDepth` with the view-projection the plane uses, so
//! glyphs and plane occlude each other per pixel.
//!
//! `cargo run --example embed [-- OUT.png]` writes the picture (default embed.png) and
//! prints how the depth buffer compares with the float64 reference (the glyphs' exact
//! intersections and the analytic plane); `cargo test --example embed` asserts it, with
//! the validation layer on. `GLYPHCAST_VALIDATION=1` turns the layer on for the program.
mod engine;
mod plane;

use ash::vk;
use engine::{Engine, subresource_range};
use glam::DVec3;
use glyphcast::demo::{direction, fibre_tensor, glyph_set, symmetric};
use glyphcast::glyph::reference::reference_depth;
use glyphcast::{
    Camera, DeviceContext, FrameParams, GlyphSetData, ImageSize, Projection, RayCastPass,
    RenderSettings, Scene, SceneExtent, TargetFormats, prepare_scene,
};
use plane::{PlanePass, Square};

type Result<T> = std::result::Result<T, Box<dyn std::error::Error>>;

const WIDTH: u32 = 256;
const HEIGHT: u32 = 192;
const COLOR_FORMAT: vk::Format = vk::Format::R8G8B8A8_SRGB;
const DEPTH_FORMAT: vk::Format = vk::Format::D32_SFLOAT;
/// The engine's depth range, shared by its plane and the glyphs.
const NEAR: f64 = 0.5;
const FAR: f64 = 40.0;

/// Six glyphs of orders 4 to 8 on a 3 x 2 grid at z = 0, and a plane just above their
/// centres that cuts all of them; the camera looks down at 35 degrees.
fn scene() -> (Scene, Square) {
    let mut centers = Vec::new();
    let mut coeffs = Vec::new();
    for (k, (x, y)) in [(-1.1, -0.55), (0.0, -0.55), (1.1, -0.55)]
        .into_iter()
        .chain([(-1.1, 0.55), (0.0, 0.55), (1.1, 0.55)])
        .enumerate()
    {
        centers.push(DVec3::new(x, y, 0.0));
        let turn = 30.0 * k as f64;
        coeffs.push(fibre_tensor(
            6,
            &[
                (direction(turn, 40.0), 1.0),
                (direction(turn + 90.0, -20.0), 0.7),
            ],
        ));
    }
    let camera = Camera {
        projection: Projection::Perspective { fov_y_deg: 35.0 },
        eye: DVec3::new(1.2, -4.2, 3.0),
        target: DVec3::new(0.0, 0.0, 0.0),
        up: DVec3::Z,
    };
    let scene = Scene {
        glyph_sets: vec![glyph_set(symmetric(6), centers, 0.5, coeffs)],
        camera,
        image: ImageSize {
            width: WIDTH,
            height: HEIGHT,
        },
    };
    let square = Square {
        center: [0.0, 0.0],
        height: 0.08,
        half: 2.2,
    };
    (scene, square)
}

/// What the engine's frame produced.
struct Frame {
    rgba: Vec<u8>,
    /// Ray distance per pixel from the depth buffer, NaN where nothing was drawn.
    distance: Vec<f64>,
    sets: Vec<GlyphSetData>,
    validation: Vec<String>,
}

fn render(validation: bool, scene: &Scene, square: &Square) -> Result<Frame> {
    let engine = Engine::new(validation)?;
    let (rgba, depth, sets) = render_with(&engine, scene, square)?;
    let distance = depth_to_distance(&depth, &scene.camera);
    Ok(Frame {
        rgba,
        distance,
        sets,
        validation: engine.validation_messages(),
    })
}

/// One frame: clear, the engine's plane, glyphcast's glyphs, read back colour and depth.
fn render_with(
    engine: &Engine,
    scene: &Scene,
    square: &Square,
) -> Result<(Vec<u8>, Vec<f32>, Vec<GlyphSetData>)> {
    // glyphcast on the engine's device and allocator: no instance or device of its own.
    // SAFETY: the device was made from this physical device and instance with dynamic
    // rendering, and the allocator is its own. The context, pass and scene are locals of
    // this function, which borrows the engine: they are dropped before the engine can
    // destroy its allocator, device and instance.
    let context = unsafe {
        DeviceContext::new(
            &engine.instance,
            engine.physical_device,
            engine.device.clone(),
            engine.allocator(),
        )
    };
    let formats = TargetFormats {
        color: COLOR_FORMAT,
        depth: DEPTH_FORMAT,
        distance: None,
    };
    let mut glyphs = RayCastPass::new(&context, formats)?;
    let plane = PlanePass::new(&engine.device, COLOR_FORMAT, DEPTH_FORMAT)?;
    let settings = RenderSettings::default();
    let sets = prepare_scene(scene, settings.offset as f64)?;
    // The engine's depth range; the glyphs' extent only sets the magnitude colour range.
    let extent = SceneExtent {
        near: NEAR,
        far: FAR,
        ..SceneExtent::of_glyph_sets(&scene.camera, &sets)
    };
    let params = FrameParams::new(&scene.camera, WIDTH, HEIGHT, &extent, &settings);
    let gpu_scene = glyphs.upload(&context, &sets, &params, settings.method)?;

    let size = vk::Extent2D {
        width: WIDTH,
        height: HEIGHT,
    };
    let read = vk::ImageUsageFlags::TRANSFER_SRC;
    let color = engine.create_image(
        "colour",
        size,
        COLOR_FORMAT,
        vk::ImageUsageFlags::COLOR_ATTACHMENT | read,
        vk::ImageAspectFlags::COLOR,
    )?;
    let depth = engine.create_image(
        "depth",
        size,
        DEPTH_FORMAT,
        vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT | read,
        vk::ImageAspectFlags::DEPTH,
    )?;
    let bytes = 4 * WIDTH as u64 * HEIGHT as u64;
    let color_readback = engine.create_readback("colour readback", bytes)?;
    let depth_readback = engine.create_readback("depth readback", bytes)?;
    engine.submit(|cmd| {
        let d = &engine.device;
        let images = [
            (color.image, vk::ImageAspectFlags::COLOR, Attachment::Color),
            (depth.image, vk::ImageAspectFlags::DEPTH, Attachment::Depth),
        ];
        let to_attachment: Vec<_> = images
            .iter()
            .map(|(image, aspect, kind)| kind.to_attachment(*image, *aspect))
            .collect();
        // SAFETY: `cmd` is recording; all handles live until the submission completed.
        unsafe {
            d.cmd_pipeline_barrier2(
                cmd,
                &vk::DependencyInfo::default().image_memory_barriers(&to_attachment),
            );
        }
        let color_attachment = [vk::RenderingAttachmentInfo::default()
            .image_view(color.view)
            .image_layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)
            .load_op(vk::AttachmentLoadOp::CLEAR)
            .store_op(vk::AttachmentStoreOp::STORE)
            .clear_value(vk::ClearValue {
                color: vk::ClearColorValue {
                    float32: [0.55, 0.65, 0.8, 1.0],
                },
            })];
        let depth_attachment = vk::RenderingAttachmentInfo::default()
            .image_view(depth.view)
            .image_layout(vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL)
            .load_op(vk::AttachmentLoadOp::CLEAR)
            .store_op(vk::AttachmentStoreOp::STORE)
            .clear_value(vk::ClearValue {
                depth_stencil: vk::ClearDepthStencilValue {
                    depth: 0.0,
                    stencil: 0,
                },
            });
        let rendering = vk::RenderingInfo::default()
            .render_area(size.into())
            .layer_count(1)
            .color_attachments(&color_attachment)
            .depth_attachment(&depth_attachment);
        // SAFETY: as above.
        unsafe { d.cmd_begin_rendering(cmd, &rendering) };
        // The engine's geometry first, then the glyphs into the same attachments.
        plane.record(cmd, size, params.view_proj, square);
        glyphs.record(cmd, &gpu_scene, size, settings.method)?;
        let to_transfer: Vec<_> = images
            .iter()
            .map(|(image, aspect, kind)| kind.to_transfer(*image, *aspect))
            .collect();
        let copy = |aspect| {
            vk::BufferImageCopy::default()
                .image_subresource(vk::ImageSubresourceLayers {
                    aspect_mask: aspect,
                    mip_level: 0,
                    base_array_layer: 0,
                    layer_count: 1,
                })
                .image_extent(size.into())
        };
        let host_read = [vk::MemoryBarrier2::default()
            .src_stage_mask(vk::PipelineStageFlags2::COPY)
            .src_access_mask(vk::AccessFlags2::TRANSFER_WRITE)
            .dst_stage_mask(vk::PipelineStageFlags2::HOST)
            .dst_access_mask(vk::AccessFlags2::HOST_READ)];
        // SAFETY: as above.
        unsafe {
            d.cmd_end_rendering(cmd);
            d.cmd_pipeline_barrier2(
                cmd,
                &vk::DependencyInfo::default().image_memory_barriers(&to_transfer),
            );
            let src = vk::ImageLayout::TRANSFER_SRC_OPTIMAL;
            let color_copy = [copy(vk::ImageAspectFlags::COLOR)];
            let depth_copy = [copy(vk::ImageAspectFlags::DEPTH)];
            d.cmd_copy_image_to_buffer(cmd, color.image, src, color_readback.buffer, &color_copy);
            d.cmd_copy_image_to_buffer(cmd, depth.image, src, depth_readback.buffer, &depth_copy);
            d.cmd_pipeline_barrier2(
                cmd,
                &vk::DependencyInfo::default().memory_barriers(&host_read),
            );
        }
        Ok(())
    })?;
    let rgba = engine.read(&color_readback)?.to_vec();
    let depth_values = bytemuck::pod_collect_to_vec::<u8, f32>(engine.read(&depth_readback)?);
    engine.destroy_readback(color_readback)?;
    engine.destroy_readback(depth_readback)?;
    engine.destroy_image(color)?;
    engine.destroy_image(depth)?;
    Ok((rgba, depth_values, sets))
}

#[derive(Clone, Copy)]
enum Attachment {
    Color,
    Depth,
}

impl Attachment {
    fn stage_access(self) -> (vk::PipelineStageFlags2, vk::AccessFlags2, vk::ImageLayout) {
        match self {
            Attachment::Color => (
                vk::PipelineStageFlags2::COLOR_ATTACHMENT_OUTPUT,
                vk::AccessFlags2::COLOR_ATTACHMENT_WRITE,
                vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
            ),
            Attachment::Depth => (
                vk::PipelineStageFlags2::EARLY_FRAGMENT_TESTS
                    | vk::PipelineStageFlags2::LATE_FRAGMENT_TESTS,
                vk::AccessFlags2::DEPTH_STENCIL_ATTACHMENT_READ
                    | vk::AccessFlags2::DEPTH_STENCIL_ATTACHMENT_WRITE,
                vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL,
            ),
        }
    }

    fn to_attachment(
        self,
        image: vk::Image,
        aspect: vk::ImageAspectFlags,
    ) -> vk::ImageMemoryBarrier2<'static> {
        let (stage, access, layout) = self.stage_access();
        vk::ImageMemoryBarrier2::default()
            .image(image)
            .subresource_range(subresource_range(aspect))
            .old_layout(vk::ImageLayout::UNDEFINED)
            .new_layout(layout)
            .dst_stage_mask(stage)
            .dst_access_mask(access)
    }

    fn to_transfer(
        self,
        image: vk::Image,
        aspect: vk::ImageAspectFlags,
    ) -> vk::ImageMemoryBarrier2<'static> {
        let (stage, access, layout) = self.stage_access();
        vk::ImageMemoryBarrier2::default()
            .image(image)
            .subresource_range(subresource_range(aspect))
            .old_layout(layout)
            .new_layout(vk::ImageLayout::TRANSFER_SRC_OPTIMAL)
            .src_stage_mask(stage)
            .src_access_mask(access)
            .dst_stage_mask(vk::PipelineStageFlags2::COPY)
            .dst_access_mask(vk::AccessFlags2::TRANSFER_READ)
    }
}

/// Depth-buffer values back to distances along each pixel's ray. The camera's
/// perspective depth is reversed, z = near / e for eye depth e along the forward axis
/// ([`Camera::view_projection`]); a cleared 0 is a miss.
fn depth_to_distance(depth: &[f32], camera: &Camera) -> Vec<f64> {
    let fwd = camera.frame().fwd;
    depth
        .iter()
        .enumerate()
        .map(|(k, &z)| {
            if z <= 0.0 {
                return f64::NAN;
            }
            let (i, j) = ((k as u32) % WIDTH, (k as u32) / WIDTH);
            let eye_depth = NEAR / z as f64;
            eye_depth / camera.ray(i, j, WIDTH, HEIGHT).dir.dot(fwd)
        })
        .collect()
}

/// The depth buffer against the float64 reference: per pixel, the nearer of the glyphs'
/// exact first hit and the analytic plane.
#[derive(Debug, Default)]
struct Compositing {
    /// Pixels judged: away from every edge where the nearest surface changes (glyph
    /// silhouettes, plane border, the curves where plane and glyphs cut each other).
    judged: usize,
    /// The reference has a hit, the depth buffer none.
    holes: usize,
    /// The depth buffer has a hit, the reference none.
    false_hits: usize,
    /// Both hit, at distances further apart than the tolerance (wrong surface in front).
    wrong_surface: usize,
    /// Judged pixels where glyphs hide the plane, and where the plane hides glyphs.
    glyph_over_plane: usize,
    plane_over_glyph: usize,
    median_error: f64,
    max_error: f64,
    /// The largest glyph's bounding radius: errors are in these units.
    scale: f64,
}

/// Depth tolerance, in units of the glyph scale: the ray caster's error at default
/// settings is below 1e-3 (tests/depth_accuracy.rs); a wrong surface in front is off by
/// far more away from the curves where the two cross, which are not judged.
const TOLERANCE: f64 = 1e-2;

fn compare(frame: &Frame, scene: &Scene, square: &Square) -> Compositing {
    let camera = &scene.camera;
    let world: Vec<_> = frame.sets.iter().flat_map(|s| s.world.clone()).collect();
    let scale = world.iter().map(|g| g.scale * g.bound).fold(0.0, f64::max);
    let glyph = reference_depth(&world, camera, WIDTH, HEIGHT);
    let (w, h) = (WIDTH as usize, HEIGHT as usize);
    let plane: Vec<f64> = (0..w * h)
        .map(|k| {
            let ray = camera.ray((k % w) as u32, (k / w) as u32, WIDTH, HEIGHT);
            square.hit(ray.origin, ray.dir).unwrap_or(f64::NAN)
        })
        .collect();
    // 0: nothing, 1: a glyph in front, 2: the plane in front.
    let surface: Vec<u8> = glyph
        .iter()
        .zip(&plane)
        .map(|(g, p)| match (g.is_nan(), p.is_nan()) {
            (true, true) => 0,
            (false, true) => 1,
            (true, false) => 2,
            (false, false) => 1 + u8::from(p < g),
        })
        .collect();
    let mut c = Compositing {
        scale,
        ..Default::default()
    };
    let mut errors = Vec::new();
    for k in 0..w * h {
        let (x, y) = (k % w, k / w);
        let edge = (y.saturating_sub(1)..=(y + 1).min(h - 1))
            .flat_map(|ny| (x.saturating_sub(1)..=(x + 1).min(w - 1)).map(move |nx| ny * w + nx))
            .any(|n| surface[n] != surface[k]);
        let crossing = (glyph[k] - plane[k]).abs() < 2.0 * TOLERANCE * scale;
        if edge || crossing {
            continue;
        }
        c.judged += 1;
        let expected = glyph[k].min(plane[k]); // f64::min ignores one NaN
        let actual = frame.distance[k];
        match (expected.is_nan(), actual.is_nan()) {
            (false, true) => c.holes += 1,
            (true, false) => c.false_hits += 1,
            (true, true) => {}
            (false, false) => {
                let error = (actual - expected).abs() / scale;
                if error > TOLERANCE {
                    c.wrong_surface += 1;
                }
                errors.push(error);
                if !glyph[k].is_nan() && !plane[k].is_nan() {
                    if surface[k] == 1 {
                        c.glyph_over_plane += 1;
                    } else {
                        c.plane_over_glyph += 1;
                    }
                }
            }
        }
    }
    errors.sort_by(f64::total_cmp);
    c.median_error = errors.get(errors.len() / 2).copied().unwrap_or(0.0);
    c.max_error = errors.last().copied().unwrap_or(0.0);
    c
}

fn main() -> Result<()> {
    let output = std::env::args()
        .nth(1)
        .unwrap_or_else(|| "embed.png".into());
    let validation = std::env::var("GLYPHCAST_VALIDATION").is_ok_and(|v| v != "0");
    let (scene, square) = scene();
    let frame = render(validation, &scene, &square)?;
    glyphcast::io::png::write_png_rgba8(output.as_ref(), WIDTH, HEIGHT, &frame.rgba)?;
    println!("wrote {output}");
    let c = compare(&frame, &scene, &square);
    println!("errors in units of the glyph scale {:.3}: {c:#?}", c.scale);
    if !frame.validation.is_empty() {
        return Err(format!("{} validation message(s)", frame.validation.len()).into());
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The plane and the glyphs occlude each other exactly where the float64 reference
    /// says, with the validation layer clean (no errors, no warnings).
    #[test]
    fn glyphs_and_plane_share_the_depth_buffer() {
        let (scene, square) = scene();
        let frame = render(true, &scene, &square).expect("rendering the engine's frame");
        let c = compare(&frame, &scene, &square);
        eprintln!("{c:#?}");
        if c.holes + c.false_hits + c.wrong_surface > 0 {
            let dir = std::env::temp_dir();
            let path = dir.join("embed-actual.png");
            let _ = glyphcast::io::png::write_png_rgba8(&path, WIDTH, HEIGHT, &frame.rgba);
            eprintln!("image: {}", path.display());
        }
        assert!(
            frame.validation.is_empty(),
            "validation: {:?}",
            frame.validation
        );
        assert!(c.judged > WIDTH as usize * HEIGHT as usize / 2);
        // Both kinds of occlusion are on screen, in numbers.
        assert!(c.glyph_over_plane > 1000, "{c:?}");
        assert!(c.plane_over_glyph > 300, "{c:?}");
        assert_eq!((c.holes, c.false_hits, c.wrong_surface), (0, 0, 0), "{c:?}");
        assert!(c.median_error < 1e-3, "{c:?}");
    }
}
