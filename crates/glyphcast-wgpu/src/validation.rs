//! A wgpu instance on the Vulkan backend with the Khronos validation layer on, whose
//! messages are collected so that a test (or a CI check) fails on any: the way glyphcast's
//! own tests run every GPU call.
//!
//! wgpu's `InstanceFlags::VALIDATION` turns the layer on; this instance also asks for the layer's synchronization validation (a
//! `VkValidationFeaturesEXT` added by wgpu-hal's instance-creation callback), and has a
//! debug messenger of its own that keeps every validation error and warning.
use crate::{Error, Result};
use glyphcast::ash;
use glyphcast::ash::vk;
use std::ffi::{CStr, c_void};
use std::sync::{Arc, Mutex};
use wgpu::hal::api::Vulkan;

/// The messages a messenger collected.
type Messages = Mutex<Vec<String>>;

/// A validated wgpu instance (Vulkan backend only) and the messages of its layer.
pub struct ValidatedInstance {
    // The messenger is destroyed (in `Drop`) before the instance can go.
    messenger: Option<(ash::ext::debug_utils::Instance, vk::DebugUtilsMessengerEXT)>,
    messages: Arc<Messages>,
    instance: wgpu::Instance,
}

impl ValidatedInstance {
    /// The instance, with synchronization validation too when `sync` is set. Refuses
    /// when the validation layer is not installed (Debian: vulkan-validationlayers).
    pub fn new(sync: bool) -> Result<ValidatedInstance> {
        let desc = wgpu::hal::InstanceDescriptor {
            name: "glyphcast-wgpu",
            // Not DEBUG: with it, wgpu's shaders carry their WGSL source (OpSource of
            // language 10), which older layers' SPIR-V validators refuse.
            flags: wgpu::InstanceFlags::VALIDATION,
            memory_budget_thresholds: Default::default(),
            backend_options: Default::default(),
            telemetry: None,
            display: None,
        };
        const ENABLES: [vk::ValidationFeatureEnableEXT; 1] =
            [vk::ValidationFeatureEnableEXT::SYNCHRONIZATION_VALIDATION];
        let mut features =
            vk::ValidationFeaturesEXT::default().enabled_validation_features(&ENABLES);
        let features = &mut features;
        let callback: Box<wgpu::hal::vulkan::CreateInstanceCallback<'_>> = Box::new(move |args| {
            // The messenger's extension, which wgpu adds only with DEBUG.
            if !args.extensions.contains(&ash::ext::debug_utils::NAME) {
                args.extensions.push(ash::ext::debug_utils::NAME);
            }
            if sync {
                let info = std::mem::take(args.create_info);
                *args.create_info = info.push_next(features);
            }
        });
        // SAFETY: the callback only chains the layer's validation features, which the
        // layer (checked below) takes.
        let hal = unsafe { wgpu::hal::vulkan::Instance::init_with_callback(&desc, Some(callback)) }
            .map_err(|e| Error::Device(format!("creating the Vulkan instance: {e}")))?;
        let shared = hal.shared_instance();
        let has_layer = {
            // SAFETY: enumerating layers has no preconditions.
            let layers =
                unsafe { shared.entry().enumerate_instance_layer_properties() }.unwrap_or_default();
            layers.iter().any(|l| {
                l.layer_name_as_c_str()
                    .is_ok_and(|n| n == c"VK_LAYER_KHRONOS_validation")
            })
        };
        let has_debug_utils = shared.extensions().contains(&ash::ext::debug_utils::NAME);
        if !(has_layer && has_debug_utils) {
            return Err(Error::Device(
                "the Vulkan validation layer (VK_LAYER_KHRONOS_validation with \
                 VK_EXT_debug_utils) is not installed (Debian: vulkan-validationlayers)"
                    .into(),
            ));
        }
        let messages = Arc::new(Messages::default());
        let loader = ash::ext::debug_utils::Instance::new(shared.entry(), shared.raw_instance());
        let info = vk::DebugUtilsMessengerCreateInfoEXT::default()
            .message_severity(
                vk::DebugUtilsMessageSeverityFlagsEXT::ERROR
                    | vk::DebugUtilsMessageSeverityFlagsEXT::WARNING,
            )
            .message_type(
                vk::DebugUtilsMessageTypeFlagsEXT::VALIDATION
                    | vk::DebugUtilsMessageTypeFlagsEXT::PERFORMANCE,
            )
            .pfn_user_callback(Some(on_message))
            .user_data(Arc::as_ptr(&messages) as *mut c_void);
        // SAFETY: the instance has VK_EXT_debug_utils; `messages` outlives the messenger
        // (destroyed in `Drop`, before this struct's Arc goes).
        let handle = unsafe { loader.create_debug_utils_messenger(&info, None) }
            .map_err(|e| Error::Device(format!("vkCreateDebugUtilsMessengerEXT: {e}")))?;
        // SAFETY: `hal` is a Vulkan instance made above.
        let instance = unsafe { wgpu::Instance::from_hal::<Vulkan>(hal) };
        Ok(ValidatedInstance {
            messenger: Some((loader, handle)),
            messages,
            instance,
        })
    }

    /// The wgpu instance.
    pub fn instance(&self) -> &wgpu::Instance {
        &self.instance
    }

    /// The instance's first Vulkan adapter (the one `VK_DRIVER_FILES` leaves: lavapipe
    /// in glyphcast's tests).
    pub fn adapter(&self) -> Result<wgpu::Adapter> {
        block_on(self.instance.enumerate_adapters(wgpu::Backends::VULKAN))
            .into_iter()
            .next()
            .ok_or_else(|| Error::Device("no Vulkan adapter".into()))
    }

    /// The validation errors and warnings so far.
    pub fn messages(&self) -> Vec<String> {
        self.messages.lock().map(|m| m.clone()).unwrap_or_default()
    }
}

