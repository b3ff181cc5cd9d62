//! Run-time settings of the ray caster. None of them needs a new shader permutation:
//! they reach the shaders through the frame's parameter block.
use crate::error::quoted;
use crate::render::{MeshKind, Method};
use crate::{Error, Result, Setting};
use ash::vk;

/// How the first sign change along the ray is refined (`--refine`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Refinement {
    /// The first sample found inside the glyph.
    None,
    /// K bisection steps (0 to 3 in the paper), then the midpoint of the bracket.
    Bisect(u32),
    /// Linear interpolation of the last two samples (one secant step).
    Interpolate,
    /// K steps of regula falsi with the Illinois modification, starting from the same
    /// bracket as `Interpolate`: converges to float precision in a few steps on smooth
    /// surfaces, where one secant step leaves an error quadratic in the step size.
    Secant(u32),
}

impl std::str::FromStr for Refinement {
    type Err = Error;
    fn from_str(s: &str) -> Result<Self> {
        match s {
            "none" => Ok(Refinement::None),
            "interp" => Ok(Refinement::Interpolate),
            _ => {
                let count = |prefix: &str| {
                    s.strip_prefix(prefix)
                        .and_then(|k| k.parse::<u32>().ok())
                        .filter(|k| *k <= 16)
                };
                count("bisect:")
                    .map(Refinement::Bisect)
                    .or_else(|| count("secant:").map(Refinement::Secant))
                    .ok_or_else(|| {
                        Error::setting_value(
                            Setting::Refine,
                            format!("'{}'", quoted(s)),
                            "not one of bisect:K, secant:K (K = 0..16), interp, none",
                        )
                    })
            }
        }
    }
}

/// Glyph colouring (`--color`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ColorMode {
    /// The paper's |p^|: absolute components of the direction from the centre.
    Direction,
    /// A perceptual colormap of the surface point's distance from the centre (world
    /// units) over `range`, or over the scene's largest glyph when `None`.
    Magnitude {
        /// Low and high end of the map, world units; `None`: 0 to the largest radius.
        range: Option<(f32, f32)>,
    },
    /// One colour for every glyph (linear RGB).
    Uniform([f32; 3]),
    /// Two colours (linear RGB) by the sign of the glyph function at the surface point:
    /// positive lobes and negative ones (shown with `NegativeMode::Abs`), as FURY draws
    /// signed glyphs. Ray-casting methods only: meshes and impostors do not know the sign.
    Sign {
        /// Colour of the lobes where f > 0 (linear RGB).
        positive: [f32; 3],
        /// Colour of the lobes where f < 0 (linear RGB).
        negative: [f32; 3],
    },
}

impl ColorMode {
    /// The colour's name, as `color` takes it.
    pub fn name(&self) -> &'static str {
        match self {
            ColorMode::Direction => "direction",
            ColorMode::Magnitude { .. } => "magnitude",
            ColorMode::Uniform(_) => "uniform",
            ColorMode::Sign { .. } => "sign",
        }
    }
}

impl std::fmt::Display for ColorMode {
    /// The name ([`ColorMode::name`]).
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

impl std::fmt::Display for Refinement {
    /// As `refine` takes it (`secant:4`).
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Refinement::None => f.write_str("none"),
            Refinement::Interpolate => f.write_str("interp"),
            Refinement::Bisect(k) => write!(f, "bisect:{k}"),
            Refinement::Secant(k) => write!(f, "secant:{k}"),
        }
    }
}

/// `--color sign`'s colours, linear RGB: a red for positive lobes, a blue for negative.
pub const SIGN_COLORS: ([f32; 3], [f32; 3]) = ([0.8, 0.03, 0.03], [0.03, 0.1, 0.8]);

impl std::str::FromStr for ColorMode {
    type Err = Error;
    fn from_str(s: &str) -> Result<Self> {
        match s {
            "direction" => Ok(ColorMode::Direction),
            "magnitude" => Ok(ColorMode::Magnitude { range: None }),
            "uniform" => Ok(ColorMode::Uniform([0.8, 0.8, 0.8])),
            "sign" => Ok(ColorMode::Sign {
                positive: SIGN_COLORS.0,
                negative: SIGN_COLORS.1,
            }),
            _ => Err(Error::setting_value(
                Setting::Color,
                format!("'{}'", quoted(s)),
                "not one of direction, magnitude, uniform, sign",
            )),
        }
    }
}

impl std::str::FromStr for Method {
    type Err = Error;
    fn from_str(s: &str) -> Result<Self> {
        let bad = || {
            Error::setting_value(
                Setting::Method,
                format!("'{}'", quoted(s)),
                format!(
                    "not one of {}, impostor, mesh:LEVEL (icosphere, 0..={}), latlong:N \
                     (latitude bands, 2..={})",
                    crate::catalog::RAY_CAST_METHODS.map(|m| m.name).join(", "),
                    crate::glyph::tessellate::MAX_ICOSPHERE_LEVEL,
                    crate::glyph::tessellate::MAX_LAT_LONG_RINGS
                ),
            )
        };
        let count = |prefix: &str| s.strip_prefix(prefix).and_then(|n| n.parse::<u32>().ok());
        let ray_cast = Method::RAY_CASTING
            .into_iter()
            .find(|m| m.ray_cast_entry().is_some_and(|entry| entry.name == s));
        let method = match (ray_cast, s) {
            (Some(method), _) => method,
            (None, "impostor") => Method::Impostor,
            (None, _) => count("mesh:")
                .map(MeshKind::Icosphere)
                .or_else(|| count("latlong:").map(MeshKind::LatLong))
                .map(Method::Mesh)
                .ok_or_else(bad)?,
        };
        if let Method::Mesh(kind) = method {
            kind.validate().map_err(|_| bad())?;
        }
        Ok(method)
    }
}

