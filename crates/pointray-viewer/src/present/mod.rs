//! Host-path presentation (the CPU backend): a Vulkan swapchain on the window, fed with the
//! host pixels of each frame. The Vulkan backend presents with pointray-vulkan's
//! `WindowTarget` instead.

mod byte_order;
mod presenter;

pub(crate) use byte_order::ByteOrder;
pub use presenter::Presenter;
