//! gzip compression for the `.gz` outputs of both image formats (`.nii.gz`, `.mif.gz`):
//! one encoder, at flate2's default level.
use std::io::Write as _;

use glyphcast::{Error, Result};

/// `bytes` gzip-compressed (the default level), as both formats' `.gz` files hold them.
pub fn gzip(bytes: Vec<u8>, file: &str) -> Result<Vec<u8>> {
    let mut encoder = flate2::write::GzEncoder::new(
        Vec::with_capacity(bytes.len() / 2),
        flate2::Compression::default(),
    );
    encoder
        .write_all(&bytes)
        .and_then(|()| encoder.finish())
        .map_err(|err| Error::io(file, err))
}
