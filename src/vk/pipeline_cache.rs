//! A `VkPipelineCache` kept on disk between runs, so that a device whose driver caches
//! compiled pipelines (every desktop driver; not lavapipe before Mesa 23, whose cache
//! data is a bare header) creates a scene's pipelines from it instead of compiling them
//! again in every process.
//!
//! - **Where:** one file per device, driver and glyphcast build in
//!   `$GLYPHCAST_CACHE_DIR`, else `$XDG_CACHE_HOME/glyphcast`, else
//!   `$HOME/.cache/glyphcast`. `GLYPHCAST_PIPELINE_CACHE=0` turns it off.
//! - **Key:** the file name holds a hash of the device's vendor and device IDs, its driver
//!   version, its `pipelineCacheUUID`, glyphcast's version and the hash of its shader
//!   table, so another device, driver or build never reads the file.
//! - **Checked:** the file is a header of its own (magic, length, FNV-1a checksum of the
//!   driver's data) and the driver's data, whose Vulkan header must name this device. A
//!   file that fails any check is ignored (one note on stderr) and replaced when the
//!   process ends; a driver is never handed bytes it did not write.
//! - **Written:** when the device goes, only if the driver's data changed, through a
//!   temporary file of the process's own renamed over the target: processes that run at
//!   once (a job array) each leave a whole file, the last one's.
use ash::vk;
use std::path::{Path, PathBuf};

// `SHADERS_HASH`: a hash of every shader's source and compile options, from build.rs.
include!(concat!(env!("OUT_DIR"), "/shaders_hash.rs"));

/// The file's own header: magic, then the data's length and checksum (u64 each, LE).
const MAGIC: &[u8; 8] = b"GCPCACHE";
const HEADER_BYTES: usize = 8 + 8 + 8;
/// `VkPipelineCacheHeaderVersionOne`: length, version, vendor, device, UUID.
const VULKAN_HEADER_BYTES: usize = 16 + vk::UUID_SIZE;

/// The disk side of a device's pipeline cache: where it lives and what was read.
pub(crate) struct PipelineCacheFile {
    path: PathBuf,
    /// The driver's data as read (empty when there was no valid file).
    loaded: Vec<u8>,
}

/// FNV-1a, 64 bit.
fn fnv1a(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325_u64, |hash, &b| {
        (hash ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3)
    })
}

/// The folder the cache files go to, or `None` when the cache is off or no folder is
/// known.
fn cache_dir() -> Option<PathBuf> {
    if std::env::var("GLYPHCAST_PIPELINE_CACHE").is_ok_and(|v| v == "0") {
        return None;
    }
    let var = |name: &str| std::env::var_os(name).filter(|v| !v.is_empty());
    if let Some(dir) = var("GLYPHCAST_CACHE_DIR") {
        return Some(PathBuf::from(dir));
    }
    if let Some(dir) = var("XDG_CACHE_HOME") {
        return Some(PathBuf::from(dir).join("glyphcast"));
    }
    var("HOME").map(|home| PathBuf::from(home).join(".cache").join("glyphcast"))
}

/// The file name of `props`'s cache for this build of glyphcast.
fn file_name(props: &vk::PhysicalDeviceProperties) -> String {
    let mut key = Vec::new();
    key.extend_from_slice(&props.vendor_id.to_le_bytes());
    key.extend_from_slice(&props.device_id.to_le_bytes());
    key.extend_from_slice(&props.driver_version.to_le_bytes());
    key.extend_from_slice(&props.pipeline_cache_uuid);
    key.extend_from_slice(env!("CARGO_PKG_VERSION").as_bytes());
    key.extend_from_slice(&SHADERS_HASH.to_le_bytes());
    format!("pipelines-{:016x}.bin", fnv1a(&key))
}

/// The driver's data in `file`, if the file is whole and its Vulkan header names the
/// device of `props`; otherwise why not.
fn parse(file: &[u8], props: &vk::PhysicalDeviceProperties) -> Result<Vec<u8>, &'static str> {
    if file.len() < HEADER_BYTES || &file[..8] != MAGIC {
        return Err("not a glyphcast pipeline cache");
    }
    let word = |at: usize| {
        let mut bytes = [0u8; 8];
        bytes.copy_from_slice(&file[at..at + 8]);
        u64::from_le_bytes(bytes)
    };
    let data = &file[HEADER_BYTES..];
    if word(8) != data.len() as u64 {
        return Err("truncated");
    }
    if word(16) != fnv1a(data) {
        return Err("checksum mismatch");
    }
    if data.len() < VULKAN_HEADER_BYTES {
        return Err("no Vulkan header");
    }
    let u32_at =
        |at: usize| u32::from_le_bytes([data[at], data[at + 1], data[at + 2], data[at + 3]]);
    let header_ok = u32_at(4) == vk::PipelineCacheHeaderVersion::ONE.as_raw() as u32
        && u32_at(8) == props.vendor_id
        && u32_at(12) == props.device_id
        && data[16..VULKAN_HEADER_BYTES] == props.pipeline_cache_uuid;
    if !header_ok {
        return Err("written by another device or driver");
    }
    Ok(data.to_vec())
}

