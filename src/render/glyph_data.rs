//! Scene glyph sets turned into what the passes and the reference consume: per glyph a
//! bounding radius B and an oriented box (guaranteed bounds of r(u), computed once on the
//! CPU by `glyph_bounds_with` in microseconds, with the sampled bound for sets of up to
//! `SAMPLED_BOUNDS_GLYPHS`), coefficients divided by B (so every glyph's
//! bound is 1 in its normalised frame, and the shader's numbers stay near 1 whatever the
//! data's units), one 16-byte instance (centre, world radius of the bounding sphere) and
//! one 32-byte box (rotation, half extents). The float64 [`WorldGlyph`]s describe the
//! same surfaces for the reference.
use crate::error::Problem;
use crate::glyph::bounds::{climbed_max_radius, least_abs, sizing_lattice};
use crate::glyph::ellipsoid::Ellipsoid;
use crate::glyph::intersect::{WorldGlyph, climbed_max};
use crate::glyph::pieces::{PIECE_WORDS, glyph_pieces, polytope_piece_words};
use crate::glyph::polynomial::GlyphPolynomial;
use crate::glyph::proxy::{GlyphBounds, Sampling, glyph_bounds_with};
use crate::glyph::sh::sh_to_tensor;
use crate::glyph::{GlyphShape, NegativeMode, Symmetry, TensorLayout};
use crate::parallel::{Progress, map_chunks};
use crate::scene::{GlyphKind, GlyphSet, MAX_SCENE_MAGNITUDE, Scene, fits_float32};
use crate::{Error, Result, Setting};
use std::borrow::Cow;

/// One glyph set, ready for upload.
#[derive(Clone, Debug)]
pub struct GlyphSetData {
    /// The tensor layout of `coefficients` (an SH set's is its symmetric tensor's).
    pub layout: TensorLayout,
    /// How negative values of f are drawn.
    pub negative: NegativeMode,
    /// The polynomial glyph, or the ellipsoid, whose `coefficients` are then those of its
    /// quadric form ([`Ellipsoid::quadric`] in units of B): x^T A x = 1 on the surface.
    pub shape: GlyphShape,
    /// Per drawn glyph: centre xyz and the world radius of its bounding sphere,
    /// scale * B * (1 + offset) (the half-size of the cube around it).
    pub instances: Vec<[f32; 4]>,
    /// Per drawn glyph: its oriented box, the unit quaternion (x, y, z, w) from the box's
    /// frame to the world's, then the half extents along the box axes in units of the
    /// sphere radius (each at most 1; w unused). The ray-casting pass draws this box.
    pub boxes: Vec<[f32; 8]>,
    /// Per drawn glyph: its extents along the box frame's ten diagonals
    /// ([`crate::glyph::proxy::diagonal_directions`]) in units of the sphere radius, as
    /// the box's (the last two unused): with the box, a 26-sided polytope around the
    /// glyph, whose outline on the screen the ray-casting pass draws.
    pub hulls: Vec<[f32; 12]>,
    /// Per drawn glyph: its eight pieces as the GPU reads them (`--proxy pieces`), made
    /// by [`add_pieces`]; empty until then (the GPU then cuts each glyph's 26-sided
    /// polytope into octants instead).
    pub pieces: Vec<[u32; PIECE_WORDS]>,
    /// Per drawn glyph: the tensor's coefficients divided by B, `layout.coefficient_count()` each.
    pub coefficients: Vec<f32>,
    /// The same glyphs in float64, for the reference.
    pub world: Vec<WorldGlyph>,
    /// World radius of the set's largest glyph as drawn, offset included (0 for an empty
    /// set): the top of `--color magnitude`'s default range ([`largest_radius`]); 0 until
    /// [`measure_largest_radius`] measured it.
    pub largest_radius: f64,
}

impl GlyphSetData {
    /// Number of drawn glyphs.
    pub fn len(&self) -> usize {
        self.instances.len()
    }

    /// Whether the set draws no glyph.
    pub fn is_empty(&self) -> bool {
        self.instances.is_empty()
    }