/// Which ray caster runs the method (`--path`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum RenderPath {
    /// The ray caster measured faster on the device that draws the frame
    /// ([`RenderPath::on_device`]): the compute ray caster on a GPU where it can draw the
    /// frame, the fragment path on a CPU (lavapipe) and wherever the compute ray caster
    /// cannot draw the frame (another method, glyph shapes other than the polynomial
    /// glyph). In an engine's own frame it takes the compute path only where the host
    /// records its dispatches ([`GlyphRenderer::record_compute`](crate::render::component::GlyphRenderer::record_compute)).
    #[default]
    Auto,
    /// Instanced proxy boxes whose fragment shader ray-casts the glyph
    /// ([`RayCastPass`](crate::render::raycast::RayCastPass)); what engines embed.
    Fragment,
    /// A compute shader per pixel walking its screen tile's glyphs front to back
    /// ([`ComputeRayCastPass`](crate::render::compute::ComputeRayCastPass)); exact only.
    Compute,
}

impl RenderPath {
    /// The ray caster that draws glyphs of `shapes` with `method` on a device of type
    /// `device`: `self`, unless it is [`RenderPath::Auto`], which takes
    ///
    /// - the fragment path where the compute ray caster cannot draw the frame (a method
    ///   other than `exact`, a glyph shape other than the polynomial glyph);
    /// - the fragment path on a CPU device (lavapipe), where the compute ray caster is
    ///   3 to 7 times slower: its invocations run in lockstep lanes over every pixel of
    ///   every tile, so a pixel's early stop saves nothing there, while the fragment path
    ///   launches fragments only inside the glyphs' boxes;
    /// - the compute ray caster on a GPU (discrete, integrated or virtual), where it was
    ///   measured 5 to 20 times faster than the fragment path: each pixel walks its tile's
    ///   glyphs front to back and stops behind its nearest hit, and the GPU's warps skip
    ///   the work of lanes that stopped;
    /// - the fragment path on a device of another type, which nothing was measured on.
    ///
    /// docs/guide/performance.md has the measurements and their commands.
    pub fn on_device(
        self,
        device: vk::PhysicalDeviceType,
        method: Method,
        shapes: impl IntoIterator<Item = crate::glyph::GlyphShape>,
    ) -> RenderPath {
        if self != RenderPath::Auto {
            return self;
        }
        let computable = method == Method::Exact
            && shapes
                .into_iter()
                .all(|shape| shape == crate::glyph::GlyphShape::Polynomial);
        let gpu = matches!(
            device,
            vk::PhysicalDeviceType::DISCRETE_GPU
                | vk::PhysicalDeviceType::INTEGRATED_GPU
                | vk::PhysicalDeviceType::VIRTUAL_GPU
        );
        if computable && gpu {
            RenderPath::Compute
        } else {
            RenderPath::Fragment
        }
    }

    /// [`RenderPath::on_device`] for the device of `ctx`, where `auto` also takes the
    /// fragment path if the device's compute shaders lack subgroup vote and ballot
    /// operations, which the compute ray caster needs
    /// ([`compute_votes`](crate::vk::DeviceContext::compute_votes)).
    pub fn on_context(
        self,
        ctx: &crate::vk::DeviceContext,
        method: Method,
        shapes: impl IntoIterator<Item = crate::glyph::GlyphShape>,
    ) -> RenderPath {
        if self == RenderPath::Auto && !ctx.compute_votes() {
            return RenderPath::Fragment;
        }
        self.on_device(ctx.device_type(), method, shapes)
    }
}

impl std::str::FromStr for RenderPath {
    type Err = Error;
    fn from_str(s: &str) -> Result<Self> {
        match s {
            "auto" => Ok(RenderPath::Auto),
            "fragment" => Ok(RenderPath::Fragment),
            "compute" => Ok(RenderPath::Compute),
            _ => Err(Error::setting_value(
                Setting::Path,
                format!("'{}'", quoted(s)),
                "not one of auto, fragment, compute",
            )),
        }
    }
}

impl std::fmt::Display for RenderPath {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            RenderPath::Auto => "auto",
            RenderPath::Fragment => "fragment",
            RenderPath::Compute => "compute",
        })
    }
}

/// The refusal of [`RenderPath::Compute`] for glyphs of `shape` (any but the polynomial
/// glyph), with the way out.
pub(crate) fn compute_refuses_shape(shape: crate::glyph::GlyphShape) -> Error {
    Error::setting_value(
        Setting::Path,
        "compute",
        crate::message![
            format!(
                "the compute ray caster draws polynomial glyphs only, not {} glyphs; use ",
                shape.name()
            ),
            Setting::Path.with("fragment"),
            " or ",
            Setting::Path.with("auto"),
            " (which takes the fragment path for them)"
        ],
    )
}

