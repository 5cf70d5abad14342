//! Tests that need a Vulkan device skip without one on a developer's machine, and fail under
//! CI (`CI=true`), where the device must be there.

/// Whether this run is CI's (`CI=true`).
pub fn in_ci() -> bool {
    std::env::var("CI").is_ok_and(|value| value == "true")
}

/// Called when no usable Vulkan device could be had (`error` says why): fails under CI, else
/// notes the skip.
pub fn skip_without_device(error: &dyn std::fmt::Display) {
    assert!(!in_ci(), "CI=true but no usable Vulkan device: {error}");
    eprintln!("note: skipping, no usable Vulkan device: {error}");
}

/// A renderer on the best device with the validation layer on; `None` (after a note) when no
/// device fits outside CI.
#[cfg(feature = "vulkan")]
pub fn vulkan_renderer() -> Option<pointray_vulkan::VulkanRenderer> {
    use pointray_vulkan::{DeviceOptions, DeviceSelector, VulkanRenderer};
    match VulkanRenderer::new(DeviceSelector::Auto, DeviceOptions::VALIDATED) {
        Ok(renderer) => Some(renderer),
        Err(error) if error.is_no_device() => {
            skip_without_device(&error);
            None
        }
        Err(error) => panic!("creating the renderer failed: {error}"),
    }
}

/// Fails if the validation layer reported anything while `renderer` worked (the messages are
/// printed as they come).
#[cfg(feature = "vulkan")]
pub fn assert_no_validation_messages(renderer: &pointray_vulkan::VulkanRenderer) {
    assert_eq!(renderer.validation_messages(), 0, "the validation layer reported messages (printed above)");
}
