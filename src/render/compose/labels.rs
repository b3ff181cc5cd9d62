//! Orientation labels (L/R, A/P, S/I) at the edges of a rendered image, drawn onto its
//! RGBA pixels with DejaVu Sans rasterised by `ab_glyph`.
//!
//! The letter at an edge names the world direction (scanner RAS+: +x right, +y anterior,
//! +z superior) that points towards that edge on screen: the camera's right vector for
//! the right edge, its up vector for the top, their negatives for the others. A direction
//! between axes (the oblique three-slice view) gets the letters of every axis above
//! 0.6 of its largest component, largest first ("LP").
use ab_glyph::{Font, FontRef, OutlinedGlyph, PxScale, ScaleFont, point};
use glam::DVec3;
use std::sync::OnceLock;

use crate::camera::Camera;
use crate::{Error, Result};

/// Where DejaVu Sans is looked for (Debian's fonts-dejavu-core, then Arch's path).
pub(crate) const FONT_PATHS: [&str; 2] = [
    "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf",
    "/usr/share/fonts/TTF/DejaVuSans.ttf",
];

/// A direction's component above this fraction of its largest one adds its letter.
const MIXED_AXIS_FRACTION: f64 = 0.6;

/// Letter height as a fraction of the image's shorter side, and the least in pixels.
const LETTER_FRACTION: f32 = 0.05;
const MIN_LETTER_PX: f32 = 12.0;

/// The caption's box is opaque black, and encloses every pixel of its text: a caption's
/// pixels are then its own whatever the panel shows under it (it reads over a bright
/// underlay too), so the viewer copies them into its window byte for byte
/// ([`caption_patch`]).
const CAPTION_BOX: [u8; 3] = [0, 0, 0];

/// DejaVu Sans, read once per process; an error names the paths tried.
pub fn dejavu_sans() -> Result<&'static [u8]> {
    static FONT: OnceLock<Option<Vec<u8>>> = OnceLock::new();
    FONT.get_or_init(|| FONT_PATHS.iter().find_map(|p| std::fs::read(p).ok()))
        .as_deref()
        .ok_or_else(|| {
            Error::setup(
                "DejaVu Sans font, which text needs (Debian: fonts-dejavu-core)",
                format_args!("looked in {}", FONT_PATHS.join(", ")),
            )
        })
}

/// The letters of the four image edges.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct EdgeLabels {
    /// Letters of the direction the left edge faces (e.g. "R", "LP").
    pub left: String,
    /// Letters of the right edge's direction.
    pub right: String,
    /// Letters of the top edge's direction.
    pub top: String,
    /// Letters of the bottom edge's direction.
    pub bottom: String,
}

/// The anatomical letters of world direction `d`.
fn letters(d: DVec3) -> String {
    let largest = d.abs().max_element();
    let mut axes: Vec<usize> = (0..3)
        .filter(|&a| d[a].abs() > MIXED_AXIS_FRACTION * largest)
        .collect();
    axes.sort_by(|&a, &b| d[b].abs().total_cmp(&d[a].abs()));
    axes.iter()
        .map(|&a| {
            let [positive, negative] = [['R', 'L'], ['A', 'P'], ['S', 'I']][a];
            if d[a] > 0.0 { positive } else { negative }
        })
        .collect()
}

/// The labels of the edges of an image taken by `camera`.
pub fn edge_labels(camera: &Camera) -> EdgeLabels {
    let frame = camera.frame();
    EdgeLabels {
        left: letters(-frame.right),
        right: letters(frame.right),
        top: letters(frame.up),
        bottom: letters(-frame.up),
    }
}

