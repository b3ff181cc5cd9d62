//! Built-in scenes: the demo that `glyphcast demo` renders, fibre-like glyphs that
//! tests and benchmarks build on, and stiffness-tensor scenes (`glyphcast demo
//! --stiffness`, `glyphcast stiffness`).
//!
//! A fibre population with unit directions d_i and weights w_i gives the symmetric tensor
//! T = sum_i w_i d_i (x) ... (x) d_i, whose glyph function is f(u) = sum_i w_i (u . d_i)^n:
//! even orders give crossing lobes that sharpen as n grows and that touch the centre
//! wherever u is orthogonal to every d_i.
use crate::camera::{Camera, Projection};
use crate::glyph::bounds::bounding_radius;
use crate::glyph::monomials::monomials;
use crate::glyph::polynomial::GlyphPolynomial;
use crate::glyph::stiffness::VoigtStiffness;
use crate::glyph::{GlyphShape, NegativeMode, Symmetry, TensorLayout};
use crate::scene::{GlyphKind, GlyphSet, ImageSize, Scene};
use crate::{Error, Result};
use glam::{DMat3, DVec3};

/// Unique coefficients (scene order) of sum_i w_i d_i^(x)n.
pub fn fibre_tensor(order: u32, fibres: &[(DVec3, f64)]) -> Vec<f64> {
    monomials(order)
        .iter()
        .map(|m| {
            fibres
                .iter()
                .map(|(d, w)| {
                    let d = d.normalize();
                    w * d.x.powi(m.a as i32) * d.y.powi(m.b as i32) * d.z.powi(m.c as i32)
                })
                .sum()
        })
        .collect()
}

/// A direction in the xy-plane at `deg` degrees from x, tilted `elev` degrees towards z.
pub fn direction(deg: f64, elev: f64) -> DVec3 {
    let (a, e) = (deg.to_radians(), elev.to_radians());
    DVec3::new(a.cos() * e.cos(), a.sin() * e.cos(), e.sin())
}

/// The kind of fully symmetric tensor glyphs of the given order.
pub fn symmetric(order: u32) -> GlyphKind {
    GlyphKind::Tensor(TensorLayout {
        order,
        symmetry: Symmetry::Symmetric,
    })
}

/// A glyph set of one kind at the given centres, one scale for all.
pub fn glyph_set(
    kind: GlyphKind,
    centers: Vec<DVec3>,
    scale: f64,
    coeffs: Vec<Vec<f64>>,
) -> GlyphSet {
    GlyphSet {
        kind,
        negative: NegativeMode::Abs,
        shape: GlyphShape::Polynomial,
        scales: vec![scale; centers.len()],
        centers,
        coeffs,
    }
}

/// The demo: a 6 x 4 field of fibre glyphs of orders 4, 6 and 8 with one, two and three
/// crossing populations that turn across the field, seen from above at an angle.
pub fn demo_scene() -> Scene {
    let mut sets = Vec::new();
    for (row, order) in [4u32, 6, 8, 8].into_iter().enumerate() {
        let mut centers = Vec::new();
        let mut coeffs = Vec::new();
        for col in 0..6 {
            let turn = 15.0 * col as f64;
            let fibres: Vec<(DVec3, f64)> = match row {
                0 => vec![(direction(turn, 10.0), 1.0)],
                1 => vec![
                    (direction(turn, 0.0), 1.0),
                    (direction(turn + 70.0, 20.0), 0.8),
                ],
                2 => vec![
                    (direction(turn, 0.0), 1.0),
                    (direction(turn + 90.0, 0.0), 0.9),
                ],
                _ => vec![
                    (direction(turn, 0.0), 1.0),
                    (direction(turn + 60.0, 0.0), 0.9),
                    (direction(turn + 120.0, 35.0), 0.8),
                ],
            };
            centers.push(DVec3::new(col as f64 - 2.5, row as f64 - 1.5, 0.0));
            coeffs.push(fibre_tensor(order, &fibres));
        }
        sets.push(glyph_set(symmetric(order), centers, 0.48, coeffs));
    }
    let mut scene = Scene {
        glyph_sets: sets,
        camera: Camera {
            projection: Projection::Perspective { fov_y_deg: 30.0 },
            eye: DVec3::new(0.0, -7.4, 6.4),
            target: DVec3::new(0.0, 0.0, 0.0),
            up: DVec3::Z,
        },
        image: ImageSize {
            width: 800,
            height: 600,
        },
    };
    frame_glyphs(&mut scene, 800, 600);
    scene
}