    /// Frees the float64 glyphs, which only the reference and the mesh pass read: a
    /// million band-8 glyphs hold about half a gigabyte there.
    pub fn drop_reference_glyphs(&mut self) {
        self.world = Vec::new();
    }

    /// Bytes the GPU holds for this set: coefficients, instances and boxes.
    pub fn gpu_bytes(&self) -> usize {
        4 * self.coefficients.len()
            + 16 * self.instances.len()
            + 32 * self.boxes.len()
            + 48 * self.hulls.len()
            + 4 * PIECE_WORDS * self.pieces.len()
    }
}

/// The tensor layout a set is drawn with: its own, or for SH glyphs the symmetric tensor
/// of order max(L, 2) that the paper's map t = M w turns the series into.
pub(crate) fn tensor_layout(set: &GlyphSet) -> TensorLayout {
    match set.kind {
        GlyphKind::Tensor(layout) => layout,
        GlyphKind::Sh { band, .. } => TensorLayout {
            order: band.max(2),
            symmetry: Symmetry::Symmetric,
        },
    }
}

/// One glyph's tensor coefficients in the set's drawing layout.
fn tensor_coefficients<'a>(set: &GlyphSet, coeffs: &'a [f64]) -> Result<Cow<'a, [f64]>> {
    match set.kind {
        GlyphKind::Tensor(_) => Ok(Cow::Borrowed(coeffs)),
        GlyphKind::Sh {
            band,
            basis,
            legacy,
        } => Ok(Cow::Owned(sh_to_tensor(band, basis, legacy, coeffs)?.1)),
    }
}

/// Prepares every glyph set of `scene`. `offset` is the isotropic offset as a fraction of
/// each glyph's bound. Glyphs whose tensor is zero (an empty surface) are left out.
pub fn prepare_scene(scene: &Scene, offset: f64) -> Result<Vec<GlyphSetData>> {
    prepare_scene_with(scene, offset, WorldGlyphs::Keep)
}

/// Whether a preparation keeps the float64 glyphs ([`GlyphSetData::world`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum WorldGlyphs {
    /// For the reference, the mesh pass and the largest radius of `--color magnitude`.
    Keep,
    /// Not even made: a million band-8 glyphs would take about half a gigabyte there,
    /// and as long again to allocate and free as to bound.
    Leave,
}

/// [`prepare_scene`], keeping the float64 glyphs or not.
pub(crate) fn prepare_scene_with(
    scene: &Scene,
    offset: f64,
    world: WorldGlyphs,
) -> Result<Vec<GlyphSetData>> {
    scene
        .glyph_sets
        .iter()
        .enumerate()
        .map(|(index, set)| prepare_set_keeping(set, index, offset, None, world))
        .collect()
}

/// Prepares one glyph set, the `index`-th of its scene.
pub fn prepare_set(set: &GlyphSet, index: usize, offset: f64) -> Result<GlyphSetData> {
    prepare_set_with_progress(set, index, offset, None)
}

/// [`prepare_set`], reporting the bounding of the glyphs to `progress`.
pub fn prepare_set_with_progress(
    set: &GlyphSet,
    index: usize,
    offset: f64,
    progress: Option<&Progress>,
) -> Result<GlyphSetData> {
    prepare_set_keeping(set, index, offset, progress, WorldGlyphs::Keep)
}