/// Shadows the glyphs cast (`--shadows`): from each glyph hit, rays towards the light are
/// intersected exactly with the glyphs that may block them (the same root isolation as
/// the camera's rays). Only the light's diffuse and specular terms are taken away; the
/// ambient term stays, and the depth map does not change.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum Shadows {
    /// No shadow rays (the default).
    #[default]
    Off,
    /// One ray towards a directional light: a point is lit or not.
    Hard,
    /// A disc light of this angular radius (degrees, above 0 and at most
    /// `SOFT_SHADOW_MAX_RADIUS`), sampled by `SOFT_SHADOW_SAMPLES` rays in a stratified
    /// pattern that each pixel turns by its own offset
    /// ([`crate::glyph::shadow::SamplePattern`]): the lit share of them scales the light.
    Soft {
        /// The light's angular radius in degrees.
        radius_deg: f32,
    },
}

/// Rays towards the disc of a soft light, per hit: one in each sixteenth of the disc's
/// area (glsl/shadow.glsl).
pub(crate) const SOFT_SHADOW_SAMPLES: u32 = 16;

/// The largest angular radius of `--shadows soft:RADIUS`, in degrees.
pub(crate) const SOFT_SHADOW_MAX_RADIUS: f32 = 30.0;

impl Shadows {
    /// Whether any shadow rays are cast.
    pub fn enabled(&self) -> bool {
        *self != Shadows::Off
    }

    /// The angular radius of the light in degrees (0: hard shadows or none).
    pub fn radius_deg(&self) -> f32 {
        match self {
            Shadows::Soft { radius_deg } => *radius_deg,
            _ => 0.0,
        }
    }
}

impl Shadows {
    /// Refuses a soft light's radius outside above 0 to `SOFT_SHADOW_MAX_RADIUS`.
    pub fn validate(&self) -> Result<()> {
        match *self {
            Shadows::Soft { radius_deg }
                if !(radius_deg > 0.0 && radius_deg <= SOFT_SHADOW_MAX_RADIUS) =>
            {
                Err(Error::setting_value(
                    Setting::Shadows,
                    format!("'{self}'"),
                    format!(
                        "the soft light's angular radius must be above 0 and at most \
                         {SOFT_SHADOW_MAX_RADIUS} degrees"
                    ),
                ))
            }
            _ => Ok(()),
        }
    }
}

impl std::str::FromStr for Shadows {
    type Err = Error;
    fn from_str(s: &str) -> Result<Self> {
        let refused =
            |why: String| Error::setting_value(Setting::Shadows, format!("'{}'", quoted(s)), why);
        match s.trim() {
            "off" | "none" => Ok(Shadows::Off),
            "on" | "hard" => Ok(Shadows::Hard),
            text => {
                let Some(radius) = text.strip_prefix("soft:") else {
                    return Err(refused(
                        "not one of off, hard (or on), soft:RADIUS (degrees)".into(),
                    ));
                };
                let radius_deg: f32 = radius.trim().parse().map_err(|_| {
                    refused("soft:RADIUS takes the light's angular radius in degrees".into())
                })?;
                let shadows = Shadows::Soft { radius_deg };
                shadows.validate().map(|_| shadows)
            }
        }
    }
}

impl std::fmt::Display for Shadows {
    /// As `shadows` takes it (`off`, `hard`, `soft:2`).
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Shadows::Off => f.write_str("off"),
            Shadows::Hard => f.write_str("hard"),
            Shadows::Soft { radius_deg } => write!(f, "soft:{radius_deg}"),
        }
    }
}

/// Ambient occlusion (`--ambient-occlusion`): from each glyph hit,
/// [`AMBIENT_OCCLUSION_RAYS`](crate::glyph::shadow::AMBIENT_OCCLUSION_RAYS) rays over the
/// hemisphere around the normal (cosine-weighted, the soft light's stratified pattern
/// turned per pixel) are intersected exactly with the glyphs within `reach`
/// bounding radii of the hit glyph, and the share of them that no glyph blocks scales the
/// ambient term. It approximates how much of a uniform sky light the neighbouring lobes
/// and glyphs hide from the point (no light is bounced between glyphs); the light's
/// diffuse and specular terms and the depth map do not change.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum AmbientOcclusion {
    /// No occlusion rays (the default).
    #[default]
    Off,
    /// Occlusion rays that reach this many bounding radii of the hit glyph.
    On {
        /// How far the rays reach, in bounding radii of the hit glyph (above 0 to
        /// `AMBIENT_OCCLUSION_MAX_REACH`).
        reach: f32,
    },
}

/// How far the occlusion rays of `--ambient-occlusion` alone reach, in bounding radii of
/// the hit glyph: to the glyphs next to it in a field whose glyphs touch.
pub const AMBIENT_OCCLUSION_REACH: f32 = 1.0;

/// The farthest reach of `--ambient-occlusion REACH`, in bounding radii.
pub(crate) const AMBIENT_OCCLUSION_MAX_REACH: f32 = 16.0;

impl AmbientOcclusion {
    /// Whether any occlusion rays are cast.
    pub fn enabled(&self) -> bool {
        *self != AmbientOcclusion::Off
    }

    /// How far the rays reach in bounding radii (0 when off).
    pub fn reach(&self) -> f32 {
        match self {
            AmbientOcclusion::On { reach } => *reach,
            AmbientOcclusion::Off => 0.0,
        }
    }

    /// Refuses a reach outside above 0 to `AMBIENT_OCCLUSION_MAX_REACH`.
    pub fn validate(&self) -> Result<()> {
        match *self {
            AmbientOcclusion::On { reach }
                if !(reach > 0.0 && reach <= AMBIENT_OCCLUSION_MAX_REACH) =>
            {
                Err(Error::setting_value(
                    Setting::AmbientOcclusion,
                    reach,
                    format!(
                        "the occlusion rays' reach must be above 0 and at most \
                         {AMBIENT_OCCLUSION_MAX_REACH} bounding radii"
                    ),
                ))
            }
            _ => Ok(()),
        }
    }
}

