//! Vulkan object ownership that safe code cannot break: every buffer, image and pass
//! keeps the device it was made from alive, so dropping the `Gpu` first is sound. (It
//! used to destroy the device under live objects: VUID-vkDestroyDevice-device-00378 from
//! the validation layer, then a segfault when the objects were dropped.) A device an
//! engine lends glyphcast is never destroyed by glyphcast.
use crate::common;
use ash::vk;
use glam::DVec3;
use glyphcast::camera::{Camera, Projection};
use glyphcast::demo::{glyph_set, symmetric};
use glyphcast::glyph::tessellate::MeshKind;
use glyphcast::render::glyph_data::{GlyphSetData, prepare_scene};
use glyphcast::render::headless::HeadlessRenderer;
use glyphcast::render::raycast::{RayCastPass, TargetFormats};
use glyphcast::render::{Method, RenderSettings};
use glyphcast::scene::{ImageSize, Scene};
use glyphcast::vk::{Buffer, DeviceContext, Gpu, Image};
use gpu_allocator::MemoryLocation;
use gpu_allocator::vulkan::{Allocator, AllocatorCreateDesc};
use std::sync::{Arc, Mutex};

const WIDTH: u32 = 32;
const HEIGHT: u32 = 24;

/// One order-2 identity tensor (a sphere) in front of the camera.
fn sphere() -> (Scene, Vec<GlyphSetData>) {
    let identity = vec![1.0, 0.0, 0.0, 1.0, 0.0, 1.0];
    let scene = Scene {
        glyph_sets: vec![glyph_set(
            symmetric(2),
            vec![DVec3::ZERO],
            0.8,
            vec![identity],
        )],
        camera: Camera {
            projection: Projection::Perspective { fov_y_deg: 35.0 },
            eye: DVec3::new(1.0, -4.0, 2.0),
            target: DVec3::ZERO,
            up: DVec3::Z,
        },
        image: ImageSize {
            width: WIDTH,
            height: HEIGHT,
        },
    };
    let sets = prepare_scene(&scene, 0.0).expect("preparing the sphere");
    (scene, sets)
}

/// Renders the sphere with `renderer` and checks that it covers some pixels.
fn render_sphere(gpu: &Gpu, renderer: &mut HeadlessRenderer, method: Method) {
    let (scene, sets) = sphere();
    let settings = RenderSettings {
        method,
        ..RenderSettings::default()
    };
    let image = renderer
        .render_view(
            gpu,
            &sets,
            &glyphcast::FrameView::new(&scene.camera, WIDTH, HEIGHT),
            &settings,
        )
        .expect("rendering");
    assert!(
        image.distance.iter().any(|d| d.is_finite()),
        "{method}: the sphere covers no pixel"
    );
}

#[test]
fn objects_made_from_a_gpu_may_outlive_it() {
    let gpu = common::gpu();
    let log = gpu.validation_log().expect("validation is on in tests");
    let words = [1u32, 2, 3, 4];
    let buffer = Buffer::with_data(
        gpu.context(),
        "outliving buffer",
        &words,
        vk::BufferUsageFlags::STORAGE_BUFFER,
    )
    .expect("buffer");
    let image = Image::new(
        gpu.context(),
        "outliving image",
        vk::Extent2D {
            width: 8,
            height: 8,
        },
        vk::Format::R8G8B8A8_UNORM,
        vk::ImageUsageFlags::COLOR_ATTACHMENT,
        vk::ImageAspectFlags::COLOR,
    )
    .expect("image");
    // A renderer (ray-cast and mesh passes, command pool, timer) with a prepared frame
    // of each pass: pipelines, descriptor pools, uniform and vertex buffers, targets.
    let mut renderer = HeadlessRenderer::new(&gpu).expect("renderer");
    let (scene, sets) = sphere();
    let mut frames = Vec::new();
    for method in [Method::Exact, Method::Mesh(MeshKind::Icosphere(1))] {
        let settings = RenderSettings {
            method,
            ..RenderSettings::default()
        };
        let frame = renderer
            .prepare_view(
                &gpu,
                &sets,
                &glyphcast::FrameView::new(&scene.camera, WIDTH, HEIGHT),
                &settings,
            )
            .expect("preparing a frame");
        renderer.draw(&gpu, &frame).expect("drawing");
        let rendered = renderer.read(&gpu, &frame).expect("reading back");
        assert!(
            rendered.distance.iter().any(|d| d.is_finite()),
            "{method}: the sphere covers no pixel"
        );
        frames.push(frame);
    }
    gpu.check_validation().expect("no validation error so far");

    // The order that destroyed the device under live objects: the Gpu first.
    drop(gpu);
    // The buffer's memory is still mapped and readable.
    let read = bytemuck::pod_collect_to_vec::<u8, u32>(buffer.read().expect("reading"));
    assert_eq!(read, words);
    drop(frames);
    drop(renderer);
    drop(image);
    // The last object destroys the allocator's memory, the device and the instance.
    drop(buffer);
    let errors = log.errors();
    assert!(errors.is_empty(), "{errors:?}");
}

#[test]
fn a_device_lent_by_an_engine_is_left_to_it() {
    let gpu = common::gpu();
    // The "engine": the Gpu's device with an allocator of the test's own.
    let allocator = Allocator::new(&AllocatorCreateDesc {
        instance: gpu.instance().clone(),
        device: gpu.device().clone(),
        physical_device: gpu.physical_device,
        debug_settings: Default::default(),
        buffer_device_address: false,
        allocation_sizes: Default::default(),
    })
    .expect("allocator");
    let allocator = Arc::new(Mutex::new(allocator));
    // SAFETY: the device comes from the Gpu's physical device and instance with the
    // features the passes need, and the allocator was made for it. The Gpu and the
    // test's allocator handle outlive the context and everything made with it, which
    // are dropped below before either.
    let context = unsafe {
        DeviceContext::new(
            gpu.instance(),
            gpu.physical_device,
            gpu.device().clone(),
            allocator.clone(),
        )
    };
    let formats = TargetFormats {
        color: vk::Format::R8G8B8A8_SRGB,
        depth: vk::Format::D32_SFLOAT,
        distance: None,
    };
    let pass = RayCastPass::new(&context, formats).expect("pass");
    let buffer = Buffer::new(
        &context,
        "engine buffer",
        64,
        vk::BufferUsageFlags::STORAGE_BUFFER,
        MemoryLocation::GpuOnly,
    )
    .expect("buffer");
    drop(context);
    drop(pass);
    drop(buffer);
    // The last handle: the allocator frees its memory while the device is alive.
    drop(allocator);
    // glyphcast destroyed nothing of the engine's: the device still renders.
    let mut renderer = HeadlessRenderer::new(&gpu).expect("renderer");
    render_sphere(&gpu, &mut renderer, Method::Exact);
    drop(renderer);
    let errors = gpu.validation_errors();
    assert!(errors.is_empty(), "{errors:?}");
}
