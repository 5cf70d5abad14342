//! Presentation: a Vulkan swapchain on the window, fed with the host pixels of each frame.

mod context;
mod instance;
mod presenter;
mod staging;
mod swapchain;

pub use pointray_vulkan::validation::MessageCounter;
pub use presenter::{Presented, Presenter};
pub(crate) use swapchain::ByteOrder;