impl std::str::FromStr for AmbientOcclusion {
    type Err = Error;
    fn from_str(s: &str) -> Result<Self> {
        let occlusion = match s.trim() {
            "off" | "none" => AmbientOcclusion::Off,
            "on" => AmbientOcclusion::On {
                reach: AMBIENT_OCCLUSION_REACH,
            },
            text => AmbientOcclusion::On {
                reach: text.parse().map_err(|_| {
                    Error::setting_value(
                        Setting::AmbientOcclusion,
                        format!("'{}'", quoted(s)),
                        "not one of off, on, or the rays' reach in bounding radii (a number)",
                    )
                })?,
            },
        };
        occlusion.validate().map(|_| occlusion)
    }
}

impl std::fmt::Display for AmbientOcclusion {
    /// As `ambient_occlusion` takes it (`off`, or the reach: `1`).
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            AmbientOcclusion::Off => f.write_str("off"),
            AmbientOcclusion::On { reach } => write!(f, "{reach}"),
        }
    }
}

/// Whether glyphs hidden behind others are skipped (`--cull`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Culling {
    /// The default: `early-out` on a device that jumps over code no lane of a batch of
    /// pixels runs (a GPU; lavapipe of Mesa 25 and later) where the method is `exact`,
    /// else `passes`. The image and the depth map are the same as without culling; a
    /// frame that fits in one pass (a flat field) is drawn as without it.
    #[default]
    Occluded,
    /// The headless renderer draws the glyphs in passes front to back, and each pass
    /// skips the fragments behind the depth its earlier passes wrote (the depth test
    /// before the fragment shader: saves work on every device).
    Passes,
    /// One pass front to back in which each hit raises its pixel's known depth, and a
    /// fragment whose box lies behind it skips the root isolation (the `exact` method's
    /// shader; saves work only on a device that jumps over code no lane runs).
    EarlyOut,
    /// One pass: every glyph's fragments run.
    Off,
}

impl std::str::FromStr for Culling {
    type Err = Error;
    fn from_str(s: &str) -> Result<Self> {
        match s.trim() {
            "occluded" | "on" => Ok(Culling::Occluded),
            "passes" => Ok(Culling::Passes),
            "early-out" => Ok(Culling::EarlyOut),
            "off" | "none" => Ok(Culling::Off),
            _ => Err(Error::setting_value(
                Setting::Cull,
                format!("'{}'", quoted(s)),
                "not one of occluded, passes, early-out, off",
            )),
        }
    }
}

impl std::fmt::Display for Culling {
    /// As `cull` takes it.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Culling::Occluded => "occluded",
            Culling::Passes => "passes",
            Culling::EarlyOut => "early-out",
            Culling::Off => "off",
        })
    }
}

/// What the fragment path rasterises for each glyph (`--proxy`): every pixel it covers
/// runs the ray caster, which finds the same hits whichever is drawn.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Proxy {
    /// The front faces of the glyph's oriented bounding box: the paper's proxy, and the
    /// default (its pipelines are created fastest, which a one-shot image on a CPU
    /// device mostly waits for).
    #[default]
    Box,
    /// An octagon on the screen around the outline of the glyph's 26-sided polytope (its
    /// box cut by guaranteed planes across its ten diagonals), at the glyph's nearest
    /// depth: 8 to 18 % fewer fragments and 16 to 22 % fewer root isolations than the
    /// box on fODF fields, for pipelines that take longer to create.
    Hull,
    /// Eight octagons per glyph, one around each of its pieces: the octants of a frame
    /// turned to its largest lobe, cut by guaranteed planes along 19 directions, each
    /// fragment's ray clipped to its piece. The exact method on polynomial glyphs; the
    /// other methods and shapes draw the hull's outline. Bounding the pieces costs
    /// milliseconds a glyph on the CPU.
    Pieces,
}

impl std::str::FromStr for Proxy {
    type Err = Error;
    fn from_str(s: &str) -> Result<Self> {
        match s.trim() {
            "hull" => Ok(Proxy::Hull),
            "box" => Ok(Proxy::Box),
            "pieces" => Ok(Proxy::Pieces),
            _ => Err(Error::setting_value(
                Setting::Proxy,
                format!("'{}'", quoted(s)),
                "not one of box, hull, pieces",
            )),
        }
    }
}

impl std::fmt::Display for Proxy {
    /// As `proxy` takes it.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Proxy::Hull => "hull",
            Proxy::Box => "box",
            Proxy::Pieces => "pieces",
        })
    }
}

