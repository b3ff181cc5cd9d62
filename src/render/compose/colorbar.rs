//! The colour bar of `--color magnitude` (`--colorbar`): the colour map from the low to
//! the high end of the magnitude range, with tick values and a label, drawn in a strip
//! of its own appended to the right of the rendered image. The strip is reserved, so the
//! bar never covers a glyph: the glyph pixels are those of the render without it, and the
//! depth map is NaN (no glyph) across the strip, so that it keeps the image's size.
//!
//! The bar's colours are the shaders' (glsl/shading.glsl `viridis`): the same polynomial
//! fit, the same power 2.2 to linear RGB, then the sRGB encoding the colour target
//! applies, so the bar's top row is the map's top colour and its bottom row its bottom.
use ab_glyph::{Font, FontRef, PxScale, ScaleFont};

use crate::camera::Camera;
use crate::render::compose::labels::{Canvas, dejavu_sans};
use crate::render::frame::{SceneExtent, magnitude_range};
use crate::render::glyph_data::GlyphSetData;
use crate::render::headless::RenderedImage;
use crate::render::settings::{ColorMode, RenderSettings};
use crate::scene::Scene;
use crate::{Error, Result, Setting};

/// What a colour bar shows: the values at its bottom (map position 0) and top (1), and
/// a label naming the quantity and its unit.
#[derive(Clone, Debug, PartialEq)]
pub struct ColorBar {
    /// The value at the bottom of the bar (the map's low end).
    pub low: f64,
    /// The value at the top of the bar (the map's high end).
    pub high: f64,
    /// Written above the bar.
    pub label: String,
}

/// Tick values written beside the bar, ends included.
pub(crate) const TICKS: usize = 5;

/// Text height as a fraction of the image height, and the least in pixels.
const TEXT_FRACTION: f32 = 0.045;
const MIN_TEXT_PX: f32 = 11.0;

/// The viridis fit of glsl/shading.glsl at t (clamped to 0..1), in linear RGB, computed
/// in float32 as the shader does.
pub(crate) fn viridis_linear(t: f32) -> [f32; 3] {
    const C: [[f32; 3]; 7] = [
        [0.277_727_33, 0.005_407_344_5, 0.334_099_8],
        [0.105_093_04, 1.404_613_5, 1.384_590_2],
        [-0.330_861_83, 0.214_847_56, 0.095_095_165],
        [-4.634_230_5, -5.799_101, -19.332_441],
        [6.228_27, 14.179_933, 56.690_55],
        [4.776_385, -13.745_145, -65.353_035],
        [-5.435_456, 4.645_852_6, 26.312_435],
    ];
    let t = t.clamp(0.0, 1.0);
    let mut out = [0.0f32; 3];
    for (channel, value) in out.iter_mut().enumerate() {
        let srgb = C.iter().rev().fold(0.0f32, |acc, c| acc * t + c[channel]);
        *value = srgb.clamp(0.0, 1.0).powf(2.2);
    }
    out
}

/// The 8-bit sRGB encoding of a linear value, as an sRGB colour target stores it.
pub fn srgb_byte(linear: f32) -> u8 {
    let c = f64::from(linear.clamp(0.0, 1.0));
    let encoded = if c <= 0.003_130_8 {
        12.92 * c
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    };
    (encoded * 255.0).round() as u8
}

/// The map's colour at t as the PNG stores it.
pub fn viridis_srgb8(t: f32) -> [u8; 3] {
    viridis_linear(t).map(srgb_byte)
}

/// `value` with about three significant digits, fixed-point where that stays short.
pub(crate) fn tick_text(value: f64, largest: f64) -> String {
    if value == 0.0 {
        return "0".into();
    }
    let magnitude = largest.abs().max(value.abs());
    if (1e-3..1e5).contains(&magnitude) {
        let decimals = (2 - magnitude.log10().floor() as i32).clamp(0, 6) as usize;
        format!("{value:.decimals$}")
    } else {
        format!("{value:.2e}")
    }
}

/// Positions of the strip's parts, in pixels from the strip's top-left.
struct Layout {
    size: f32,
    margin: f32,
    bar_left: u32,
    bar_width: u32,
    bar_top: u32,
    bar_bottom: u32,
    width: u32,
}

