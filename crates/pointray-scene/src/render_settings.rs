//! The settings of one render, shared by every backend.

use pointray_kernels::PatchAcceptance;

use crate::hot_records::HotRecords;
use crate::integrator::Integrator;

/// How the per-patch data reaches the GPU (METHOD.md §2.7).
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
    /// How many consecutive patches one box of a point set's bottom level bounds on the GPU
    /// (1 is the paper's box per patch). Larger boxes make a smaller BVH, and each
    /// intersection call tests its box's patches in turn, which is slower. `None` chooses:
    /// one, or more where the scene would not fit the GPU's memory whole with one
    /// (`pointray_vulkan::SceneLayout::group_to_fit`).
    pub patches_per_box: Option<u32>,
    /// The form of the point sets' hot records on the GPU. `None` chooses: unpacked for
    /// point sets small enough to gain by it, where the scene fits the GPU's memory whole
    /// with them in boxes of one patch, else packed
    /// (`pointray_vulkan::SceneLayout::unpack_to_fit`).
    pub hot_records: Option<HotRecords>,
    pub integrator: Integrator,
    /// The path integrator's random sequence: one seed gives one image on every backend.
    pub seed: u32,
    /// The index of the render's first sample (its AOVs come from it). Renders that take
    /// samples `0..n`, `n..n + m`, ... continue one another: averaged by their sample counts,
    /// they make the render of all the samples at once (a viewer refining a still view).
    pub first_sample: u32,
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
            patches_per_box: None,
            hot_records: None,
            integrator: Integrator::default(),
            seed: 0,
            first_sample: 0,
        }
    }
}

/// One of the numeric render settings, which a scene file's `[render]` table and a command's
/// flags both set: either way the value passes the same `RenderSetting::check`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RenderSetting {
    Width,
    Height,
    SamplesPerPixel,
    MaxDepth,
    PatchesPerBox,
}

/// The longest image side: beyond it the GPU's dispatch and the image formats run out.
pub const MAX_IMAGE_SIDE: u32 = 1 << 16;
/// Beyond this many samples a pixel no longer changes visibly, and a frame takes hours.
pub const MAX_SAMPLES_PER_PIXEL: u32 = 1 << 16;
/// Beyond this many patches a box's intersection call does a whole tile's work.
pub const MAX_PATCHES_PER_BOX: u32 = 64;
/// Beyond this many segments the reflection weights (< 1 each) leave nothing to see.
pub const MAX_RAY_DEPTH: u32 = 64;

/// What one pixel of a render holds on the host at its peak: the image with its AOVs (36
/// bytes), the renderer's own copy of them (the CPU's tiles, the GPU's readback) and the
/// encoder's buffers, with room to spare.
pub const FRAME_BYTES_PER_PIXEL: u64 = 112;

impl RenderSetting {
    /// The key in a scene file.
    pub fn file_key(self) -> &'static str {
        match self {
            Self::Width => "render.width",
            Self::Height => "render.height",
            Self::SamplesPerPixel => "render.spp",
            Self::MaxDepth => "render.max_depth",
            Self::PatchesPerBox => "render.patches_per_box",
        }
    }

    /// `value` when it is in this setting's range; else why not.
    pub fn check(self, value: u32) -> Result<u32, String> {
        let maximum = match self {
            Self::Width | Self::Height => MAX_IMAGE_SIDE,
            Self::SamplesPerPixel => MAX_SAMPLES_PER_PIXEL,
            Self::MaxDepth => MAX_RAY_DEPTH,
            Self::PatchesPerBox => MAX_PATCHES_PER_BOX,
        };
        if (1..=maximum).contains(&value) {
            Ok(value)
        } else {
            Err(format!("must be between 1 and {maximum}, got {value}"))
        }
    }

    /// Parses a flag's text and checks it, for the command-line parser.
    pub fn parse(self, text: &str) -> Result<u32, String> {
        let value = text.trim().parse::<u32>().map_err(|e| format!("`{text}`: {e}"))?;
        self.check(value)
    }
}

impl RenderSettings {
    /// The image's width over its height.
    pub fn aspect(&self) -> f32 {
        self.width as f32 / self.height.max(1) as f32
    }

    /// Whether an image of this size fits in `budget`; the error says which size would.
    pub fn check_memory(&self, budget: &pointray_io::MemoryBudget) -> Result<(), String> {
        let pixels = u64::from(self.width) * u64::from(self.height);
        budget.check(pixels, FRAME_BYTES_PER_PIXEL, "pixels").map_err(|shortfall| {
            let shrink = (shortfall.fitting as f64 / pixels as f64).sqrt();
            let side = |length: u32| ((f64::from(length) * shrink) as u32).max(1);
            format!(
                "a {}x{} image: {shortfall}, e.g. {}x{}",
                self.width,
                self.height,
                side(self.width),
                side(self.height)
            )
        })
    }
}