/// The share of the image's limiting side (half of it, on each side) that
/// [`frame_glyphs`] leaves free around the glyphs.
pub const FRAME_MARGIN: f64 = 0.06;

/// Points of every glyph's surface, centre + scale h(f(u)) u over a Fibonacci lattice of
/// directions u (h = |f|, or f where it is positive with negative lobes hidden); a
/// spherical-harmonic glyph counts as the sphere of its scale.
fn surface_points(scene: &Scene) -> Vec<DVec3> {
    const DIRECTIONS: usize = 4096;
    let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
    let directions: Vec<DVec3> = (0..DIRECTIONS)
        .map(|i| {
            let z = 1.0 - (2.0 * i as f64 + 1.0) / DIRECTIONS as f64;
            let r = (1.0 - z * z).sqrt();
            let phi = golden * i as f64;
            DVec3::new(r * phi.cos(), r * phi.sin(), z)
        })
        .collect();
    let mut points = Vec::new();
    for set in &scene.glyph_sets {
        for (i, center) in set.centers.iter().enumerate() {
            let scale = set.scales.get(i).copied().unwrap_or(1.0);
            let poly = match set.kind {
                GlyphKind::Tensor(layout) => {
                    GlyphPolynomial::from_tensor(layout, &set.coeffs[i]).ok()
                }
                GlyphKind::Sh { .. } => None,
            };
            for &u in &directions {
                let radius = match &poly {
                    Some(poly) => match set.negative {
                        NegativeMode::Abs => poly.eval(u).abs(),
                        NegativeMode::Hide => poly.eval(u).max(0.0),
                    },
                    None => 1.0,
                };
                points.push(*center + scale * radius * u);
            }
        }
    }
    points
}

/// Frames the glyphs of `scene` for a `width` x `height` image: the camera keeps its
/// direction, up and projection and moves (its eye sideways and along the view; the
/// orthographic height) until the glyphs' surfaces fill the image's limiting side but
/// for [`FRAME_MARGIN`] on each side, centred in both directions. The built-in scenes
/// are framed so at their own size; `glyphcast demo` frames them again at the size asked
/// for, so that no aspect ratio clips a glyph.
pub fn frame_glyphs(scene: &mut Scene, width: u32, height: u32) {
    let points = surface_points(scene);
    if points.is_empty() || width == 0 || height == 0 {
        return;
    }
    let aspect = f64::from(width) / f64::from(height);
    let frame = scene.camera.frame();
    let (fwd, right, up) = (frame.fwd, frame.right, frame.up);
    let centroid = points.iter().copied().sum::<DVec3>() / points.len() as f64;
    let reach = points
        .iter()
        .map(|p| (*p - centroid).length())
        .fold(0.0, f64::max)
        .max(1e-9);
    // The extents of the points on the screen, in the units of the half image height
    // (perspective: tangents over the half field of view's; orthographic: world units
    // over the half height), about the screen's centre.
    let extents = |eye: DVec3, unit: f64, perspective: bool| {
        let (mut x0, mut x1, mut y0, mut y1) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
        for p in &points {
            let v = *p - eye;
            let depth = if perspective { fwd.dot(v) } else { 1.0 };
            let (x, y) = (right.dot(v) / depth / unit, up.dot(v) / depth / unit);
            (x0, x1, y0, y1) = (x0.min(x), x1.max(x), y0.min(y), y1.max(y));
        }
        (0.5 * (x0 + x1), 0.5 * (y0 + y1), 0.5 * (x1 - x0), 0.5 * (y1 - y0))
    };
    let fill = |half_x: f64, half_y: f64| (half_x / aspect).max(half_y) / (1.0 - FRAME_MARGIN);
    match &mut scene.camera.projection {
        Projection::Perspective { fov_y_deg } => {
            let k = (fov_y_deg.to_radians() * 0.5).tan();
            // Start far enough back that every point is in front of the eye.
            let mut eye = centroid - fwd * (reach / k * 2.0 + 2.0 * reach);
            for _ in 0..200 {
                let (mid_x, mid_y, half_x, half_y) = extents(eye, k, true);
                let distance = fwd.dot(centroid - eye);
                // Sideways by the offset of the middle, then along the view by how much
                // too large or small the glyphs are (never past their nearest point).
                eye += (right * mid_x + up * mid_y) * k * distance;
                let ratio = fill(half_x, half_y).clamp(0.5, 2.0);
                let nearest = points.iter().map(|p| fwd.dot(*p - eye)).fold(f64::MAX, f64::min);
                let step = (distance * (1.0 - ratio)).min(0.5 * nearest);
                eye += fwd * step;
                if mid_x.abs() < 1e-9 && mid_y.abs() < 1e-9 && (ratio - 1.0).abs() < 1e-9 {
                    break;
                }
            }
            scene.camera.eye = eye;
            scene.camera.target = eye + fwd * fwd.dot(centroid - eye);
        }
        Projection::Orthographic { height } => {
            let eye = scene.camera.eye;
            let (mid_x, mid_y, half_x, half_y) = extents(eye, 1.0, false);
            let eye = eye + right * mid_x + up * mid_y;
            *height = 2.0 * fill(half_x, half_y);
            scene.camera.eye = eye;
            scene.camera.target = eye + fwd * fwd.dot(centroid - eye).abs().max(reach);
        }
    }
}