impl ColorBar {
    /// The bar of a frame drawn with `settings` whose glyphs have `extent`: the range the
    /// shaders map ([`magnitude_range`]), None unless the colour is magnitude. Where
    /// every glyph has the same scale (`common_scale`, see [`common_scale`]) the values
    /// are divided by it, glyph radii in data units; else they are world units. `label`
    /// replaces the default label, which names the unit.
    pub fn of_magnitude(
        settings: &RenderSettings,
        extent: &SceneExtent,
        common_scale: Option<f64>,
        label: Option<&str>,
    ) -> Option<ColorBar> {
        let (low, high) = magnitude_range(settings, extent)?;
        let (unit, default_label) = match common_scale {
            Some(scale) => (scale, "radius (data units)"),
            None => (1.0, "radius (world units)"),
        };
        Some(ColorBar {
            low: f64::from(low) / unit,
            high: f64::from(high) / unit,
            label: label.unwrap_or(default_label).to_owned(),
        })
    }

    /// The bar of glyphs `sets` seen by `camera` and drawn with `settings`
    /// ([`ColorBar::of_magnitude`] of their extent): the one the command line and Python
    /// append to a render.
    pub fn of_glyphs(
        settings: &RenderSettings,
        (sets, camera): (&[GlyphSetData], &Camera),
        common_scale: Option<f64>,
        label: Option<&str>,
    ) -> Option<ColorBar> {
        let extent = SceneExtent::for_settings(camera, sets, settings);
        ColorBar::of_magnitude(settings, &extent, common_scale, label)
    }

    fn check(&self) -> Result<()> {
        if !(self.low.is_finite() && self.high.is_finite() && self.high > self.low) {
            return Err(Error::setting_value(
                Setting::Colorbar,
                format_args!("{}:{}", self.low, self.high),
                "the range needs finite ends, low < high",
            ));
        }
        Ok(())
    }

    /// The tick values, low to high.
    pub fn ticks(&self) -> Vec<f64> {
        (0..TICKS)
            .map(|k| self.low + (self.high - self.low) * k as f64 / (TICKS - 1) as f64)
            .collect()
    }

    fn layout(&self, font: &FontRef, height: u32) -> Layout {
        let size = (TEXT_FRACTION * height as f32).max(MIN_TEXT_PX);
        let scaled = font.as_scaled(PxScale::from(size));
        let text_width = |text: &str| -> f32 {
            text.chars()
                .map(|c| scaled.h_advance(font.glyph_id(c)))
                .sum()
        };
        let margin = (0.6 * size).round();
        let bar_width = (1.2 * size).round().max(8.0) as u32;
        let largest = self.low.abs().max(self.high.abs());
        let ticks = self
            .ticks()
            .iter()
            .map(|&v| text_width(&tick_text(v, largest)))
            .fold(0.0f32, f32::max);
        let beside = margin + bar_width as f32 + 0.5 * margin + ticks + margin;
        let width = beside.max(text_width(&self.label) + 2.0 * margin).ceil() as u32;
        let bar_top = (margin + size * 1.6).round() as u32;
        let bar_bottom = (height as f32 - margin - 0.5 * size)
            .round()
            .max(bar_top as f32 + 2.0);
        Layout {
            size,
            margin,
            bar_left: margin as u32,
            bar_width,
            bar_top,
            bar_bottom: bar_bottom as u32,
            width,
        }
    }

    /// Width in pixels of the strip this bar takes beside an image of `height` rows.
    pub fn strip_width(&self, height: u32) -> Result<u32> {
        let font = font()?;
        Ok(self.layout(&font, height).width)
    }

    /// The bar's rows from top (map position 1) to bottom (0), and its columns, in the
    /// strip's coordinates: what tests read back.
    pub fn bar_geometry(
        &self,
        height: u32,
    ) -> Result<(std::ops::Range<u32>, std::ops::Range<u32>)> {
        let font = font()?;
        let l = self.layout(&font, height);
        Ok((
            l.bar_top..l.bar_bottom + 1,
            l.bar_left..l.bar_left + l.bar_width,
        ))
    }

    /// The image `rgba` (`width` x `height`) and its depth map with the bar's strip
    /// appended on the right: the strip is [`ColorBar::strip`] of `background` (linear
    /// RGB and alpha, as the renderer cleared the image); the depth map is NaN there.
    /// Returns the new width, pixels and depth map.
    pub fn append(
        &self,
        rgba: &[u8],
        distance: &[f32],
        width: u32,
        height: u32,
        background: [f32; 4],
    ) -> Result<(u32, Vec<u8>, Vec<f32>)> {
        let pixels = width as usize * height as usize;
        if rgba.len() != 4 * pixels || distance.len() != pixels {
            return Err(Error::data(
                "colour bar image's bytes and depths",
                crate::error::Problem::Count {
                    expected: 5 * pixels,
                    found: rgba.len() + distance.len(),
                },
            ));
        }
        let (strip_width, strip) = self.strip(height, background)?;
        let total = width + strip_width;
        let (row, strip_row) = (width as usize, strip_width as usize);
        let mut out = Vec::with_capacity(4 * total as usize * height as usize);
        let mut depth = Vec::with_capacity(total as usize * height as usize);
        for y in 0..height as usize {
            out.extend_from_slice(&rgba[4 * y * row..4 * (y + 1) * row]);
            out.extend_from_slice(&strip[4 * y * strip_row..4 * (y + 1) * strip_row]);
            depth.extend_from_slice(&distance[y * row..(y + 1) * row]);
            depth.extend(std::iter::repeat_n(f32::NAN, strip_row));
        }
        Ok((total, out, depth))
    }