/// Everything that decides how glyphs are drawn, beside the scene and the camera: the
/// command line's drawing options.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RenderSettings {
    /// How each pixel's surface point is found.
    pub method: Method,
    /// The ray caster that runs `method`.
    pub path: RenderPath,
    /// March step in units of the glyph's bounding radius.
    pub step: f32,
    /// How a sign change of the fixed march is refined to the surface.
    pub refinement: Refinement,
    /// Step factor inside the centre zone (the paper uses a third).
    pub centre_step_factor: f32,
    /// Radius of the centre zone, in units of the glyph's bounding radius.
    pub centre_zone: f32,
    /// Isotropic offset added to every radius, as a fraction of the glyph's bounding radius.
    pub offset: f32,
    /// How surface points are coloured.
    pub color: ColorMode,
    /// Background colour: linear RGB and alpha (1 opaque, 0 transparent: `--background
    /// none`); see [`parse_background`].
    pub background: [f32; 4],
    /// Robust methods (interval, affine): segments are split until their length is below
    /// this many pixels' footprint at their depth.
    pub precision_px: f32,
    /// Samples per pixel (`--samples`): 1, or 4 or 16 by supersampling
    /// ([`crate::render::antialias`]).
    pub samples: u32,
    /// The light and the Blinn-Phong terms every pass shades with.
    pub lighting: Lighting,
    /// Shadows cast by the glyphs (`--shadows`; the exact method's fragment path only).
    pub shadows: Shadows,
    /// Ambient occlusion by the glyphs (`--ambient-occlusion`; the exact method's
    /// fragment path only).
    pub ambient_occlusion: AmbientOcclusion,
    /// Whether glyphs hidden behind others are skipped (`--cull`).
    pub cull: Culling,
    /// What the fragment path draws for each glyph (`--proxy`).
    pub proxy: Proxy,
}

/// Blinn-Phong lighting (`--light`, `--ambient`, `--specular`, `--shininess`): a surface
/// point of base colour c, unit normal n (turned towards the viewer) and view direction v
/// is shaded
///
/// ```text
///   c (ambient + (1 - ambient) max(n . l, 0)) + specular max(n . h, 0)^shininess,
///   h = normalize(l + v),
/// ```
///
/// with l the unit direction towards the light. The light is fixed to the camera: l is
/// given in view coordinates (x to the right of the image, y up, z towards the viewer),
/// so every view of a montage and every orbit of the viewer is lit alike.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Lighting {
    /// Direction towards the light in view coordinates (any length > 0).
    pub direction: [f32; 3],
    /// The share of the base colour that is lit whatever the normal, 0 to 1.
    pub ambient: f32,
    /// Strength of the white highlight, 0 to 1.
    pub specular: f32,
    /// Blinn-Phong exponent of the highlight, 1 to 1024.
    pub shininess: f32,
}

impl Default for Lighting {
    /// Above, right and in front of the viewer; a dim ambient and a small highlight.
    fn default() -> Self {
        Lighting {
            direction: [0.35, 0.5, 1.0],
            ambient: 0.18,
            specular: 0.25,
            shininess: 48.0,
        }
    }
}

/// The range of `--shininess`.
pub(crate) const SHININESS_RANGE: (f32, f32) = (1.0, 1024.0);

impl Lighting {
    /// The unit direction towards the light in view coordinates.
    pub fn unit_direction(&self) -> [f32; 3] {
        let [x, y, z] = self.direction;
        let length = (x * x + y * y + z * z).sqrt();
        [x / length, y / length, z / length]
    }

    /// Checks the direction: finite and of non-zero length (the numbers' ranges are
    /// the render settings table's).
    pub fn validate(&self) -> Result<()> {
        let [x, y, z] = self.direction;
        let length = (x * x + y * y + z * z).sqrt();
        if !(length.is_finite() && length > 1e-6) {
            return Err(Error::setting_value(
                Setting::Light,
                format!("{x},{y},{z}"),
                "needs a finite direction of non-zero length",
            ));
        }
        Ok(())
    }
}

impl Default for RenderSettings {
    fn default() -> Self {
        RenderSettings {
            // The fastest method with no holes and no false hits on the accuracy suite
            // and a median depth error at float32 level (docs/guide/accuracy.md): the first
            // real root of the ray polynomial. It refuses an offset; the command line
            // then takes affine, the next fastest.
            method: Method::Exact,
            path: RenderPath::Auto,
            step: 0.02,
            refinement: Refinement::Secant(4),
            centre_step_factor: 1.0 / 3.0,
            centre_zone: 0.3,
            offset: 0.0,
            color: ColorMode::Direction,
            background: DARK_BACKGROUND,
            precision_px: 0.25,
            samples: 1,
            lighting: Lighting::default(),
            shadows: Shadows::Off,
            ambient_occlusion: AmbientOcclusion::Off,
            cull: Culling::Occluded,
            proxy: Proxy::Box,
        }
    }
}

/// The default background, `--background dark`: a near-black grey (linear RGB, opaque).
pub(crate) const DARK_BACKGROUND: [f32; 4] = [0.02, 0.02, 0.025, 1.0];

/// The supersampling factor s (samples per pixel s^2): 1, 2 or 4; other counts are an
/// error naming the samples setting.
pub fn supersampling_factor(samples: u32) -> Result<u32> {
    match samples {
        1 => Ok(1),
        4 => Ok(2),
        16 => Ok(4),
        _ => Err(Error::setting_value(
            Setting::Samples,
            samples,
            "must be 1, 4 or 16",
        )),
    }
}

/// The linear value of an 8-bit sRGB-encoded value (the sRGB transfer function), so
/// that an sRGB colour target writes `byte` back.
pub fn srgb_to_linear(byte: u8) -> f32 {
    let c = byte as f64 / 255.0;
    let linear = if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    };
    linear as f32
}