/// Draws `labels` onto `rgba` (`width` x `height`, row-major RGBA8), white with a dark
/// shadow so that they read on any background, each centred on its edge.
pub fn draw_edge_labels(
    rgba: &mut [u8],
    width: u32,
    height: u32,
    labels: &EdgeLabels,
) -> Result<()> {
    let (font, size) = lettering(rgba, width, height, "bytes of the labelled RGBA image")?;
    let scaled = font.as_scaled(PxScale::from(size));
    let (w, h) = (width as f32, height as f32);
    let margin = 0.3 * size;
    let text_width = |text: &str| -> f32 {
        text.chars()
            .map(|c| scaled.h_advance(font.glyph_id(c)))
            .sum()
    };
    // Baseline-left positions: the cap height is about the ascent's 0.73 in DejaVu Sans.
    let cap = 0.73 * scaled.ascent();
    let placements = [
        (&labels.left, margin, 0.5 * (h + cap)),
        (
            &labels.right,
            w - margin - text_width(&labels.right),
            0.5 * (h + cap),
        ),
        (
            &labels.top,
            0.5 * (w - text_width(&labels.top)),
            margin + cap,
        ),
        (
            &labels.bottom,
            0.5 * (w - text_width(&labels.bottom)),
            h - margin,
        ),
    ];
    let mut canvas = Canvas {
        rgba,
        width,
        height,
    };
    for (text, x, baseline) in placements {
        let shadow = (1.0f32).max(0.06 * size);
        canvas.text(&font, size, text, x + shadow, baseline + shadow, [0, 0, 0]);
        canvas.text(&font, size, text, x, baseline, [255, 255, 255]);
    }
    Ok(())
}

/// Checks that `rgba` holds `width` x `height` RGBA8 pixels (`what` names its bytes in
/// the error) and gives the font and the letters' size in pixels for that image.
fn lettering(
    rgba: &[u8],
    width: u32,
    height: u32,
    what: &'static str,
) -> Result<(FontRef<'static>, f32)> {
    let expected = 4 * width as usize * height as usize;
    if rgba.len() != expected {
        return Err(Error::data(
            what,
            crate::error::Problem::Count {
                expected,
                found: rgba.len(),
            },
        ));
    }
    Ok((font()?, letter_size(width, height)))
}

/// DejaVu Sans as `ab_glyph` reads it.
fn font() -> Result<FontRef<'static>> {
    FontRef::try_from_slice(dejavu_sans()?)
        .map_err(|err| Error::setup("usable DejaVu Sans font", err))
}

/// The band along each edge of a `width` x `height` image, in pixels, that its edge
/// labels ([`draw_edge_labels`]) and a caption ([`draw_caption`]) may cover: their margin,
/// letters and shadow, with room to spare. Framing that keeps glyphs out of it keeps
/// every letter off the glyphs.
pub fn edge_band(width: u32, height: u32) -> f64 {
    1.25 * f64::from(letter_size(width, height))
}

/// The letter size of labels on a `width` x `height` image.
fn letter_size(width: u32, height: u32) -> f32 {
    (LETTER_FRACTION * width.min(height) as f32).max(MIN_LETTER_PX)
}

/// Draws `text` (a panel's slice, "k=12") in the top-left corner of `rgba` (`width` x
/// `height`, row-major RGBA8), as the edge labels are drawn: white with a dark shadow,
/// at their size, on an opaque black box.
pub fn draw_caption(rgba: &mut [u8], width: u32, height: u32, text: &str) -> Result<()> {
    let (font, size) = lettering(rgba, width, height, "bytes of the captioned RGBA image")?;
    let layout = CaptionLayout::new(&font, size, text);
    let mut canvas = Canvas {
        rgba,
        width,
        height,
    };
    layout.draw(&mut canvas, &font, size, text);
    Ok(())
}

/// A caption's pixels: the rectangle of a `width` x `height` panel that
/// [`draw_caption`] covers, at (`x`, `y`) in the panel, `w` x `h` pixels of RGBA8.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct CaptionPatch {
    /// Left column in the panel.
    pub x: u32,
    /// Top row in the panel.
    pub y: u32,
    /// Width in pixels.
    pub w: u32,
    /// Height in pixels.
    pub h: u32,
    /// The pixels, row by row (sRGB-encoded RGBA8, as a PNG stores them).
    pub rgba: Vec<u8>,
}

