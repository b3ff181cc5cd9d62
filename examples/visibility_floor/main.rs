//! The least work any culling of hidden glyphs can leave, for a scene file: how many glyph
//! evaluations (root isolations) per covered pixel a perfect front-to-back walk would
//! still make, on the CPU in float64.
//!
//! ```sh
//! cargo run --release --example visibility_floor -- SCENE.json [STEP]
//! ```
//!
//! Every glyph is drawn through its proxy, the oriented box of `prepare_scene` clipped to
//! the bounding sphere, as the fragment and compute paths draw it. A ray must evaluate a
//! glyph whose proxy it enters before its nearest hit: until the glyph has been evaluated
//! nothing says that the ray misses it. So the walk that takes each pixel's proxies in the
//! order of their entry along the ray and stops at the first proxy entered behind the
//! nearest hit found so far makes the fewest evaluations any exact culling can make
//! (`floor`); what the GPU makes is in `glyphcast bench`'s `evaluations` column. The hits
//! are the float64 reference's ([`glyphcast::glyph::intersect::first_hit`]).
//!
//! The same count with each proxy cut down to a 13-axis k-DOP (the box and its 10
//! diagonal slabs, in the box's frame) is printed as an estimate of what tighter proxies
//! would leave: its extents are taken from 6,000 sampled surface points, padded by 3 %,
//! not bounded as the boxes are, so this column is a measurement aid, not a renderer.
//!
//! A second line counts the same with each glyph cut into eight convex pieces with
//! guaranteed bounds ([`glyphcast::glyph::pieces`]: the octants of a frame turned to the
//! largest lobe, each cut by seven support planes): the fragments of the pieces' polytopes
//! and of their boxes, the evaluations of a ray caster that evaluates each piece it enters
//! while outside the glyph, and the floor with pieces; and how long bounding them took.
//!
//! Pixels are sampled every STEP pixels in x and y (default 2) and counts are scaled by
//! STEP squared.
use glyphcast::Scene;
use glyphcast::glam::{DQuat, DVec3, DVec4};
use glyphcast::glyph::intersect::first_hit;
use glyphcast::glyph::pieces::{
    GlyphPieces, PIECE_PLANES, PIECES, glyph_pieces, octant_signs, piece_directions,
};
use glyphcast::glyph::proxy::glyph_bounds;
use glyphcast::glyph::{GlyphShape, NegativeMode};
use glyphcast::prepare_scene;

/// One proxy a sampled pixel's ray enters.
struct Entry {
    /// Where the ray enters the box clipped to the sphere.
    box_entry: f64,
    /// Where it enters the k-DOP, or infinity when it misses it.
    kdop_entry: f64,
    set: usize,
    glyph: usize,
}

/// The ray's span in piece `piece` (glyph-local coordinates, the ray o + s d with unit d),
/// clipped to `span`: empty (start >= end) when it misses.
fn piece_span(
    pieces: &GlyphPieces,
    piece: usize,
    o: DVec3,
    d: DVec3,
    span: (f64, f64),
) -> (f64, f64) {
    let signs = octant_signs(piece);
    let to_frame = |v: DVec3| {
        DVec3::new(
            v.dot(pieces.axes[0]),
            v.dot(pieces.axes[1]),
            v.dot(pieces.axes[2]),
        ) * signs
    };
    let (of, df) = (to_frame(o), to_frame(d));
    let mut span = span;
    // Cone planes x_k >= 0, i.e. -x_k <= 0.
    for k in 0..3 {
        half_space(&mut span, -of[k], -df[k], 0.0);
    }
    for (n, h) in piece_directions().iter().zip(&pieces.supports[piece]) {
        half_space(&mut span, of.dot(*n), df.dot(*n), *h);
    }
    span
}

