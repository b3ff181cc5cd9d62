//! The render options as the front ends take them (the CLI's flags, the Python module's
//! keyword arguments): text and numbers, turned into [`RenderSettings`] with one set of
//! defaults and one set of checks, so that both front ends read alike. A refused value
//! is an [`Error::Setting`] naming the [`Setting`]; each front end spells it (`--step`,
//! `step=`).
use crate::camera::Camera;
use crate::error::Relation;
use crate::error::quoted;
use crate::glyph::{GlyphShape, NegativeMode};
use crate::render::glyph_data::{
    GlyphSetData, WorldGlyphs, measure_largest_radius, prepare_scene_with,
};
use crate::render::peaks::PeakSet;
use crate::render::promote::promote_small_sets;
use crate::render::settings::{parse_background, parse_light};
use crate::render::{ColorMode, Method, Refinement, RenderSettings};
use crate::scene::Scene;
use crate::vk::GpuOptions;
use crate::{Error, Result, Setting};

/// The render options, unparsed; `None` (or `false`) is the default. Each field is the
/// [`Setting`] of the same name.
#[derive(Clone, Debug, Default)]
pub struct RenderOptions {
    /// `--method`: fixed, interval, affine, exact, impostor, mesh:LEVEL or latlong:N.
    /// Default exact, or affine with a nonzero offset.
    pub method: Option<String>,
    /// `--path`: fragment (the default) or compute.
    pub path: Option<String>,
    /// `--precision`: segment length limit of the robust methods, in pixels.
    pub precision: Option<f32>,
    /// `--step`: march step, in units of each glyph's bounding radius.
    pub step: Option<f32>,
    /// `--refine`: bisect:K, interp or none.
    pub refine: Option<String>,
    /// `--color`: direction (the default), magnitude, uniform or sign.
    pub color: Option<String>,
    /// `--magnitude-range`: LOW:HIGH in world units.
    pub magnitude_range: Option<String>,
    /// `--negative`: abs or hide, replacing every glyph set's mode.
    pub negative: Option<String>,
    /// `--background`: none, dark (the default), black, white, grey, #rrggbb or r,g,b.
    pub background: Option<String>,
    /// `--offset`: isotropic offset, as a fraction of each glyph's bounding radius.
    pub offset: f32,
    /// `--light`: X,Y,Z, the direction towards the light in view coordinates.
    pub light: Option<String>,
    /// `--ambient`: 0 to 1.
    pub ambient: Option<f32>,
    /// `--specular`: 0 to 1.
    pub specular: Option<f32>,
    /// `--shininess`: 1 to 1024.
    pub shininess: Option<f32>,
    /// `--samples`: 1, 4 or 16 samples per pixel.
    pub samples: Option<u32>,
    /// `--device`: part of the Vulkan device's name or its index (also GLYPHCAST_DEVICE).
    pub device: Option<String>,
    /// `--validation`: the Vulkan validation layer (also GLYPHCAST_VALIDATION=1).
    pub validation: bool,
}

impl RenderOptions {
    /// The render settings these options ask for; a bad value is an [`Error::Setting`]
    /// that names the option.
    pub fn settings(&self) -> Result<RenderSettings> {
        let method = match &self.method {
            Some(name) => name.parse::<Method>()?,
            None if self.offset != 0.0 => Method::Affine,
            None => RenderSettings::default().method,
        };
        let mut s = RenderSettings {
            method,
            ..Default::default()
        };
        if let Some(path) = &self.path {
            s.path = path.parse()?;
        }
        if let Some(step) = self.step {
            s.step = step;
        }
        if let Some(precision) = self.precision {
            s.precision_px = precision;
        }
        if let Some(refine) = &self.refine {
            s.refinement = refine.parse::<Refinement>()?;
        }
        if let Some(color) = &self.color {
            s.color = color.parse::<ColorMode>()?;
        }
        if let Some(range) = &self.magnitude_range {
            let range = parse_range(range)?;
            // The range maps the magnitude colours only: with another colour it would be
            // ignored (or, as before, replace the colour asked for).
            if !matches!(s.color, ColorMode::Magnitude { .. }) {
                return Err(Error::conflict(
                    Setting::MagnitudeRange,
                    Relation::Requires,
                    Setting::Color.with("magnitude"),
                ));
            }
            s.color = ColorMode::Magnitude { range: Some(range) };
        }
        if let Some(background) = &self.background {
            s.background = parse_background(background)?;
        }
        if let Some(light) = &self.light {
            s.lighting.direction = parse_light(light)?;
        }
        s.lighting.ambient = self.ambient.unwrap_or(s.lighting.ambient);
        s.lighting.specular = self.specular.unwrap_or(s.lighting.specular);
        s.lighting.shininess = self.shininess.unwrap_or(s.lighting.shininess);
        s.samples = self.samples.unwrap_or(s.samples);
        s.offset = self.offset;
        s.validate()?;
        Ok(s)
    }

