//! Host-path presentation (the CPU backend): a Vulkan swapchain on the window, fed with the
//! host pixels of each frame. The Vulkan backend presents with pointray-vulkan's
//! `WindowTarget` instead.

mod context;
mod instance;
mod presenter;
mod staging;
mod swapchain;

pub use presenter::{Presented, Presenter};
pub(crate) use swapchain::ByteOrder;
