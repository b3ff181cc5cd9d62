//! Device memory for glyphcast's buffers and images, through a small trait a host can
//! implement: [`MemoryAllocator`] hands out a block of `VkDeviceMemory` (memory, offset,
//! size, and a host pointer when the block is mapped) and takes it back. glyphcast binds
//! its buffers and images to the blocks itself, so an allocator never sees a buffer.
//!
//! gpu-allocator is the default implementation ([`GpuAllocatorMemory`]), the one a
//! [`Gpu`](super::Gpu) makes and [`DeviceContext::new`](super::DeviceContext::new) wraps;
//! an engine on VMA, on its own arena or on the C API's callbacks implements the trait
//! and passes it to [`DeviceContext::with_memory`](super::DeviceContext::with_memory).
//! Blocks are taken by token rather than by a Rust object so that a C host can
//! implement the same contract with two function pointers.
use crate::error::{Error, Result};
use ash::vk;
use gpu_allocator::AllocationError;
use gpu_allocator::MemoryLocation;
use gpu_allocator::vulkan::{
    Allocation, AllocationCreateDesc, AllocationScheme, Allocator, AllocatorCreateDesc,
};
use std::collections::HashMap;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex};

/// What the memory is for: it decides the memory properties a block needs.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum MemoryUse {
    /// Read by the GPU only (images): DEVICE_LOCAL.
    DeviceLocal,
    /// Written by the host, read by the GPU (glyph data, frame blocks): HOST_VISIBLE and
    /// HOST_COHERENT, mapped; DEVICE_LOCAL preferred.
    Upload,
    /// Written by the GPU, read by the host (read-backs): HOST_VISIBLE and HOST_COHERENT,
    /// mapped; HOST_CACHED preferred.
    Readback,
}

impl MemoryUse {
    /// Properties a memory type must have for this use. glyphcast writes and reads
    /// mapped memory without flushing or invalidating, so host memory must be coherent.
    pub fn required_flags(self) -> vk::MemoryPropertyFlags {
        match self {
            MemoryUse::DeviceLocal => vk::MemoryPropertyFlags::DEVICE_LOCAL,
            MemoryUse::Upload | MemoryUse::Readback => {
                vk::MemoryPropertyFlags::HOST_VISIBLE | vk::MemoryPropertyFlags::HOST_COHERENT
            }
        }
    }

    /// Properties that are better to have, if a type with them exists.
    pub fn preferred_flags(self) -> vk::MemoryPropertyFlags {
        match self {
            MemoryUse::DeviceLocal => vk::MemoryPropertyFlags::empty(),
            MemoryUse::Upload => vk::MemoryPropertyFlags::DEVICE_LOCAL,
            MemoryUse::Readback => vk::MemoryPropertyFlags::HOST_CACHED,
        }
    }

    /// Whether glyphcast reads or writes the block through a host pointer.
    pub fn mapped(self) -> bool {
        self != MemoryUse::DeviceLocal
    }
}

impl From<MemoryLocation> for MemoryUse {
    /// gpu-allocator's locations, which glyphcast's passes name their buffers by. Its
    /// `Unknown` (any memory type) is taken as device-local: no glyphcast buffer maps
    /// such memory.
    fn from(location: MemoryLocation) -> MemoryUse {
        match location {
            MemoryLocation::CpuToGpu => MemoryUse::Upload,
            MemoryLocation::GpuToCpu => MemoryUse::Readback,
            MemoryLocation::GpuOnly | MemoryLocation::Unknown => MemoryUse::DeviceLocal,
        }
    }
}

/// One allocation glyphcast asks for.
#[derive(Clone, Copy, Debug)]
pub struct MemoryRequest<'a> {
    /// A label for the allocation (debuggers, out-of-memory messages).
    pub name: &'a str,
    /// The buffer's or image's requirements (size, alignment, memory type bits).
    pub requirements: vk::MemoryRequirements,
    /// What the memory is for.
    pub usage: MemoryUse,
    /// A buffer or linear image (true) or an optimal-tiling image (false): allocators
    /// that share a memory object between both keep bufferImageGranularity apart.
    pub linear: bool,
}

/// A block of device memory handed out by a [`MemoryAllocator`].
#[derive(Debug)]
pub struct MemoryBlock {
    /// The memory object the block lies in.
    pub memory: vk::DeviceMemory,
    /// Where the block starts in `memory`, a multiple of the request's alignment.
    pub offset: u64,
    /// The block's size, at least the request's.
    pub size: u64,
    /// The host address of the block's first byte, for mapped uses
    /// ([`MemoryUse::mapped`]); null otherwise. It stays valid until the block is freed.
    pub mapped: *mut u8,
    /// The allocator's own name for the block, handed back to `free`.
    pub token: u64,
}

// SAFETY: a block is plain data: the handles are Vulkan's, which any thread may use, and
// `mapped` points into device memory that only the block's one owner reads or writes,
// through `&`/`&mut` of the buffer that holds it.
unsafe impl Send for MemoryBlock {}
// SAFETY: as above; shared access only reads.
unsafe impl Sync for MemoryBlock {}