    /// [`ColorBar::append`] to a rendered image, in place: its width, pixels and depth
    /// map take the strip.
    pub fn append_to(&self, image: &mut RenderedImage, background: [f32; 4]) -> Result<()> {
        let (width, rgba, distance) = self.append(
            &image.rgba,
            &image.distance,
            image.width,
            image.height,
            background,
        )?;
        (image.width, image.rgba, image.distance) = (width, rgba, distance);
        Ok(())
    }

    /// The strip alone, [`ColorBar::strip_width`] x `height` RGBA pixels (sRGB-encoded as
    /// the PNG stores them): `background` with the bar, its ticks and its label. The
    /// render appends it to the image ([`ColorBar::append`]); the viewer copies it into
    /// the window beside the glyphs, so both show the same pixels.
    pub fn strip(&self, height: u32, background: [f32; 4]) -> Result<(u32, Vec<u8>)> {
        self.check()?;
        let font = font()?;
        let l = self.layout(&font, height);
        let [r, g, b, a] = background;
        let clear = [
            srgb_byte(r),
            srgb_byte(g),
            srgb_byte(b),
            (a.clamp(0.0, 1.0) * 255.0).round() as u8,
        ];
        let pixels = l.width as usize * height as usize;
        let mut out: Vec<u8> = clear.iter().copied().cycle().take(4 * pixels).collect();
        let mut canvas = Canvas {
            rgba: &mut out,
            width: l.width,
            height,
        };
        // The bar: row y holds map position (bottom - y) / (bottom - top).
        let span = (l.bar_bottom - l.bar_top) as f32;
        for y in l.bar_top..=l.bar_bottom.min(height.saturating_sub(1)) {
            let [cr, cg, cb] = viridis_srgb8((l.bar_bottom - y) as f32 / span);
            for x in l.bar_left..l.bar_left + l.bar_width {
                let at = 4 * (y as usize * l.width as usize + x as usize);
                canvas.rgba[at..at + 4].copy_from_slice(&[cr, cg, cb, 255]);
            }
        }
        // Dark text on a light background, light text on a dark or clear one.
        let luminance = 0.2126 * r + 0.7152 * g + 0.0722 * b;
        let ink = if a > 0.5 && luminance > 0.25 {
            [0, 0, 0]
        } else {
            [255, 255, 255]
        };
        let scaled = font.as_scaled(PxScale::from(l.size));
        let cap = 0.73 * scaled.ascent();
        let x0 = l.bar_left as f32;
        canvas.text(&font, l.size, &self.label, x0, l.margin + cap, ink);
        let largest = self.low.abs().max(self.high.abs());
        let text_x = x0 + l.bar_width as f32 + 0.5 * l.margin;
        let ticks = self.ticks();
        for k in shown_ticks(span, l.size) {
            let y = l.bar_bottom as f32 - span * k as f32 / (TICKS - 1) as f32;
            let text = tick_text(ticks[k], largest);
            canvas.text(&font, l.size, &text, text_x, y + 0.5 * cap, ink);
        }
        Ok((l.width, out))
    }
}

/// Which of the [`TICKS`] ticks are labelled on a bar `span` pixels tall with text of
/// `size` pixels: every one where their labels are at least 1.2 text heights apart,
/// else every other one, else the two ends only (a short image's bar; its labels would
/// run into each other).
fn shown_ticks(span: f32, size: f32) -> Vec<usize> {
    let gap = |step: usize| span * step as f32 / (TICKS - 1) as f32;
    let step = [1, 2]
        .into_iter()
        .find(|&step| gap(step) >= 1.2 * size)
        .unwrap_or(TICKS - 1);
    (0..TICKS).step_by(step).collect()
}

/// Checks that a colour bar is asked of a magnitude colouring (the bar shows its map).
pub fn check_colorbar(settings: &RenderSettings) -> Result<()> {
    if matches!(settings.color, ColorMode::Magnitude { .. }) {
        return Ok(());
    }
    Err(Error::setting(
        Setting::Colorbar,
        crate::message![
            "shows the magnitude colour map: it needs ",
            Setting::Color.with("magnitude")
        ],
    ))
}