/// What [`draw_caption`] draws on a `width` x `height` panel, whatever the panel shows:
/// the box is opaque and holds the whole text.
pub fn caption_patch(width: u32, height: u32, text: &str) -> Result<CaptionPatch> {
    // The letters are sized by the panel; only its corner up to the box's end is drawn.
    let (font, size) = (font()?, letter_size(width, height));
    let layout = CaptionLayout::new(&font, size, text);
    let (x0, y0, x1, y1) = layout.bounds;
    let clamp = |v: i64, hi: u32| v.clamp(0, i64::from(hi)) as u32;
    let (x, y, right, bottom) = (
        clamp(x0, width),
        clamp(y0, height),
        clamp(x1, width),
        clamp(y1, height),
    );
    let mut corner = vec![0u8; 4 * right as usize * bottom as usize];
    layout.draw(
        &mut Canvas {
            rgba: &mut corner,
            width: right,
            height: bottom,
        },
        &font,
        size,
        text,
    );
    let (w, h) = (right - x, bottom - y);
    let rgba = (y..bottom)
        .flat_map(|row| {
            let at = 4 * (row as usize * right as usize + x as usize);
            corner[at..at + 4 * w as usize].to_vec()
        })
        .collect();
    Ok(CaptionPatch { x, y, w, h, rgba })
}

/// Where a caption's text and box go: the text's pen start and baseline, its shadow's
/// offset, and the box (x0, y0, x1, y1), end exclusive: a margin of a quarter letter
/// round the text and its shadow, and round every pixel their outlines touch.
struct CaptionLayout {
    x: f32,
    baseline: f32,
    shadow: f32,
    bounds: (i64, i64, i64, i64),
}

impl CaptionLayout {
    fn new(font: &FontRef, size: f32, text: &str) -> CaptionLayout {
        let scaled = font.as_scaled(PxScale::from(size));
        let (margin, cap) = (0.3 * size, 0.73 * scaled.ascent());
        let shadow = (1.0f32).max(0.06 * size);
        let (x, baseline) = (margin, margin + cap);
        let text_width: f32 = text
            .chars()
            .map(|c| scaled.h_advance(font.glyph_id(c)))
            .sum();
        let pad = 0.25 * size;
        let mut bounds = (
            (x - pad).floor() as i64,
            (baseline - cap - pad).floor() as i64,
            (x + text_width + shadow + pad).ceil() as i64,
            (baseline + shadow + pad).ceil() as i64,
        );
        for (dx, dy) in [(0.0, 0.0), (shadow, shadow)] {
            if let Some((x0, y0, x1, y1)) = text_bounds(font, size, text, x + dx, baseline + dy) {
                bounds = (
                    bounds.0.min(x0),
                    bounds.1.min(y0),
                    bounds.2.max(x1),
                    bounds.3.max(y1),
                );
            }
        }
        CaptionLayout {
            x,
            baseline,
            shadow,
            bounds,
        }
    }

    /// The box, the shadow and the text onto `canvas`.
    fn draw(&self, canvas: &mut Canvas, font: &FontRef, size: f32, text: &str) {
        let (x0, y0, x1, y1) = self.bounds;
        for y in y0.max(0)..y1 {
            for x in x0.max(0)..x1 {
                canvas.blend(x, y, CAPTION_BOX, 1.0);
            }
        }
        let (x, baseline, shadow) = (self.x, self.baseline, self.shadow);
        canvas.text(font, size, text, x + shadow, baseline + shadow, [0, 0, 0]);
        canvas.text(font, size, text, x, baseline, [255, 255, 255]);
    }
}

/// The pixels (x0, y0, x1, y1), end exclusive, that [`Canvas::text`] may touch drawing
/// `text` from (x, baseline); None for text without outlines.
fn text_bounds(
    font: &FontRef,
    size: f32,
    text: &str,
    x: f32,
    baseline: f32,
) -> Option<(i64, i64, i64, i64)> {
    outlines(font, size, text, x, baseline)
        .map(|outline| {
            let b = outline.px_bounds();
            (
                b.min.x.floor() as i64,
                b.min.y.floor() as i64,
                b.max.x.ceil() as i64 + 1,
                b.max.y.ceil() as i64 + 1,
            )
        })
        .reduce(|a, b| (a.0.min(b.0), a.1.min(b.1), a.2.max(b.2), a.3.max(b.3)))
}

/// The outlines of `text`'s letters set from (x, baseline), letters without one (a
/// space) left out.
fn outlines<'a>(
    font: &'a FontRef,
    size: f32,
    text: &'a str,
    x: f32,
    baseline: f32,
) -> impl Iterator<Item = OutlinedGlyph> + 'a {
    let scaled = font.as_scaled(PxScale::from(size));
    let mut pen = x;
    text.chars().filter_map(move |c| {
        let id = font.glyph_id(c);
        let glyph = id.with_scale_and_position(size, point(pen, baseline));
        pen += scaled.h_advance(id);
        font.outline_glyph(glyph)
    })
}

