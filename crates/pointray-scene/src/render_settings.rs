//! The settings of one render, shared by every backend.

/// Which hits on a patch's quadratic count (SPEC.md §3, intersection step 3).
///
/// The disk test is the default: against the meshes it has fewer false surfaces, smaller depth
/// and normal errors and a higher PSNR than the box test at every k, with no more holes
/// (bench/FIDELITY.md), for 0–7% more frame time (bench/RESULTS.md, ablations).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum AcceptanceTest {
    /// The hit point must lie inside the patch's box (the paper's test).
    Box,
    /// The hit point must also lie over the patch's own disk, `u² + v² <= d_i²`.
    #[default]
    Disk,
}

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
    pub acceptance: AcceptanceTest,
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
            acceptance: AcceptanceTest::default(),
            buffer_layout: BufferLayout::default(),
        }
    }
}
