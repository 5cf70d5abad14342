//! The settings of one render, shared by every backend.

use pointray_kernels::PatchAcceptance;

/// How the per-patch data reaches the GPU (SPEC.md §2.7).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum BufferLayout {
    /// Hot (intersection) and cold (shading) data in separate buffers.
    #[default]
    Split,
    /// Both in one interleaved buffer.
    Combined,
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RenderSettings {
    pub width: u32,
    pub height: u32,
    /// Samples per pixel; 1 shoots through pixel centres, more jitter inside the pixel.
    pub samples_per_pixel: u32,
    /// Ray depth: 1 = primary rays only, 2 = one reflection bounce (the paper's setting).
    pub max_depth: u32,
    pub shadows: bool,
    pub acceptance: PatchAcceptance,
    pub buffer_layout: BufferLayout,
}

impl Default for RenderSettings {
    fn default() -> Self {
        Self {
            width: 640,
            height: 640,
            samples_per_pixel: 1,
            max_depth: 2,
            shadows: true,
            acceptance: PatchAcceptance::default(),
            buffer_layout: BufferLayout::default(),
        }
    }
}
