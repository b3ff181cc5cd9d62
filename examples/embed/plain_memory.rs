//! A second implementation of glyphcast's `MemoryAllocator`, the simplest an engine could
//! write: one `vkAllocateMemory` per block, host-visible blocks mapped whole, freed with
//! `vkFreeMemory`. (Real engines sub-allocate; this one shows the contract, and counts
//! what it hands out so that the tests see glyphcast's memory go through it.)
use ash::vk;
use glyphcast::vk::{MemoryAllocator, MemoryBlock, MemoryRequest, memory_type_index};
use std::collections::HashMap;
use std::sync::Mutex;

pub struct PlainMemory {
    device: ash::Device,
    properties: vk::PhysicalDeviceMemoryProperties,
    /// Live memory objects by token (the token is the handle's raw value).
    live: Mutex<HashMap<u64, vk::DeviceMemory>>,
    /// Blocks handed out since creation.
    allocated: Mutex<usize>,
}

impl PlainMemory {
    pub fn new(
        instance: &ash::Instance,
        physical_device: vk::PhysicalDevice,
        device: ash::Device,
    ) -> PlainMemory {
        // SAFETY: the physical device belongs to the instance.
        let properties = unsafe { instance.get_physical_device_memory_properties(physical_device) };
        PlainMemory {
            device,
            properties,
            live: Mutex::new(HashMap::new()),
            allocated: Mutex::new(0),
        }
    }

    /// (blocks handed out so far, blocks not yet given back).
    pub fn counts(&self) -> (usize, usize) {
        let allocated = self.allocated.lock().map(|n| *n).unwrap_or(0);
        let live = self.live.lock().map(|l| l.len()).unwrap_or(0);
        (allocated, live)
    }
}

impl MemoryAllocator for PlainMemory {
    fn allocate(&self, request: &MemoryRequest<'_>) -> glyphcast::Result<MemoryBlock> {
        let type_index = memory_type_index(&self.properties, request)?;
        let info = vk::MemoryAllocateInfo::default()
            .allocation_size(request.requirements.size)
            .memory_type_index(type_index);
        let vulkan = |call, result| glyphcast::Error::Vulkan { call, result };
        // SAFETY: a valid allocate info for this device; freed in `free`.
        let memory = unsafe { self.device.allocate_memory(&info, None) }
            .map_err(|r| vulkan("vkAllocateMemory", r))?;
        let mapped = if request.usage.mapped() {
            // SAFETY: host-visible memory (the type's required flags), mapped once.
            let map = unsafe {
                self.device
                    .map_memory(memory, 0, vk::WHOLE_SIZE, vk::MemoryMapFlags::empty())
            };
            match map {
                Ok(p) => p.cast::<u8>(),
                Err(r) => {
                    // SAFETY: the memory was just allocated and is not in use.
                    unsafe { self.device.free_memory(memory, None) };
                    return Err(vulkan("vkMapMemory", r));
                }
            }
        } else {
            std::ptr::null_mut()
        };
        let token = vk::Handle::as_raw(memory);
        if let Ok(mut live) = self.live.lock() {
            live.insert(token, memory);
        }
        if let Ok(mut n) = self.allocated.lock() {
            *n += 1;
        }
        Ok(MemoryBlock {
            memory,
            offset: 0,
            size: request.requirements.size,
            mapped,
            token,
        })
    }

    fn free(&self, block: MemoryBlock) {
        let memory = self
            .live
            .lock()
            .ok()
            .and_then(|mut l| l.remove(&block.token));
        if let Some(memory) = memory {
            // SAFETY: glyphcast destroyed the buffer or image bound to it and the GPU is
            // done with it (the trait's contract); freeing unmaps it.
            unsafe { self.device.free_memory(memory, None) };
        }
    }
}
