//! The cap on the memory one input volume may take once read (its voxels as f64). The
//! declared size is checked against it before anything is allocated, so a small file
//! that declares a huge volume (a few bytes of gzip can declare terabytes) is refused
//! with a message instead of exhausting memory.
//!
//! The cap is `GLYPHCAST_MAX_INPUT_BYTES` when set (a number of bytes), else half of
//! this machine's memory (`MemTotal` of /proc/meminfo), else 8 GiB where that cannot
//! be read.
use glyphcast::{Error, Result};

/// The environment variable that sets the cap, in bytes.
pub const MAX_INPUT_BYTES_VARIABLE: &str = "GLYPHCAST_MAX_INPUT_BYTES";

/// The cap when the machine's memory is unknown.
const FALLBACK_BYTES: u64 = 8 << 30;

/// The cap in bytes; Err when the variable is set to something that is not a number.
pub fn max_input_bytes() -> Result<u64> {
    match std::env::var(MAX_INPUT_BYTES_VARIABLE) {
        Ok(text) => text.trim().parse().map_err(|_| Error::Environment {
            variable: MAX_INPUT_BYTES_VARIABLE,
            value: format!("{:?}", glyphcast::error::quoted(&text)),
            expected: "a number of bytes",
        }),
        Err(_) => Ok(machine_memory().map_or(FALLBACK_BYTES, |total| total / 2)),
    }
}

/// Err naming `file` and `dim` when a volume of `bytes` bytes in memory is over the cap.
pub fn check_input_size(file: &str, bytes: u64, what: &str) -> Result<()> {
    let limit = max_input_bytes()?;
    if bytes > limit {
        return Err(Error::input(
            file,
            "dim",
            format!(
                "{what} would take {bytes} bytes in memory, over the input limit of {limit} \
                 bytes ({MAX_INPUT_BYTES_VARIABLE}; by default half this machine's memory)"
            ),
        ));
    }
    Ok(())
}

/// A vector with room for `count` elements, or an error naming `file` when that memory
/// cannot be had (never an abort).
pub fn try_vec<T>(count: usize, file: &str) -> Result<Vec<T>> {
    let mut values = Vec::new();
    values.try_reserve_exact(count).map_err(|err| {
        let _ = err;
        Error::OutOfMemory {
            what: "the values the header declares",
            file: Some(file.to_string()),
            bytes: Some((count * size_of::<T>()) as u64),
            settings: &[],
        }
    })?;
    Ok(values)
}

/// Total memory in bytes, from /proc/meminfo.
fn machine_memory() -> Option<u64> {
    let text = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = text.lines().find(|l| l.starts_with("MemTotal:"))?;
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    kib.checked_mul(1024)
}