    /// The negative-lobe mode asked for, if any.
    pub fn negative(&self) -> Result<Option<NegativeMode>> {
        let parse = |text: &str| match text {
            "abs" => Ok(NegativeMode::Abs),
            "hide" => Ok(NegativeMode::Hide),
            _ => Err(Error::setting_value(
                Setting::Negative,
                format!("'{}'", quoted(text)),
                "not one of abs, hide",
            )),
        };
        self.negative.as_deref().map(parse).transpose()
    }

    /// The device options: the environment's (GLYPHCAST_VALIDATION, GLYPHCAST_DEVICE),
    /// with `validation` and `device` on top.
    pub fn gpu_options(&self) -> GpuOptions {
        let mut options = GpuOptions::from_env();
        options.validation |= self.validation;
        if self.device.is_some() {
            options.device = self.device.clone();
        }
        options
    }
}

/// A scene made ready for [`HeadlessRenderer`](crate::render::headless::HeadlessRenderer):
/// its glyph sets prepared, with the camera, image size and settings to draw them with.
pub struct PreparedScene {
    /// The glyph sets, GPU-ready.
    pub sets: Vec<GlyphSetData>,
    /// The scene's camera.
    pub camera: Camera,
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// How to draw.
    pub settings: RenderSettings,
    /// Fibre peaks drawn with the glyphs, if any (the caller's: a volume view's).
    pub peaks: Option<PeakSet>,
}

impl PreparedScene {
    /// Glyphs in all sets.
    pub fn glyph_count(&self) -> usize {
        self.sets.iter().map(GlyphSetData::len).sum()
    }
}

/// Prepares `scene` for rendering with `settings`, every polynomial set's negative mode
/// replaced by `negative` if given (ellipsoids have no negative lobes): what `glyphcast render` and the Python module do before the GPU
/// work. The scene's float64 glyphs are kept only where a mesh method tessellates them,
/// and the scene is dropped (a million glyphs: most of a gigabyte). Small symmetric sets
/// of lower orders are raised to the highest order of their parity
/// ([`promote_small_sets`]): a one-shot image then creates fewer pipelines.
pub fn prepare_render(
    mut scene: Scene,
    settings: RenderSettings,
    negative: Option<NegativeMode>,
) -> Result<PreparedScene> {
    check_negative(&scene, negative)?;
    if let Some(mode) = negative {
        scene
            .glyph_sets
            .iter_mut()
            .filter(|set| set.shape == GlyphShape::Polynomial)
            .for_each(|set| set.negative = mode);
    }
    let mesh = matches!(settings.method, Method::Mesh(_));
    let world = if mesh || settings.needs_largest_radius() {
        WorldGlyphs::Keep
    } else {
        WorldGlyphs::Leave
    };
    let mut sets = prepare_scene_with(&scene, settings.offset as f64, world)?;
    if settings.needs_largest_radius() {
        measure_largest_radius(&mut sets);
    }
    let (width, height) = (scene.image.width, scene.image.height);
    promote_small_sets(&mut sets, &scene.camera, width, height, &settings);
    if !mesh {
        sets.iter_mut().for_each(|s| s.drop_reference_glyphs());
    }
    Ok(PreparedScene {
        sets,
        camera: scene.camera,
        width: scene.image.width,
        height: scene.image.height,
        settings,
        peaks: None,
    })
}