/// A colour written `#rrggbb` or `r,g,b` (0 to 255 each), as 8-bit values; `None` for
/// anything else (the callers add their own names).
pub fn parse_rgb8(text: &str) -> Option<[u8; 3]> {
    match text.strip_prefix('#') {
        Some(hex) if hex.len() == 6 && hex.bytes().all(|b| b.is_ascii_hexdigit()) => {
            u32::from_str_radix(hex, 16)
                .ok()
                .map(|v| [(v >> 16) as u8, (v >> 8) as u8, v as u8])
        }
        Some(_) => None,
        None => {
            let parts: Vec<Option<u8>> = text.split(',').map(|v| v.trim().parse().ok()).collect();
            match parts[..] {
                [Some(r), Some(g), Some(b)] => Some([r, g, b]),
                _ => None,
            }
        }
    }
}

/// `--background`: `none` (transparent), a name (dark, the default; black, white,
/// grey or gray), `#rrggbb` or `r,g,b` (0 to 255 each). The 8-bit values are sRGB, as
/// written in the PNG; the result is linear RGB and alpha.
pub fn parse_background(text: &str) -> Result<[f32; 4]> {
    let srgb = |bytes: [u8; 3]| bytes.map(srgb_to_linear);
    let bytes = match text {
        "none" => return Ok([0.0; 4]),
        "dark" => return Ok(DARK_BACKGROUND),
        "black" => Some([0, 0, 0]),
        "white" => Some([255, 255, 255]),
        "grey" | "gray" => Some([128, 128, 128]),
        _ => parse_rgb8(text),
    };
    let [r, g, b] = bytes.map(srgb).ok_or_else(|| {
        Error::setting_value(
            Setting::Background,
            format!("'{}'", quoted(text)),
            "not none, dark, black, white, grey, #rrggbb or r,g,b (0-255)",
        )
    })?;
    Ok([r, g, b, 1.0])
}

/// The fixed-step march's step (bounding radii) that float32 draws reliably. Measured
/// with `glyphcast accuracy --methods fixed --steps 0.001,0.0003,0.0001 --refine none`:
/// at 1e-4 the order-12 scene gets false hits (the float32 polynomial's rounding noise
/// changes sign between such close samples) and a 1e6 scale range errs by 2 px; 3e-4 is
/// clean on every scene. The bound keeps a margin of 3 over that.
pub const STEP_RANGE: (f32, f32) = (1e-3, 2.0);

/// The robust methods' segment limit (pixels) that float32 draws reliably. A segment of
/// p pixels at depth t is about p (fov / height) t long; below a few float32 epsilons of
/// t its ends round together and the range test loses the surface. Measured on the demo
/// at 160 px (fov 30 degrees, 3.3e-3 rad per pixel) against --method exact: 1e-4 px
/// (2.8 epsilons of t) has no holes, 1e-5 px (0.3 epsilons) 34, 1e-6 px 89, for interval
/// and affine alike. 0.01 px keeps 2.8 epsilons up to the largest image, 16384 px high.
pub(crate) const PRECISION_RANGE: (f32, f32) = (0.01, 64.0);

impl RenderSettings {
    /// Whether frames read the largest glyph radius: `--color magnitude` without an
    /// explicit range, whose default range ends there.
    pub fn needs_largest_radius(&self) -> bool {
        matches!(self.color, ColorMode::Magnitude { range: None })
    }

