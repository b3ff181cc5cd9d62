//! PNG output of rendered images: 8-bit RGBA, already sRGB-encoded by the renderer, so
//! the file is marked with an sRGB chunk (plus the gAMA and cHRM fallbacks the PNG
//! specification recommends for decoders that ignore sRGB). The image is encoded in
//! memory and published with an atomic rename, never half-written.
use std::fs::File;
use std::io::BufReader;
use std::path::Path;

use png::{BitDepth, ColorType, ScaledFloat, SourceChromaticities, SrgbRenderingIntent};

use crate::io::atomic::write_atomic;
use crate::{Error, Result};

const RGBA_BYTES: usize = 4;

/// Writes `rgba` (rows top to bottom, 4 bytes per pixel, sRGB-encoded) as a PNG file.
pub fn write_png_rgba8(path: &Path, width: u32, height: u32, rgba: &[u8]) -> Result<()> {
    write_atomic(path, &encode_png_rgba8(path, width, height, rgba)?)
}

/// The PNG file [`write_png_rgba8`] writes, as bytes (for a set of outputs written
/// together); `path` names it in errors.
pub fn encode_png_rgba8(path: &Path, width: u32, height: u32, rgba: &[u8]) -> Result<Vec<u8>> {
    encode_png_rgba8_at(path, (width, height), rgba, None)
}

/// [`encode_png_rgba8`] with a print resolution: `dpi` pixels per inch, recorded in the
/// file's pHYs chunk (as pixels per metre, rounded), so that a page layout program
/// places the image at its intended size.
pub fn encode_png_rgba8_at(
    path: &Path,
    (width, height): (u32, u32),
    rgba: &[u8],
    dpi: Option<f64>,
) -> Result<Vec<u8>> {
    check_size(path, width, height, rgba.len())?;
    check_encoding_memory(path, rgba.len())?;
    let per_metre = dpi.map(|dpi| (dpi / 0.0254).round() as u32);
    encode(width, height, rgba, per_metre).map_err(|err| Error::io(path, err))
}

/// The encoder's working memory (a filtered copy of the image and the compressed
/// stream, each up to the image's size) is allocated inside the `png` crate, where a
/// failure aborts the process. So much is asked for here first, fallibly, and given
/// back: under a memory limit (`ulimit -v`) a large image is then an error naming the
/// file instead of an abort.
fn check_encoding_memory(path: &Path, image_bytes: usize) -> Result<()> {
    let mut probe: Vec<u8> = Vec::new();
    probe
        .try_reserve_exact(image_bytes.saturating_mul(2))
        .map_err(|_| Error::OutOfMemory {
            what: "the PNG encoder's buffer",
            file: Some(path.display().to_string()),
            bytes: Some(image_bytes.saturating_mul(2) as u64),
            settings: &[],
        })
}

/// Reads an 8-bit RGBA PNG; returns width, height and the pixels, rows top to bottom.
pub fn read_png_rgba8(path: &Path) -> Result<(u32, u32, Vec<u8>)> {
    let file = File::open(path).map_err(|err| Error::io(path, err))?;
    let decoding_error = |err: png::DecodingError| match err {
        png::DecodingError::IoError(io) => Error::io(path, io),
        other => Error::input(path.display().to_string(), "png", other.to_string()),
    };
    let mut reader = png::Decoder::new(BufReader::new(file))
        .read_info()
        .map_err(decoding_error)?;
    let (color, depth) = reader.output_color_type();
    if (color, depth) != (ColorType::Rgba, BitDepth::Eight) {
        return Err(Error::input(
            path.display().to_string(),
            "png",
            format!("expected 8-bit RGBA, found {color:?} with {depth:?}-bit samples"),
        ));
    }
    let mut pixels = vec![0; reader.output_buffer_size().unwrap_or(0)];
    let frame = reader.next_frame(&mut pixels).map_err(decoding_error)?;
    pixels.truncate(frame.buffer_size());
    Ok((frame.width, frame.height, pixels))
}

fn check_size(path: &Path, width: u32, height: u32, len: usize) -> Result<()> {
    let expected = (width as usize)
        .checked_mul(height as usize)
        .and_then(|pixels| pixels.checked_mul(RGBA_BYTES));
    if width == 0 || height == 0 || expected != Some(len) {
        return Err(Error::input(
            path.display().to_string(),
            "pixels",
            format!(
                "an RGBA image of {width} x {height} pixels needs {} bytes, found {len}",
                expected.map_or_else(|| "too many".to_string(), |n| n.to_string()),
            ),
        ));
    }
    Ok(())
}