/// Refuses a negative mode that no glyph set of `scene` takes: `hide` when every set is
/// drawn as the ellipsoid (`--glyph ellipsoid`), which has no negative lobes. A scene
/// that mixes shapes hides the polynomial sets' lobes.
pub fn check_negative(scene: &Scene, negative: Option<NegativeMode>) -> Result<()> {
    let Some(mode) = negative else {
        return Ok(());
    };
    let takes = |set: &crate::scene::GlyphSet| set.shape.takes(mode);
    if scene.glyph_sets.is_empty() || scene.glyph_sets.iter().any(takes) {
        return Ok(());
    }
    Err(Error::setting_value(
        Setting::Negative,
        "hide",
        crate::message![
            "the ellipsoid has no negative lobes to hide (",
            Setting::Glyph.with("ellipsoid"),
            " draws every glyph set as one); use ",
            Setting::Negative.with("abs"),
            " or leave it out"
        ],
    ))
}

/// The march and range settings a one-shot image refuses when its method does not read
/// them (`step` for fixed only, `refine` for fixed, interval and affine, `precision` for
/// interval and affine): given with another method they would change nothing. The
/// viewer takes them all, since its method can be switched to one that reads them.
pub fn check_method_reads(options: &RenderOptions, settings: &RenderSettings) -> Result<()> {
    let method = settings.method;
    let entry = method.ray_cast_entry();
    let marches = method.marches();
    let ranges = entry.is_some_and(|e| e.uses_ranges);
    let unread = |setting: Setting, value: String, readers: &[&str]| {
        let mut pieces: Vec<crate::error::Piece> = vec!["is read only by ".into()];
        for (n, reader) in readers.iter().enumerate() {
            if n > 0 {
                pieces.push(", ".into());
            }
            pieces.push(Setting::Method.with(reader));
        }
        pieces.extend([
            "; ".into(),
            Setting::Method.with(method),
            " does not read it (leave it out, or choose a method that does)".into(),
        ]);
        Error::setting_value(setting, value, crate::error::Message::from_pieces(pieces))
    };
    if let Some(step) = options.step.filter(|_| !marches) {
        return Err(unread(Setting::Step, step.to_string(), &["fixed"]));
    }
    if let Some(precision) = options.precision.filter(|_| !ranges) {
        let readers = ["interval", "affine"];
        return Err(unread(Setting::Precision, precision.to_string(), &readers));
    }
    if let Some(refine) = options.refine.as_ref().filter(|_| !(marches || ranges)) {
        let readers = ["fixed", "interval", "affine"];
        let value = format!("'{}'", quoted(refine));
        return Err(unread(Setting::Refine, value, &readers));
    }
    Ok(())
}