/// Cubic copper, GPa: C11, C12, C44.
pub(crate) const COPPER_GPA: (f64, f64, f64) = (168.4, 121.4, 75.4);

/// Stiffness glyphs are scaled so that their largest radius is this fraction of the
/// grid spacing.
const STIFFNESS_GLYPH_SIZE: f64 = 0.45;

/// The `--stiffness` demo: a 5 x 5 field of copper crystals as non-symmetric order-4
/// glyphs (all 81 C_ijkl). Orientations are graded: along x the crystal turns about z by
/// 0 to 45 degrees (a quarter of the cubic period of 90), along y it tilts about x by 0
/// to 54.7 degrees (the angle between \[001\] and \[111\]), so the corner glyphs show the
/// cube axes, a <110> and a <111> direction facing up.
pub fn stiffness_demo_scene() -> Scene {
    let (c11, c12, c44) = COPPER_GPA;
    let copper = VoigtStiffness::cubic(c11, c12, c44);
    let largest = max_radius(4, Symmetry::NonSymmetric, &copper.full_tensor()).unwrap_or(1.0);
    let tilt_max = (2f64.sqrt()).atan();
    let mut centers = Vec::new();
    let mut coeffs = Vec::new();
    for row in 0..5 {
        for col in 0..5 {
            let turn = std::f64::consts::FRAC_PI_4 * col as f64 / 4.0;
            let tilt = tilt_max * row as f64 / 4.0;
            let rotation = DMat3::from_rotation_z(turn) * DMat3::from_rotation_x(tilt);
            centers.push(DVec3::new(col as f64 - 2.0, row as f64 - 2.0, 0.0));
            coeffs.push(copper.rotated(rotation));
        }
    }
    let kind = GlyphKind::Tensor(TensorLayout {
        order: 4,
        symmetry: Symmetry::NonSymmetric,
    });
    let mut scene = Scene {
        glyph_sets: vec![glyph_set(
            kind,
            centers,
            STIFFNESS_GLYPH_SIZE / largest,
            coeffs,
        )],
        camera: Camera {
            projection: Projection::Perspective { fov_y_deg: 30.0 },
            eye: DVec3::new(0.0, -7.6, 7.4),
            target: DVec3::new(0.0, 0.2, 0.0),
            up: DVec3::Z,
        },
        image: ImageSize {
            width: 800,
            height: 680,
        },
    };
    frame_glyphs(&mut scene, 800, 680);
    scene
}

/// One stiffness glyph at the origin, scaled to radius 1 at its largest, as all 81
/// entries (non-symmetric order 4) or as the 15 of its fully symmetric part.
pub fn stiffness_scene(stiffness: &VoigtStiffness, symmetric_part: bool) -> Result<Scene> {
    stiffness_row_scene(std::slice::from_ref(stiffness), symmetric_part)
}

/// One stiffness glyph a material in a row along x, 2.4 apart and centred on the origin
/// (one material: at the origin), all on one scale: the largest glyph has radius 1, so
/// the glyphs compare in size as the materials compare in stiffness.
pub fn stiffness_row_scene(materials: &[VoigtStiffness], symmetric_part: bool) -> Result<Scene> {
    let symmetry = if symmetric_part {
        Symmetry::Symmetric
    } else {
        Symmetry::NonSymmetric
    };
    let glyphs = materials
        .iter()
        .map(|m| {
            let coeffs = if symmetric_part {
                m.symmetric_part()
            } else {
                m.full_tensor()
            };
            Ok(RowGlyph {
                largest_radius: max_radius(4, symmetry, &coeffs)?,
                layout: TensorLayout { order: 4, symmetry },
                shape: GlyphShape::Polynomial,
                coeffs,
            })
        })
        .collect::<Result<Vec<_>>>()?;
    material_row_scene(&glyphs)
}

