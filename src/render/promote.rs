//! Fewer pipelines for one image. Most of a one-shot render of a small scene on lavapipe
//! is spent creating the `exact` pipelines, one per tensor layout (order 4 about 20 ms of
//! CPU, order 6 about 35, order 8 about 50, on every run: lavapipe keeps no pipeline
//! cache), while the glyphs themselves take a few milliseconds to draw.
//!
//! A symmetric glyph of order n is also one of order n + 2k: f(q) (q . q)^k
//! (`raised_symmetric_tensor`) has the same surface, sign and normals. So a one-shot
//! render draws a small set of a lower order with the pipeline of the highest order of
//! the same parity in its scene ([`promote_small_sets`]), when that saves compiling a
//! pipeline and costs few pixels: the higher order's shader does more per pixel (an
//! order-4 field of 256 glyphs filling a 1280x720 image drew in 50 to 78 ms with its own
//! pipeline and 101 to 104 ms with order 8's, on lavapipe). The picture is the same up to
//! float32 rounding (`tests/promotion.rs`). Renders of many frames (the viewer, the
//! benchmarks, engines) keep one pipeline per layout.

use crate::camera::{Camera, Projection};
use crate::glyph::polynomial::raised_symmetric_tensor;
use crate::glyph::{GlyphShape, Symmetry, TensorLayout};
use crate::render::glyph_data::{GlyphSetData, tensor_layout};
use crate::render::raycast::{Variant, batch_variant};
use crate::render::{Method, RenderPath, RenderSettings};
use crate::scene::Scene;
use glam::DVec3;

/// The most pixels that the sets of one layout may cover (the sum of their glyphs'
/// bounding discs on screen, an overestimate, times the samples per pixel) to be drawn
/// with a higher order's pipeline:
/// at the per-pixel cost measured above, about 10 ms of lavapipe's time against the 20
/// to 35 ms that the pipeline of their own would take to create.
pub(crate) const PROMOTED_PIXELS: f64 = 131_072.0;

/// Sets of more glyphs keep their own pipeline, so that which pipelines a render needs
/// is known before the glyphs are prepared ([`early_variants`]) for every larger set.
pub const PROMOTABLE_GLYPHS: usize = 4096;

/// Whether the render draws with the per-order `exact` shaders that promotion serves.
fn promotes(settings: &RenderSettings) -> bool {
    settings.path != RenderPath::Compute && settings.method == Method::Exact
}

/// The highest order of each parity (even, odd) among symmetric polynomial layouts.
fn top_orders(layouts: impl Iterator<Item = (TensorLayout, GlyphShape)>) -> [Option<u32>; 2] {
    let mut tops = [None, None];
    for (layout, shape) in layouts {
        if shape == GlyphShape::Polynomial && layout.symmetry == Symmetry::Symmetric {
            let top = &mut tops[(layout.order % 2) as usize];
            *top = Some(top.map_or(layout.order, |t: u32| t.max(layout.order)));
        }
    }
    tops
}

/// The order a symmetric polynomial layout may be raised to: the top of its parity, if
/// higher.
fn target_order(layout: TensorLayout, shape: GlyphShape, tops: [Option<u32>; 2]) -> Option<u32> {
    let eligible = shape == GlyphShape::Polynomial && layout.symmetry == Symmetry::Symmetric;
    tops[(layout.order % 2) as usize].filter(|&top| eligible && top > layout.order)
}

/// The ray-casting pipelines (layout, method, shape's shader) that drawing `scene` with `settings`
/// needs whatever its preparation finds: a one-shot render compiles these while the
/// glyphs are prepared, and the rest (layouts whose sets may be promoted) at upload, if
/// they are still needed. Empty for the mesh methods and the compute path, whose
/// pipelines are made elsewhere; for [`RenderPath::Auto`], the fragment path's (to be
/// made only where the device takes that path, [`RenderPath::on_device`]).
pub fn early_variants(scene: &Scene, settings: &RenderSettings) -> Vec<Variant> {
    if settings.path == RenderPath::Compute || matches!(settings.method, Method::Mesh(_)) {
        return Vec::new();
    }
    let sets: Vec<_> = scene
        .glyph_sets
        .iter()
        .filter(|set| !set.centers.is_empty())
        .map(|set| (tensor_layout(set), set.shape, set.len()))
        .collect();
    let tops = top_orders(sets.iter().map(|&(layout, shape, _)| (layout, shape)));
    let may_be_promoted = |layout: TensorLayout| {
        promotes(settings)
            && sets
                .iter()
                .filter(|&&(l, ..)| l == layout)
                .all(|&(l, shape, len)| {
                    len <= PROMOTABLE_GLYPHS && target_order(l, shape, tops).is_some()
                })
    };
    let mut variants: Vec<Variant> = Vec::new();
    for &(layout, shape, _) in &sets {
        // A method the set's shape refuses is refused when the glyphs are uploaded.
        let Ok(variant) = batch_variant(layout, shape, settings.method) else {
            continue;
        };
        if !may_be_promoted(layout) && !variants.contains(&variant) {
            variants.push(variant);
        }
    }
    variants
}

