//! The frame's parameter block, laid out exactly as `FrameParams` in glsl/frame.glsl (std140:
//! a mat4 and vec4/ivec4 members only, so there is no padding to get wrong).
use crate::camera::{Camera, Projection};
use crate::catalog::codes;
use crate::render::glyph_data::GlyphSetData;
use crate::render::settings::{ColorMode, Refinement, RenderSettings, SOFT_SHADOW_SAMPLES};
use bytemuck::{Pod, Zeroable};

/// The frame's parameter block (glsl/frame.glsl `FrameParams`, std430 = std140 here): camera, march
/// settings, colour and lighting. `render::interface` holds the offsets to the SPIR-V.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct FrameParams {
    /// World to clip space, column-major, with reversed depth (near plane at 1).
    pub view_proj: [[f32; 4]; 4],
    /// xyz: the eye; w: 1 for an orthographic camera, 0 for a perspective one.
    pub eye: [f32; 4],
    /// xyz: the camera's right axis times tan(fov/2) (or the half height); w: aspect W/H.
    pub right: [f32; 4],
    /// xyz: the camera's up axis, scaled as `right`.
    pub up: [f32; 4],
    /// xyz: the viewing direction (unit).
    pub fwd: [f32; 4],
    /// x: 1/width, y: 1/height (pixels); z: the near plane's distance (0 orthographic).
    pub viewport: [f32; 4],
    /// x: step, y: centre step factor, z: centre zone radius (units of the bound), w:
    /// offset.
    pub march: [f32; 4],
    /// x: refinement (`catalog::codes::REFINE_*`), y: its steps, z: colour mode
    /// (`catalog::codes::COLOR_*`), w: the march's step limit.
    pub modes: [i32; 4],
    /// x: the magnitude range's low end, y: 1 / (high - low) (world units).
    pub magnitude_range: [f32; 4],
    /// rgb (linear): the uniform colour, or `--color sign`'s positive lobes'.
    pub uniform_color: [f32; 4],
    /// xyz: unit direction towards the light, world space.
    pub light: [f32; 4],
    /// x: the robust methods' segment limit, the precision in pixels times one pixel's
    /// footprint at unit distance (world units if orthographic).
    pub robust: [f32; 4],
    /// `--color sign`: the negative lobes' colour (rgb, linear); `uniform_color` holds the
    /// positive lobes'.
    pub negative_color: [f32; 4],
    /// Blinn-Phong terms ([`crate::render::settings::Lighting`]): x ambient, y specular
    /// strength, z shininess.
    pub shading: [f32; 4],
    /// xy: the viewport's origin in framebuffer pixels (0 but for a host's
    /// sub-rectangle); z: the window depth of the near plane, where the ray-cast pass puts
    /// boxes that the near plane cuts (1 for reversed depth, 0 for standard).
    pub window: [f32; 4],
    /// Shadows and ambient occlusion ([`crate::render::settings::Shadows`],
    /// [`crate::render::settings::AmbientOcclusion`], glsl/shadow.glsl): x the occlusion
    /// rays' reach in bounding radii of the hit glyph (0: none), y rays towards the light
    /// per hit (0 none, 1 hard, `SOFT_SHADOW_SAMPLES` soft), z the tangent of the
    /// light's angular radius, w where a shadow ray starts: that fraction of the hit
    /// glyph's bounding radius along the ray
    /// (`SHADOW_RAY_OFFSET`). Either x or y above 0 picks the
    /// shaders that cast rays from the hits ([`FrameParams::casts_rays`]).
    pub shadow: [f32; 4],
}

/// How every pass binds the frame block (and the underlay its parameters): as a read-only
/// storage buffer, not a uniform buffer. lavapipe (Mesa 22.3) inlines the values of
/// uniform-buffer members that steer a branch or a loop into the shader and compiles it
/// again for every command buffer: for the exact method 10 to 20 ms a frame whatever the
/// image size, and memory that grew by megabytes a frame. Storage-buffer reads are left
/// alone. glsl/frame.glsl declares the block to match; `render::interface` checks it.
pub(crate) const FRAME_DESCRIPTOR: ash::vk::DescriptorType =
    ash::vk::DescriptorType::STORAGE_BUFFER;

/// The usage of the buffer that holds the frame block ([`FRAME_DESCRIPTOR`]).
pub(crate) const FRAME_USAGE: ash::vk::BufferUsageFlags = ash::vk::BufferUsageFlags::STORAGE_BUFFER;

