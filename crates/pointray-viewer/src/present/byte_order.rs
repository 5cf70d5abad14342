//! How the bytes of one swapchain pixel are ordered, from the display output that
//! pointray-vulkan's `Swapchain` says fills its images.

use pointray_vulkan::PixelOutput;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum ByteOrder {
    Bgra,
    Rgba,
}

impl From<PixelOutput> for ByteOrder {
    fn from(output: PixelOutput) -> Self {
        match output {
            PixelOutput::DisplayBgra => Self::Bgra,
            PixelOutput::Display | PixelOutput::Aovs => Self::Rgba,
        }
    }
}
