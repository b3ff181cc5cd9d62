//! A scene prepared for rendering with the render options ([`RenderOptions`], declared in
//! [`crate::render::table`]): the glyph sets made GPU-ready, the negative mode applied.
use crate::camera::Camera;
use crate::glyph::{GlyphShape, NegativeMode};
use crate::render::glyph_data::{
    GlyphSetData, WorldGlyphs, add_pieces, measure_largest_radius, prepare_scene_with,
};
use crate::render::peaks::PeakSet;
use crate::render::promote::promote_small_sets;
use crate::render::{Method, Proxy, RenderSettings};
use crate::scene::Scene;
use crate::{Error, Result, Setting};

pub use crate::render::table::{RenderOptions, Value};

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
    let pieces = settings.proxy == Proxy::Pieces;
    let world = if mesh || pieces || settings.needs_largest_radius() {
        WorldGlyphs::Keep
    } else {
        WorldGlyphs::Leave
    };
    let mut sets = prepare_scene_with(&scene, settings.offset as f64, world)?;
    if settings.needs_largest_radius() {
        measure_largest_radius(&mut sets);
    }
    if pieces {
        add_pieces(&mut sets)?;
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
pub(crate) fn check_negative(scene: &Scene, negative: Option<NegativeMode>) -> Result<()> {
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::ColorMode;

    /// Options from text, as the command line gives them.
    fn options(pairs: &[(Setting, &str)]) -> RenderOptions {
        let mut options = RenderOptions::default();
        for &(setting, text) in pairs {
            options.set(setting, Value::Text(text)).unwrap();
        }
        options
    }

    #[test]
    fn options_reach_the_settings() {
        let options = options(&[
            (Setting::Offset, "0.2"),
            (Setting::Color, "magnitude"),
            (Setting::MagnitudeRange, "0.5:2"),
            (Setting::Negative, "hide"),
        ]);
        let settings = options.settings().unwrap();
        // An offset glyph is no polynomial surface: affine, not exact.
        assert_eq!(settings.method, Method::Affine);
        assert_eq!(
            settings.color,
            ColorMode::Magnitude {
                range: Some((0.5, 2.0))
            }
        );
        assert_eq!(options.negative, Some(NegativeMode::Hide));
    }

    /// A range maps the magnitude colours only: with another colour (or the default)
    /// it is refused, naming both settings, not dropped or put in the colour's place.
    #[test]
    fn a_magnitude_range_needs_the_magnitude_colour() {
        for color in [None, Some("direction"), Some("sign")] {
            let mut pairs = vec![(Setting::MagnitudeRange, "0:1")];
            pairs.extend(color.map(|c| (Setting::Color, c)));
            let err = options(&pairs).settings().unwrap_err();
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
        let cases = [
            ("fixed", (Setting::Step, "0.01"), true),
            ("exact", (Setting::Step, "0.01"), false),
            ("affine", (Setting::Step, "0.01"), false),
            ("impostor", (Setting::Step, "0.01"), false),
            ("interval", (Setting::Precision, "0.5"), true),
            ("affine", (Setting::Precision, "0.5"), true),
            ("fixed", (Setting::Precision, "0.5"), false),
            ("exact", (Setting::Precision, "0.5"), false),
            ("fixed", (Setting::Refine, "none"), true),
            ("interval", (Setting::Refine, "none"), true),
            ("exact", (Setting::Refine, "none"), false),
            ("mesh:2", (Setting::Refine, "none"), false),
        ];
        for (method, (setting, value), read) in cases {
            let options = options(&[(Setting::Method, method), (setting, value)]);
            let settings = options.settings().unwrap();
            match options.check_method_reads(&settings) {
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
        options
            .check_method_reads(&options.settings().unwrap())
            .unwrap();
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
        let mut options = RenderOptions::default();
        let range = options
            .set(Setting::MagnitudeRange, Value::Text("1-2"))
            .unwrap_err();
        assert_eq!(range.setting_of(), Some(Setting::MagnitudeRange));
        assert_eq!(range.to_string(), "magnitude range '1-2': not LOW:HIGH");
        let negative = options
            .set(Setting::Negative, Value::Text("show"))
            .unwrap_err();
        assert_eq!(negative.setting_of(), Some(Setting::Negative));
        assert_eq!(
            negative.to_string(),
            "negative 'show': not one of abs, hide"
        );
        // Every option's refusal names its setting, and no front end's spelling of it:
        // whether the value is refused as it is set or when the settings are made.
        let cases: [(&[(Setting, &str)], Setting); 13] = [
            (&[(Setting::Step, "1e-5")], Setting::Step),
            (&[(Setting::Precision, "100")], Setting::Precision),
            (
                &[(Setting::Method, "exact"), (Setting::Offset, "0.1")],
                Setting::Offset,
            ),
            (&[(Setting::Method, "magic")], Setting::Method),
            (&[(Setting::Method, "mesh:99")], Setting::Method),
            (&[(Setting::Refine, "bisect:99")], Setting::Refine),
            (&[(Setting::Path, "vertex")], Setting::Path),
            (
                &[(Setting::Color, "sign"), (Setting::Method, "impostor")],
                Setting::Color,
            ),
            (&[(Setting::Background, "mauve")], Setting::Background),
            (&[(Setting::Light, "0,0,0")], Setting::Light),
            (&[(Setting::Ambient, "2")], Setting::Ambient),
            (&[(Setting::Shininess, "0")], Setting::Shininess),
            (&[(Setting::Samples, "3")], Setting::Samples),
        ];
        for (pairs, setting) in cases {
            let mut options = RenderOptions::default();
            let err = pairs
                .iter()
                .try_for_each(|&(s, text)| options.set(s, Value::Text(text)))
                .and_then(|()| options.settings().map(drop))
                .unwrap_err();
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