    /// Checks what the table does not declare: the light's direction, the internal
    /// numbers, and the settings' combinations ([`RenderSettings::validate`] checks the
    /// table's ranges, then these).
    pub(crate) fn validate_rest(&self) -> Result<()> {
        if let Method::Mesh(kind) = self.method {
            kind.validate()?;
        }
        let positive = |name: &'static str, v: f32, max: f32| {
            if v.is_finite() && v > 0.0 && v <= max {
                Ok(())
            } else {
                Err(Error::data(
                    name,
                    crate::error::Problem::OutOfRange {
                        value: f64::from(v),
                        min: 0.0,
                        max: f64::from(max),
                    },
                ))
            }
        };
        self.lighting.validate()?;
        positive("centre step factor", self.centre_step_factor, 1.0)?;
        if !(self.centre_zone.is_finite() && self.centre_zone >= 0.0) {
            return Err(Error::data(
                "centre zone",
                crate::error::Problem::OutOfRange {
                    value: f64::from(self.centre_zone),
                    min: 0.0,
                    max: f64::INFINITY,
                },
            ));
        }
        // A glyph with an offset is no polynomial surface: there is no ray polynomial to solve.
        if self.method == Method::Exact && self.offset != 0.0 {
            return Err(Error::setting_value(
                Setting::Offset,
                self.offset,
                crate::message![
                    Setting::Method.with("exact"),
                    " needs offset 0 (offset glyphs are not polynomial surfaces); use ",
                    Setting::Method.with("fixed")
                ],
            ));
        }
        if matches!(self.color, ColorMode::Sign { .. })
            && matches!(self.method, Method::Mesh(_) | Method::Impostor)
        {
            return Err(Error::setting_value(
                Setting::Color,
                "sign",
                crate::message![
                    Setting::Method.with(self.method),
                    " does not know the sign of the glyph function; use a ray-casting \
                     method (exact, fixed, interval, affine)"
                ],
            ));
        }
        if !(self.background.iter().all(|c| (0.0..=1.0).contains(c))) {
            return Err(Error::setting_value(
                Setting::Background,
                format_args!("{:?}", self.background),
                "every component must be in 0 to 1",
            ));
        }
        supersampling_factor(self.samples)?;
        if self.path == RenderPath::Compute && self.method != Method::Exact {
            return Err(Error::setting_value(
                Setting::Path,
                "compute",
                crate::message![
                    "only ",
                    Setting::Method.with("exact"),
                    format!(" has a compute ray caster, not {}", self.method)
                ],
            ));
        }
        self.shadows.validate()?;
        self.ambient_occlusion.validate()?;
        let cast_by_exact = self.method == Method::Exact;
        for (setting, value, enabled) in [
            (
                Setting::Shadows,
                self.shadows.to_string(),
                self.shadows.enabled(),
            ),
            (
                Setting::AmbientOcclusion,
                self.ambient_occlusion.to_string(),
                self.ambient_occlusion.enabled(),
            ),
        ] {
            if enabled && !cast_by_exact {
                return Err(Error::setting_value(
                    setting,
                    value,
                    crate::message![
                        "rays are cast only by ",
                        Setting::Method.with("exact"),
                        format!(", not by {}", self.method)
                    ],
                ));
            }
        }
        if let ColorMode::Magnitude {
            range: Some((lo, hi)),
        } = self.color
            && !(lo.is_finite() && hi.is_finite() && hi > lo)
        {
            return Err(Error::setting_value(
                Setting::MagnitudeRange,
                format!("{lo}:{hi}"),
                "needs low < high",
            ));
        }
        Ok(())
    }

    /// Whether rays are cast from the hits (shadows or ambient occlusion): the exact
    /// method then draws with shaders of their own.
    pub fn casts_rays(&self) -> bool {
        self.shadows.enabled() || self.ambient_occlusion.enabled()
    }

    /// What to tell a user who asks for shadows or ambient occlusion on glyphs whose
    /// shape takes no rays (ellipsoids, the reciprocal, plane and ratio glyphs: drawn
    /// without them), naming the first such shape of `shapes`; `None` when neither is
    /// asked for or every shape takes them. The command line prints it as a note,
    /// Python warns with it.
    pub fn shapes_without_rays_note(
        &self,
        shapes: impl IntoIterator<Item = crate::glyph::GlyphShape>,
    ) -> Option<String> {
        if !self.casts_rays() {
            return None;
        }
        let shape = shapes
            .into_iter()
            .find(|shape| *shape != crate::glyph::GlyphShape::Polynomial)?;
        Some(format!(
            "glyphs of shape {} receive and cast no shadows or ambient occlusion; they are \
             drawn without them",
            shape.name()
        ))
    }

    /// Refuses [`RenderPath::Compute`] for glyphs of `shapes` it cannot draw (any shape
    /// but the polynomial glyph): a refused setting, as `compute` with another method is,
    /// so that a front end refuses it in the same words (and exit code) before it opens
    /// a device. The compute pass refuses the same shapes itself.
    pub fn check_shapes(
        &self,
        shapes: impl IntoIterator<Item = crate::glyph::GlyphShape>,
    ) -> Result<()> {
        if self.path != RenderPath::Compute {
            return Ok(());
        }
        match shapes
            .into_iter()
            .find(|shape| *shape != crate::glyph::GlyphShape::Polynomial)
        {
            Some(shape) => Err(compute_refuses_shape(shape)),
            None => Ok(()),
        }
    }

    /// Worst-case number of march steps along one chord, with the centre zone's finer steps.
    pub fn max_steps(&self) -> i32 {
        let chord = 2.0 * (1.0 + self.offset);
        let zone = 2.0 * self.centre_zone.min(1.0 + self.offset);
        let steps = chord / self.step + zone / (self.step * self.centre_step_factor) + 4.0;
        steps.ceil().min(1.0e6) as i32
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn auto_takes_compute_on_gpus_where_it_draws_the_glyphs_and_fragment_elsewhere() {
        use crate::glyph::GlyphShape;
        use vk::PhysicalDeviceType as Kind;
        let polynomial = [GlyphShape::Polynomial];
        let path = |device, method, shapes: &[GlyphShape]| {
            RenderPath::Auto.on_device(device, method, shapes.iter().copied())
        };
        for gpu in [Kind::DISCRETE_GPU, Kind::INTEGRATED_GPU, Kind::VIRTUAL_GPU] {
            assert_eq!(path(gpu, Method::Exact, &polynomial), RenderPath::Compute);
            assert_eq!(path(gpu, Method::Exact, &[]), RenderPath::Compute);
            // Only the exact method and the polynomial glyph have a compute ray caster.
            assert_eq!(path(gpu, Method::Affine, &polynomial), RenderPath::Fragment);
            let mixed = [GlyphShape::Polynomial, GlyphShape::Ellipsoid];
            assert_eq!(path(gpu, Method::Exact, &mixed), RenderPath::Fragment);
        }
        for other in [Kind::CPU, Kind::OTHER] {
            assert_eq!(
                path(other, Method::Exact, &polynomial),
                RenderPath::Fragment
            );
        }
        // A path asked for is kept, whatever the device.
        for asked in [RenderPath::Fragment, RenderPath::Compute] {
            let on_cpu = asked.on_device(Kind::CPU, Method::Exact, polynomial);
            let on_gpu = asked.on_device(Kind::DISCRETE_GPU, Method::Exact, polynomial);
            assert_eq!((on_cpu, on_gpu), (asked, asked));
        }
        assert_eq!(RenderSettings::default().path, RenderPath::Auto);
        assert_eq!("auto".parse::<RenderPath>().unwrap(), RenderPath::Auto);
        let error = "gpu".parse::<RenderPath>().unwrap_err().to_string();
        assert!(
            error.contains("not one of auto, fragment, compute"),
            "{error}"
        );
    }

    #[test]
    fn every_method_parses_and_the_error_lists_them() {
        for (name, method) in [
            ("fixed", Method::Fixed),
            ("interval", Method::Interval),
            ("affine", Method::Affine),
            ("exact", Method::Exact),
        ] {
            assert_eq!(name.parse::<Method>().ok(), Some(method));
        }
        let error = "magic"
            .parse::<Method>()
            .expect_err("unknown method")
            .to_string();
        assert!(error.contains("fixed, interval, affine, exact"), "{error}");
    }

    /// The enum, the parser, the names and the compiled shaders all follow the one table
    /// of methods and orders in `crate::catalog`.
    #[test]
    fn methods_and_shaders_follow_the_catalog() {
        use crate::catalog::{RAY_CAST_METHODS, max_order};
        use crate::glyph::{Symmetry, TensorLayout};
        use crate::render::shaders::{compute_raycast_shader, raycast_shader};
        assert_eq!(Method::RAY_CASTING.len(), RAY_CAST_METHODS.len());
        for (method, entry) in Method::RAY_CASTING.into_iter().zip(RAY_CAST_METHODS) {
            assert_eq!(format!("{method:?}").to_lowercase(), entry.name);
            assert_eq!(method.to_string(), entry.name);
            assert_eq!(entry.name.parse::<Method>().ok(), Some(method));
            assert_eq!(method.marches(), entry.marches);
            for symmetry in [Symmetry::Symmetric, Symmetry::NonSymmetric] {
                let max = max_order(symmetry == Symmetry::Symmetric);
                for order in 1..=max + 1 {
                    let layout = TensorLayout { order, symmetry };
                    let drawable = order <= max;
                    let polynomial = crate::render::ShapeShader::Polynomial;
                    assert_eq!(
                        raycast_shader(layout, method, polynomial).is_some(),
                        drawable
                    );
                    let compute = compute_raycast_shader(layout, method).is_some();
                    assert_eq!(compute, drawable && entry.compute.is_some());
                }
            }
        }
    }

    /// Each glyph shape with a shader of its own is the catalog's entry of its name, and
    /// has shaders exactly for the layouts the entry lists (the exact method's key).
    #[test]
    fn glyph_shapes_and_their_shaders_follow_the_catalog() {
        use crate::catalog::{GLYPH_SHAPES, max_order};
        use crate::glyph::{GlyphShape, Symmetry, TensorLayout};
        use crate::render::ShapeShader;
        use crate::render::shaders::raycast_shader;
        let shapes = [
            GlyphShape::Ellipsoid,
            GlyphShape::Reciprocal,
            GlyphShape::PlaneMin,
            GlyphShape::PlaneMax,
            GlyphShape::RatioMin,
            GlyphShape::RatioMax,
        ];
        let mut seen = Vec::new();
        for shape in shapes {
            let shader = ShapeShader::of(shape);
            let entry = shader.entry().expect("a shape with a shader of its own");
            assert_eq!(format!("{shader:?}").to_lowercase(), entry.name);
            assert!(shader.asked().is_some());
            seen.push(entry.name);
            for symmetry in [Symmetry::Symmetric, Symmetry::NonSymmetric] {
                let symmetric = symmetry == Symmetry::Symmetric;
                for order in 1..=max_order(symmetric) {
                    let layout = TensorLayout { order, symmetry };
                    let compiled = raycast_shader(layout, Method::Exact, shader).is_some();
                    assert_eq!(compiled, entry.compiled_for(symmetric, order), "{shape:?}");
                }
            }
        }
        seen.dedup();
        let names: Vec<_> = GLYPH_SHAPES.iter().map(|e| e.name).collect();
        assert_eq!(seen, names, "every catalog shape is reached, in its order");
        assert_eq!(ShapeShader::of(GlyphShape::Polynomial).entry(), None);
    }

    #[test]
    fn precision_must_be_positive() {
        let zero = RenderSettings {
            precision_px: 0.0,
            ..Default::default()
        };
        assert!(zero.validate().is_err());
        assert!(RenderSettings::default().validate().is_ok());
    }

    #[test]
    fn the_compute_path_is_exact_only() {
        let compute = RenderSettings {
            path: "compute".parse().expect("compute"),
            ..Default::default()
        };
        assert!(compute.validate().is_ok());
        let fixed = RenderSettings {
            method: Method::Fixed,
            ..compute
        };
        let error = fixed.validate().expect_err("fixed");
        assert_eq!(error.setting_of(), Some(Setting::Path));
        let error = error.to_string();
        assert!(error.starts_with("path compute: "), "{error}");
        assert!(!error.contains("--"), "{error}");
        assert!("vertex".parse::<RenderPath>().is_err());
    }

    #[test]
    fn exact_refuses_an_offset() {
        let exact = RenderSettings {
            method: Method::Exact,
            ..Default::default()
        };
        assert!(exact.validate().is_ok());
        let with_offset = RenderSettings {
            offset: 0.1,
            ..exact
        };
        let error = with_offset.validate().expect_err("offset");
        assert_eq!(error.setting_of(), Some(Setting::Offset));
        assert_eq!(
            error.to_string(),
            "offset 0.1: method exact needs offset 0 (offset glyphs are not polynomial \
             surfaces); use method fixed"
        );
        let fixed = RenderSettings {
            method: Method::Fixed,
            ..with_offset
        };
        assert!(fixed.validate().is_ok());
    }
}