/// The ray's span within the piece's box [0, h0] x [0, h1] x [0, h2] (frame, reflected).
fn piece_box_span(
    pieces: &GlyphPieces,
    piece: usize,
    o: DVec3,
    d: DVec3,
    span: (f64, f64),
) -> (f64, f64) {
    let signs = octant_signs(piece);
    let to_frame = |v: DVec3| {
        DVec3::new(
            v.dot(pieces.axes[0]),
            v.dot(pieces.axes[1]),
            v.dot(pieces.axes[2]),
        ) * signs
    };
    let (of, df) = (to_frame(o), to_frame(d));
    let mut span = span;
    for k in 0..3 {
        half_space(&mut span, -of[k], -df[k], 0.0);
        half_space(&mut span, of[k], df[k], pieces.supports[piece][k]);
    }
    span
}

/// Clips `span` to the half-space a + s b <= h.
fn half_space(span: &mut (f64, f64), a: f64, b: f64, h: f64) {
    if b.abs() < 1e-300 {
        if a > h {
            *span = (1.0, 0.0);
        }
        return;
    }
    let s = (h - a) / b;
    if b > 0.0 {
        span.1 = span.1.min(s);
    } else {
        span.0 = span.0.max(s);
    }
}

/// Ray parameters [t0, t1] inside the slab |(o + t d) . a| <= e, intersected into `span`.
fn clip_slab(span: &mut (f64, f64), o: DVec3, d: DVec3, a: DVec3, e: f64) {
    let (oa, da) = (o.dot(a), d.dot(a));
    let (p, q) = ((-e - oa) / da, (e - oa) / da);
    span.0 = span.0.max(p.min(q));
    span.1 = span.1.min(p.max(q));
}

fn diagonal_axes() -> [DVec3; 10] {
    let s2 = 0.5f64.sqrt();
    let s3 = (1.0f64 / 3.0).sqrt();
    [
        DVec3::new(s2, s2, 0.0),
        DVec3::new(s2, -s2, 0.0),
        DVec3::new(s2, 0.0, s2),
        DVec3::new(s2, 0.0, -s2),
        DVec3::new(0.0, s2, s2),
        DVec3::new(0.0, s2, -s2),
        DVec3::new(s3, s3, s3),
        DVec3::new(s3, s3, -s3),
        DVec3::new(s3, -s3, s3),
        DVec3::new(-s3, s3, s3),
    ]
}

fn sphere_directions(count: usize) -> Vec<DVec3> {
    let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
    (0..count)
        .map(|k| {
            let z = 1.0 - (k as f64 + 0.5) * 2.0 / count as f64;
            let r = (1.0 - z * z).sqrt();
            let phi = k as f64 * golden;
            DVec3::new(r * phi.cos(), r * phi.sin(), z)
        })
        .collect()
}

