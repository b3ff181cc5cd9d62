//! The order-2 identity tensor is a sphere: its render must match the analytic sphere to
//! float32 precision, under perspective and orthographic cameras, and the pixel
//! coverage must be that of the analytic sphere, with every intersection method.
use crate::common;
use glam::DVec3;
use glyphcast::accuracy::silhouette_band;
use glyphcast::camera::{Camera, Projection};
use glyphcast::demo::{glyph_set, symmetric};
use glyphcast::render::glyph_data::prepare_scene;
use glyphcast::render::headless::HeadlessRenderer;
use glyphcast::render::{Method, RenderSettings};
use glyphcast::scene::{ImageSize, Scene};

const CENTER: DVec3 = DVec3::new(0.3, -0.2, 0.1);
const RADIUS: f64 = 0.8;

fn analytic(camera: &Camera, i: u32, j: u32, w: u32, h: u32) -> f64 {
    let ray = camera.ray(i, j, w, h);
    let o = ray.origin - CENTER;
    let b = o.dot(ray.dir);
    let disc = b * b - (o.dot(o) - RADIUS * RADIUS);
    if disc < 0.0 {
        f64::NAN
    } else {
        -b - disc.sqrt()
    }
}

fn check(projection: Projection) {
    let gpu = common::gpu();
    let mut renderer = HeadlessRenderer::new(&gpu).expect("renderer");
    let identity = vec![1.0, 0.0, 0.0, 1.0, 0.0, 1.0];
    let camera = Camera {
        projection,
        eye: DVec3::new(1.0, -4.0, 2.0),
        target: DVec3::ZERO,
        up: DVec3::Z,
    };
    let (w, h) = (160, 120);
    let scene = Scene {
        glyph_sets: vec![glyph_set(
            symmetric(2),
            vec![CENTER],
            RADIUS,
            vec![identity],
        )],
        camera,
        image: ImageSize {
            width: w,
            height: h,
        },
    };
    let sets = prepare_scene(&scene, 0.0).expect("prepare");
    let exact: Vec<f64> = (0..h)
        .flat_map(|j| (0..w).map(move |i| (i, j)))
        .map(|(i, j)| analytic(&camera, i, j, w, h))
        .collect();
    let band = silhouette_band(&exact, w as usize, h as usize);
    for method in Method::RAY_CASTING {
        let settings = RenderSettings {
            method,
            ..Default::default()
        };
        let image = renderer
            .render_view(
                &gpu,
                &sets,
                &glyphcast::FrameView::new(&camera, w, h),
                &settings,
            )
            .expect("render");
        check_image(
            &format!("{projection:?} {method:?}"),
            &image.distance,
            &exact,
            &band,
        );
    }
}

fn check_image(name: &str, distance: &[f32], exact: &[f64], band: &[bool]) {
    let (mut worst, mut covered, mut coverage_mismatch) = (0.0f64, 0, 0);
    for (k, (&d, &e)) in distance.iter().zip(exact).enumerate() {
        if band[k] {
            continue;
        }
        if d.is_nan() != e.is_nan() {
            coverage_mismatch += 1;
        } else if !e.is_nan() {
            covered += 1;
            worst = worst.max((d as f64 - e).abs() / e);
        }
    }
    eprintln!(
        "{name}: covered {covered}, mismatches {coverage_mismatch}, worst relative error {worst:.2e}"
    );
    assert!(covered > 2000, "{name}: the sphere covers {covered} pixels");
    assert_eq!(
        coverage_mismatch, 0,
        "{name}: coverage differs from the analytic sphere away from its silhouette"
    );
    // float32 carries 6e-8 relative; the distance is assembled from a few float32
    // operations on numbers of the size of the camera distance, so allow a few ulps.
    assert!(
        worst < 2e-6,
        "{name}: worst relative depth error {worst:.2e}"
    );
}

#[test]
fn sphere_matches_analytic_perspective() {
    check(Projection::Perspective { fov_y_deg: 30.0 });
}

#[test]
fn sphere_matches_analytic_orthographic() {
    check(Projection::Orthographic { height: 2.5 });
}
