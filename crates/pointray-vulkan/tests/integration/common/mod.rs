//! What the Vulkan tests share, from `pointray-test-support`: a validated renderer (or a skip
//! note), small scenes built in code, and image comparisons.

pub use pointray_test_support::floor_scenes::*;
pub use pointray_test_support::{assert_no_validation_messages, vulkan_renderer as renderer};