/// One material's glyph in a row of materials: the tensor, the surface drawn of it, and
/// its largest radius in the material's units (what puts the row on one scale).
#[derive(Clone, Debug, PartialEq)]
pub struct RowGlyph {
    /// The tensor layout of `coeffs`.
    pub layout: TensorLayout,
    /// [`GlyphShape::Polynomial`] (r = |f|), [`GlyphShape::Reciprocal`] (r = 1/|f|), a
    /// plane shape (r = 1/λ, [`RowGlyph::of_plane`]) or a ratio shape (r = |λ/Q|,
    /// [`RowGlyph::of_ratio`]).
    pub shape: GlyphShape,
    /// The coefficients, in the scene order of `layout` (a plane glyph's T's after them,
    /// a ratio glyph's T's and Q's).
    pub coeffs: Vec<f64>,
    /// The glyph's largest radius (at least its true maximum; it is drawn as
    /// radius/largest of the row's largest).
    pub largest_radius: f64,
}

impl RowGlyph {
    /// The glyph of the form of a full order-n tensor (3^n entries, row-major), r = |f|
    /// or, `reciprocal`, r = 1/|f|; drawn by its fully symmetric part (the same form on
    /// unit vectors, in (n+1)(n+2)/2 coefficients). A reciprocal glyph whose f may vanish
    /// on the sphere (unbounded) is an error carrying the guaranteed least |f|.
    pub fn of_form(
        order: u32,
        full: &[f64],
        reciprocal: bool,
        largest_radius: f64,
    ) -> Result<Self> {
        let layout = TensorLayout {
            order,
            symmetry: Symmetry::Symmetric,
        };
        let coeffs = crate::glyph::stiffness::fully_symmetric_part(order, full);
        let shape = if reciprocal {
            let poly = GlyphPolynomial::from_tensor(layout, &coeffs)?;
            let least = crate::glyph::bounds::least_abs(&poly).map_or(0.0, |l| l.lower);
            // NaN (no bound) is refused too.
            if least.is_nan() || least <= 0.0 {
                return Err(Error::data(
                    "guaranteed least |f| over the sphere (the surface r = 1/|f| is unbounded \
                     where f vanishes)",
                    crate::error::Problem::NotPositive { value: least },
                ));
            }
            GlyphShape::Reciprocal
        } else {
            GlyphShape::Polynomial
        };
        Ok(RowGlyph {
            layout,
            shape,
            coeffs,
            largest_radius,
        })
    }

    /// The plane glyph r = 1/λ, λ² − T λ + D = 0, of two full tensors (row-major): D of
    /// order 6 and T of order 4, with the larger root (`larger_root`, shape `plane-min`)
    /// or the smaller (`plane-max`); drawn by their fully symmetric parts. Roots that may
    /// vanish or not be positive somewhere (the surface is unbounded) are an error.
    pub fn of_plane(
        determinant: &[f64],
        trace: &[f64],
        larger_root: bool,
        largest_radius: f64,
    ) -> Result<Self> {
        use crate::glyph::{PLANE_LAYOUT, PLANE_TRACE_LAYOUT};
        let d = crate::glyph::stiffness::fully_symmetric_part(PLANE_LAYOUT.order, determinant);
        let t = crate::glyph::stiffness::fully_symmetric_part(PLANE_TRACE_LAYOUT.order, trace);
        let d_poly = GlyphPolynomial::from_tensor(PLANE_LAYOUT, &d)?;
        let t_poly = GlyphPolynomial::from_tensor(PLANE_TRACE_LAYOUT, &t)?;
        if crate::glyph::intersect::plane_bound(&d_poly, &t_poly).is_none() {
            let least = crate::glyph::bounds::least_abs(&d_poly).map_or(0.0, |l| l.lower);
            return Err(Error::data(
                "guaranteed least D over the sphere, with D and T positive (the surface \
                 r = 1/λ needs two positive roots λ in every direction)",
                crate::error::Problem::NotPositive { value: least },
            ));
        }
        Ok(RowGlyph {
            layout: PLANE_LAYOUT,
            shape: if larger_root {
                GlyphShape::PlaneMin
            } else {
                GlyphShape::PlaneMax
            },
            coeffs: d.into_iter().chain(t).collect(),
            largest_radius,
        })
    }

