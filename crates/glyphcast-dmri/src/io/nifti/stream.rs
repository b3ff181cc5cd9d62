//! The bytes of one NIfTI file, plain or gzip-compressed (by the `.gz` ending), from
//! disk or from memory, read strictly in order and never more than asked for.
//!
//! A gzip stream is decoded as a sequence of members (`MultiGzDecoder`, as gzip(1)
//! does), and [`ByteStream::finish`] reads it to its end, so that the CRC-32 and length
//! of every member's trailer are checked and bytes after the last member that are not
//! another member are an error. Deflate expands at most 1032 to 1 (a 258-byte match per
//! two bits), which bounds what a compressed file of a given size can hold.
use std::io::{BufReader, ErrorKind, Read};
use std::path::Path;

use flate2::read::MultiGzDecoder;

use glyphcast::{Error, Result};

/// The most bytes one compressed byte can expand to, with room to spare.
const DEFLATE_EXPANSION: u64 = 1040;

/// One file's bytes, decompressed as they are read.
pub struct ByteStream<'a> {
    reader: Box<dyn Read + 'a>,
    /// The name for messages.
    pub file: String,
    /// Bytes on disk (for gzip, the compressed size).
    stored: u64,
    gzip: bool,
    /// Bytes handed out so far.
    position: u64,
}

/// Whether the name ends in `.gz` (any case).
pub fn is_gzip_name(name: &str) -> bool {
    name.to_ascii_lowercase().ends_with(".gz")
}

impl<'a> ByteStream<'a> {
    /// Opens `path`; a missing or unreadable file is an I/O error naming it.
    pub fn open(path: &Path) -> Result<ByteStream<'static>> {
        let opened = std::fs::File::open(path).map_err(|err| Error::io(path, err))?;
        let stored = opened.metadata().map_err(|err| Error::io(path, err))?.len();
        let file = path.display().to_string();
        let gzip = is_gzip_name(&file);
        Ok(ByteStream::new(
            Box::new(BufReader::new(opened)),
            file,
            stored,
            gzip,
        ))
    }

    /// The bytes of a file called `name` (its ending decides about gzip).
    pub fn from_bytes(bytes: &'a [u8], name: &str) -> Self {
        Self::new(
            Box::new(bytes),
            name.to_string(),
            bytes.len() as u64,
            is_gzip_name(name),
        )
    }

    fn new(reader: Box<dyn Read + 'a>, file: String, stored: u64, gzip: bool) -> Self {
        let reader: Box<dyn Read + 'a> = if gzip {
            Box::new(MultiGzDecoder::new(reader))
        } else {
            reader
        };
        Self {
            reader,
            file,
            stored,
            gzip,
            position: 0,
        }
    }

    /// The most bytes the stream can hold: the file size, or what its compressed size
    /// can expand to.
    pub fn capacity(&self) -> u64 {
        if self.gzip {
            self.stored.saturating_mul(DEFLATE_EXPANSION)
        } else {
            self.stored
        }
    }

    /// Whether `capacity` is the exact length (an uncompressed file).
    pub fn is_exact(&self) -> bool {
        !self.gzip
    }

    /// Bytes read so far.
    pub fn position(&self) -> u64 {
        self.position
    }

    /// Fills as much of `buf` as the stream holds; returns the count (less than
    /// `buf.len()` only at the end of the stream).
    pub fn fill(&mut self, buf: &mut [u8]) -> Result<usize> {
        let mut filled = 0;
        while filled < buf.len() {
            match self.reader.read(&mut buf[filled..]) {
                Ok(0) => break,
                Ok(n) => filled += n,
                Err(err) if err.kind() == ErrorKind::Interrupted => {}
                Err(err) => return Err(self.read_error(err)),
            }
        }
        self.position += filled as u64;
        Ok(filled)
    }

    /// Reads and drops bytes up to `position`; returns the position reached (short of it
    /// at the end of the stream).
    pub fn skip_to(&mut self, position: u64) -> Result<u64> {
        let mut scratch = [0u8; 8192];
        while self.position < position {
            let want = (position - self.position).min(scratch.len() as u64) as usize;
            if self.fill(&mut scratch[..want])? < want {
                break;
            }
        }
        Ok(self.position)
    }

    /// Reads a gzip stream to its end, checking every member's CRC-32 and length and
    /// that nothing but members follows. Uncompressed bytes after the data are allowed
    /// (as after the data of an uncompressed file).
    pub fn finish(mut self) -> Result<()> {
        if self.gzip {
            let mut scratch = [0u8; 8192];
            while self.fill(&mut scratch)? > 0 {}
        }
        Ok(())
    }

    fn read_error(&self, err: std::io::Error) -> Error {
        if !self.gzip {
            return Error::io(&self.file, err);
        }
        let what = if err.kind() == ErrorKind::UnexpectedEof {
            "the compressed stream ends early (truncated file, or its CRC-32 and length \
             trailer is missing)"
                .to_string()
        } else {
            format!("corrupt compressed data: {err}")
        };
        Error::input(&self.file, "gzip", what)
    }
}