/// Depth range and magnitude range of what is drawn.
#[derive(Clone, Copy, Debug)]
pub struct SceneExtent {
    /// Nearest eye depth any glyph's box reaches (world units along the view direction).
    pub near: f64,
    /// Farthest eye depth any glyph's box reaches.
    pub far: f64,
    /// The largest glyph radius drawn (world units): the top of `--color magnitude`'s
    /// default range, which starts at 0.
    pub max_radius: f64,
}

impl SceneExtent {
    /// From the boxes of prepared glyph sets: each box's half-diagonal bounds what its
    /// rasterised cube can reach; the largest radius is the sets' own
    /// ([`GlyphSetData::largest_radius`]) where it was measured, so that the largest glyph
    /// reaches the top of the colour map, else the largest box's.
    pub fn of_glyph_sets(camera: &Camera, sets: &[GlyphSetData]) -> SceneExtent {
        let largest = sets.iter().map(|s| s.largest_radius).fold(0.0, f64::max);
        let boxes = SceneExtent::of_spheres(
            camera,
            sets.iter().flat_map(|s| s.instances.iter()).map(|i| {
                let center = [i[0] as f64, i[1] as f64, i[2] as f64];
                (center, i[3] as f64 * 3f64.sqrt())
            }),
        );
        SceneExtent {
            max_radius: if largest > 0.0 {
                largest
            } else {
                boxes.max_radius
            },
            ..boxes
        }
    }

    /// [`SceneExtent::of_glyph_sets`] for a frame drawn with `settings`: when they need the
    /// largest glyph radius and no set has it yet, it is measured here from the float64
    /// glyphs (the headless renderer and the viewer frame with this).
    pub fn for_settings(
        camera: &Camera,
        sets: &[GlyphSetData],
        settings: &RenderSettings,
    ) -> SceneExtent {
        let mut extent = SceneExtent::of_glyph_sets(camera, sets);
        let measured = sets.iter().any(|s| s.largest_radius > 0.0);
        if settings.needs_largest_radius() && !measured {
            let largest = sets
                .iter()
                .map(|s| crate::render::glyph_data::largest_radius(&s.world))
                .fold(0.0, f64::max);
            if largest > 0.0 {
                extent.max_radius = largest;
            }
        }
        extent
    }

    /// From bounding spheres (centre, radius) seen by `camera`; the largest sphere's
    /// radius stands for the largest glyph's.
    pub fn of_spheres(
        camera: &Camera,
        spheres: impl Iterator<Item = ([f64; 3], f64)>,
    ) -> SceneExtent {
        let frame = camera.frame();
        let (mut lo, mut hi, mut max_radius) = (f64::INFINITY, f64::NEG_INFINITY, 0.0f64);
        for (c, r) in spheres {
            let z = frame.fwd.dot(glam::DVec3::from(c) - camera.eye);
            lo = lo.min(z - r);
            hi = hi.max(z + r);
            max_radius = max_radius.max(r);
        }
        if !hi.is_finite() || hi <= 0.0 {
            return SceneExtent {
                near: 0.1,
                far: 10.0,
                max_radius: 1.0,
            };
        }
        let far = hi * 1.01 + 1e-6;
        let near = match camera.projection {
            // Perspective depth needs near > 0. Reversed depth (near / e) keeps its
            // relative precision at any distance, so near can be tiny: only what lies
            // nearer than it is cut, and a box that the near plane cuts is still drawn
            // (raycast.vert), its ray-cast depths clamped to 1.
            Projection::Perspective { .. } => {
                if lo > 0.0 {
                    (lo * 0.99).max(far * 1e-9)
                } else {
                    far * 1e-9
                }
            }
            Projection::Orthographic { .. } => lo - 0.01 * (hi - lo) - 1e-6,
        };
        SceneExtent {
            near,
            far,
            max_radius,
        }
    }
}

/// The range `--color magnitude` maps onto its colours (world units): the settings' own,
/// or 0 to the largest glyph radius of `extent`; `None` for the other colour modes. The
/// colour bar reads it from here, so that it shows the range the shaders use.
pub fn magnitude_range(settings: &RenderSettings, extent: &SceneExtent) -> Option<(f32, f32)> {
    match settings.color {
        ColorMode::Magnitude { range } => Some(range.unwrap_or((0.0, extent.max_radius as f32))),
        _ => None,
    }
}

impl FrameParams {
    /// Whether the block asks for rays from the hits (shadows or ambient occlusion): the
    /// exact method then draws with the shaders that cast them.
    pub fn casts_rays(&self) -> bool {
        self.shadow[0] > 0.0 || self.shadow[1] > 0.0
    }