/// [`prepare_set_with_progress`], keeping the float64 glyphs or not.
fn prepare_set_keeping(
    set: &GlyphSet,
    index: usize,
    offset: f64,
    progress: Option<&Progress>,
    world: WorldGlyphs,
) -> Result<GlyphSetData> {
    let layout = tensor_layout(set);
    // Only the polynomial glyph takes an offset.
    let unsupported = crate::render::ShapeShader::of(set.shape).asked();
    if let Some(what) = unsupported
        && offset != 0.0
    {
        // The glyphs come from the scene, the offset from the request: the data decide.
        return Err(Error::Item {
            what: "glyph set",
            index,
            error: Box::new(Error::Unsupported {
                what,
                by: Setting::Offset.with(offset as f32),
            }),
        });
    }
    let mut data = GlyphSetData {
        layout,
        negative: set.negative,
        shape: set.shape,
        instances: Vec::with_capacity(set.len()),
        boxes: Vec::with_capacity(set.len()),
        hulls: Vec::with_capacity(set.len()),
        pieces: Vec::new(),
        coefficients: Vec::with_capacity(set.len() * layout.coefficient_count()),
        world: match world {
            WorldGlyphs::Keep => Vec::with_capacity(set.len()),
            WorldGlyphs::Leave => Vec::new(),
        },
        largest_radius: 0.0,
    };
    // The bounds of each glyph are the costly part: glyphs are bounded on every core, a
    // block at a time, so that the bounded glyphs in flight (each with its own float32
    // and float64 coefficients) never take more memory than one block's.
    if let Some(p) = progress {
        p.start("bounds", set.len());
    }
    let sampling = if set.len() <= SAMPLED_BOUNDS_GLYPHS {
        Sampling::Lattice
    } else {
        Sampling::None
    };
    let blocks = set
        .coeffs
        .chunks(BOUNDING_BLOCK)
        .zip(set.centers.chunks(BOUNDING_BLOCK))
        .zip(set.scales.chunks(BOUNDING_BLOCK));
    let in_set = |error| Error::Item {
        what: "glyph set",
        index,
        error: Box::new(error),
    };
    for (block, ((coeffs, centers), scales)) in blocks.enumerate() {
        let first = block * BOUNDING_BLOCK;
        // Each glyph with its index in the set, which an error names.
        let numbered: Vec<(usize, &[f64])> = (first..).zip(coeffs.iter().map(|c| &c[..])).collect();
        let bounded = map_chunks(&numbered, "bounds", |&(glyph, c)| {
            bound_glyph(set, layout, glyph, c, sampling, world)
        })
        .map_err(in_set)?;
        if let Some(p) = progress {
            p.advance(coeffs.len());
        }
        add_bounded(&mut data, set, offset, first, centers, scales, bounded).map_err(in_set)?;
    }
    Ok(data)
}

/// Sets of at most this many glyphs get boxes from the sampled bound as well
/// ([`Sampling::Lattice`]): about half the volume on fibre ODFs, so a third less of the
/// frame on the 256-glyph field, for 45 microseconds more a glyph (0.2 s of CPU for
/// this many). Larger sets (brain slices, a million glyphs) are small on screen, where
/// one frame gains less than the sampling costs.
pub(crate) const SAMPLED_BOUNDS_GLYPHS: usize = 4096;

/// Glyphs bounded at a time by [`prepare_set_with_progress`].
const BOUNDING_BLOCK: usize = 1 << 16;

/// Appends bounded glyphs (with their centres and scales; the first is glyph `first` of
/// the set) to `data`; empty glyphs are left out. A glyph whose world size is beyond
/// float32's range (a large scale times a large tensor) is refused: the GPU would draw
/// nothing for it.
fn add_bounded(
    data: &mut GlyphSetData,
    set: &GlyphSet,
    offset: f64,
    first: usize,
    centers: &[glam::DVec3],
    scales: &[f64],
    bounded: Vec<Option<Bounded>>,
) -> Result<()> {
    let glyphs = centers.iter().zip(scales).zip(bounded).enumerate();
    for (n, ((center, scale), glyph)) in glyphs {
        let Some(Bounded {
            gpu_coefficients,
            poly,
            bounds,
            trace,
            denominator,
        }) = glyph
        else {
            continue;
        };
        let bound = bounds.radius;
        let half_size = scale * bound * (1.0 + offset);
        let beyond = |what, value: f64| Error::Item {
            what: "glyph",
            index: first + n,
            error: Box::new(Error::data(
                what,
                Problem::OutOfRange {
                    value,
                    min: -MAX_SCENE_MAGNITUDE,
                    max: MAX_SCENE_MAGNITUDE,
                },
            )),
        };
        if !fits_float32(half_size) {
            return Err(beyond(
                "world radius (scale times the glyph's radius)",
                half_size,
            ));
        }
        if let Some(&c) = center.as_ref().iter().find(|c| !fits_float32(**c)) {
            return Err(beyond("centre coordinate", c));
        }
        data.boxes.push(box_instance(&bounds, offset));
        data.hulls.push(hull_instance(&bounds, offset));
        data.instances.push([
            center.x as f32,
            center.y as f32,
            center.z as f32,
            half_size as f32,
        ]);
        data.coefficients.extend_from_slice(&gpu_coefficients);
        if let Some(poly) = poly {
            data.world.push(WorldGlyph {
                center: *center,
                scale: *scale,
                poly,
                shape: set.shape,
                negative: set.negative,
                offset: offset * bound,
                bound: bound * (1.0 + offset),
                trace,
                denominator,
            });
        }
    }
    Ok(())
}

