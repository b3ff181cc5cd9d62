//! What glyphcast's passes need of the Vulkan device under wgpu, and the device-creation
//! callback that turns on what wgpu does not.
//!
//! glyphcast's core asks of a device (src/vk/device.rs): Vulkan 1.3, dynamic rendering and
//! synchronization2 (sampleRateShading too for multisampled targets; fragmentStoresAndAtomics
//! where hidden glyphs are to be culled: without it every glyph is drawn, from fragment
//! shaders that write no buffer). wgpu's Vulkan backend creates the device with
//! fragmentStoresAndAtomics and sampleRateShading wherever the adapter has them (its
//! downlevel flags), but it never
//! enables dynamic rendering or synchronization2: those two are added by a device-creation
//! callback ([`enable_features`]), which [`request_device`] passes to wgpu-hal and which a
//! Bevy app registers with its raw Vulkan initialisation.
//!
//! The two feature structs go into the device's `pNext` chain one by one, not as
//! `VkPhysicalDeviceVulkan13Features`: wgpu already chains some of 1.3's own structs
//! (maintenance4, image robustness...), and Vulkan forbids both in one chain.
use crate::{Error, Result};
use glyphcast::ash::vk;
use wgpu::hal::api::Vulkan;
use wgpu::hal::vulkan::CreateDeviceCallbackArgs;

/// The Vulkan features glyphcast's passes use, by their Vulkan names: the device must be
/// Vulkan 1.3 with the last three enabled (sampleRateShading for multisampled targets).
/// The first, fragmentStoresAndAtomics, is used where the device has it (culling hidden
/// glyphs); a device without it draws every glyph. wgpu enables the first two where the
/// adapter has them; [`enable_features`] adds the last two at device creation.
pub const REQUIRED_VULKAN_FEATURES: [&str; 4] = [
    "fragmentStoresAndAtomics",
    "sampleRateShading",
    "dynamicRendering",
    "synchronization2",
];

/// Adds what glyphcast needs that wgpu does not enable (dynamic rendering and
/// synchronization2) to a Vulkan device being created by wgpu-hal: call it from a
/// device-creation callback, the one [`request_device`] passes, or a Bevy app's
/// (`RawVulkanInitSettings::add_create_device_callback` of bevy_render's
/// `raw_vulkan_init` feature), or any callback given to wgpu-hal's
/// `Adapter::open_with_callback`. Only for an adapter that [`check_adapter`] accepts.
///
/// The two feature structs must outlive `vkCreateDevice`, which runs after the callback
/// returns: they are leaked, 48 bytes per device created.
pub fn enable_features(args: &mut CreateDeviceCallbackArgs<'_, '_, '_>) {
    let rendering: &'static mut _ = Box::leak(Box::new(
        vk::PhysicalDeviceDynamicRenderingFeatures::default().dynamic_rendering(true),
    ));
    let sync2: &'static mut _ = Box::leak(Box::new(
        vk::PhysicalDeviceSynchronization2Features::default().synchronization2(true),
    ));
    let info = std::mem::take(args.create_info);
    *args.create_info = info.push_next(rendering).push_next(sync2);
}

/// Creates a wgpu device and queue on `adapter` as [`wgpu::Adapter::request_device`]
/// does, with the Vulkan features glyphcast needs enabled ([`enable_features`]). Refuses
/// an adapter of another backend than Vulkan, or one that lacks a feature
/// ([`check_adapter`]), with an error that names it.
pub fn request_device(
    adapter: &wgpu::Adapter,
    desc: &wgpu::DeviceDescriptor<'_>,
) -> Result<(wgpu::Device, wgpu::Queue)> {
    check_adapter(adapter, desc.required_features)?;
    // SAFETY: the hal adapter is only read and used to open a device, which wgpu then
    // owns (`create_device_from_hal`).
    let hal = unsafe { adapter.as_hal::<Vulkan>() }.ok_or_else(|| not_vulkan(adapter))?;
    let callback: Box<wgpu::hal::vulkan::CreateDeviceCallback<'_>> =
        Box::new(|mut args| enable_features(&mut args));
    // SAFETY: the callback only adds features that `check_adapter` found supported.
    let open = unsafe {
        hal.open_with_callback(
            desc.required_features,
            &desc.required_limits,
            &desc.memory_hints,
            Some(callback),
        )
    }
    .map_err(|e| Error::CreateDevice(e.to_string()))?;
    drop(hal);
    // SAFETY: `open` was created from this adapter's hal adapter with the features and
    // limits of `desc`.
    unsafe { adapter.create_device_from_hal(open, desc) }
        .map_err(|e| Error::CreateDevice(e.to_string()))
}

