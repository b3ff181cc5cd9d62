//! Physical-device choice (discrete > integrated > virtual > CPU, or named by the user)
//! and logical-device creation with the Vulkan 1.3 features the passes use.
use crate::error::{Error, Result, VkContext};
use ash::vk;
use std::ffi::CStr;

/// What the chosen device is, for printing and for reports.
#[derive(Clone, Debug, Default)]
pub struct DeviceInfo {
    /// The device name the driver reports.
    pub name: String,
    /// "discrete GPU", "integrated GPU", "virtual GPU", "CPU" or "other".
    pub kind: String,
    /// The driver's info string (VkPhysicalDeviceDriverProperties::driverInfo).
    pub driver: String,
    /// The Vulkan version the device supports, "major.minor.patch".
    pub api_version: String,
    /// Valid bits of timestamps on the chosen queue family (0: no timestamps).
    pub timestamp_valid_bits: u32,
}

impl std::fmt::Display for DeviceInfo {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{} ({}, Vulkan {}, {})",
            self.name, self.kind, self.api_version, self.driver
        )
    }
}

fn kind_rank(kind: vk::PhysicalDeviceType) -> (u32, &'static str) {
    match kind {
        vk::PhysicalDeviceType::DISCRETE_GPU => (0, "discrete GPU"),
        vk::PhysicalDeviceType::INTEGRATED_GPU => (1, "integrated GPU"),
        vk::PhysicalDeviceType::VIRTUAL_GPU => (2, "virtual GPU"),
        vk::PhysicalDeviceType::CPU => (3, "CPU"),
        _ => (4, "other"),
    }
}

fn graphics_queue_family(instance: &ash::Instance, pd: vk::PhysicalDevice) -> Option<u32> {
    // SAFETY: `pd` was enumerated from this instance.
    let families = unsafe { instance.get_physical_device_queue_family_properties(pd) };
    families
        .iter()
        .position(|f| {
            f.queue_flags
                .contains(vk::QueueFlags::GRAPHICS | vk::QueueFlags::COMPUTE)
        })
        .map(|i| i as u32)
}

fn describe(instance: &ash::Instance, pd: vk::PhysicalDevice) -> DeviceInfo {
    let mut driver = vk::PhysicalDeviceDriverProperties::default();
    let mut props2 = vk::PhysicalDeviceProperties2::default().push_next(&mut driver);
    // SAFETY: `pd` was enumerated from a Vulkan 1.3 instance.
    unsafe { instance.get_physical_device_properties2(pd, &mut props2) };
    let props = props2.properties;
    let v = props.api_version;
    DeviceInfo {
        name: props
            .device_name_as_c_str()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_default(),
        kind: kind_rank(props.device_type).1.to_owned(),
        driver: driver
            .driver_info_as_c_str()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_default(),
        api_version: format!(
            "{}.{}.{}",
            vk::api_version_major(v),
            vk::api_version_minor(v),
            vk::api_version_patch(v)
        ),
        timestamp_valid_bits: graphics_queue_family(instance, pd)
            .and_then(|family| {
                // SAFETY: `pd` was enumerated from this instance.
                let families = unsafe { instance.get_physical_device_queue_family_properties(pd) };
                families
                    .get(family as usize)
                    .map(|f| f.timestamp_valid_bits)
            })
            .unwrap_or(0),
    }
}

fn has_extensions(instance: &ash::Instance, pd: vk::PhysicalDevice, names: &[&CStr]) -> bool {
    // SAFETY: `pd` was enumerated from this instance.
    let Ok(available) = (unsafe { instance.enumerate_device_extension_properties(pd) }) else {
        return false;
    };
    names.iter().all(|name| {
        available
            .iter()
            .any(|e| e.extension_name_as_c_str().is_ok_and(|n| n == *name))
    })
}

fn supports_required_features(instance: &ash::Instance, pd: vk::PhysicalDevice) -> bool {
    let mut v13 = vk::PhysicalDeviceVulkan13Features::default();
    let mut features = vk::PhysicalDeviceFeatures2::default().push_next(&mut v13);
    // SAFETY: `pd` was enumerated from a Vulkan 1.3 instance.
    unsafe { instance.get_physical_device_features2(pd, &mut features) };
    let stores = features.features.fragment_stores_and_atomics == vk::TRUE;
    // SAFETY: as above.
    let api = unsafe { instance.get_physical_device_properties(pd) }.api_version;
    api >= vk::API_VERSION_1_3
        && v13.dynamic_rendering == vk::TRUE
        && v13.synchronization2 == vk::TRUE
        && stores
}

