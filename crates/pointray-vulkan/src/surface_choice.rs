//! How a window's swapchain is set up from what its surface offers: format, size,
//! composition and present mode, for every `Swapchain` (the `WindowTarget`'s and the
//! viewer's host-copy presenter's).

use ash::vk;

use crate::trace_target::PixelOutput;

/// 8-bit RGBA or BGRA, UNORM first, and the display output whose bytes fill it: the bytes
/// are sRGB-encoded already and a copy converts nothing, so the presentation engine must
/// take them as they are.
pub fn pick_format(formats: &[vk::SurfaceFormatKHR]) -> Option<(vk::SurfaceFormatKHR, PixelOutput)> {
    let preference = [
        (vk::Format::R8G8B8A8_UNORM, PixelOutput::Display),
        (vk::Format::B8G8R8A8_UNORM, PixelOutput::DisplayBgra),
        (vk::Format::R8G8B8A8_SRGB, PixelOutput::Display),
        (vk::Format::B8G8R8A8_SRGB, PixelOutput::DisplayBgra),
    ];
    preference.into_iter().find_map(|(wanted, output)| {
        formats.iter().find(|f| f.format == wanted).map(|&format| (format, output))
    })
}

/// The surface's own extent, or `window_size` clamped to its limits when it leaves the
/// extent to the application.
pub fn pick_extent(capabilities: &vk::SurfaceCapabilitiesKHR, (width, height): (u32, u32)) -> vk::Extent2D {
    if capabilities.current_extent.width != u32::MAX {
        return capabilities.current_extent;
    }
    let (min, max) = (capabilities.min_image_extent, capabilities.max_image_extent);
    vk::Extent2D { width: width.clamp(min.width, max.width), height: height.clamp(min.height, max.height) }
}

/// Opaque when the surface allows it: the pixels' alpha is 1 anyway.
pub fn pick_composite_alpha(supported: vk::CompositeAlphaFlagsKHR) -> vk::CompositeAlphaFlagsKHR {
    [
        vk::CompositeAlphaFlagsKHR::OPAQUE,
        vk::CompositeAlphaFlagsKHR::INHERIT,
        vk::CompositeAlphaFlagsKHR::PRE_MULTIPLIED,
    ]
    .into_iter()
    .find(|&mode| supported.contains(mode))
    .unwrap_or(vk::CompositeAlphaFlagsKHR::POST_MULTIPLIED)
}

/// FIFO waits for the display (vsync, always supported); without vsync, mailbox or immediate.
pub fn pick_present_mode(modes: &[vk::PresentModeKHR], vsync: bool) -> vk::PresentModeKHR {
    let unsynced = [vk::PresentModeKHR::MAILBOX, vk::PresentModeKHR::IMMEDIATE];
    let chosen = unsynced.into_iter().find(|mode| modes.contains(mode));
    if vsync { vk::PresentModeKHR::FIFO } else { chosen.unwrap_or(vk::PresentModeKHR::FIFO) }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn format(format: vk::Format) -> vk::SurfaceFormatKHR {
        vk::SurfaceFormatKHR { format, color_space: vk::ColorSpaceKHR::SRGB_NONLINEAR }
    }

    #[test]
    fn unorm_formats_come_first_and_bgra_asks_for_the_swizzle() {
        let offered = [format(vk::Format::B8G8R8A8_SRGB), format(vk::Format::B8G8R8A8_UNORM)];
        let (chosen, output) = pick_format(&offered).expect("a format");
        assert_eq!((chosen.format, output), (vk::Format::B8G8R8A8_UNORM, PixelOutput::DisplayBgra));
        let offered = [format(vk::Format::B8G8R8A8_UNORM), format(vk::Format::R8G8B8A8_UNORM)];
        assert_eq!(pick_format(&offered).map(|(_, o)| o), Some(PixelOutput::Display));
        assert!(pick_format(&[format(vk::Format::R16G16B16A16_SFLOAT)]).is_none());
    }

    #[test]
    fn vsync_off_prefers_mailbox_then_immediate() {
        let modes = [vk::PresentModeKHR::FIFO, vk::PresentModeKHR::IMMEDIATE];
        assert_eq!(pick_present_mode(&modes, true), vk::PresentModeKHR::FIFO);
        assert_eq!(pick_present_mode(&modes, false), vk::PresentModeKHR::IMMEDIATE);
        assert_eq!(pick_present_mode(&[vk::PresentModeKHR::FIFO], false), vk::PresentModeKHR::FIFO);
    }
}