/// Bounds each polynomial set's pieces ([`GlyphSetData::pieces`], `--proxy pieces`) from
/// its float64 glyphs, on every core: a few milliseconds a glyph. Sets of other shapes,
/// and sets whose float64 glyphs were dropped, keep none (the GPU cuts their 26-sided
/// polytopes instead).
pub fn add_pieces(sets: &mut [GlyphSetData]) -> Result<()> {
    for data in sets.iter_mut() {
        if data.shape != GlyphShape::Polynomial || data.world.len() != data.len() {
            continue;
        }
        data.pieces = map_chunks(&data.world, "pieces", |glyph| {
            // B, the unit of the GPU's extents: bound = B (1 + offset), offset = offset B.
            let unit = glyph.bound - glyph.offset;
            let offset = glyph.offset / unit;
            let words = crate::glyph::proxy::glyph_bounds(&glyph.poly)
                .and_then(|bounds| glyph_pieces(&glyph.poly, glyph.negative, &bounds))
                .map(|pieces| pieces.gpu_words(unit, offset, BOX_PADDING));
            Ok(words)
        })?
        .into_iter()
        .zip(data.boxes.iter().zip(&data.hulls))
        .map(|(words, (b, h))| words.unwrap_or_else(|| polytope_piece_words(b, h)))
        .collect();
    }
    Ok(())
}

/// Fills in each set's [`GlyphSetData::largest_radius`] from its float64 glyphs (sets
/// whose glyphs were dropped keep theirs). Only `--color magnitude` without a range reads
/// it, and it costs about 2 us a glyph, so it is measured on demand
/// ([`crate::render::RenderSettings::needs_largest_radius`]), before the float64 glyphs
/// are freed.
pub fn measure_largest_radius(sets: &mut [GlyphSetData]) {
    for set in sets.iter_mut().filter(|s| !s.world.is_empty()) {
        set.largest_radius = largest_radius(&set.world);
    }
}

/// The largest world radius scale (max r(u) + offset) of `glyphs`. The bound B is an
/// upper bound of max r(u), often well above it; so the glyphs are taken by decreasing
/// scale B, and each is climbed to its true maximum ([`climbed_max_radius`], to about
/// 1e-7) until the next one's bound is below the largest found: few glyphs are climbed.
pub fn largest_radius(glyphs: &[WorldGlyph]) -> f64 {
    let upper = |g: &WorldGlyph| g.scale * g.bound;
    let mut by_bound: Vec<&WorldGlyph> = glyphs.iter().collect();
    by_bound.sort_unstable_by(|a, b| upper(b).total_cmp(&upper(a)));
    let mut largest = 0.0f64;
    for glyph in by_bound {
        if upper(glyph) <= largest {
            break;
        }
        // An ellipsoid's bound is exact: its longest semi-axis.
        let radius = match glyph.shape {
            GlyphShape::Ellipsoid => glyph.bound,
            // 1 / the least |f| the bound's search evaluated: within 1 % of the largest.
            GlyphShape::Reciprocal => least_abs(&glyph.poly).map_or(0.0, |l| 1.0 / l.attained),
            GlyphShape::Polynomial => {
                climbed_max_radius(&glyph.poly, glyph.negative, sizing_lattice(), 3)
            }
            // The largest radius found on 200 directions, the best 8 climbed (a lower
            // bound that reaches the cone tips where a plane or ratio glyph's two
            // surfaces touch, which a lattice misses).
            GlyphShape::RatioMin | GlyphShape::RatioMax => {
                climbed_max(|u| glyph.ratio_radius(u).abs(), 200, 8)
            }
            GlyphShape::PlaneMin | GlyphShape::PlaneMax => {
                climbed_max(|u| glyph.plane_radius(u), 200, 8)
            }
        };
        largest = largest.max(glyph.scale * (radius + glyph.offset));
    }
    largest
}