/// RGBA8 pixels that text is blended onto (the labels here, the colour bar's ticks).
pub(crate) struct Canvas<'a> {
    pub(crate) rgba: &'a mut [u8],
    pub(crate) width: u32,
    pub(crate) height: u32,
}

impl Canvas<'_> {
    /// Blends `text` in `colour` with its baseline starting at (x, baseline).
    pub(crate) fn text(
        &mut self,
        font: &FontRef,
        size: f32,
        text: &str,
        x: f32,
        baseline: f32,
        colour: [u8; 3],
    ) {
        for outline in outlines(font, size, text, x, baseline) {
            let bounds = outline.px_bounds();
            outline.draw(|gx, gy, coverage| {
                let px = bounds.min.x as i64 + i64::from(gx);
                let py = bounds.min.y as i64 + i64::from(gy);
                self.blend(px, py, colour, coverage);
            });
        }
    }

    pub(crate) fn blend(&mut self, x: i64, y: i64, colour: [u8; 3], coverage: f32) {
        if x < 0 || y < 0 || x >= i64::from(self.width) || y >= i64::from(self.height) {
            return;
        }
        let at = 4 * (y as usize * self.width as usize + x as usize);
        let a = coverage.clamp(0.0, 1.0);
        for (channel, &target) in self.rgba[at..at + 3].iter_mut().zip(&colour) {
            *channel = (f32::from(*channel) * (1.0 - a) + f32::from(target) * a).round() as u8;
        }
        let alpha = &mut self.rgba[at + 3];
        *alpha = (*alpha).max((a * 255.0).round() as u8);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn letters_name_the_dominant_axes() {
        assert_eq!(letters(DVec3::X), "R");
        assert_eq!(letters(DVec3::NEG_X), "L");
        assert_eq!(letters(DVec3::new(0.1, -1.0, 0.0)), "P");
        assert_eq!(letters(DVec3::new(-1.0, -0.9, 0.2)), "LP");
        assert_eq!(letters(DVec3::new(0.0, 0.3, 0.9)), "S");
        // The three-slice view's up vector: superior, a little right and posterior.
        assert_eq!(letters(DVec3::new(1.0, -1.0, 2.0)), "S");
    }

    /// A caption's patch is what draw_caption draws over any panel (a black and a bright
    /// noisy one), and draw_caption touches no pixel outside it: the box is opaque and
    /// holds the text, the descender of `j` too.
    #[test]
    fn a_caption_is_its_patch_over_any_panel() {
        if dejavu_sans().is_err() {
            eprintln!("SKIPPED: DejaVu Sans is not installed");
            return;
        }
        for (width, height, text) in [(72, 56, "j=5"), (300, 200, "k=12"), (40, 30, "i=3")] {
            let patch = caption_patch(width, height, text).expect("patch");
            assert!(patch.w > 0 && patch.h > 0 && patch.x + patch.w <= width);
            let mut noise = 7u32;
            let bright: Vec<u8> = (0..4 * width * height)
                .map(|_| {
                    noise = noise.wrapping_mul(1_103_515_245).wrapping_add(12_345);
                    128 + (noise >> 25) as u8
                })
                .collect();
            for panel in [vec![0u8; bright.len()], bright] {
                let mut drawn = panel.clone();
                draw_caption(&mut drawn, width, height, text).expect("caption");
                for y in 0..height {
                    for x in 0..width {
                        let at = 4 * (y * width + x) as usize;
                        let inside = (patch.x..patch.x + patch.w).contains(&x)
                            && (patch.y..patch.y + patch.h).contains(&y);
                        let expected = if inside {
                            let p = 4 * ((y - patch.y) * patch.w + x - patch.x) as usize;
                            &patch.rgba[p..p + 4]
                        } else {
                            &panel[at..at + 4]
                        };
                        assert_eq!(&drawn[at..at + 4], expected, "{text}: pixel ({x}, {y})");
                    }
                }
            }
            // White text on the box: the patch is not all black.
            assert!(patch.rgba.chunks_exact(4).any(|p| p[0] > 200));
        }
    }
}