fn encode(
    width: u32,
    height: u32,
    rgba: &[u8],
    per_metre: Option<u32>,
) -> std::result::Result<Vec<u8>, png::EncodingError> {
    let mut encoded = Vec::new();
    let mut encoder = png::Encoder::new(&mut encoded, width, height);
    encoder.set_color(ColorType::Rgba);
    encoder.set_depth(BitDepth::Eight);
    // fdeflate's fast mode rather than zlib's default level: encoding the demo or the
    // 256-glyph field took 25 to 90 ms of CPU (a quarter to a half of a one-shot render),
    // now 1 to 3 ms, for files from 3 % smaller (glyphs on a plain background) to 45 %
    // larger (the sphere impostor's shaded discs). docs/guide/performance.md, "First image".
    encoder.set_compression(png::Compression::Fast);
    encoder.set_source_srgb(SrgbRenderingIntent::Perceptual);
    // The fallback values of PNG 3rd edition, 11.3.2.5 (gAMA 45455 and the sRGB
    // primaries with a D65 white point).
    encoder.set_source_gamma(ScaledFloat::from_scaled(45455));
    encoder.set_source_chromaticities(SourceChromaticities::new(
        (0.3127, 0.3290),
        (0.64, 0.33),
        (0.30, 0.60),
        (0.15, 0.06),
    ));
    encoder.set_pixel_dims(per_metre.map(|ppu| png::PixelDimensions {
        xppu: ppu,
        yppu: ppu,
        unit: png::Unit::Meter,
    }));
    let mut writer = encoder.write_header()?;
    writer.write_image_data(rgba)?;
    writer.finish()?;
    Ok(encoded)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::io::atomic::tests::scratch_dir;

    fn gradient(width: u32, height: u32) -> Vec<u8> {
        (0..width * height)
            .flat_map(|p| {
                [
                    (p % 256) as u8,
                    (p / 3) as u8,
                    255 - (p % 7) as u8,
                    (p * 5) as u8,
                ]
            })
            .collect()
    }

    /// `dpi` is recorded as pixels per metre (300 dpi: 11811), read back by a decoder.
    #[test]
    fn the_print_resolution_is_recorded() {
        let rgba = gradient(4, 3);
        let path = Path::new("x.png");
        for (dpi, expected) in [
            (Some(300.0), Some(11811)),
            (Some(72.0), Some(2835)),
            (None, None),
        ] {
            let bytes = encode_png_rgba8_at(path, (4, 3), &rgba, dpi).unwrap();
            let reader = png::Decoder::new(std::io::Cursor::new(bytes))
                .read_info()
                .unwrap();
            let dims = reader.info().pixel_dims;
            assert_eq!(dims.map(|d| (d.xppu, d.yppu)), expected.map(|e| (e, e)));
            assert!(dims.is_none_or(|d| d.unit == png::Unit::Meter));
        }
    }

    #[test]
    fn round_trip_keeps_every_byte_and_marks_srgb() {
        let dir = scratch_dir("png-round-trip");
        let path = dir.join("image.png");
        let rgba = gradient(7, 5);
        write_png_rgba8(&path, 7, 5, &rgba).unwrap();
        assert_eq!(read_png_rgba8(&path).unwrap(), (7, 5, rgba));

        let decoder = png::Decoder::new(BufReader::new(File::open(&path).unwrap()));
        let reader = decoder.read_info().unwrap();
        assert_eq!(reader.info().srgb, Some(SrgbRenderingIntent::Perceptual));
        let names: Vec<String> = std::fs::read_dir(&dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        assert_eq!(names, vec!["image.png".to_string()]);
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn wrong_buffer_size_is_refused_and_writes_nothing() {
        let dir = scratch_dir("png-wrong-size");
        let path = dir.join("image.png");
        for (width, height, len) in [(4, 4, 63), (4, 4, 65), (0, 4, 0)] {
            let err = write_png_rgba8(&path, width, height, &vec![0; len]).unwrap_err();
            assert!(matches!(err, Error::Input { .. }), "{err}");
            assert!(err.to_string().contains("image.png"), "{err}");
        }
        assert!(!path.exists());
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn reading_rgb_or_garbage_names_the_file() {
        let dir = scratch_dir("png-read-errors");
        let garbage = dir.join("garbage.png");
        std::fs::write(&garbage, b"not a png at all").unwrap();
        let err = read_png_rgba8(&garbage).unwrap_err();
        assert!(err.to_string().contains("garbage.png"), "{err}");

        let rgb = dir.join("rgb.png");
        let mut encoded = Vec::new();
        let mut encoder = png::Encoder::new(&mut encoded, 2, 1);
        encoder.set_color(ColorType::Rgb);
        let mut writer = encoder.write_header().unwrap();
        writer.write_image_data(&[0; 6]).unwrap();
        writer.finish().unwrap();
        std::fs::write(&rgb, &encoded).unwrap();
        let err = read_png_rgba8(&rgb).unwrap_err();
        assert!(matches!(err, Error::Input { .. }), "{err}");
        assert!(err.to_string().contains("rgb.png") && err.to_string().contains("RGBA"));
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
