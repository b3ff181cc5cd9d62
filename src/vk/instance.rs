//! Instance creation: Vulkan 1.3, VK_EXT_debug_utils and the Khronos validation layer
//! when asked for, and the surface extensions of a window system when there is a window.
use super::debug::{ValidationLog, messenger_info};
use crate::error::{Error, Result, VkContext};
use ash::vk;
use std::ffi::{CStr, c_char};

const VALIDATION_LAYER: &CStr = c"VK_LAYER_KHRONOS_validation";

fn has_layer(entry: &ash::Entry, name: &CStr) -> Result<bool> {
    // SAFETY: enumerating layers has no preconditions.
    let layers = unsafe { entry.enumerate_instance_layer_properties() }
        .vk("vkEnumerateInstanceLayerProperties")?;
    Ok(layers
        .iter()
        .any(|l| l.layer_name_as_c_str().is_ok_and(|n| n == name)))
}

/// Whether GLYPHCAST_SYNC_VALIDATION asks for synchronization validation.
fn sync_validation_requested() -> bool {
    std::env::var("GLYPHCAST_SYNC_VALIDATION").is_ok_and(|v| !v.is_empty() && v != "0")
}

fn has_extension(entry: &ash::Entry, name: &CStr) -> Result<bool> {
    // SAFETY: enumerating extensions has no preconditions.
    let extensions = unsafe { entry.enumerate_instance_extension_properties(None) }
        .vk("vkEnumerateInstanceExtensionProperties")?;
    Ok(extensions
        .iter()
        .any(|e| e.extension_name_as_c_str().is_ok_and(|n| n == name)))
}

/// Creates the instance, and the debug messenger when `validation` is on. The messenger
/// info is also chained into instance creation so that messages from
/// vkCreateInstance/vkDestroyInstance are caught. With validation on,
/// GLYPHCAST_SYNC_VALIDATION=1 adds the layer's synchronization validation
/// (VK_VALIDATION_FEATURE_ENABLE_SYNCHRONIZATION_VALIDATION_EXT): hazards between frames
/// in flight are reported like any other validation message. `surface_extensions` are those a window
/// system needs (none when headless).
pub(crate) fn create(
    entry: &ash::Entry,
    validation: bool,
    log: &ValidationLog,
    surface_extensions: &[*const c_char],
) -> Result<(ash::Instance, Option<vk::DebugUtilsMessengerEXT>)> {
    // SAFETY: querying the loader's version has no preconditions.
    let version = unsafe { entry.try_enumerate_instance_version() }
        .vk("vkEnumerateInstanceVersion")?
        .unwrap_or(vk::API_VERSION_1_0);
    if version < vk::API_VERSION_1_3 {
        return Err(Error::setup(
            "Vulkan 1.3 loader",
            format_args!(
                "the loader supports {}.{}",
                vk::api_version_major(version),
                vk::api_version_minor(version)
            ),
        ));
    }
    let debug_utils = ash::ext::debug_utils::NAME;
    if validation && !has_layer(entry, VALIDATION_LAYER)? {
        return Err(Error::Setup {
            missing: "validation layer VK_LAYER_KHRONOS_validation, which validation needs \
                      (Debian: vulkan-validationlayers)",
            found: None,
        });
    }
    let use_debug_utils = validation && has_extension(entry, debug_utils)?;
    let app = vk::ApplicationInfo::default()
        .application_name(c"glyphcast")
        .engine_name(c"glyphcast")
        .api_version(vk::API_VERSION_1_3);
    let layers = if validation {
        vec![VALIDATION_LAYER.as_ptr()]
    } else {
        vec![]
    };
    let mut extensions = surface_extensions.to_vec();
    if use_debug_utils {
        extensions.push(debug_utils.as_ptr());
    }
    let mut chained = messenger_info(log);
    let mut info = vk::InstanceCreateInfo::default()
        .application_info(&app)
        .enabled_layer_names(&layers)
        .enabled_extension_names(&extensions);
    if use_debug_utils {
        info = info.push_next(&mut chained);
    }
    let sync = [vk::ValidationFeatureEnableEXT::SYNCHRONIZATION_VALIDATION];
    let mut features = vk::ValidationFeaturesEXT::default().enabled_validation_features(&sync);
    if validation && sync_validation_requested() {
        info = info.push_next(&mut features);
    }
    // SAFETY: every pointer in `info` refers to locals that outlive the call.
    let instance = unsafe { entry.create_instance(&info, None) }.map_err(|result| match result {
        vk::Result::ERROR_INCOMPATIBLE_DRIVER => Error::Setup {
            missing: "Vulkan driver (install mesa-vulkan-drivers for lavapipe, or a GPU driver)",
            found: None,
        },
        vk::Result::ERROR_EXTENSION_NOT_PRESENT => Error::Setup {
            missing: "surface extensions of this window system in the Vulkan loader",
            found: None,
        },
        result => Error::Vulkan { call: "vkCreateInstance", result },
    })?;
    if !use_debug_utils {
        return Ok((instance, None));
    }
    let loader = ash::ext::debug_utils::Instance::new(entry, &instance);
    // SAFETY: the instance was created with VK_EXT_debug_utils enabled.
    match unsafe { loader.create_debug_utils_messenger(&messenger_info(log), None) } {
        Ok(messenger) => Ok((instance, Some(messenger))),
        Err(result) => {
            // SAFETY: nothing else was created from this instance yet.
            unsafe { instance.destroy_instance(None) };
            Err(Error::Vulkan {
                call: "vkCreateDebugUtilsMessengerEXT",
                result,
            })
        }
    }
}