/// Relative enlargement of the oriented box, so that the glyph never touches its faces
/// (the ray casters need g < 0 where the chord starts and ends) and the float32 box
/// stays outside the float64 one.
const BOX_PADDING: f64 = 1.0 / 4096.0;

/// The least half extent, in units of the sphere radius: far above the float32 rounding
/// of the rotation (about 1e-7), so that even a flat glyph's box holds it.
const BOX_MIN_EXTENT: f64 = 1.0 / 65536.0;

/// The GPU box of a glyph: rotation and half extents in units of the bounding-sphere
/// radius B (1 + offset), an offset glyph's box grown by the offset.
fn box_instance(bounds: &GlyphBounds, offset: f64) -> [f32; 8] {
    let q = bounds.rotation();
    let extent = |e: f64| relative_extent(bounds, e, offset);
    [
        q.x as f32,
        q.y as f32,
        q.z as f32,
        q.w as f32,
        extent(bounds.extents[0]),
        extent(bounds.extents[1]),
        extent(bounds.extents[2]),
        0.0,
    ]
}

/// The GPU's diagonal extents of a glyph, in units of the bounding-sphere radius B
/// (1 + offset) and padded as the box's ([`box_instance`]).
fn hull_instance(bounds: &GlyphBounds, offset: f64) -> [f32; 12] {
    let mut hull = [0.0; 12];
    for (gpu, e) in hull.iter_mut().zip(bounds.diagonals) {
        *gpu = relative_extent(bounds, e, offset);
    }
    hull
}

/// A half extent `e` of `bounds` in units of the bounding-sphere radius B (1 + offset),
/// grown by the offset and padded outward (BOX_PADDING, BOX_MIN_EXTENT), at most 1.
fn relative_extent(bounds: &GlyphBounds, e: f64, offset: f64) -> f32 {
    let relative = (e / bounds.radius + offset) / (1.0 + offset);
    (relative * (1.0 + BOX_PADDING) + BOX_MIN_EXTENT).min(1.0) as f32
}

/// A glyph's tensor coefficients divided by B in float32 (what the GPU reads),
/// polynomial (where the float64 glyphs are kept) and bounds (radius B and box). For an
/// ellipsoid: the quadric form's entries in units of B, the quadric form, and its exact
/// bounds.
struct Bounded {
    gpu_coefficients: Vec<f32>,
    poly: Option<GlyphPolynomial>,
    bounds: GlyphBounds,
    /// A plane or ratio glyph's T, kept with `poly` (its D).
    trace: Option<GlyphPolynomial>,
    /// A ratio glyph's Q, kept with `poly`.
    denominator: Option<GlyphPolynomial>,
}

/// A glyph's float64 forms: f (a plane or ratio glyph's D), T and Q where it has them.
type Forms = (
    GlyphPolynomial,
    Option<GlyphPolynomial>,
    Option<GlyphPolynomial>,
);

impl Bounded {
    /// A glyph bounded by the sphere of `radius` about its centre, its box the cube
    /// around that sphere; `forms` where the float64 glyphs are kept.
    fn in_sphere(gpu_coefficients: Vec<f32>, radius: f64, forms: Option<Forms>) -> Bounded {
        let (poly, trace, denominator) = match forms {
            Some((poly, trace, denominator)) => (Some(poly), trace, denominator),
            None => (None, None, None),
        };
        Bounded {
            gpu_coefficients,
            poly,
            trace,
            denominator,
            bounds: GlyphBounds::from_box(
                radius,
                [glam::DVec3::X, glam::DVec3::Y, glam::DVec3::Z],
                [radius; 3],
            ),
        }
    }
}