/// Where glyphcast's buffers and images take their memory from. Calls may come from any
/// thread (each takes `&self`).
pub trait MemoryAllocator: Send + Sync {
    /// A block that satisfies `request`: its memory type is one of the requirements'
    /// type bits with `request.usage.required_flags()`, and a mapped use comes mapped.
    fn allocate(&self, request: &MemoryRequest<'_>) -> Result<MemoryBlock>;

    /// Takes back a block this allocator handed out; the GPU no longer uses it, and the
    /// buffer or image bound to it is destroyed.
    fn free(&self, block: MemoryBlock);
}

/// The index of the memory type for `request` among `properties`' types: one with the
/// required flags, preferring one that also has the preferred flags. For implementers of
/// [`MemoryAllocator`] that pick memory types themselves.
pub fn memory_type_index(
    properties: &vk::PhysicalDeviceMemoryProperties,
    request: &MemoryRequest<'_>,
) -> Result<u32> {
    let usage = request.usage;
    let types = &properties.memory_types[..properties.memory_type_count as usize];
    let allowed = |k: usize, flags: vk::MemoryPropertyFlags| {
        request.requirements.memory_type_bits & (1 << k) != 0
            && types[k].property_flags.contains(flags)
    };
    let required = usage.required_flags();
    let preferred = required | usage.preferred_flags();
    (0..types.len())
        .find(|&k| allowed(k, preferred))
        .or_else(|| (0..types.len()).find(|&k| allowed(k, required)))
        .map(|k| k as u32)
        .ok_or_else(|| {
            Error::setup(
                "memory type with the properties asked for",
                format_args!(
                    "{}: none with {required:?} among the allowed types {:#b}",
                    request.name, request.requirements.memory_type_bits
                ),
            )
        })
}

/// gpu-allocator as a [`MemoryAllocator`]: the default, shared with a host that uses
/// gpu-allocator itself.
pub struct GpuAllocatorMemory {
    allocator: Arc<Mutex<Allocator>>,
    /// The allocations handed out, by token.
    live: Mutex<HashMap<u64, Allocation>>,
    next: AtomicU64,
}

/// gpu-allocator's allocator for `device` (created from `physical_device` of `instance`)
/// with glyphcast's settings: the default implementation's, for the library's own
/// devices and for hosts (the C API) that give no allocator.
pub fn default_allocator(
    instance: &ash::Instance,
    device: &ash::Device,
    physical_device: vk::PhysicalDevice,
) -> std::result::Result<Allocator, AllocationError> {
    Allocator::new(&AllocatorCreateDesc {
        instance: instance.clone(),
        device: device.clone(),
        physical_device,
        debug_settings: Default::default(),
        buffer_device_address: false,
        allocation_sizes: Default::default(),
    })
}

impl GpuAllocatorMemory {
    /// Allocates through `allocator` (which may be a host's, shared).
    pub fn new(allocator: Arc<Mutex<Allocator>>) -> GpuAllocatorMemory {
        GpuAllocatorMemory {
            allocator,
            live: Mutex::new(HashMap::new()),
            next: AtomicU64::new(1),
        }
    }
}

impl MemoryAllocator for GpuAllocatorMemory {
    fn allocate(&self, request: &MemoryRequest<'_>) -> Result<MemoryBlock> {
        let location = match request.usage {
            MemoryUse::DeviceLocal => MemoryLocation::GpuOnly,
            MemoryUse::Upload => MemoryLocation::CpuToGpu,
            MemoryUse::Readback => MemoryLocation::GpuToCpu,
        };
        let allocation = self
            .allocator
            .lock()
            .map_err(|_| Error::Thread {
                what: "the GPU memory allocator",
            })?
            .allocate(&AllocationCreateDesc {
                name: request.name,
                requirements: request.requirements,
                location,
                linear: request.linear,
                allocation_scheme: AllocationScheme::GpuAllocatorManaged,
            })?;
        let block = MemoryBlock {
            // SAFETY: the memory is used only while the allocation lives (until `free`).
            memory: unsafe { allocation.memory() },
            offset: allocation.offset(),
            size: allocation.size(),
            mapped: allocation
                .mapped_ptr()
                .map_or(std::ptr::null_mut(), |p| p.as_ptr().cast()),
            token: self.next.fetch_add(1, Ordering::Relaxed),
        };
        let mut live = self.live.lock().map_err(|_| Error::Thread {
            what: "the GPU allocation table",
        })?;
        live.insert(block.token, allocation);
        Ok(block)
    }

    fn free(&self, block: MemoryBlock) {
        let allocation = self
            .live
            .lock()
            .ok()
            .and_then(|mut l| l.remove(&block.token));
        if let (Some(allocation), Ok(mut allocator)) = (allocation, self.allocator.lock()) {
            let _ = allocator.free(allocation);
        }
    }
}
