//! The render settings, each declared once ([`RENDER_SETTINGS`]): its key (the flag, the
//! Python keyword, the C field), its type, its default, what it accepts, a line of
//! documentation and which methods or colours read it. The command line's flags, the
//! Python keywords, the docs' settings table and the refusals (a value out of range, a
//! setting the chosen method or colour does not read) are made from it; the library takes
//! its values typed ([`RenderOptions`]), whatever the front end.
use crate::error::quoted;
use crate::glyph::NegativeMode;
use crate::render::settings::{PRECISION_RANGE, SHININESS_RANGE, STEP_RANGE, parse_background};
use crate::render::{
    AmbientOcclusion, ColorMode, Culling, Method, Proxy, Refinement, RenderPath, RenderSettings,
    Shadows,
};
use crate::{Error, Result, Setting};

/// A value as a front end hands it over: text from a command line, numbers and texts
/// from Python or C.
#[derive(Clone, Copy, Debug)]
pub enum Value<'a> {
    /// Text (`"exact"`, `"0.35,0.5,1"`, `"0.02"`).
    Text(&'a str),
    /// One number.
    Number(f64),
    /// Several numbers (a direction, a range).
    Numbers(&'a [f64]),
}

/// What a setting's values are, for its documentation and the front ends' types.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// A number.
    Number,
    /// A whole number.
    Count,
    /// A name (or a name with a parameter, `mesh:3`).
    Name,
    /// Several numbers (`X,Y,Z`, `LOW:HIGH`).
    Numbers,
    /// A name that may be switched on alone: the flag without a value, or Python's
    /// `True`, is `on`; Python's `False` is `off`.
    Switch,
}

/// The allowed values of a number.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Range {
    /// Any value the type takes (further checks are the setting's own).
    Any,
    /// `min` to `max`, both included; the text says why, if the bounds need a reason.
    Closed(f32, f32, &'static str),
    /// At least `min`.
    AtLeast(f32),
}

/// Which requests read a setting: given with any other, it would change nothing, so a
/// one-shot image refuses it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Reads {
    /// Every method and colour.
    Always,
    /// These methods only (their names, as `method` takes them).
    Methods(&'static [&'static str]),
    /// This colour only (as `color` takes it).
    Color(&'static str),
}

impl std::fmt::Display for Reads {
    /// Who reads the setting, in words (`method fixed, interval`).
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Reads::Always => f.write_str("every method"),
            Reads::Methods(methods) => write!(f, "method {}", methods.join(", ")),
            Reads::Color(color) => write!(f, "color {color}"),
        }
    }
}

/// One render setting, declared once.
#[derive(Clone, Copy, Debug)]
pub struct SettingSpec {
    /// The setting (its key and name).
    pub setting: Setting,
    /// What its values are.
    pub kind: Kind,
    /// Its placeholder in usage text (`PX`, `X,Y,Z`).
    pub value_name: &'static str,
    /// Its default, in words.
    pub default: &'static str,
    /// The values it accepts, in words.
    pub accepts: &'static str,
    /// The allowed range of a number, checked by [`RenderSettings::validate`].
    pub range: Range,
    /// Which methods or colours read it.
    pub reads: Reads,
    /// Its documentation, one sentence or a few.
    pub doc: &'static str,
    /// The number it sets in [`RenderSettings`], for the range check.
    pub number: Option<fn(&RenderSettings) -> f32>,
}

impl SettingSpec {
    /// The spec of `setting`, if it is a render setting.
    pub fn of(setting: Setting) -> Option<&'static SettingSpec> {
        RENDER_SETTINGS.iter().find(|spec| spec.setting == setting)
    }

    /// Refuses `value` outside [`range`](Self::range).
    pub fn check(&self, value: f32) -> Result<()> {
        let v = value;
        let (inside, text) = match self.range {
            Range::Any => (v.is_finite(), String::from("must be finite")),
            Range::Closed(min, max, why) => {
                let why = if why.is_empty() {
                    String::new()
                } else {
                    format!(" ({why})")
                };
                (
                    v.is_finite() && (min..=max).contains(&v),
                    format!("must be in {min} to {max}{why}"),
                )
            }
            Range::AtLeast(min) => (v.is_finite() && v >= min, format!("must be >= {min}")),
        };
        if inside {
            Ok(())
        } else {
            Err(Error::setting_value(self.setting, value, text))
        }
    }

    /// The usage text: the doc, what it accepts and its default.
    pub fn help(&self) -> String {
        format!(
            "{} Accepts {}; default {}.",
            self.doc, self.accepts, self.default
        )
    }
}