/// Raises the small symmetric sets of lower orders to the highest order of their parity
/// in `sets` (see the module's text), for a one-shot render with `settings` of the view
/// `camera`, `width` x `height`. A layout is raised only as a whole (when every set of
/// it qualifies, so that its pipeline is saved) and only for the default method on the
/// fragment path. Returns the number of sets raised.
pub fn promote_small_sets(
    sets: &mut [GlyphSetData],
    camera: &Camera,
    width: u32,
    height: u32,
    settings: &RenderSettings,
) -> usize {
    if !promotes(settings) {
        return 0;
    }
    let drawn = |set: &&GlyphSetData| !set.is_empty();
    let tops = top_orders(sets.iter().filter(drawn).map(|s| (s.layout, s.shape)));
    let mut layouts: Vec<TensorLayout> = Vec::new();
    for set in sets.iter().filter(drawn) {
        if !layouts.contains(&set.layout) {
            layouts.push(set.layout);
        }
    }
    let mut raised = 0;
    for layout in layouts {
        let group = || {
            sets.iter()
                .filter(drawn)
                .filter(move |s| s.layout == layout)
        };
        let targets: Vec<Option<u32>> = group()
            .map(|s| target_order(s.layout, s.shape, tops))
            .collect();
        let Some(Some(target)) = targets.first().copied() else {
            continue;
        };
        let qualifies = targets.iter().all(|t| *t == Some(target))
            && group().all(|s| s.len() <= PROMOTABLE_GLYPHS)
            && group()
                .map(|s| covered_pixels(s, camera, width, height))
                .sum::<f64>()
                * f64::from(settings.samples.max(1))
                <= PROMOTED_PIXELS;
        if !qualifies {
            continue;
        }
        for set in sets
            .iter_mut()
            .filter(|s| !s.is_empty() && s.layout == layout)
        {
            raise_set(set, target);
            raised += 1;
        }
    }
    raised
}

/// Draws `set` with the symmetric layout of order `target` (same parity, higher).
fn raise_set(set: &mut GlyphSetData, target: u32) {
    let order = set.layout.order;
    let k = (target - order) / 2;
    let count = set.layout.coefficient_count();
    let raised_layout = TensorLayout {
        order: target,
        symmetry: Symmetry::Symmetric,
    };
    let mut coefficients = Vec::with_capacity(set.len() * raised_layout.coefficient_count());
    for glyph in set.coefficients.chunks_exact(count) {
        let tensor: Vec<f64> = glyph.iter().map(|&c| f64::from(c)).collect();
        let raised = raised_symmetric_tensor(order, &tensor, k);
        coefficients.extend(raised.iter().map(|&c| c as f32));
    }
    set.coefficients = coefficients;
    set.layout = raised_layout;
}

/// The pixels that the bounding spheres of `set`'s glyphs cover on screen, at most the
/// image each (a sphere that reaches the eye's plane counts as the whole image).
fn covered_pixels(set: &GlyphSetData, camera: &Camera, width: u32, height: u32) -> f64 {
    let image = f64::from(width) * f64::from(height);
    let fwd = camera.frame().fwd;
    let pixels_per_unit = |depth: f64| match camera.projection {
        Projection::Perspective { fov_y_deg } => {
            0.5 * f64::from(height) / ((0.5 * fov_y_deg.to_radians()).tan() * depth)
        }
        Projection::Orthographic { height: extent } => f64::from(height) / extent,
    };
    set.instances
        .iter()
        .map(|&[x, y, z, r]| {
            let (center, radius) = (DVec3::new(x.into(), y.into(), z.into()), f64::from(r));
            let near = (center - camera.eye).dot(fwd) - radius;
            let perspective = matches!(camera.projection, Projection::Perspective { .. });
            if perspective && near <= 0.0 {
                return image;
            }
            let radius_px = radius * pixels_per_unit(if perspective { near } else { 1.0 });
            (std::f64::consts::PI * radius_px * radius_px).min(image)
        })
        .sum()
}