impl Drop for ValidatedInstance {
    fn drop(&mut self) {
        if let Some((loader, handle)) = self.messenger.take() {
            // SAFETY: made on this instance, which is still alive (this struct holds it).
            unsafe { loader.destroy_debug_utils_messenger(handle, None) };
        }
    }
}

/// Runs a future of wgpu's native backend to completion: they are ready at once.
pub fn block_on<F: std::future::Future>(future: F) -> F::Output {
    let mut future = std::pin::pin!(future);
    let mut context = std::task::Context::from_waker(std::task::Waker::noop());
    loop {
        if let std::task::Poll::Ready(output) = future.as_mut().poll(&mut context) {
            return output;
        }
        std::thread::yield_now();
    }
}

unsafe extern "system" fn on_message(
    severity: vk::DebugUtilsMessageSeverityFlagsEXT,
    _kind: vk::DebugUtilsMessageTypeFlagsEXT,
    data: *const vk::DebugUtilsMessengerCallbackDataEXT<'_>,
    user: *mut c_void,
) -> vk::Bool32 {
    // SAFETY: the layer passes valid callback data or null.
    let Some(data) = (unsafe { data.as_ref() }) else {
        return vk::FALSE;
    };
    let text = |p: *const std::ffi::c_char| {
        if p.is_null() {
            String::new()
        } else {
            // SAFETY: the layer's strings are NUL-terminated.
            unsafe { CStr::from_ptr(p) }.to_string_lossy().into_owned()
        }
    };
    let message = format!(
        "{severity:?} [{}] {}",
        text(data.p_message_id_name),
        text(data.p_message)
    );
    eprintln!("validation: {message}");
    // SAFETY: `user` is the Arc'd message list, alive while the messenger is.
    if let Some(messages) = unsafe { (user as *const Messages).as_ref() }
        && let Ok(mut messages) = messages.lock()
    {
        messages.push(message);
    }
    vk::FALSE
}
