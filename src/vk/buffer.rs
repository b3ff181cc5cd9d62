//! Buffers backed by gpu-allocator. Host-visible ones are written and read through their
//! persistent mapping; device-local ones are filled by a staging copy. A buffer keeps
//! its [`DeviceContext`], so the device outlives it.
use super::DeviceContext;
use crate::error::{Error, Result, VkContext};
use ash::vk;
use gpu_allocator::MemoryLocation;
use gpu_allocator::vulkan::{Allocation, AllocationCreateDesc, AllocationScheme, Allocator};
use std::sync::Mutex;

/// A Vulkan buffer with its memory; both are freed on drop.
pub struct Buffer {
    /// The Vulkan buffer.
    pub handle: vk::Buffer,
    /// Size asked for, bytes (the buffer itself has at least 4).
    pub size: u64,
    allocation: Option<Allocation>,
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
        let allocation = lock(ctx.allocator())?.allocate(&AllocationCreateDesc {
            name,
            requirements,
            location,
            linear: true,
            allocation_scheme: AllocationScheme::GpuAllocatorManaged,
        });
        let allocation = match allocation {
            Ok(a) => a,
            Err(e) => {
                // SAFETY: the buffer has no memory bound and is not in use.
                unsafe { device.destroy_buffer(handle, None) };
                return Err(e.into());
            }
        };
        let buffer = Buffer {
            handle,
            size,
            allocation: Some(allocation),
            ctx: ctx.clone(),
        };
        let a = buffer.allocation()?;
        // SAFETY: the allocation satisfies the buffer's requirements and is not bound yet.
        unsafe { device.bind_buffer_memory(handle, a.memory(), a.offset()) }
            .vk("vkBindBufferMemory")?;
        Ok(buffer)
    }

    fn allocation(&self) -> Result<&Allocation> {
        self.allocation
            .as_ref()
            .ok_or_else(|| Error::Setup("buffer memory was freed".into()))
    }

    /// Copies `bytes` to the start of a host-visible buffer.
    pub fn write(&mut self, bytes: &[u8]) -> Result<()> {
        let slice = self
            .allocation
            .as_mut()
            .and_then(|a| a.mapped_slice_mut())
            .ok_or_else(|| Error::Setup("buffer is not host visible".into()))?;
        let capacity = slice.len();
        let target = slice.get_mut(..bytes.len()).ok_or_else(|| {
            Error::Invalid(format!(
                "{} bytes do not fit a buffer of {capacity}",
                bytes.len()
            ))
        })?;
        target.copy_from_slice(bytes);
        Ok(())
    }

    /// The contents of a host-visible buffer (after the GPU's writes were made visible).
    pub fn read(&self) -> Result<&[u8]> {
        let slice = self
            .allocation()?
            .mapped_slice()
            .ok_or_else(|| Error::Setup("buffer is not host visible".into()))?;
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

fn lock(allocator: &Mutex<Allocator>) -> Result<std::sync::MutexGuard<'_, Allocator>> {
    allocator
        .lock()
        .map_err(|_| Error::Setup("the allocator lock is poisoned".into()))
}

impl Drop for Buffer {
    fn drop(&mut self) {
        // SAFETY: the owner guarantees the GPU no longer uses the buffer; the device is
        // alive while `self.ctx` is.
        unsafe { self.ctx.device().destroy_buffer(self.handle, None) };
        if let (Some(a), Ok(mut allocator)) = (self.allocation.take(), self.ctx.allocator().lock())
        {
            let _ = allocator.free(a);
        }
    }
}