impl PipelineCacheFile {
    /// The cache file of the device of `props` (its data if it is valid), or `None` when
    /// the cache is off.
    pub(crate) fn open(props: &vk::PhysicalDeviceProperties) -> Option<PipelineCacheFile> {
        let path = cache_dir()?.join(file_name(props));
        let loaded = match std::fs::read(&path) {
            Ok(bytes) => parse(&bytes, props).unwrap_or_else(|why| {
                eprintln!(
                    "note: {}: ignoring the pipeline cache ({why}); it will be replaced",
                    path.display()
                );
                Vec::new()
            }),
            Err(_) => Vec::new(),
        };
        Some(PipelineCacheFile { path, loaded })
    }

    /// The driver's data read from disk, for `VkPipelineCacheCreateInfo`.
    pub(crate) fn initial_data(&self) -> &[u8] {
        &self.loaded
    }

    /// The cache file's path.
    pub(crate) fn path(&self) -> &Path {
        &self.path
    }

    /// Writes `data` (the driver's current cache) if it differs from what was read. A
    /// failure is a note: the cache only saves time.
    pub(crate) fn save(&self, data: &[u8]) {
        if data == self.loaded.as_slice() || data.len() < VULKAN_HEADER_BYTES {
            return;
        }
        let mut file = Vec::with_capacity(HEADER_BYTES + data.len());
        file.extend_from_slice(MAGIC);
        file.extend_from_slice(&(data.len() as u64).to_le_bytes());
        file.extend_from_slice(&fnv1a(data).to_le_bytes());
        file.extend_from_slice(data);
        let mut temporary = self.path.clone().into_os_string();
        temporary.push(format!(".{}.tmp", std::process::id()));
        let temporary = PathBuf::from(temporary);
        let written = match self.path.parent() {
            Some(dir) => std::fs::create_dir_all(dir),
            None => Ok(()),
        }
        .and_then(|()| std::fs::write(&temporary, &file))
        .and_then(|()| std::fs::rename(&temporary, &self.path));
        if let Err(e) = written {
            let _ = std::fs::remove_file(&temporary);
            eprintln!(
                "note: the pipeline cache was not saved to {}: {e}",
                self.path.display()
            );
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn props() -> vk::PhysicalDeviceProperties {
        vk::PhysicalDeviceProperties {
            vendor_id: 0x10de,
            device_id: 0x2330,
            pipeline_cache_uuid: [7; vk::UUID_SIZE],
            ..Default::default()
        }
    }

    fn driver_data(props: &vk::PhysicalDeviceProperties, body: &[u8]) -> Vec<u8> {
        let mut data = Vec::new();
        data.extend_from_slice(&(VULKAN_HEADER_BYTES as u32).to_le_bytes());
        data.extend_from_slice(&1u32.to_le_bytes());
        data.extend_from_slice(&props.vendor_id.to_le_bytes());
        data.extend_from_slice(&props.device_id.to_le_bytes());
        data.extend_from_slice(&props.pipeline_cache_uuid);
        data.extend_from_slice(body);
        data
    }

    fn file(data: &[u8]) -> Vec<u8> {
        let mut file = MAGIC.to_vec();
        file.extend_from_slice(&(data.len() as u64).to_le_bytes());
        file.extend_from_slice(&fnv1a(data).to_le_bytes());
        file.extend_from_slice(data);
        file
    }

    #[test]
    fn whole_files_are_read_and_damaged_ones_refused() {
        let props = props();
        let data = driver_data(&props, b"compiled pipelines");
        assert_eq!(parse(&file(&data), &props), Ok(data.clone()));
        let mut flipped = file(&data);
        let last = flipped.len() - 1;
        flipped[last] ^= 1;
        assert_eq!(parse(&flipped, &props), Err("checksum mismatch"));
        let whole = file(&data);
        assert_eq!(parse(&whole[..whole.len() - 3], &props), Err("truncated"));
        assert_eq!(
            parse(b"GCPC", &props),
            Err("not a glyphcast pipeline cache")
        );
        assert_eq!(parse(&file(b"short"), &props), Err("no Vulkan header"));
        let other = vk::PhysicalDeviceProperties {
            device_id: 1,
            ..props
        };
        assert_eq!(
            parse(&file(&data), &other),
            Err("written by another device or driver")
        );
    }

    #[test]
    fn the_key_tells_devices_and_drivers_apart() {
        let device = props();
        let newer = vk::PhysicalDeviceProperties {
            driver_version: 2,
            ..device
        };
        assert_ne!(file_name(&device), file_name(&newer));
        assert_eq!(file_name(&device), file_name(&props()));
    }
}