    /// The ratio glyph r = |λ/Q|, λ² − T λ + D = 0, of three full tensors (row-major): D
    /// of order 6, T and Q of order 4, with the smaller root (`smaller_root`, shape
    /// `ratio-min`) or the larger (`ratio-max`); drawn by their fully symmetric parts. A Q
    /// that may vanish or is not positive somewhere (the surface is unbounded) is an
    /// error.
    pub fn of_ratio(
        [determinant, trace, denominator]: [&[f64]; 3],
        smaller_root: bool,
        largest_radius: f64,
    ) -> Result<Self> {
        use crate::glyph::{PLANE_LAYOUT, PLANE_TRACE_LAYOUT};
        let symmetric = crate::glyph::stiffness::fully_symmetric_part;
        let d = symmetric(PLANE_LAYOUT.order, determinant);
        let t = symmetric(PLANE_TRACE_LAYOUT.order, trace);
        let q = symmetric(PLANE_TRACE_LAYOUT.order, denominator);
        let d_poly = GlyphPolynomial::from_tensor(PLANE_LAYOUT, &d)?;
        let t_poly = GlyphPolynomial::from_tensor(PLANE_TRACE_LAYOUT, &t)?;
        let q_poly = GlyphPolynomial::from_tensor(PLANE_TRACE_LAYOUT, &q)?;
        if crate::glyph::intersect::ratio_bound(&d_poly, &t_poly, &q_poly).is_none() {
            let least = crate::glyph::bounds::least_abs(&q_poly).map_or(0.0, |l| l.lower);
            return Err(Error::data(
                "guaranteed least Q over the sphere (the surface r = |λ/Q| is unbounded \
                 where Q vanishes)",
                crate::error::Problem::NotPositive { value: least },
            ));
        }
        Ok(RowGlyph {
            layout: PLANE_LAYOUT,
            shape: if smaller_root {
                GlyphShape::RatioMin
            } else {
                GlyphShape::RatioMax
            },
            coeffs: d.into_iter().chain(t).chain(q).collect(),
            largest_radius,
        })
    }
}

/// Materials' glyphs in a row along x, 2.4 apart and centred on the origin (one
/// material: at the origin), all on one scale: the largest radius of the row is 1, so
/// the glyphs compare in size as the materials' moduli do (world length 1 is
/// 1 / scale of the moduli's units: [`Scene`]'s set scale). Glyphs of one layout and
/// shape share a set. An error for a row whose largest radius is not positive and finite.
pub fn material_row_scene(glyphs: &[RowGlyph]) -> Result<Scene> {
    let largest = glyphs.iter().map(|g| g.largest_radius).fold(0.0, f64::max);
    if !(largest > 0.0 && largest.is_finite()) {
        return Err(Error::data(
            "largest radius of the materials' glyphs (there is no glyph to draw)",
            crate::error::Problem::NotPositive { value: largest },
        ));
    }
    let count = glyphs.len();
    let center = |k: usize| DVec3::new(2.4 * (k as f64 - (count as f64 - 1.0) / 2.0), 0.0, 0.0);
    let mut sets: Vec<GlyphSet> = Vec::new();
    for (k, glyph) in glyphs.iter().enumerate() {
        let kind = GlyphKind::Tensor(glyph.layout);
        match sets
            .iter_mut()
            .find(|s| s.kind == kind && s.shape == glyph.shape)
        {
            Some(set) => {
                set.centers.push(center(k));
                set.scales.push(1.0 / largest);
                set.coeffs.push(glyph.coeffs.clone());
            }
            None => {
                let mut set = glyph_set(
                    kind,
                    vec![center(k)],
                    1.0 / largest,
                    vec![glyph.coeffs.clone()],
                );
                set.shape = glyph.shape;
                sets.push(set);
            }
        }
    }
    // One material: seen from the side and above; a row: from the front and above,
    // backed off so that the whole row fits.
    let eye = if count == 1 {
        DVec3::new(2.4, -3.6, 2.2)
    } else {
        DVec3::new(0.0, -4.4, 2.2) * (1.0 + 0.55 * (count as f64 - 1.0))
    };
    Ok(Scene {
        glyph_sets: sets,
        camera: Camera {
            projection: Projection::Perspective { fov_y_deg: 30.0 },
            eye,
            target: DVec3::ZERO,
            up: DVec3::Z,
        },
        image: ImageSize::default(),
    })
}

/// A guaranteed bound of max |f(u)| over unit u; an error for a zero tensor, which has
/// no glyph to draw.
fn max_radius(order: u32, symmetry: Symmetry, coeffs: &[f64]) -> Result<f64> {
    let poly = GlyphPolynomial::from_tensor(TensorLayout { order, symmetry }, coeffs)?;
    let radius = bounding_radius(&poly, NegativeMode::Abs);
    if radius > 0.0 {
        Ok(radius)
    } else {
        Err(Error::data(
            "stiffness tensor (there is no glyph to draw)",
            crate::error::Problem::AllZero,
        ))
    }
}
