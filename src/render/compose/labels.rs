//! Orientation labels (L/R, A/P, S/I) at the edges of a rendered image, drawn onto its
//! RGBA pixels with DejaVu Sans rasterised by `ab_glyph`.
//!
//! The letter at an edge names the world direction (scanner RAS+: +x right, +y anterior,
//! +z superior) that points towards that edge on screen: the camera's right vector for
//! the right edge, its up vector for the top, their negatives for the others. A direction
//! between axes (the oblique three-slice view) gets the letters of every axis above
//! 0.6 of its largest component, largest first ("LP").
use ab_glyph::{Font, FontRef, PxScale, ScaleFont, point};
use glam::DVec3;
use std::sync::OnceLock;

use crate::camera::Camera;
use crate::{Error, Result};

/// Where DejaVu Sans is looked for (Debian's fonts-dejavu-core, then Arch's path).
pub const FONT_PATHS: [&str; 2] = [
    "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf",
    "/usr/share/fonts/TTF/DejaVuSans.ttf",
];

/// A direction's component above this fraction of its largest one adds its letter.
const MIXED_AXIS_FRACTION: f64 = 0.6;

/// Letter height as a fraction of the image's shorter side, and the least in pixels.
const LETTER_FRACTION: f32 = 0.05;
const MIN_LETTER_PX: f32 = 12.0;

/// Opacity of the dark box behind a panel's caption.
const CAPTION_BOX_OPACITY: f32 = 0.6;

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
    let font = FontRef::try_from_slice(dejavu_sans()?)
        .map_err(|err| Error::setup("usable DejaVu Sans font", err))?;
    let size = (LETTER_FRACTION * width.min(height) as f32).max(MIN_LETTER_PX);
    Ok((font, size))
}

/// Draws `text` (a panel's slice, "k=12") in the top-left corner of `rgba` (`width` x
/// `height`, row-major RGBA8), as the edge labels are drawn: white with a dark shadow,
/// at their size.
pub fn draw_caption(rgba: &mut [u8], width: u32, height: u32, text: &str) -> Result<()> {
    let (font, size) = lettering(rgba, width, height, "bytes of the captioned RGBA image")?;
    let scaled = font.as_scaled(PxScale::from(size));
    let (margin, cap) = (0.3 * size, 0.73 * scaled.ascent());
    let shadow = (1.0f32).max(0.06 * size);
    let mut canvas = Canvas {
        rgba,
        width,
        height,
    };
    let (x, baseline) = (margin, margin + cap);
    // A dark box behind the text, so that it reads over a bright underlay too.
    let text_width: f32 = text
        .chars()
        .map(|c| scaled.h_advance(font.glyph_id(c)))
        .sum();
    let pad = 0.25 * size;
    let (x0, y0) = (
        (x - pad).floor() as i64,
        (baseline - cap - pad).floor() as i64,
    );
    let (x1, y1) = (
        (x + text_width + shadow + pad).ceil() as i64,
        (baseline + shadow + pad).ceil() as i64,
    );
    for y in y0.max(0)..y1 {
        for x in x0.max(0)..x1 {
            canvas.blend(x, y, [0, 0, 0], CAPTION_BOX_OPACITY);
        }
    }
    canvas.text(&font, size, text, x + shadow, baseline + shadow, [0, 0, 0]);
    canvas.text(&font, size, text, x, baseline, [255, 255, 255]);
    Ok(())
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
        let scaled = font.as_scaled(PxScale::from(size));
        let mut pen = x;
        for c in text.chars() {
            let id = font.glyph_id(c);
            let glyph = id.with_scale_and_position(size, point(pen, baseline));
            pen += scaled.h_advance(id);
            let Some(outline) = font.outline_glyph(glyph) else {
                continue;
            };
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
}