/// Glyph `glyph` of `set` bounded; an error names the glyph. `None` for a glyph with an
/// empty surface (zero tensor).
fn bound_glyph(
    set: &GlyphSet,
    layout: TensorLayout,
    glyph: usize,
    coeffs: &[f64],
    sampling: Sampling,
    world: WorldGlyphs,
) -> Result<Option<Bounded>> {
    bound_shape(set, layout, coeffs, sampling, world).map_err(|e| Error::Item {
        what: "glyph",
        index: glyph,
        error: Box::new(e),
    })
}

/// [`bound_glyph`] by the set's shape.
fn bound_shape(
    set: &GlyphSet,
    layout: TensorLayout,
    coeffs: &[f64],
    sampling: Sampling,
    world: WorldGlyphs,
) -> Result<Option<Bounded>> {
    if set.shape == GlyphShape::Ellipsoid {
        return bound_ellipsoid(coeffs, world);
    }
    let coeffs = tensor_coefficients(set, coeffs)?;
    if set.shape.is_plane() {
        return bound_plane(&coeffs, world);
    }
    if set.shape.is_ratio() {
        return bound_ratio(&coeffs, world);
    }
    let poly = GlyphPolynomial::from_tensor(layout, &coeffs)?;
    if set.shape == GlyphShape::Reciprocal {
        return bound_reciprocal(poly, &coeffs, world);
    }
    Ok(glyph_bounds_with(&poly, sampling)
        .filter(|b| b.radius > 0.0 && b.radius.is_finite())
        .map(|bounds| Bounded {
            gpu_coefficients: coeffs.iter().map(|c| (c / bounds.radius) as f32).collect(),
            poly: (world == WorldGlyphs::Keep).then_some(poly),
            bounds,
            trace: None,
            denominator: None,
        }))
}

/// The plane glyph r = 1/λ, λ² − T λ + D = 0, of D (the set's `layout`) and T
/// (`coeffs` after D's): radius B = a guaranteed bound of 1/λ
/// ([`crate::glyph::intersect::plane_bound`]), the box the cube around that sphere, and
/// in the normalised frame q = p / B the roots B λ: D's coefficients times B², T's times
/// B. Roots that may vanish or not be positive somewhere (an unstable crystal) are
/// refused. `None` for a zero D.
fn bound_plane(coeffs: &[f64], world: WorldGlyphs) -> Result<Option<Bounded>> {
    let (determinant, trace, _) = GlyphShape::PlaneMin.pair_forms(coeffs)?;
    if determinant.abs_coefficient_sum() == 0.0 {
        return Ok(None);
    }
    let Some(radius) = crate::glyph::intersect::plane_bound(&determinant, &trace) else {
        return Err(Error::data(
            "guaranteed least |D| over the sphere, with D and T positive (r = 1/λ of a \
             plane glyph needs two positive roots λ in every direction)",
            Problem::NotPositive {
                value: least_abs(&determinant).map_or(0.0, |l| l.lower),
            },
        ));
    };
    let (d, t) = coeffs.split_at(determinant.coeffs.len().min(coeffs.len()));
    let gpu_coefficients = d
        .iter()
        .map(|c| c * radius * radius)
        .chain(t.iter().map(|c| c * radius))
        .map(|c| c as f32)
        .collect();
    let keep = world == WorldGlyphs::Keep;
    Ok(Some(Bounded::in_sphere(
        gpu_coefficients,
        radius,
        keep.then_some((determinant, Some(trace), None)),
    )))
}

