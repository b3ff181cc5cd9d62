//! Anti-aliasing by supersampling (`--samples 1|4|16`): the frame is drawn at s = 2 or
//! 4 times the width and height, one ray per sample as at one sample per pixel, and each
//! s x s block is averaged into one pixel. Supersampling rather than multisampling: the
//! ray casters write `gl_FragDepth` and their colour per fragment, so MSAA would need
//! per-sample shading anyway, and the same code serves every method and both paths.
//!
//! The average is taken in linear light, weighted by alpha: a pixel's alpha is the
//! fraction of its samples that something (a glyph, the underlay, an opaque background)
//! covers, and its colour the mean colour of those samples, as a PNG's straight alpha
//! wants it. The depth map is not averaged: it comes from a render at the image's own
//! size (see `HeadlessRenderer::render_view`).
use crate::error::{Error, Result, Setting};
use crate::render::settings::srgb_to_linear;
pub use crate::render::settings::supersampling_factor;
use crate::scene::MAX_IMAGE_SIDE;

/// The size drawn for `width` x `height` at `factor` (s): an error naming the sizes when
/// a side would exceed [`MAX_IMAGE_SIDE`].
pub(crate) fn supersampled_size(
    width: u32,
    height: u32,
    factor: u32,
    samples: u32,
) -> Result<(u32, u32)> {
    let (w, h) = (width as u64 * factor as u64, height as u64 * factor as u64);
    if w > MAX_IMAGE_SIDE as u64 || h > MAX_IMAGE_SIDE as u64 {
        return Err(Error::setting_value(
            Setting::Samples,
            samples,
            crate::message![
                format!(
                    "draws {width} x {height} at {factor} times the size, {w} x {h}, beyond \
                     {MAX_IMAGE_SIDE} pixels per side: ask for fewer samples or a smaller \
                     image (at most {} pixels per side with ",
                    MAX_IMAGE_SIDE / factor
                ),
                Setting::Samples.with(samples),
                ")"
            ],
        ));
    }
    Ok((w as u32, h as u32))
}

/// The 8-bit sRGB encoding of a linear value in [0, 1], rounded to nearest.
fn linear_to_srgb_byte(linear: f64) -> u8 {
    let c = linear.clamp(0.0, 1.0);
    let encoded = if c <= 0.0031308 {
        12.92 * c
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    };
    (encoded * 255.0).round().clamp(0.0, 255.0) as u8
}

/// Averages each `factor` x `factor` block of `big` (sRGB RGBA8, `width * factor` wide)
/// into one pixel of a `width` x `height` image: alpha is the blocks' mean alpha, colour
/// the alpha-weighted mean in linear light, encoded back to sRGB.
pub(crate) fn box_filter(big: &[u8], width: u32, height: u32, factor: u32) -> Result<Vec<u8>> {
    let (w, h, s) = (width as usize, height as usize, factor as usize);
    if big.len() != 4 * w * s * h * s {
        return Err(Error::data(
            "bytes of the supersampled image",
            crate::error::Problem::Count {
                expected: 4 * w * s * h * s,
                found: big.len(),
            },
        ));
    }
    let linear: Vec<f64> = (0..=255u8).map(|b| srgb_to_linear(b) as f64).collect();
    let mut out = Vec::new();
    out.try_reserve_exact(4 * w * h)
        .map_err(|_| Error::OutOfMemory {
            what: "the antialiased image",
            file: None,
            bytes: Some(4 * w as u64 * h as u64),
            settings: &[],
        })?;
    let row = 4 * w * s;
    let n = (s * s) as f64;
    for y in 0..h {
        for x in 0..w {
            let (mut rgb, mut alpha) = ([0.0f64; 3], 0.0f64);
            for sy in 0..s {
                let start = (y * s + sy) * row + 4 * x * s;
                for px in big[start..start + 4 * s].chunks_exact(4) {
                    let a = px[3] as f64 / 255.0;
                    for c in 0..3 {
                        rgb[c] += linear[px[c] as usize] * a;
                    }
                    alpha += a;
                }
            }
            let colour = rgb.map(|c| if alpha > 0.0 { c / alpha } else { 0.0 });
            out.extend(colour.map(linear_to_srgb_byte));
            out.push((alpha / n * 255.0).round() as u8);
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sample_counts_and_sizes() {
        assert_eq!(supersampling_factor(1).ok(), Some(1));
        assert_eq!(supersampling_factor(4).ok(), Some(2));
        assert_eq!(supersampling_factor(16).ok(), Some(4));
        assert!(supersampling_factor(8).is_err());
        assert_eq!(supersampled_size(4096, 100, 4, 16).ok(), Some((16384, 400)));
        let error = supersampled_size(4097, 100, 4, 16).expect_err("too wide");
        assert!(error.to_string().contains("4096"), "{error}");
    }

    #[test]
    fn the_box_filter_keeps_flat_colours_and_measures_coverage() {
        // Every 8-bit value survives decoding and encoding.
        for b in 0..=255u8 {
            let block: Vec<u8> = [b, 255 - b, b / 2, 255].repeat(4);
            let out = box_filter(&block, 1, 1, 2).expect("filter");
            assert_eq!(out, vec![b, 255 - b, b / 2, 255]);
        }
        // One opaque red sample of four over a transparent background: red, alpha 1/4.
        let mut block = vec![0u8; 16];
        block[..4].copy_from_slice(&[255, 0, 0, 255]);
        assert_eq!(
            box_filter(&block, 1, 1, 2).expect("filter"),
            vec![255, 0, 0, 64]
        );
        // Black and white opaque halves average in linear light: 0.5 linear is 188.
        let block = [[0, 0, 0, 255], [255, 255, 255, 255]].concat().repeat(2);
        assert_eq!(
            box_filter(&block, 1, 1, 2).expect("filter"),
            vec![188, 188, 188, 255]
        );
    }
}