/// A value type of a render setting: made from what a front end hands over, and
/// written back in messages.
pub(crate) trait SettingValue: Sized {
    /// The value of `setting` from `value`; a value of the wrong kind is refused naming
    /// the setting.
    fn from_value(setting: Setting, value: Value<'_>) -> Result<Self>;
    /// The value as messages write it (`0.01`, `'bisect:2'`).
    fn spelled(&self) -> String;
}

fn wrong(setting: Setting, value: Value<'_>, expected: &str) -> Error {
    let given = match value {
        Value::Text(text) => format!("'{}'", quoted(text)),
        Value::Number(v) => v.to_string(),
        Value::Numbers(vs) => vs.iter().map(f64::to_string).collect::<Vec<_>>().join(","),
    };
    Error::setting_value(setting, given, format!("not {expected}"))
}

impl SettingValue for f32 {
    fn from_value(setting: Setting, value: Value<'_>) -> Result<Self> {
        match value {
            Value::Number(v) => Ok(v as f32),
            Value::Text(text) => text
                .trim()
                .parse::<f32>()
                .map_err(|_| wrong(setting, value, "a number")),
            Value::Numbers(_) => Err(wrong(setting, value, "one number")),
        }
    }
    fn spelled(&self) -> String {
        self.to_string()
    }
}

impl SettingValue for u32 {
    fn from_value(setting: Setting, value: Value<'_>) -> Result<Self> {
        match value {
            Value::Number(v) if v.fract() == 0.0 && (0.0..=f64::from(u32::MAX)).contains(&v) => {
                Ok(v as u32)
            }
            Value::Text(text) => text
                .trim()
                .parse::<u32>()
                .map_err(|_| wrong(setting, value, "a whole number >= 0")),
            _ => Err(wrong(setting, value, "a whole number >= 0")),
        }
    }
    fn spelled(&self) -> String {
        self.to_string()
    }
}

/// Numbers written with `separator` in text (`X,Y,Z`, `LOW:HIGH`).
fn numbers<const N: usize>(
    setting: Setting,
    value: Value<'_>,
    separator: char,
    expected: &str,
) -> Result<[f32; N]> {
    let parsed: Option<Vec<f32>> = match value {
        Value::Text(text) => text
            .split(separator)
            .map(|v| v.trim().parse::<f32>().ok())
            .collect(),
        Value::Numbers(vs) => Some(vs.iter().map(|&v| v as f32).collect()),
        Value::Number(_) => None,
    };
    parsed
        .and_then(|vs| <[f32; N]>::try_from(vs).ok())
        .ok_or_else(|| wrong(setting, value, expected))
}

/// A direction, `X,Y,Z` (`light`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Direction(pub [f32; 3]);

impl SettingValue for Direction {
    fn from_value(setting: Setting, value: Value<'_>) -> Result<Self> {
        let expected = "X,Y,Z (the direction towards the light: x right, y up, z towards \
                        the viewer)";
        numbers(setting, value, ',', expected).map(Direction)
    }
    fn spelled(&self) -> String {
        let [x, y, z] = self.0;
        format!("{x},{y},{z}")
    }
}

/// A range of values, `LOW:HIGH` (`magnitude_range`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Span(pub [f32; 2]);

impl SettingValue for Span {
    fn from_value(setting: Setting, value: Value<'_>) -> Result<Self> {
        numbers(setting, value, ':', "LOW:HIGH").map(Span)
    }
    fn spelled(&self) -> String {
        let [low, high] = self.0;
        format!("{low}:{high}")
    }
}

/// A background colour: none (transparent), a name, `#rrggbb` or `r,g,b`; linear RGB
/// and alpha.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Background(pub [f32; 4]);

impl SettingValue for Background {
    fn from_value(setting: Setting, value: Value<'_>) -> Result<Self> {
        match value {
            Value::Text(text) => parse_background(text).map(Background),
            _ => Err(wrong(setting, value, "a colour's name, #rrggbb or r,g,b")),
        }
    }
    fn spelled(&self) -> String {
        format!("{:?}", self.0)
    }
}

/// Ambient occlusion: `on`, `off` or the rays' reach, as text or a number.
impl SettingValue for AmbientOcclusion {
    fn from_value(setting: Setting, value: Value<'_>) -> Result<Self> {
        match value {
            Value::Text(text) => text.parse(),
            Value::Number(reach) => {
                let occlusion = AmbientOcclusion::On {
                    reach: reach as f32,
                };
                occlusion.validate().map(|_| occlusion)
            }
            Value::Numbers(_) => Err(wrong(setting, value, "on, off or one number")),
        }
    }
    fn spelled(&self) -> String {
        format!("'{self}'")
    }
}

/// Names: parsed by their `FromStr`, which names the setting when it refuses.
macro_rules! named_values {
    ($($ty:ty),*) => {$(
        impl SettingValue for $ty {
            fn from_value(setting: Setting, value: Value<'_>) -> Result<Self> {
                match value {
                    Value::Text(text) => text.parse(),
                    _ => Err(wrong(setting, value, "a name")),
                }
            }
            fn spelled(&self) -> String {
                format!("'{self}'")
            }
        }
    )*};
}

named_values!(
    Method,
    RenderPath,
    Culling,
    Proxy,
    Refinement,
    ColorMode,
    NegativeMode,
    Shadows
);

/// The table: from each entry the setting's constant ([`Setting`]), its field of
/// [`RenderOptions`], its [`SettingSpec`] and its arms of [`RenderOptions::set`].
macro_rules! render_settings {
    ($(
        $(#[doc = $doc:literal])+
        $field:ident: $ty:ty = $variant:ident($name:literal) {
            kind: $kind:ident, value: $value_name:literal, default: $default:literal,
            accepts: $accepts:literal, range: $range:expr, reads: $reads:expr,
            number: $number:expr $(,)?
        }
    )*) => {
        /// The render settings ([`RENDER_SETTINGS`]).
        #[allow(non_upper_case_globals)]
        impl Setting {
            $($(#[doc = $doc])+ pub const $variant: Setting =
                crate::setting!(value(stringify!($field), $name));)*
        }

        /// The render options as a front end takes them, typed: each field is the
        /// [`Setting`] of the same key in [`RENDER_SETTINGS`]; `None` is the default.
        #[derive(Clone, Debug, Default, PartialEq)]
        pub struct RenderOptions {
            $($(#[doc = $doc])+ pub $field: Option<$ty>,)*
        }

        /// Every render setting, in the order of the command line's help.
        pub const RENDER_SETTINGS: &[SettingSpec] = &[$(SettingSpec {
            setting: Setting::$variant,
            kind: Kind::$kind,
            value_name: $value_name,
            default: $default,
            accepts: $accepts,
            range: $range,
            reads: $reads,
            doc: concat!($($doc),+),
            number: $number,
        },)*];

        impl RenderOptions {
            /// Sets `setting` (a render setting) from `value`; a value of the wrong kind
            /// is refused naming the setting (ranges are checked by
            /// [`settings`](Self::settings)).
            pub fn set(&mut self, setting: Setting, value: Value<'_>) -> Result<()> {
                $(if setting == Setting::$variant {
                    self.$field = Some(<$ty as SettingValue>::from_value(setting, value)?);
                    return Ok(());
                })*
                Err(Error::Call {
                    call: "RenderOptions::set",
                    expected: "a render setting (one of RENDER_SETTINGS)",
                })
            }

            /// The value given for `setting`, as messages write it; `None` when not given.
            pub fn given(&self, setting: Setting) -> Option<String> {
                $(if setting == Setting::$variant {
                    return self.$field.as_ref().map(SettingValue::spelled);
                })*
                None
            }
        }
    };
}

render_settings! {
    /// How glyphs are drawn: fixed (ray casting at a fixed step), interval or affine
    /// (robust ray casting by range arithmetic), exact (first real root of the ray
    /// polynomial; offset 0 only), impostor (bounding spheres), mesh:LEVEL (icosphere)
    /// or latlong:N (latitude bands) tessellations.
    method: Method = Method("method") {
        kind: Name, value: "METHOD", default: "exact, or affine with an offset",
        accepts: "fixed, interval, affine, exact, impostor, mesh:0 to mesh:7, latlong:N",
        range: Range::Any, reads: Reads::Always, number: None,
    }
    /// Which ray caster runs the method: auto (the one measured faster on the device:
    /// compute on a GPU, fragment on a CPU such as lavapipe, and fragment wherever compute
    /// cannot draw the glyphs), fragment (proxy boxes) or compute (a compute shader per
    /// pixel over screen tiles; exact only, polynomial glyphs).
    path: RenderPath = Path("path") {
        kind: Name, value: "PATH", default: "auto", accepts: "auto, fragment, compute",
        range: Range::Any, reads: Reads::Always, number: None,
    }
    /// The robust methods' segment length limit, in pixels at the segment's depth.
    precision: f32 = Precision("precision") {
        kind: Number, value: "PX", default: "0.25", accepts: "0.01 to 64",
        range: Range::Closed(
            PRECISION_RANGE.0,
            PRECISION_RANGE.1,
            "the range float32 ray casting draws reliably",
        ),
        reads: Reads::Methods(&["interval", "affine"]),
        number: Some(|s| s.precision_px),
    }
    /// The fixed march's step, in units of each glyph's bounding radius.
    step: f32 = Step("step") {
        kind: Number, value: "STEP", default: "0.02", accepts: "0.001 to 2",
        range: Range::Closed(
            STEP_RANGE.0,
            STEP_RANGE.1,
            "the range float32 ray casting draws reliably",
        ),
        reads: Reads::Methods(&["fixed"]), number: Some(|s| s.step),
    }
    /// The refinement of the first sign change along the ray.
    refine: Refinement = Refine("refine") {
        kind: Name, value: "REFINE", default: "secant:4",
        accepts: "bisect:K, secant:K (K = 0 to 16), interp, none",
        range: Range::Any, reads: Reads::Methods(&["fixed", "interval", "affine"]),
        number: None,
    }
    /// Glyph colour: direction, magnitude, uniform or sign (positive lobes red, negative
    /// ones blue; ray-casting methods only).
    color: ColorMode = Color("color") {
        kind: Name, value: "COLOR", default: "direction",
        accepts: "direction, magnitude, uniform, sign", range: Range::Any,
        reads: Reads::Always, number: None,
    }
    /// The magnitude colour map's range, LOW:HIGH in world units.
    magnitude_range: Span = MagnitudeRange("magnitude range") {
        kind: Numbers, value: "LOW:HIGH",
        default: "0 to the largest glyph radius drawn",
        accepts: "two numbers, low below high", range: Range::Any,
        reads: Reads::Color("magnitude"), number: None,
    }
    /// Negative lobes: abs (drawn as |f|) or hide; replaces every glyph set's mode.
    negative: NegativeMode = Negative("negative") {
        kind: Name, value: "abs|hide", default: "the scene's (abs for volumes)",
        accepts: "abs, hide", range: Range::Any, reads: Reads::Always, number: None,
    }
    /// Background: none (transparent PNG), a name, #rrggbb or r,g,b (sRGB, 0 to 255, as
    /// written in the PNG).
    background: Background = Background("background") {
        kind: Name, value: "COLOR", default: "dark",
        accepts: "none, dark, black, white, grey, #rrggbb, r,g,b", range: Range::Any,
        reads: Reads::Always, number: None,
    }
    /// Isotropic offset added to every glyph, as a fraction of its bounding radius.
    offset: f32 = Offset("offset") {
        kind: Number, value: "OFFSET", default: "0", accepts: "a number >= 0",
        range: Range::AtLeast(0.0), reads: Reads::Always, number: Some(|s| s.offset),
    }
    /// Direction towards the light, X,Y,Z in view coordinates (x to the image's right,
    /// y up, z towards the viewer); the light moves with the camera.
    light: Direction = Light("light") {
        kind: Numbers, value: "X,Y,Z", default: "0.35,0.5,1 (above right, in front)",
        accepts: "three numbers, not all 0", range: Range::Any, reads: Reads::Always,
        number: None,
    }
    /// Ambient share of the base colour.
    ambient: f32 = Ambient("ambient") {
        kind: Number, value: "A", default: "0.18", accepts: "0 to 1",
        range: Range::Closed(0.0, 1.0, ""), reads: Reads::Always,
        number: Some(|s| s.lighting.ambient),
    }
    /// Strength of the white specular highlight (0: matte).
    specular: f32 = Specular("specular") {
        kind: Number, value: "S", default: "0.25", accepts: "0 to 1",
        range: Range::Closed(0.0, 1.0, ""), reads: Reads::Always,
        number: Some(|s| s.lighting.specular),
    }
    /// Blinn-Phong exponent of the highlight.
    shininess: f32 = Shininess("shininess") {
        kind: Number, value: "E", default: "48", accepts: "1 to 1024",
        range: Range::Closed(SHININESS_RANGE.0, SHININESS_RANGE.1, ""),
        reads: Reads::Always, number: Some(|s| s.lighting.shininess),
    }
    /// Shadows the glyphs cast on themselves, on the other glyphs of their set and on the
    /// underlay: off, hard (one ray from each hit towards the light, intersected exactly)
    /// or soft:RADIUS (a disc light of that angular radius in degrees, 16 rays). The
    /// depth map does not change.
    shadows: Shadows = Shadows("shadows") {
        kind: Switch, value: "off|hard|soft:R", default: "off",
        accepts: "off, hard (or the flag alone), soft:RADIUS (degrees, above 0 to 30)",
        range: Range::Any, reads: Reads::Methods(&["exact"]), number: None,
    }
    /// Ambient occlusion: 16 rays over the hemisphere of each hit (cosine-weighted),
    /// intersected exactly with the glyphs within REACH bounding radii of the hit glyph;
    /// the share no glyph blocks scales the ambient term (no light bounces between
    /// glyphs). Shows where lobes and glyphs crowd each other; a larger --ambient makes
    /// it stronger. The depth map does not change.
    ambient_occlusion: AmbientOcclusion = AmbientOcclusion("ambient occlusion") {
        kind: Switch, value: "off|on|REACH", default: "off",
        accepts: "off, on (or the flag alone: reach 1), REACH (bounding radii, above 0 to 16)",
        range: Range::Any, reads: Reads::Methods(&["exact"]), number: None,
    }
    /// Glyphs hidden behind others: occluded (the device's best of the two ways below;
    /// the image and the depth map are the same; a flat field is drawn as without it),
    /// passes (the glyphs are drawn in passes front to back, and each pass skips the
    /// pixels where an earlier one drew a nearer surface), early-out (one pass front to
    /// back whose fragments behind a hit found before skip the root isolation: the
    /// exact method, on a device that jumps over code no pixel of a batch runs, such as
    /// a GPU or lavapipe of Mesa 25) or off (one pass: every glyph's pixels run).
    cull: Culling = Cull("cull") {
        kind: Name, value: "occluded|passes|early-out|off", default: "occluded",
        accepts: "occluded, passes, early-out, off",
        range: Range::Any, reads: Reads::Always, number: None,
    }
    /// What the fragment path draws around each glyph, whose every pixel runs the ray
    /// caster: box (the front faces of the oriented box, the paper's proxy), hull (an
    /// octagon around the outline of the box cut by guaranteed planes across its
    /// diagonals, at the glyph's nearest depth: fewer fragments, slower pipeline
    /// creation; the image and the depth map are the box's) or pieces (an octagon around
    /// each of the glyph's eight pieces, each ray clipped to its piece: fewer root
    /// isolations; the exact method's polynomial glyphs, others draw the hull; bounding
    /// the pieces takes milliseconds a glyph).
    proxy: Proxy = Proxy("proxy") {
        kind: Name, value: "box|hull|pieces", default: "box", accepts: "box, hull, pieces",
        range: Range::Any, reads: Reads::Always, number: None,
    }
    /// Samples per pixel: supersampling draws at 2 or 4 times the width and height, then
    /// averages; the depth map stays one ray per pixel centre.
    samples: u32 = Samples("samples") {
        kind: Count, value: "1|4|16", default: "1", accepts: "1, 4, 16",
        range: Range::Any, reads: Reads::Always, number: None,
    }
}

impl RenderSettings {
    /// Checks every setting: each number the table declares in its range
    /// ([`RENDER_SETTINGS`]), then the rest (the light's direction, the settings'
    /// combinations). Every front end's request passes here, as
    /// [`RenderOptions::settings`] and the renderers call it.
    pub fn validate(&self) -> Result<()> {
        for spec in RENDER_SETTINGS {
            if let Some(number) = spec.number {
                spec.check(number(self))?;
            }
        }
        self.validate_rest()
    }
}

impl RenderOptions {
    /// The render settings these options ask for, every value checked
    /// ([`RenderSettings::validate`]); a refused value is an [`Error::Setting`] naming
    /// its setting, and a setting the chosen colour does not read is refused.
    pub fn settings(&self) -> Result<RenderSettings> {
        let offset = self.offset.unwrap_or(0.0);
        let defaults = RenderSettings::default();
        let method = match self.method {
            Some(method) => method,
            None if offset != 0.0 => Method::Affine,
            None => defaults.method,
        };
        let mut lighting = defaults.lighting;
        if let Some(Direction(direction)) = self.light {
            lighting.direction = direction;
        }
        lighting.ambient = self.ambient.unwrap_or(lighting.ambient);
        lighting.specular = self.specular.unwrap_or(lighting.specular);
        lighting.shininess = self.shininess.unwrap_or(lighting.shininess);
        let mut color = self.color.unwrap_or(defaults.color);
        self.check_color_reads(color)?;
        if let Some(Span([low, high])) = self.magnitude_range {
            color = ColorMode::Magnitude {
                range: Some((low, high)),
            };
        }
        let settings = RenderSettings {
            method,
            path: self.path.unwrap_or(defaults.path),
            step: self.step.unwrap_or(defaults.step),
            precision_px: self.precision.unwrap_or(defaults.precision_px),
            refinement: self.refine.unwrap_or(defaults.refinement),
            color,
            background: self.background.map_or(defaults.background, |b| b.0),
            offset,
            samples: self.samples.unwrap_or(defaults.samples),
            lighting,
            shadows: self.shadows.unwrap_or(defaults.shadows),
            ambient_occlusion: self.ambient_occlusion.unwrap_or(defaults.ambient_occlusion),
            cull: self.cull.unwrap_or(defaults.cull),
            proxy: self.proxy.unwrap_or(defaults.proxy),
            ..defaults
        };
        settings.validate()?;
        Ok(settings)
    }

    /// Refuses a setting given that `color` does not read ([`Reads::Color`]).
    fn check_color_reads(&self, color: ColorMode) -> Result<()> {
        for spec in RENDER_SETTINGS {
            if let Reads::Color(reader) = spec.reads
                && self.given(spec.setting).is_some()
                && color.name() != reader
            {
                return Err(Error::conflict(
                    spec.setting,
                    crate::error::Relation::Requires,
                    Setting::Color.with(reader),
                ));
            }
        }
        Ok(())
    }

    /// Refuses a setting given that `settings.method` does not read ([`Reads::Methods`]):
    /// given with another method it would change nothing. A one-shot image calls this;
    /// the viewer does not, since its method can be switched to one that reads them.
    pub fn check_method_reads(&self, settings: &RenderSettings) -> Result<()> {
        self.check_cull_applies(settings)?;
        let method = settings.method;
        for spec in RENDER_SETTINGS {
            let Reads::Methods(readers) = spec.reads else {
                continue;
            };
            let Some(value) = self.given(spec.setting) else {
                continue;
            };
            let name = method.to_string();
            if readers.contains(&name.as_str()) {
                continue;
            }
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
            let message = crate::error::Message::from_pieces(pieces);
            return Err(Error::setting_value(spec.setting, value, message));
        }
        Ok(())
    }
}

impl RenderOptions {
    /// Refuses a `cull` given that no frame of `settings` could take: early outs are the
    /// `exact` method's on the fragment path (its shader has them), passes the
    /// ray-casting methods' on the fragment path. Given anyway, it would change nothing
    /// (the frame is drawn as without culling), so a one-shot image refuses it, as
    /// [`check_method_reads`](Self::check_method_reads) does a setting the method does
    /// not read. `occluded` (the default) and `off` always apply.
    fn check_cull_applies(&self, settings: &RenderSettings) -> Result<()> {
        let Some(cull) = self.cull else {
            return Ok(());
        };
        let method = settings.method;
        let ray_cast = !matches!(method, Method::Impostor | Method::Mesh(_));
        let why: crate::error::Message = match cull {
            Culling::Occluded | Culling::Off => return Ok(()),
            Culling::EarlyOut if method != Method::Exact => crate::message![
                "early outs are for ",
                Setting::Method.with("exact"),
                " (its root isolation is what they skip); ",
                Setting::Method.with(method),
                " does not take them (leave it out, or use ",
                Setting::Cull.with("occluded"),
                ")"
            ],
            Culling::Passes if !ray_cast => crate::message![
                "passes skip ray-cast fragments; ",
                Setting::Method.with(method),
                " draws every glyph (leave it out, or choose a ray-casting method)"
            ],
            Culling::EarlyOut | Culling::Passes if settings.path == RenderPath::Compute => {
                crate::message![
                    "applies to the fragment path; ",
                    Setting::Path.with("compute"),
                    " already stops each pixel behind its nearest hit (leave it out, or \
                     use ",
                    Setting::Path.with("fragment"),
                    ")"
                ]
            }
            Culling::EarlyOut | Culling::Passes => return Ok(()),
        };
        Err(Error::setting_value(Setting::Cull, cull, why))
    }
}

/// The settings table of the docs (Markdown): one row per render setting, with the
/// flag, the Python keyword, what it accepts, its default, which methods or colours
/// read it and its documentation.
pub fn markdown_table() -> String {
    let mut out = String::from(
        "| setting | command line | Python | accepts | default | read by | what it does |\n\
         |---|---|---|---|---|---|---|\n",
    );
    for spec in RENDER_SETTINGS {
        let cell = |text: &str| text.replace('|', "\\|");
        out.push_str(&format!(
            "| {} | `{} {}` | `{}=` | {} | {} | {} | {} |\n",
            spec.setting.name(),
            spec.setting.flag(),
            cell(spec.value_name),
            spec.setting.keyword(),
            cell(spec.accepts),
            cell(spec.default),
            spec.reads,
            cell(spec.doc.trim()),
        ));
    }
    out
}

/// The Python keywords of the render settings, in the table's order, as the Python
/// guide lists them (docs/guide/python.md, between its generated-list markers):
/// `` `method`, `path`, ... `` (a test keeps the guide's copy current).
pub fn python_keywords() -> String {
    RENDER_SETTINGS
        .iter()
        .map(|spec| format!("`{}`", spec.setting.keyword()))
        .collect::<Vec<_>>()
        .join(", ")
}

/// Replaces what lies between `start` and `end` in the page at `path` with `generated`
/// when `GLYPHCAST_BLESS=1`, else asserts that it is `generated` (`what` names the
/// list in the message).
#[cfg(test)]
fn check_generated(path: &str, start: &str, end: &str, generated: &str, what: &str) {
    let page = std::fs::read_to_string(path).unwrap();
    let from = page.find(start).expect("the start marker") + start.len();
    let to = from + page[from..].find(end).expect("the end marker");
    if std::env::var("GLYPHCAST_BLESS").is_ok_and(|v| v == "1") {
        let page = format!("{}{generated}{}", &page[..from], &page[to..]);
        std::fs::write(path, page).unwrap();
    } else {
        assert!(
            page[from..to] == *generated,
            "{what} in {path} is stale: GLYPHCAST_BLESS=1 cargo test -p glyphcast --lib table \
             (or bash tools/gen-docs.sh)"
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The methods each setting is read by follow the catalog: `step` by the marching
    /// methods, `precision` by the range methods, `refine` by both.
    #[test]
    fn the_readers_follow_the_catalog() {
        use crate::catalog::RAY_CAST_METHODS;
        let names = |keep: fn(&crate::catalog::RayCastMethod) -> bool| -> Vec<&str> {
            RAY_CAST_METHODS
                .iter()
                .filter(|e| keep(e))
                .map(|e| e.name)
                .collect()
        };
        let readers = |setting: Setting| match SettingSpec::of(setting).unwrap().reads {
            Reads::Methods(methods) => {
                let mut methods = methods.to_vec();
                methods.sort();
                methods
            }
            other => panic!("{setting:?}: {other:?}"),
        };
        let sorted = |mut v: Vec<&'static str>| {
            v.sort();
            v
        };
        assert_eq!(readers(Setting::Step), sorted(names(|e| e.marches)));
        assert_eq!(
            readers(Setting::Precision),
            sorted(names(|e| e.uses_ranges))
        );
        assert_eq!(
            readers(Setting::Refine),
            sorted(names(|e| e.marches || e.uses_ranges))
        );
    }

    /// Every default the table states is the one the settings take.
    #[test]
    fn the_stated_defaults_are_the_defaults() {
        let s = RenderSettings::default();
        let none = RenderOptions::default().settings().unwrap();
        assert_eq!(none, s);
        for spec in RENDER_SETTINGS {
            if let Some(number) = spec.number {
                let stated: f32 = spec.default.parse().unwrap();
                assert_eq!(number(&s), stated, "{:?}", spec.setting);
            }
        }
        assert_eq!(s.method.to_string(), "exact");
        assert_eq!(
            s.path.to_string(),
            SettingSpec::of(Setting::Path).unwrap().default
        );
        assert_eq!(
            s.color.name(),
            SettingSpec::of(Setting::Color).unwrap().default
        );
        assert_eq!(
            s.refinement.to_string(),
            SettingSpec::of(Setting::Refine).unwrap().default
        );
        assert_eq!(
            s.samples.to_string(),
            SettingSpec::of(Setting::Samples).unwrap().default
        );
    }

    /// Every render setting can be set from text (the command line's way), and a value
    /// of the wrong kind is refused naming it.
    #[test]
    fn every_setting_takes_text_and_refuses_the_wrong_kind() {
        let text = |setting: Setting| match setting.key() {
            "method" => "fixed",
            "path" => "compute",
            "refine" => "bisect:2",
            "color" => "magnitude",
            "magnitude_range" => "0:1",
            "negative" => "hide",
            "background" => "white",
            "light" => "1,0,0",
            "samples" => "4",
            "shadows" => "soft:2",
            "ambient_occlusion" => "on",
            "cull" => "off",
            "proxy" => "box",
            _ => "0.5",
        };
        for spec in RENDER_SETTINGS {
            let mut options = RenderOptions::default();
            options
                .set(spec.setting, Value::Text(text(spec.setting)))
                .unwrap();
            assert!(options.given(spec.setting).is_some(), "{:?}", spec.setting);
            let wrong = match spec.kind {
                // The occlusion rays' reach may be one number, not several.
                Kind::Switch if spec.setting == Setting::AmbientOcclusion => {
                    Value::Numbers(&[1.0, 2.0])
                }
                Kind::Name | Kind::Numbers | Kind::Switch => Value::Number(1.5),
                Kind::Number | Kind::Count => Value::Text("many"),
            };
            let err = RenderOptions::default()
                .set(spec.setting, wrong)
                .unwrap_err();
            assert_eq!(err.setting_of(), Some(spec.setting), "{err}");
            assert!(err.is_usage(), "{err}");
        }
    }

    /// Python's numbers reach the same values as the command line's text.
    #[test]
    fn numbers_and_text_give_the_same_options() {
        let mut from_text = RenderOptions::default();
        let mut from_numbers = RenderOptions::default();
        for (setting, text, value) in [
            (
                Setting::Light,
                "1,0.5,-2",
                Value::Numbers(&[1.0, 0.5, -2.0]),
            ),
            (
                Setting::MagnitudeRange,
                "0.5:2",
                Value::Numbers(&[0.5, 2.0]),
            ),
            (Setting::Ambient, "0.3", Value::Number(0.3)),
            (Setting::Samples, "4", Value::Number(4.0)),
        ] {
            from_text.set(setting, Value::Text(text)).unwrap();
            from_numbers.set(setting, value).unwrap();
        }
        assert_eq!(from_text, from_numbers);
        let err = RenderOptions::default()
            .set(Setting::Samples, Value::Number(2.5))
            .unwrap_err();
        assert_eq!(err.setting_of(), Some(Setting::Samples));
        let err = RenderOptions::default()
            .set(Setting::Light, Value::Numbers(&[1.0, 2.0]))
            .unwrap_err();
        assert_eq!(err.setting_of(), Some(Setting::Light));
    }

    /// Every number's range refuses a value just outside it and takes its bounds.
    #[test]
    fn ranges_come_from_the_table() {
        for spec in RENDER_SETTINGS {
            let (low, high) = match spec.range {
                Range::Closed(low, high, _) => (low, Some(high)),
                Range::AtLeast(low) => (low, None),
                Range::Any => continue,
            };
            let with = |v: f32| {
                let mut options = RenderOptions {
                    method: Some(Method::Fixed),
                    ..Default::default()
                };
                options
                    .set(spec.setting, Value::Number(f64::from(v)))
                    .unwrap();
                options.settings()
            };
            with(low).unwrap();
            let err = with(low - low.abs().max(1.0) * 0.5).unwrap_err();
            assert_eq!(err.setting_of(), Some(spec.setting), "{err}");
            if let Some(high) = high {
                with(high).unwrap();
                assert!(with(high * 2.0 + 1.0).is_err(), "{:?}", spec.setting);
            }
        }
    }

    /// docs/guide/settings.md holds the table as generated; `GLYPHCAST_BLESS=1`
    /// rewrites it.
    #[test]
    fn the_docs_settings_table_is_current() {
        let path = concat!(env!("CARGO_MANIFEST_DIR"), "/docs/guide/settings.md");
        let page = std::fs::read_to_string(path).unwrap();
        let (start, end) = (
            "<!-- settings table: generated -->\n",
            "<!-- end of the settings table -->",
        );
        let from = page.find(start).expect("the start marker") + start.len();
        let to = page.find(end).expect("the end marker");
        let generated = markdown_table();
        if std::env::var("GLYPHCAST_BLESS").is_ok_and(|v| v == "1") {
            let page = format!("{}{generated}{}", &page[..from], &page[to..]);
            std::fs::write(path, page).unwrap();
        } else {
            assert!(
                page[from..to] == generated,
                "docs/guide/settings.md is stale: GLYPHCAST_BLESS=1 cargo test -p glyphcast \
                 --lib table"
            );
        }
    }

    /// docs/guide/python.md lists the render settings' keywords as generated from the
    /// table; `GLYPHCAST_BLESS=1` writes them.
    #[test]
    fn the_python_guide_keywords_are_current() {
        check_generated(
            concat!(env!("CARGO_MANIFEST_DIR"), "/docs/guide/python.md"),
            "<!-- render keywords: generated -->",
            "<!-- end of the render keywords -->",
            &python_keywords(),
            "the render settings' keywords",
        );
        assert!(python_keywords().starts_with("`method`, `path`, "));
        assert!(python_keywords().contains("`magnitude_range`"));
    }

    #[test]
    fn the_docs_table_has_a_row_per_setting() {
        let table = markdown_table();
        assert_eq!(table.lines().count(), RENDER_SETTINGS.len() + 2);
        assert!(table.contains("| ambient | `--ambient A` | `ambient=` | 0 to 1 | 0.18 |"));
    }
}