fn main() -> Result<(), String> {
    let mut args = std::env::args().skip(1);
    let path = args
        .next()
        .ok_or("usage: visibility_floor SCENE.json [STEP]")?;
    let step: u32 = match args.next() {
        Some(s) => s
            .parse()
            .ok()
            .filter(|&s| s > 0)
            .ok_or(format!("STEP: expected a positive integer, got {s}"))?,
        None => 2,
    };
    let text = std::fs::read_to_string(&path).map_err(|e| format!("{path}: {e}"))?;
    let scene = Scene::from_json_str(&text, &path).map_err(|e| e.to_string())?;
    let sets = prepare_scene(&scene, 0.0).map_err(|e| e.to_string())?;
    let (width, height) = (scene.image.width, scene.image.height);
    let camera = &scene.camera;
    let view_proj = camera.view_projection(width, height, 1e-3, 1e6);
    let axes = diagonal_axes();
    let directions = sphere_directions(6000);
    let columns = width.div_ceil(step);
    let rows = height.div_ceil(step);
    let mut lists: Vec<Vec<Entry>> = (0..columns * rows).map(|_| Vec::new()).collect();
    let mut proxy_fragments = 0u64;
    // Pieces: fragments of the polytopes and of their boxes; per pixel the world entry
    // distances of the pieces a ray enters while outside its glyph.
    let (mut piece_fragments, mut piece_box_fragments, mut piece_casts) = (0u64, 0u64, 0u64);
    let mut piece_lists: Vec<Vec<f64>> = (0..columns * rows).map(|_| Vec::new()).collect();
    let mut bound_time = std::time::Duration::ZERO;
    for (s, set) in sets.iter().enumerate() {
        for g in 0..set.len() {
            let [cx, cy, cz, radius] = set.instances[g].map(f64::from);
            let center = DVec3::new(cx, cy, cz);
            let b = set.boxes[g].map(f64::from);
            let rotation = DQuat::from_xyzw(b[0], b[1], b[2], b[3]).normalize();
            let to_box = rotation.inverse();
            let extent = DVec3::new(b[4], b[5], b[6]) * radius;
            let world = &set.world[g];
            let started = std::time::Instant::now();
            let pieces = (world.shape == GlyphShape::Polynomial && world.offset == 0.0)
                .then(|| glyph_bounds(&world.poly))
                .flatten()
                .and_then(|b| glyph_pieces(&world.poly, world.negative, &b));
            bound_time += started.elapsed();
            // The sampled surface points in the box's frame, once for the ten slabs.
            let surface: Vec<DVec3> = directions
                .iter()
                .map(|&u| to_box * u * world.poly.eval(u).abs())
                .collect();
            let kdop: Vec<f64> = axes
                .iter()
                .map(|&a| {
                    surface.iter().map(|p| p.dot(a).abs()).fold(0.0, f64::max) * world.scale * 1.03
                })
                .collect();
            // The box's pixels: the bounding rectangle of its projected corners.
            let (mut x0, mut y0, mut x1, mut y1) = (f64::MAX, f64::MAX, f64::MIN, f64::MIN);
            for k in 0..8 {
                let sign = |bit: i32| if k & bit == 0 { -1.0 } else { 1.0 };
                let corner = center + rotation * (DVec3::new(sign(1), sign(2), sign(4)) * extent);
                let clip: DVec4 = view_proj * corner.extend(1.0);
                if clip.w <= 0.0 {
                    (x0, y0, x1, y1) = (0.0, 0.0, width as f64, height as f64);
                    break;
                }
                let x = (clip.x / clip.w * 0.5 + 0.5) * width as f64;
                let y = (clip.y / clip.w * 0.5 + 0.5) * height as f64;
                (x0, y0, x1, y1) = (x0.min(x), y0.min(y), x1.max(x), y1.max(y));
            }
            let first = |v: f64| (v.floor().max(0.0) as u32).div_ceil(step);
            let last = |v: f64, n: u32| ((v.ceil().max(0.0) as u32).min(n - 1)) / step;
            for row in first(y0)..=last(y1, height) {
                for column in first(x0)..=last(x1, width) {
                    let (i, j) = (column * step, row * step);
                    if i >= width || j >= height {
                        continue;
                    }
                    let ray = camera.ray(i, j, width, height);
                    let o = to_box * (ray.origin - center);
                    let d = to_box * ray.dir;
                    let mut span = (0.0f64, f64::INFINITY);
                    for (k, e) in extent.to_array().into_iter().enumerate() {
                        clip_slab(&mut span, o, d, DVec3::AXES[k], e);
                    }
                    // The sphere's chord.
                    let mid = -o.dot(d);
                    let miss2 = (o + mid * d).length_squared();
                    if miss2 >= radius * radius {
                        continue;
                    }
                    let half = (radius * radius - miss2).sqrt();
                    span = (span.0.max(mid - half), span.1.min(mid + half));
                    if span.0 >= span.1 {
                        continue;
                    }
                    proxy_fragments += 1;
                    if let Some(pieces) = &pieces {
                        // Glyph-local ray: o_l + s d, s in local units (world = scale s).
                        let o_local = (ray.origin - center) / world.scale;
                        let d_world = ray.dir;
                        let sphere = {
                            let mid = -o_local.dot(d_world);
                            let miss2 = (o_local + mid * d_world).length_squared();
                            let half = (world.bound * world.bound - miss2).max(0.0).sqrt();
                            ((mid - half).max(0.0), mid + half)
                        };
                        for piece in 0..PIECES {
                            if pieces.supports[piece] == [0.0; PIECE_PLANES] {
                                continue;
                            }
                            let b = piece_box_span(pieces, piece, o_local, d_world, sphere);
                            if b.0 < b.1 {
                                piece_box_fragments += 1;
                            }
                            let p = piece_span(pieces, piece, o_local, d_world, sphere);
                            if p.0 >= p.1 {
                                continue;
                            }
                            piece_fragments += 1;
                            let q = o_local + p.0 * d_world;
                            let len = q.length();
                            let f = if len > 0.0 {
                                world.poly.eval(q / len)
                            } else {
                                1.0
                            };
                            let r = match world.negative {
                                NegativeMode::Abs => f.abs(),
                                NegativeMode::Hide => f.max(0.0),
                            };
                            if len >= r {
                                piece_casts += 1;
                                piece_lists[(row * columns + column) as usize]
                                    .push(p.0 * world.scale);
                            }
                        }
                    }
                    let mut cut = span;
                    for (&a, &e) in axes.iter().zip(&kdop) {
                        clip_slab(&mut cut, o, d, a, e);
                    }
                    lists[(row * columns + column) as usize].push(Entry {
                        box_entry: span.0,
                        kdop_entry: if cut.0 < cut.1 { cut.0 } else { f64::INFINITY },
                        set: s,
                        glyph: g,
                    });
                }
            }
        }
    }
    let (mut covered, mut floor, mut kdop_floor, mut piece_floor) = (0u64, 0u64, 0u64, 0u64);
    for (p, list) in lists.iter_mut().enumerate() {
        list.sort_by(|a, b| a.box_entry.total_cmp(&b.box_entry));
        let ray = camera.ray(
            (p as u32 % columns) * step,
            (p as u32 / columns) * step,
            width,
            height,
        );
        let mut nearest = f64::INFINITY;
        for e in list.iter() {
            if e.box_entry > nearest {
                break;
            }
            floor += 1;
            let hit = first_hit(&ray, &sets[e.set].world[e.glyph]).unwrap_or(f64::INFINITY);
            nearest = nearest.min(hit);
        }
        if nearest.is_finite() {
            covered += 1;
        }
        // Through k-DOPs: the proxies entered before the same nearest hit (a proxy the
        // walk above did not reach is entered behind it, as a k-DOP lies inside its box).
        kdop_floor += list
            .iter()
            .filter(|e| e.kdop_entry.is_finite() && e.kdop_entry <= nearest)
            .count() as u64;
        piece_floor += piece_lists[p].iter().filter(|&&t| t <= nearest).count() as u64;
    }
    let scale = u64::from(step * step);
    let per = |n: u64| n as f64 / covered.max(1) as f64;
    println!(
        "{path}: covered pixels {}, proxy fragments/px {:.2}, floor evaluations/px {:.2}, \
         with 13-axis k-DOPs (sampled estimate) {:.2}",
        covered * scale,
        per(proxy_fragments),
        per(floor),
        per(kdop_floor)
    );
    let glyphs: usize = sets.iter().map(|s| s.len()).sum();
    println!(
        "pieces: polytope fragments/px {:.2}, piece-box fragments/px {:.2}, casts/px {:.2}, \
         floor evaluations/px {:.2}; bounds {:.0} us a glyph",
        per(piece_fragments),
        per(piece_box_fragments),
        per(piece_casts),
        per(piece_floor),
        bound_time.as_secs_f64() * 1e6 / glyphs.max(1) as f64
    );
    Ok(())
}