/// Checks that `adapter` is on wgpu's Vulkan backend, Vulkan 1.3, and has dynamic
/// rendering and synchronization2 (sampleRateShading is checked when a multisampled
/// target asks; fragmentStoresAndAtomics is used where wgpu enables it).
pub fn check_adapter(adapter: &wgpu::Adapter, _features: wgpu::Features) -> Result<()> {
    // SAFETY: the hal adapter is only read.
    let hal = unsafe { adapter.as_hal::<Vulkan>() }.ok_or_else(|| not_vulkan(adapter))?;
    let instance = hal.shared_instance().raw_instance();
    let pd = hal.raw_physical_device();
    let api = hal.physical_device_capabilities().properties().api_version;
    let mut missing = Vec::new();
    if api < vk::API_VERSION_1_3 {
        missing.push(format!(
            "Vulkan 1.3 (the device has {}.{})",
            vk::api_version_major(api),
            vk::api_version_minor(api)
        ));
    }
    if api >= vk::API_VERSION_1_3 {
        let mut v13 = vk::PhysicalDeviceVulkan13Features::default();
        let mut all = vk::PhysicalDeviceFeatures2::default().push_next(&mut v13);
        // SAFETY: `pd` belongs to this instance, whose device supports Vulkan 1.3.
        unsafe { instance.get_physical_device_features2(pd, &mut all) };
        if v13.dynamic_rendering != vk::TRUE {
            missing.push(REQUIRED_VULKAN_FEATURES[2].to_owned());
        }
        if v13.synchronization2 != vk::TRUE {
            missing.push(REQUIRED_VULKAN_FEATURES[3].to_owned());
        }
    }
    if missing.is_empty() {
        return Ok(());
    }
    Err(Error::MissingFeatures {
        adapter: adapter.get_info().name,
        missing: missing.join(", "),
    })
}

/// The core Vulkan features wgpu-hal enables on a device of `adapter` with `features`
/// (what it computes when it opens one); `None` off the Vulkan backend.
fn core_features(
    adapter: &wgpu::Adapter,
    features: wgpu::Features,
) -> Option<vk::PhysicalDeviceFeatures> {
    // SAFETY: the hal adapter is only read.
    let hal = unsafe { adapter.as_hal::<Vulkan>() }?;
    let extensions = hal.required_device_extensions(features);
    Some(
        hal.physical_device_features(&extensions, features)
            .get_core(),
    )
}

/// Whether the adapter can enable sampleRateShading (multisampled targets need it).
pub(crate) fn has_sample_rate_shading(adapter: &wgpu::Adapter, features: wgpu::Features) -> bool {
    core_features(adapter, features).is_some_and(|core| core.sample_rate_shading == vk::TRUE)
}

/// Whether wgpu enables fragmentStoresAndAtomics on a device of `adapter` with
/// `features`, which culling hidden glyphs needs.
pub(crate) fn enables_fragment_stores(adapter: &wgpu::Adapter, features: wgpu::Features) -> bool {
    core_features(adapter, features)
        .is_some_and(|core| core.fragment_stores_and_atomics == vk::TRUE)
}

/// The error for an adapter (or a device of one) on another backend than Vulkan.
pub(crate) fn not_vulkan(adapter: &wgpu::Adapter) -> Error {
    Error::NotVulkan {
        backend: adapter.get_info().backend,
    }
}
