//! The presenter's own validation messenger. The renderer counts its messages inside its own
//! crate; the presentation context is a second Vulkan instance, so it counts its own, and
//! prints them with the same `[vulkan validation ...]` prefix so logs read alike.

use std::ffi::{CStr, c_void};
use std::sync::atomic::{AtomicU32, Ordering};

use ash::vk;

pub(crate) const VALIDATION_LAYER: &CStr = c"VK_LAYER_KHRONOS_validation";

/// Warnings and errors reported. Shared (`Arc`) so the count can be read after teardown,
/// whose leak reports come last; the instance holds a clone, so the address given to the
/// driver stays valid as long as the instance.
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
    // SAFETY: `user_data` is the counter, kept alive by the instance that calls us; `data` is valid for the duration of this call.
    unsafe {
        let counter = &*(user_data as *const MessageCounter);
        counter.count.fetch_add(1, Ordering::Relaxed);
        let message = (*data).message_as_c_str().map(|m| m.to_string_lossy()).unwrap_or_default();
        eprintln!("[vulkan validation {severity:?}] (presenter) {message}");
    }
    vk::FALSE
}

pub(crate) fn messenger_info(counter: &MessageCounter) -> vk::DebugUtilsMessengerCreateInfoEXT<'_> {
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

pub(crate) fn layer_available(entry: &ash::Entry) -> bool {
    // SAFETY: plain enumeration on a loaded entry.
    let layers = unsafe { entry.enumerate_instance_layer_properties() }.unwrap_or_default();
    layers.iter().any(|l| l.layer_name_as_c_str().is_ok_and(|name| name == VALIDATION_LAYER))
}
