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
    entries: Arc<Mutex<Entries>>,
}

#[derive(Default)]
struct Entries {
    errors: Vec<String>,
    /// How many of `errors` a caller has seen through [`ValidationLog::errors`].
    read: usize,
}

impl ValidationLog {
    /// Every error so far; they count as read from then on.
    pub fn errors(&self) -> Vec<String> {
        self.entries
            .lock()
            .map(|mut e| {
                e.read = e.errors.len();
                e.errors.clone()
            })
            .unwrap_or_default()
    }

    pub(crate) fn user_data(&self) -> *mut c_void {
        Arc::as_ptr(&self.entries) as *mut c_void
    }

    /// Prints the errors no caller has read: those that arrived after the last check,
    /// such as errors raised while the device and instance were destroyed after the
    /// [`Gpu`](super::Gpu) itself was dropped.
    pub(crate) fn report_unread(&self) {
        let Ok(entries) = self.entries.lock() else {
            return;
        };
        let unread = entries.errors.get(entries.read..).unwrap_or_default();
        if !unread.is_empty() {
            eprintln!(
                "glyphcast: {} validation error(s) were never checked:",
                unread.len()
            );
            for error in unread {
                eprintln!("  {error}");
            }
        }
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
        // SAFETY: `user` is the Mutex inside the log's Arc, alive while the messenger is
        // (and, for the messenger chained into instance creation, until the instance
        // is destroyed).
        if let Some(entries) = unsafe { (user as *const Mutex<Entries>).as_ref() }
            && let Ok(mut entries) = entries.lock()
        {
            entries.errors.push(message);
        }
    } else {
        eprintln!("validation: {message}");
    }
    vk::FALSE
}