/// The ratio glyph r = |λ/Q| of D, T and Q: radius B = [`ratio_bound`], the box the
/// cube around that sphere, and the coefficients scaled so that the normalised radius
/// λ'/Q' is r/B with Q' = Q/m of size 1 (m its largest coefficient): T' = T/(B m),
/// D' = D/(B m)². A Q that may vanish or is not positive makes the surface unbounded:
/// refused, with the least Q found. `None` for a zero glyph.
///
/// [`ratio_bound`]: crate::glyph::intersect::ratio_bound
fn bound_ratio(coeffs: &[f64], world: WorldGlyphs) -> Result<Option<Bounded>> {
    // A ratio shape's forms always hold Q.
    let (determinant, trace, Some(denominator)) = GlyphShape::RatioMin.pair_forms(coeffs)? else {
        return Ok(None);
    };
    if determinant.abs_coefficient_sum() == 0.0 && trace.abs_coefficient_sum() == 0.0 {
        return Ok(None);
    }
    let Some(radius) = crate::glyph::intersect::ratio_bound(&determinant, &trace, &denominator)
    else {
        return Err(Error::data(
            "guaranteed least Q over the sphere (r = |λ/Q| of a ratio glyph needs Q \
             positive in every direction)",
            Problem::NotPositive {
                // Q where it is negative at x, else the guaranteed lower bound of |Q|
                // (at most 0 where Q may vanish).
                value: match denominator.eval(glam::DVec3::X) {
                    q if q <= 0.0 => q,
                    _ => least_abs(&denominator).map_or(0.0, |l| l.lower),
                },
            },
        ));
    };
    let (d, rest) = coeffs.split_at(determinant.coeffs.len().min(coeffs.len()));
    let (t, q) = rest.split_at(trace.coeffs.len().min(rest.len()));
    let m = q.iter().fold(0.0f64, |m, c| m.max(c.abs()));
    let lambda_scale = 1.0 / (radius * m);
    let gpu_coefficients = d
        .iter()
        .map(|c| c * lambda_scale * lambda_scale)
        .chain(t.iter().map(|c| c * lambda_scale))
        .chain(q.iter().map(|c| c / m))
        .map(|c| c as f32)
        .collect();
    let keep = world == WorldGlyphs::Keep;
    Ok(Some(Bounded::in_sphere(
        gpu_coefficients,
        radius,
        keep.then_some((determinant, Some(trace), Some(denominator))),
    )))
}

/// The reciprocal glyph r = 1/|f| of a tensor: radius B = 1 / (a guaranteed lower bound
/// of |f| on the sphere), the box the cube around that sphere, and coefficients times B
/// (so that |f| >= 1 and r <= 1 in the normalised frame). An f that may vanish on the
/// sphere (every odd order, or a crystal's unstable direction) makes the surface
/// unbounded: refused, with the least |f| found. `None` for a zero tensor.
fn bound_reciprocal(
    poly: GlyphPolynomial,
    coeffs: &[f64],
    world: WorldGlyphs,
) -> Result<Option<Bounded>> {
    let Some(least) = least_abs(&poly) else {
        return Ok(None);
    };
    if least.lower.is_nan() || least.lower <= 0.0 || !(1.0 / least.lower).is_finite() {
        return Err(Error::data(
            "guaranteed least |f| over the sphere (r = 1/|f| of shape reciprocal is unbounded \
             where f vanishes; every odd order does)",
            Problem::NotPositive { value: least.lower },
        ));
    }
    let radius = 1.0 / least.lower;
    Ok(Some(Bounded::in_sphere(
        coeffs.iter().map(|c| (c * radius) as f32).collect(),
        radius,
        (world == WorldGlyphs::Keep).then_some((poly, None, None)),
    )))
}

/// The ellipsoid of an order-2 tensor: `None` for one without (no positive eigenvalue).
/// The GPU reads the quadric's matrix in units of the bound B, whose eigenvalues
/// (B / s_i)^2 are at least 1 and at most 1 / [`crate::glyph::ellipsoid::EIGENVALUE_FLOOR`].
fn bound_ellipsoid(coeffs: &[f64], world: WorldGlyphs) -> Result<Option<Bounded>> {
    let Some(ellipsoid) = Ellipsoid::from_tensor(coeffs) else {
        return Ok(None);
    };
    let bounds = ellipsoid.bounds();
    let a = ellipsoid.quadric(bounds.radius);
    let entries = [
        a.x_axis.x, a.y_axis.x, a.z_axis.x, a.y_axis.y, a.z_axis.y, a.z_axis.z,
    ];
    Ok(Some(Bounded {
        gpu_coefficients: entries.iter().map(|&c| c as f32).collect(),
        poly: match world {
            WorldGlyphs::Keep => Some(ellipsoid.quadric_polynomial(1.0)?),
            WorldGlyphs::Leave => None,
        },
        bounds,
        trace: None,
        denominator: None,
    }))
}
