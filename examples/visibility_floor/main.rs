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
//! Pixels are sampled every STEP pixels in x and y (default 2) and counts are scaled by
//! STEP squared.
use glyphcast::Scene;
use glyphcast::glam::{DQuat, DVec3, DVec4};
use glyphcast::glyph::intersect::first_hit;
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
    for (s, set) in sets.iter().enumerate() {
        for g in 0..set.len() {
            let [cx, cy, cz, radius] = set.instances[g].map(f64::from);
            let center = DVec3::new(cx, cy, cz);
            let b = set.boxes[g].map(f64::from);
            let rotation = DQuat::from_xyzw(b[0], b[1], b[2], b[3]).normalize();
            let to_box = rotation.inverse();
            let extent = DVec3::new(b[4], b[5], b[6]) * radius;
            let world = &set.world[g];
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
    let (mut covered, mut floor, mut kdop_floor) = (0u64, 0u64, 0u64);
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
    Ok(())
}