/// The scale every glyph of `scenes` has, if they all have the same one (the unit of a
/// colour bar in data units; see [`ColorBar::of_magnitude`]).
pub fn common_scale<'a>(scenes: impl IntoIterator<Item = &'a Scene>) -> Option<f64> {
    let mut scales = scenes
        .into_iter()
        .flat_map(|scene| scene.glyph_sets.iter())
        .flat_map(|set| set.scales.iter());
    let first = *scales.next()?;
    scales.all(|s| *s == first).then_some(first)
}

fn font() -> Result<FontRef<'static>> {
    FontRef::try_from_slice(dejavu_sans()?)
        .map_err(|err| Error::setup("usable DejaVu Sans font", err))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn labels_of_a_short_bar_keep_apart() {
        assert_eq!(shown_ticks(400.0, 11.0), [0, 1, 2, 3, 4]);
        // 53 px between neighbours is just over 1.2 text heights at 44 px: all of them;
        // 52 px is under: every other one.
        assert_eq!(shown_ticks(4.0 * 53.0, 44.0), [0, 1, 2, 3, 4]);
        assert_eq!(shown_ticks(4.0 * 52.0, 44.0), [0, 2, 4]);
        assert_eq!(shown_ticks(40.0, 11.0), [0, 2, 4]);
        assert_eq!(shown_ticks(20.0, 11.0), [0, 4]);
        for span in 2..600 {
            let shown = shown_ticks(span as f32, 11.0);
            assert_eq!((shown[0], shown[shown.len() - 1]), (0, TICKS - 1), "{span}");
            let step = span as f32 * (shown[1] - shown[0]) as f32 / (TICKS - 1) as f32;
            assert!(shown.len() == 2 || step >= 1.2 * 11.0, "{span}: {shown:?}");
        }
    }

    #[test]
    fn ticks_are_short_and_span_the_range() {
        assert_eq!(tick_text(0.0, 1.0), "0");
        assert_eq!(tick_text(0.45, 0.9), "0.450");
        assert_eq!(tick_text(12.5, 50.0), "12.5");
        assert_eq!(tick_text(0.0017, 0.0017), "0.00170");
        assert_eq!(tick_text(2.5e-5, 5e-5), "2.50e-5");
        let bar = ColorBar {
            low: -1.0,
            high: 3.0,
            label: "x".into(),
        };
        assert_eq!(bar.ticks(), [-1.0, 0.0, 1.0, 2.0, 3.0]);
    }

    #[test]
    fn the_map_ends_are_the_shaders_polynomial_ends() {
        // t = 0 is c0 and t = 1 the sum of the coefficients, each to the power 2.2.
        let low = viridis_linear(0.0);
        assert!((low[0] - 0.277_727_33f32.powf(2.2)).abs() < 1e-6);
        assert_eq!(viridis_linear(-3.0), low);
        assert_eq!(viridis_linear(7.0), viridis_linear(1.0));
        // Viridis runs from a dark purple to a bright yellow.
        let (bottom, top) = (viridis_srgb8(0.0), viridis_srgb8(1.0));
        assert!(bottom[2] > bottom[1] && top[0] > 200 && top[1] > 200 && top[2] < 80);
    }

    #[test]
    fn a_short_image_keeps_what_fits() {
        // 16 rows: the bar would start below the image (its text is at least 11 px).
        let bar = ColorBar {
            low: 0.0,
            high: 1.0,
            label: "x".into(),
        };
        let (width, rgba, depth) = bar
            .append(
                &[7; 4 * 3 * 16],
                &[0.5; 3 * 16],
                3,
                16,
                [0.0, 0.0, 0.0, 1.0],
            )
            .unwrap();
        assert!(width > 3);
        assert_eq!(
            (rgba.len(), depth.len()),
            (64 * width as usize, 16 * width as usize)
        );
        assert_eq!(rgba[..12], [7; 12]);
        let (strip_width, strip) = bar.strip(16, [0.0, 0.0, 0.0, 1.0]).unwrap();
        assert_eq!(
            (strip_width, strip.len()),
            (width - 3, 64 * (width - 3) as usize)
        );
    }

    #[test]
    fn a_bad_range_is_refused() {
        let bar = ColorBar {
            low: 1.0,
            high: 1.0,
            label: String::new(),
        };
        let err = bar.append(&[0; 4], &[0.0], 1, 1, [0.0; 4]);
        assert!(
            matches!(&err, Err(Error::Setting { setting: Setting::Colorbar, message, .. })
                if message.to_string().contains("low < high"))
        );
    }
}