    /// The block for `camera` at `width` x `height` pixels, with the depth and magnitude
    /// ranges of `extent` and the march, colour and lighting of `settings`.
    pub fn new(
        camera: &Camera,
        width: u32,
        height: u32,
        extent: &SceneExtent,
        settings: &RenderSettings,
    ) -> Self {
        let f = camera.frame();
        let (ortho, scale) = match camera.projection {
            Projection::Perspective { fov_y_deg } => (0.0, (fov_y_deg.to_radians() * 0.5).tan()),
            Projection::Orthographic { height } => (1.0, 0.5 * height),
        };
        let v4 = |v: glam::DVec3, w: f32| [v.x as f32, v.y as f32, v.z as f32, w];
        // The light is given in view coordinates (x right, y up, z towards the viewer).
        let lighting = &settings.lighting;
        let [lx, ly, lz] = lighting.unit_direction().map(f64::from);
        let light = (lx * f.right + ly * f.up - lz * f.fwd).normalize();
        FrameParams {
            view_proj: camera
                .view_projection_f32(width, height, extent.near, extent.far)
                .to_cols_array_2d(),
            eye: v4(camera.eye, ortho),
            right: v4(f.right * scale, (width as f64 / height as f64) as f32),
            up: v4(f.up * scale, 0.0),
            fwd: v4(f.fwd, 0.0),
            // z: the near plane's distance along the view direction (perspective), which
            // the box pass uses to draw glyphs that the near plane cuts.
            viewport: [
                1.0 / width as f32,
                1.0 / height as f32,
                if ortho > 0.0 { 0.0 } else { extent.near as f32 },
                0.0,
            ],
            light: v4(light, 0.0),
            // One pixel spans 2 scale / height: at unit distance (perspective) or in world
            // units (orthographic).
            robust: [
                settings.precision_px * (2.0 * scale / height as f64) as f32,
                0.0,
                0.0,
                0.0,
            ],
            ..FrameParams::of_settings(extent, settings)
        }
    }

    /// The block's members that the settings decide (march, colour, shading), the camera's
    /// zero; the window at the origin with reversed depth.
    pub(crate) fn of_settings(extent: &SceneExtent, settings: &RenderSettings) -> Self {
        let (refine_mode, bisections) = match settings.refinement {
            Refinement::None => (codes::REFINE_NONE, 0),
            Refinement::Bisect(k) => (codes::REFINE_BISECT, k as i32),
            Refinement::Interpolate => (codes::REFINE_INTERP, 0),
            Refinement::Secant(k) => (codes::REFINE_SECANT, k as i32),
        };
        let (color_mode, range, uniform, negative) = match settings.color {
            ColorMode::Direction => (codes::COLOR_DIRECTION, (0.0, 1.0), [0.0; 3], [0.0; 3]),
            ColorMode::Magnitude { .. } => (
                codes::COLOR_MAGNITUDE,
                magnitude_range(settings, extent).unwrap_or((0.0, 1.0)),
                [0.0; 3],
                [0.0; 3],
            ),
            ColorMode::Uniform(rgb) => (codes::COLOR_UNIFORM, (0.0, 1.0), rgb, [0.0; 3]),
            ColorMode::Sign { positive, negative } => {
                (codes::COLOR_SIGN, (0.0, 1.0), positive, negative)
            }
        };
        let lighting = &settings.lighting;
        FrameParams {
            march: [
                settings.step,
                settings.centre_step_factor,
                settings.centre_zone,
                settings.offset,
            ],
            modes: [refine_mode, bisections, color_mode, settings.max_steps()],
            magnitude_range: [range.0, 1.0 / (range.1 - range.0).max(1e-30), 0.0, 0.0],
            uniform_color: [uniform[0], uniform[1], uniform[2], 1.0],
            negative_color: [negative[0], negative[1], negative[2], 1.0],
            shading: [lighting.ambient, lighting.specular, lighting.shininess, 0.0],
            window: [0.0, 0.0, 1.0, 0.0],
            shadow: [
                settings.ambient_occlusion.reach(),
                match settings.shadows {
                    crate::render::Shadows::Off => 0.0,
                    crate::render::Shadows::Hard => 1.0,
                    crate::render::Shadows::Soft { .. } => SOFT_SHADOW_SAMPLES as f32,
                },
                settings.shadows.radius_deg().to_radians().tan(),
                crate::glyph::shadow::SHADOW_RAY_OFFSET as f32,
            ],
            ..FrameParams::zeroed()
        }
    }
}