/// Chooses a device: the one named by `wanted` (a case-insensitive part of its name, or
/// its index in enumeration order), else the best kind that has what glyphcast needs.
pub fn choose_physical_device(
    instance: &ash::Instance,
    wanted: Option<&str>,
) -> Result<(vk::PhysicalDevice, DeviceInfo)> {
    choose_with_extensions(instance, wanted, &[])
}

/// As [`choose_physical_device`], among the devices that have `extensions` too.
pub(crate) fn choose_with_extensions(
    instance: &ash::Instance,
    wanted: Option<&str>,
    extensions: &[&CStr],
) -> Result<(vk::PhysicalDevice, DeviceInfo)> {
    // SAFETY: the instance is valid.
    let devices =
        unsafe { instance.enumerate_physical_devices() }.vk("vkEnumeratePhysicalDevices")?;
    let mut candidates = Vec::new();
    for (index, pd) in devices.iter().copied().enumerate() {
        let info = describe(instance, pd);
        let usable = supports_required_features(instance, pd)
            && graphics_queue_family(instance, pd).is_some()
            && has_extensions(instance, pd, extensions);
        candidates.push((index, pd, info, usable));
    }
    let needs = std::iter::once(
        "Vulkan 1.3 dynamic rendering, synchronization2 and fragmentStoresAndAtomics".to_owned(),
    )
    .chain(extensions.iter().map(|e| e.to_string_lossy().into_owned()))
    .collect::<Vec<_>>()
    .join(", ");
    let names = || {
        candidates
            .iter()
            .map(|(i, _, info, _)| format!("{i}: {}", info.name))
            .collect::<Vec<_>>()
            .join(", ")
    };
    if let Some(wanted) = wanted {
        let needle = wanted.to_lowercase();
        let found = candidates.iter().find(|(i, _, info, _)| {
            wanted.parse::<usize>().is_ok_and(|w| w == *i)
                || info.name.to_lowercase().contains(&needle)
        });
        return match found {
            Some((_, pd, info, true)) => Ok((*pd, info.clone())),
            Some((_, _, info, false)) => Err(Error::setup(
                "device with the features glyphcast needs",
                format_args!("'{}' lacks one of: {needs}", info.name),
            )),
            None => Err(Error::setup(
                "Vulkan device of the name asked for",
                format_args!("none matches '{wanted}'; devices: {}", names()),
            )),
        };
    }
    candidates
        .iter()
        .filter(|c| c.3)
        .min_by_key(|(i, pd, _, _)| {
            // SAFETY: enumerated from this instance.
            let kind = unsafe { instance.get_physical_device_properties(*pd) }.device_type;
            (kind_rank(kind).0, *i)
        })
        .map(|(_, pd, info, _)| (*pd, info.clone()))
        .ok_or_else(|| {
            Error::setup(
                "Vulkan device with the features glyphcast needs",
                format_args!("needs {needs}; devices: [{}]", names()),
            )
        })
}

/// Creates the logical device with one graphics+compute queue and `extensions` (none
/// headless; VK_KHR_swapchain for a window).
pub(crate) fn create(
    instance: &ash::Instance,
    pd: vk::PhysicalDevice,
    extensions: &[&CStr],
) -> Result<(ash::Device, u32)> {
    let family = graphics_queue_family(instance, pd).ok_or(Error::Setup {
        missing: "graphics+compute queue on the device",
        found: None,
    })?;
    let priorities = [1.0f32];
    let queues = [vk::DeviceQueueCreateInfo::default()
        .queue_family_index(family)
        .queue_priorities(&priorities)];
    // maintenance4 is mandatory in Vulkan 1.3 (the compute shaders are SPIR-V 1.5, which
    // does not need it; enabled for any 1.6 module a test compiles itself).
    let mut v13 = vk::PhysicalDeviceVulkan13Features::default()
        .dynamic_rendering(true)
        .synchronization2(true)
        .maintenance4(true);
    // The ray-casting fragment shaders write storage buffers: the work counters and the
    // known depths of culled frames (render::visibility).
    let core = vk::PhysicalDeviceFeatures::default().fragment_stores_and_atomics(true);
    let mut features = vk::PhysicalDeviceFeatures2::default()
        .features(core)
        .push_next(&mut v13);
    let extension_names: Vec<_> = extensions.iter().map(|e| e.as_ptr()).collect();
    let info = vk::DeviceCreateInfo::default()
        .queue_create_infos(&queues)
        .enabled_extension_names(&extension_names)
        .push_next(&mut features);
    // SAFETY: all pointers refer to locals alive during the call; features were checked.
    let device = unsafe { instance.create_device(pd, &info, None) }.vk("vkCreateDevice")?;
    Ok((device, family))
}
