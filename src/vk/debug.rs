//! The validation layer's messages, collected through VK_EXT_debug_utils. Errors are kept
//! so tests can fail on them (as wgpu's test harness does); warnings are printed.
use ash::vk;
use std::ffi::{CStr, c_void};
use std::sync::{Arc, Mutex};

/// Message IDs we deliberately ignore, each with the reason.
const IGNORED: &[(&str, &str)] = &[];

/// Validation errors reported so far. Shared with the callback through a raw pointer to
/// the inner `Mutex`, which the `Arc` keeps alive for as long as the messenger exists.
#[derive(Clone, Default)]
pub struct ValidationLog {
    errors: Arc<Mutex<Vec<String>>>,
}

impl ValidationLog {
    pub fn errors(&self) -> Vec<String> {
        self.errors.lock().map(|e| e.clone()).unwrap_or_default()
    }

    pub(crate) fn user_data(&self) -> *mut c_void {
        Arc::as_ptr(&self.errors) as *mut c_void
    }
}

pub(crate) struct Messenger {
    pub loader: ash::ext::debug_utils::Instance,
    pub handle: vk::DebugUtilsMessengerEXT,
    pub log: ValidationLog,
}

pub(crate) fn messenger_info(log: &ValidationLog) -> vk::DebugUtilsMessengerCreateInfoEXT<'static> {
    vk::DebugUtilsMessengerCreateInfoEXT::default()
        .message_severity(
            vk::DebugUtilsMessageSeverityFlagsEXT::ERROR
                | vk::DebugUtilsMessageSeverityFlagsEXT::WARNING,
        )
        .message_type(
            vk::DebugUtilsMessageTypeFlagsEXT::GENERAL
                | vk::DebugUtilsMessageTypeFlagsEXT::VALIDATION
                | vk::DebugUtilsMessageTypeFlagsEXT::PERFORMANCE,
        )
        .pfn_user_callback(Some(on_message))
        .user_data(log.user_data())
}

unsafe extern "system" fn on_message(
    severity: vk::DebugUtilsMessageSeverityFlagsEXT,
    kind: vk::DebugUtilsMessageTypeFlagsEXT,
    data: *const vk::DebugUtilsMessengerCallbackDataEXT<'_>,
    user: *mut c_void,
) -> vk::Bool32 {
    // SAFETY: the layer passes a valid callback-data pointer for the duration of the call.
    let Some(data) = (unsafe { data.as_ref() }) else {
        return vk::FALSE;
    };
    let text = |p: *const std::ffi::c_char| {
        if p.is_null() {
            String::new()
        } else {
            // SAFETY: non-null strings from the layer are NUL-terminated.
            unsafe { CStr::from_ptr(p) }.to_string_lossy().into_owned()
        }
    };
    let id = text(data.p_message_id_name);
    if IGNORED.iter().any(|(ignored, _)| *ignored == id) {
        return vk::FALSE;
    }
    let message = format!("[{id}] {}", text(data.p_message));
    if severity.contains(vk::DebugUtilsMessageSeverityFlagsEXT::ERROR)
        && kind.contains(vk::DebugUtilsMessageTypeFlagsEXT::VALIDATION)
    {
        eprintln!("validation error: {message}");
        // SAFETY: `user` is the Mutex inside the log's Arc, alive while the messenger is.
        if let Some(errors) = unsafe { (user as *const Mutex<Vec<String>>).as_ref() }
            && let Ok(mut errors) = errors.lock()
        {
            errors.push(message);
        }
    } else {
        eprintln!("validation: {message}");
    }
    vk::FALSE
}