/// `LOW:HIGH`, two numbers.
fn parse_range(range: &str) -> Result<(f32, f32)> {
    let parsed = range
        .split_once(':')
        .and_then(|(lo, hi)| Some((lo.parse::<f32>().ok()?, hi.parse::<f32>().ok()?)));
    parsed.ok_or_else(|| {
        Error::setting_value(
            Setting::MagnitudeRange,
            format!("'{}'", quoted(range)),
            "not LOW:HIGH",
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defaults_are_the_render_settings_defaults() {
        let settings = RenderOptions::default().settings().unwrap();
        let expected = RenderSettings::default();
        assert_eq!(settings.method, expected.method);
        assert_eq!(settings.path, expected.path);
        assert_eq!(settings.color, expected.color);
        assert_eq!(settings.background, expected.background);
        assert_eq!(RenderOptions::default().negative().unwrap(), None);
    }

    #[test]
    fn options_reach_the_settings() {
        let options = RenderOptions {
            offset: 0.2,
            color: Some("magnitude".into()),
            magnitude_range: Some("0.5:2".into()),
            negative: Some("hide".into()),
            ..Default::default()
        };
        let settings = options.settings().unwrap();
        // An offset glyph is no polynomial surface: affine, not exact.
        assert_eq!(settings.method, Method::Affine);
        assert_eq!(
            settings.color,
            ColorMode::Magnitude {
                range: Some((0.5, 2.0))
            }
        );
        assert_eq!(options.negative().unwrap(), Some(NegativeMode::Hide));
    }

    /// A range maps the magnitude colours only: with another colour (or the default)
    /// it is refused, naming both settings, not dropped or put in the colour's place.
    #[test]
    fn a_magnitude_range_needs_the_magnitude_colour() {
        for color in [None, Some("direction"), Some("sign")] {
            let options = RenderOptions {
                color: color.map(str::to_owned),
                magnitude_range: Some("0:1".into()),
                ..Default::default()
            };
            let err = options.settings().unwrap_err();
            assert_eq!(err.setting_of(), Some(Setting::MagnitudeRange), "{color:?}");
            assert!(err.is_usage(), "{err}");
            assert_eq!(err.to_string(), "magnitude range needs color magnitude");
        }
    }

    /// The march step is read by fixed only, the precision by interval and affine, the
    /// refinement by all three: given with a method that does not read them they are
    /// refused, naming the setting and the method.
    #[test]
    fn settings_the_method_does_not_read_are_refused() {
        type Edit = fn(&mut RenderOptions);
        let check = |method: &str, edit: Edit| {
            let mut options = RenderOptions {
                method: Some(method.into()),
                ..Default::default()
            };
            edit(&mut options);
            let settings = options.settings().unwrap();
            check_method_reads(&options, &settings)
        };
        let step: Edit = |o| o.step = Some(0.01);
        let precision: Edit = |o| o.precision = Some(0.5);
        let refine: Edit = |o| o.refine = Some("none".into());
        let cases: [(&str, Edit, Setting, bool); 12] = [
            ("fixed", step, Setting::Step, true),
            ("exact", step, Setting::Step, false),
            ("affine", step, Setting::Step, false),
            ("impostor", step, Setting::Step, false),
            ("interval", precision, Setting::Precision, true),
            ("affine", precision, Setting::Precision, true),
            ("fixed", precision, Setting::Precision, false),
            ("exact", precision, Setting::Precision, false),
            ("fixed", refine, Setting::Refine, true),
            ("interval", refine, Setting::Refine, true),
            ("exact", refine, Setting::Refine, false),
            ("mesh:2", refine, Setting::Refine, false),
        ];
        for (method, edit, setting, read) in cases {
            match check(method, edit) {
                Ok(()) => assert!(read, "{method} {setting:?} was not refused"),
                Err(err) => {
                    assert!(!read, "{method} {setting:?}: {err}");
                    assert_eq!(err.setting_of(), Some(setting), "{err}");
                    assert!(err.is_usage(), "{err}");
                    let text = err.to_string();
                    assert!(
                        text.contains(&format!("method {method} does not read it")),
                        "{text}"
                    );
                }
            }
        }
        // Nothing given, nothing refused.
        let options = RenderOptions::default();
        check_method_reads(&options, &options.settings().unwrap()).unwrap();
    }

    fn dti_scene(scale: f64, coeff: f64) -> Scene {
        use crate::scene::{GlyphKind, GlyphSet, ImageSize};
        use glam::DVec3;
        Scene {
            glyph_sets: vec![GlyphSet {
                kind: GlyphKind::Tensor(crate::glyph::ellipsoid::ELLIPSOID_LAYOUT),
                negative: NegativeMode::Abs,
                shape: GlyphShape::Polynomial,
                centers: vec![DVec3::ZERO, DVec3::X],
                scales: vec![0.4, scale],
                coeffs: vec![
                    vec![1.0, 0.0, 0.0, 1.0, 0.0, 1.0],
                    vec![coeff, 0.0, 0.0, coeff, 0.0, coeff],
                ],
            }],
            camera: Camera {
                projection: crate::camera::Projection::Perspective { fov_y_deg: 30.0 },
                eye: DVec3::new(0.0, -6.0, 2.0),
                target: DVec3::ZERO,
                up: DVec3::Z,
            },
            image: ImageSize {
                width: 8,
                height: 8,
            },
        }
    }

    /// `--glyph ellipsoid --negative hide`: the ellipsoid has no lobes to hide, so the
    /// mode is refused (as the scene format refuses the pair), not dropped.
    #[test]
    fn hiding_negative_lobes_of_ellipsoids_only_is_refused() {
        let settings = RenderSettings::default();
        let mut scene = dti_scene(0.4, 1.0);
        scene.set_shape(GlyphShape::Ellipsoid).unwrap();
        let hide = Some(NegativeMode::Hide);
        let err = prepare_render(scene.clone(), settings, hide).err().unwrap();
        assert_eq!(err.setting_of(), Some(Setting::Negative), "{err}");
        assert!(err.is_usage(), "{err}");
        assert!(err.to_string().contains("glyph ellipsoid"), "{err}");
        prepare_render(scene.clone(), settings, Some(NegativeMode::Abs)).unwrap();
        prepare_render(scene, settings, None).unwrap();
        // Polynomial glyphs have lobes to hide.
        prepare_render(dti_scene(0.4, 1.0), settings, hide).unwrap();
    }

    /// A glyph whose world size overflows float32 (a large scale times a large tensor,
    /// each within float32) would be drawn as nothing: preparation refuses it by index.
    #[test]
    fn a_glyph_too_large_for_float32_is_refused() {
        let settings = RenderSettings::default();
        prepare_render(dti_scene(1e30, 1e7), settings, None).unwrap();
        let err = prepare_render(dti_scene(1e30, 1e10), settings, None)
            .err()
            .unwrap();
        let text = err.to_string();
        assert!(!err.is_usage(), "{text}");
        assert!(text.contains("glyph set 0"), "{text}");
        assert!(text.contains("glyph 1"), "{text}");
        assert!(text.contains("world radius"), "{text}");
    }

    #[test]
    fn bad_values_name_the_option() {
        let bad = |options: RenderOptions| options.settings().unwrap_err();
        let range = bad(RenderOptions {
            magnitude_range: Some("1-2".into()),
            ..Default::default()
        });
        assert_eq!(range.setting_of(), Some(Setting::MagnitudeRange));
        assert_eq!(range.to_string(), "magnitude range '1-2': not LOW:HIGH");
        let negative = RenderOptions {
            negative: Some("show".into()),
            ..Default::default()
        };
        let negative = negative.negative().unwrap_err();
        assert_eq!(negative.setting_of(), Some(Setting::Negative));
        assert_eq!(
            negative.to_string(),
            "negative 'show': not one of abs, hide"
        );
        // Every option's refusal names its setting, and no front end's spelling of it.
        for (options, setting) in [
            (
                RenderOptions {
                    step: Some(1e-5),
                    ..Default::default()
                },
                Setting::Step,
            ),
            (
                RenderOptions {
                    precision: Some(100.0),
                    ..Default::default()
                },
                Setting::Precision,
            ),
            (
                RenderOptions {
                    method: Some("exact".into()),
                    offset: 0.1,
                    ..Default::default()
                },
                Setting::Offset,
            ),
            (
                RenderOptions {
                    method: Some("magic".into()),
                    ..Default::default()
                },
                Setting::Method,
            ),
            (
                RenderOptions {
                    method: Some("mesh:99".into()),
                    ..Default::default()
                },
                Setting::Method,
            ),
            (
                RenderOptions {
                    refine: Some("bisect:99".into()),
                    ..Default::default()
                },
                Setting::Refine,
            ),
            (
                RenderOptions {
                    path: Some("vertex".into()),
                    ..Default::default()
                },
                Setting::Path,
            ),
            (
                RenderOptions {
                    color: Some("sign".into()),
                    method: Some("impostor".into()),
                    ..Default::default()
                },
                Setting::Color,
            ),
            (
                RenderOptions {
                    background: Some("mauve".into()),
                    ..Default::default()
                },
                Setting::Background,
            ),
            (
                RenderOptions {
                    light: Some("0,0,0".into()),
                    ..Default::default()
                },
                Setting::Light,
            ),
            (
                RenderOptions {
                    ambient: Some(2.0),
                    ..Default::default()
                },
                Setting::Ambient,
            ),
            (
                RenderOptions {
                    shininess: Some(0.0),
                    ..Default::default()
                },
                Setting::Shininess,
            ),
            (
                RenderOptions {
                    samples: Some(3),
                    ..Default::default()
                },
                Setting::Samples,
            ),
        ] {
            let err = bad(options);
            assert_eq!(err.setting_of(), Some(setting), "{err}");
            let text = err.to_string();
            assert!(text.starts_with(setting.name()), "{text}");
            assert!(!text.contains("--"), "{text}");
            // A front end's spelling reaches every mention, the subject's and others.
            let flags = err.spelled(&|s, v| match v {
                Some(v) => format!("<{s} {v}>"),
                None => format!("<{s}>"),
            });
            assert!(flags.starts_with(&format!("<{setting}")), "{flags}");
        }
    }
}
