//! The Khronos validation layer and a debug-utils messenger that counts what it reports,
//! so that tests can assert that a whole run produced no validation message. Public so that
//! other Vulkan instances of ours (the viewer's presentation context) count the same way.

use std::ffi::{CStr, c_void};
use std::sync::atomic::{AtomicU32, Ordering};

use ash::vk;

pub const VALIDATION_LAYER: &CStr = c"VK_LAYER_KHRONOS_validation";

/// Errors and warnings the layer reported. Kept behind an `Arc` (or a `Box`) so that its
/// address, handed to the driver as user data, stays put.
#[derive(Debug, Default)]
pub struct MessageCounter {
    count: AtomicU32,
}

impl MessageCounter {
    pub fn count(&self) -> u32 {
        self.count.load(Ordering::Relaxed)
    }
}

unsafe extern "system" fn count_message(
    severity: vk::DebugUtilsMessageSeverityFlagsEXT,
    _types: vk::DebugUtilsMessageTypeFlagsEXT,
    data: *const vk::DebugUtilsMessengerCallbackDataEXT<'_>,
    user_data: *mut c_void,
) -> vk::Bool32 {
    // SAFETY: `user_data` is the boxed counter owned by the messenger's owner, which
    // destroys the messenger before dropping the box; `data` is valid for this call.
    unsafe {
        let counter = &*(user_data as *const MessageCounter);
        counter.count.fetch_add(1, Ordering::Relaxed);
        let message = (*data).message_as_c_str().map(|m| m.to_string_lossy()).unwrap_or_default();
        tracing::error!(target: "pointray_vulkan::validation", ?severity, "{message}");
        eprintln!("[vulkan validation {severity:?}] {message}");
    }
    vk::FALSE
}

/// The create-info of a messenger that counts warnings and errors into `counter`.
pub fn messenger_info(counter: &MessageCounter) -> vk::DebugUtilsMessengerCreateInfoEXT<'_> {
    vk::DebugUtilsMessengerCreateInfoEXT::default()
        .message_severity(
            vk::DebugUtilsMessageSeverityFlagsEXT::WARNING | vk::DebugUtilsMessageSeverityFlagsEXT::ERROR,
        )
        .message_type(
            vk::DebugUtilsMessageTypeFlagsEXT::GENERAL
                | vk::DebugUtilsMessageTypeFlagsEXT::VALIDATION
                | vk::DebugUtilsMessageTypeFlagsEXT::PERFORMANCE,
        )
        .pfn_user_callback(Some(count_message))
        .user_data(counter as *const MessageCounter as *mut c_void)
}

/// Whether the loader can find the validation layer.
pub fn layer_available(entry: &ash::Entry) -> bool {
    // SAFETY: plain enumeration call on a loaded entry.
    let layers = unsafe { entry.enumerate_instance_layer_properties() }.unwrap_or_default();
    layers.iter().any(|l| l.layer_name_as_c_str().is_ok_and(|name| name == VALIDATION_LAYER))
}
