//! The form in which a point set's hot records go onto the GPU.

use pointray_kernels::{PatchHot, PatchUnpacked};

/// Packed records (`PatchHot`, 32 bytes) or records unpacked at upload (`PatchUnpacked`, 64
/// bytes), which the intersection shader reads without decoding. Each form has its own hit
/// groups (`pipeline::patch_hit_group`), so that neither carries the other's code.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum HotRecords {
    #[default]
    Packed,
    Unpacked,
}

impl HotRecords {
    /// The form's name in reports.
    pub fn name(self) -> &'static str {
        match self {
            Self::Packed => "packed",
            Self::Unpacked => "unpacked",
        }
    }

    /// GPU bytes a patch.
    pub fn bytes_per_patch(self) -> usize {
        match self {
            Self::Packed => size_of::<PatchHot>(),
            Self::Unpacked => size_of::<PatchUnpacked>(),
        }
    }
}
