//! The debug-utils messenger: records every validation error so that tests (and
//! `--validate` runs) can fail on them instead of scrolling past them.

use std::ffi::{CStr, c_void};
use std::sync::Mutex;

use ash::vk;

/// Validation messages collected by the messenger callback.
#[derive(Debug, Default)]
pub struct ValidationLog {
    errors: Mutex<Vec<String>>,
}

impl ValidationLog {
    /// Removes and returns every validation error recorded so far.
    pub fn take_errors(&self) -> Vec<String> {
        match self.errors.lock() {
            Ok(mut errors) => std::mem::take(&mut *errors),
            Err(poisoned) => std::mem::take(&mut *poisoned.into_inner()),
        }
    }

    /// How many validation errors are waiting to be taken.
    pub fn error_count(&self) -> usize {
        self.errors.lock().map(|e| e.len()).unwrap_or(0)
    }

    fn record(&self, message: String) {
        match self.errors.lock() {
            Ok(mut errors) => errors.push(message),
            Err(poisoned) => poisoned.into_inner().push(message),
        }
    }
}

/// The messenger's create info; `log` must outlive the messenger.
pub(crate) fn messenger_info(log: &ValidationLog) -> vk::DebugUtilsMessengerCreateInfoEXT<'_> {
    vk::DebugUtilsMessengerCreateInfoEXT::default()
        .message_severity(
            vk::DebugUtilsMessageSeverityFlagsEXT::ERROR
                | vk::DebugUtilsMessageSeverityFlagsEXT::WARNING,
        )
        .message_type(
            vk::DebugUtilsMessageTypeFlagsEXT::VALIDATION
                | vk::DebugUtilsMessageTypeFlagsEXT::PERFORMANCE
                | vk::DebugUtilsMessageTypeFlagsEXT::GENERAL,
        )
        .pfn_user_callback(Some(on_message))
        .user_data(std::ptr::from_ref(log).cast_mut().cast())
}

unsafe extern "system" fn on_message(
    severity: vk::DebugUtilsMessageSeverityFlagsEXT,
    kind: vk::DebugUtilsMessageTypeFlagsEXT,
    data: *const vk::DebugUtilsMessengerCallbackDataEXT<'_>,
    user_data: *mut c_void,
) -> vk::Bool32 {
    // SAFETY: the loader passes a valid callback-data pointer for the duration of the call.
    let message = unsafe { data.as_ref() }
        .filter(|d| !d.p_message.is_null())
        .map(|d| {
            // SAFETY: p_message is a NUL-terminated string owned by the layer for this call.
            unsafe { CStr::from_ptr(d.p_message) }
                .to_string_lossy()
                .into_owned()
        })
        .unwrap_or_default();
    if severity.contains(vk::DebugUtilsMessageSeverityFlagsEXT::ERROR)
        && kind.contains(vk::DebugUtilsMessageTypeFlagsEXT::VALIDATION)
    {
        log::error!("Vulkan validation: {message}");
        // SAFETY: user_data is the `ValidationLog` boxed by the context, which outlives
        // the messenger (the context destroys the messenger before dropping the log).
        if let Some(log) = unsafe { user_data.cast::<ValidationLog>().as_ref() } {
            log.record(message);
        }
    } else if severity.contains(vk::DebugUtilsMessageSeverityFlagsEXT::WARNING) {
        log::warn!("Vulkan validation: {message}");
    }
    vk::FALSE
}
