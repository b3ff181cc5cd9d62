//! Descriptor sets of whole buffers, as every pass binds them: a pool sized for a number
//! of sets, each set pointing its bindings at buffers. The pool owns its sets and is
//! destroyed with them when dropped.
use ash::vk;

use super::{Buffer, DeviceContext};
use crate::error::{Result, VkContext};

/// What a set holds at one binding: a whole buffer, as a uniform or a storage buffer.
#[derive(Clone, Copy)]
pub struct BufferBinding<'a> {
    /// The binding number in the set layout.
    pub binding: u32,
    /// `UNIFORM_BUFFER` or `STORAGE_BUFFER`.
    pub kind: vk::DescriptorType,
    /// The buffer bound, whole.
    pub buffer: &'a Buffer,
}

impl<'a> BufferBinding<'a> {
    /// `buffer` as a uniform buffer at `binding`.
    pub fn uniform(binding: u32, buffer: &'a Buffer) -> Self {
        Self {
            binding,
            kind: vk::DescriptorType::UNIFORM_BUFFER,
            buffer,
        }
    }

    /// `buffer` as a storage buffer at `binding`.
    pub fn storage(binding: u32, buffer: &'a Buffer) -> Self {
        Self {
            binding,
            kind: vk::DescriptorType::STORAGE_BUFFER,
            buffer,
        }
    }
}

/// A descriptor pool and the sets allocated from it.
pub struct DescriptorPool {
    ctx: DeviceContext,
    pool: vk::DescriptorPool,
}

impl DescriptorPool {
    /// A pool for `sets` sets (at least one), each with up to `uniform` uniform-buffer and
    /// `storage` storage-buffer descriptors.
    pub fn new(ctx: &DeviceContext, sets: usize, uniform: u32, storage: u32) -> Result<Self> {
        let sets = sets.max(1) as u32;
        let sizes: Vec<vk::DescriptorPoolSize> = [
            (vk::DescriptorType::UNIFORM_BUFFER, uniform),
            (vk::DescriptorType::STORAGE_BUFFER, storage),
        ]
        .into_iter()
        .filter(|&(_, per_set)| per_set > 0)
        .map(|(ty, per_set)| vk::DescriptorPoolSize {
            ty,
            descriptor_count: per_set * sets,
        })
        .collect();
        let info = vk::DescriptorPoolCreateInfo::default()
            .max_sets(sets)
            .pool_sizes(&sizes);
        // SAFETY: valid create info; the device is alive while `ctx` is.
        let pool = unsafe { ctx.device().create_descriptor_pool(&info, None) }
            .vk("vkCreateDescriptorPool")?;
        Ok(Self {
            ctx: ctx.clone(),
            pool,
        })
    }

    /// Allocates a set of `layout` and points each of `bindings` at its whole buffer.
    /// The buffers must outlive every use of the set.
    pub fn buffer_set(
        &self,
        layout: vk::DescriptorSetLayout,
        bindings: &[BufferBinding],
    ) -> Result<vk::DescriptorSet> {
        let device = self.ctx.device();
        let layouts = [layout];
        let alloc = vk::DescriptorSetAllocateInfo::default()
            .descriptor_pool(self.pool)
            .set_layouts(&layouts);
        // SAFETY: the pool and layout are alive; a pool too small is an error, not UB.
        let set =
            unsafe { device.allocate_descriptor_sets(&alloc) }.vk("vkAllocateDescriptorSets")?[0];
        let infos: Vec<[vk::DescriptorBufferInfo; 1]> = bindings
            .iter()
            .map(|b| {
                [vk::DescriptorBufferInfo {
                    buffer: b.buffer.handle,
                    offset: 0,
                    range: vk::WHOLE_SIZE,
                }]
            })
            .collect();
        let writes: Vec<vk::WriteDescriptorSet> = bindings
            .iter()
            .zip(&infos)
            .map(|(b, info)| {
                vk::WriteDescriptorSet::default()
                    .dst_set(set)
                    .dst_binding(b.binding)
                    .descriptor_type(b.kind)
                    .buffer_info(info)
            })
            .collect();
        // SAFETY: the set and buffers are alive; no command buffer uses the set yet.
        unsafe { device.update_descriptor_sets(&writes, &[]) };
        Ok(set)
    }
}

impl Drop for DescriptorPool {
    fn drop(&mut self) {
        // SAFETY: the owner has waited for the frames that used these sets; the device is
        // alive while `self.ctx` is.
        unsafe { self.ctx.device().destroy_descriptor_pool(self.pool, None) };
    }
}
