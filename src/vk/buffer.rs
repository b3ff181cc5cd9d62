//! Buffers whose memory comes from the context's [`MemoryAllocator`](super::MemoryAllocator)
//! (gpu-allocator unless the host gave its own). Host-visible ones are written and read
//! through their persistent mapping; device-local ones are filled by a staging copy. A
//! buffer keeps its [`DeviceContext`], so the device outlives it.
use super::DeviceContext;
use super::memory::{MemoryBlock, MemoryRequest, MemoryUse};
use crate::error::{Error, Result, VkContext};
use ash::vk;
use gpu_allocator::MemoryLocation;

/// A Vulkan buffer with its memory; both are freed on drop.
pub struct Buffer {
    /// The Vulkan buffer.
    pub handle: vk::Buffer,
    /// Size asked for, bytes (the buffer itself has at least 4).
    pub size: u64,
    block: Option<MemoryBlock>,
    ctx: DeviceContext,
}

impl Buffer {
    /// A buffer of `size` bytes with `usage`, in memory at `location`; `name` labels the
    /// allocation.
    pub fn new(
        ctx: &DeviceContext,
        name: &str,
        size: u64,
        usage: vk::BufferUsageFlags,
        location: MemoryLocation,
    ) -> Result<Buffer> {
        let device = ctx.device();
        let info = vk::BufferCreateInfo::default()
            .size(size.max(4))
            .usage(usage)
            .sharing_mode(vk::SharingMode::EXCLUSIVE);
        // SAFETY: `info` is complete and the device is alive.
        let handle = unsafe { device.create_buffer(&info, None) }.vk("vkCreateBuffer")?;
        // SAFETY: `handle` was just created from this device.
        let requirements = unsafe { device.get_buffer_memory_requirements(handle) };
        let usage = MemoryUse::from(location);
        let block = ctx.memory().allocate(&MemoryRequest {
            name,
            requirements,
            usage,
            linear: true,
        });
        let block = match block.and_then(|b| checked_block(ctx, name, b, &requirements, usage)) {
            Ok(b) => b,
            Err(e) => {
                // SAFETY: the buffer has no memory bound and is not in use.
                unsafe { device.destroy_buffer(handle, None) };
                return Err(e);
            }
        };
        let (memory, offset) = (block.memory, block.offset);
        // Dropped from here on, the buffer gives the block back.
        let buffer = Buffer {
            handle,
            size,
            block: Some(block),
            ctx: ctx.clone(),
        };
        // SAFETY: the block satisfies the buffer's requirements and is not bound yet.
        unsafe { device.bind_buffer_memory(handle, memory, offset) }.vk("vkBindBufferMemory")?;
        Ok(buffer)
    }

    /// The mapped bytes of a host-visible buffer's block.
    fn mapped(&self) -> Option<(*mut u8, usize)> {
        let block = self.block.as_ref()?;
        (!block.mapped.is_null()).then_some((block.mapped, block.size as usize))
    }

    /// Copies `bytes` to the start of a host-visible buffer.
    pub fn write(&mut self, bytes: &[u8]) -> Result<()> {
        let (ptr, len) = self.mapped().ok_or(Error::Call {
            call: "Buffer::write",
            expected: "a host-visible buffer",
        })?;
        // SAFETY: the block maps `len` bytes for as long as it lives, and `&mut self`
        // is its only writer (the caller keeps the GPU off it, as for any host write).
        let slice = unsafe { std::slice::from_raw_parts_mut(ptr, len) };
        let capacity = slice.len();
        let target = slice.get_mut(..bytes.len()).ok_or(Error::Limit {
            what: "bytes written to a buffer",
            value: bytes.len() as u64,
            limit: capacity as u64,
            settings: &[],
        })?;
        target.copy_from_slice(bytes);
        Ok(())
    }

    /// The contents of a host-visible buffer (after the GPU's writes were made visible).
    pub fn read(&self) -> Result<&[u8]> {
        let (ptr, len) = self.mapped().ok_or(Error::Call {
            call: "Buffer::read",
            expected: "a host-visible buffer",
        })?;
        // SAFETY: the block maps `len` bytes for as long as `self` holds it.
        let slice = unsafe { std::slice::from_raw_parts(ptr.cast_const(), len) };
        Ok(&slice[..(self.size as usize).min(slice.len())])
    }

    /// A host-visible buffer holding `data`.
    pub fn with_data<T: bytemuck::Pod>(
        ctx: &DeviceContext,
        name: &str,
        data: &[T],
        usage: vk::BufferUsageFlags,
    ) -> Result<Buffer> {
        let bytes: &[u8] = bytemuck::cast_slice(data);
        let mut buffer = Buffer::new(
            ctx,
            name,
            bytes.len() as u64,
            usage,
            MemoryLocation::CpuToGpu,
        )?;
        buffer.write(bytes)?;
        Ok(buffer)
    }
}

/// `block` if it satisfies what was asked (a host's allocator is held to its contract
/// here rather than trusted), else an error naming the allocation; the block is freed.
pub(super) fn checked_block(
    ctx: &DeviceContext,
    name: &str,
    block: MemoryBlock,
    requirements: &vk::MemoryRequirements,
    usage: MemoryUse,
) -> Result<MemoryBlock> {
    let problem = if block.size < requirements.size {
        Some(format!(
            "a block of {} bytes for {} asked",
            block.size, requirements.size
        ))
    } else if requirements.alignment > 0 && !block.offset.is_multiple_of(requirements.alignment) {
        Some(format!(
            "offset {} is not a multiple of the alignment {}",
            block.offset, requirements.alignment
        ))
    } else if usage.mapped() && block.mapped.is_null() {
        Some("host-visible memory came unmapped".into())
    } else {
        None
    };
    match problem {
        None => Ok(block),
        Some(problem) => {
            ctx.memory().free(block);
            Err(Error::setup(
                "usable memory block from the GPU memory allocator",
                format_args!("{name}: the memory allocator returned {problem}"),
            ))
        }
    }
}

impl Drop for Buffer {
    fn drop(&mut self) {
        // SAFETY: the owner guarantees the GPU no longer uses the buffer; the device is
        // alive while `self.ctx` is.
        unsafe { self.ctx.device().destroy_buffer(self.handle, None) };
        if let Some(block) = self.block.take() {
            self.ctx.memory().free(block);
        }
    }
}
