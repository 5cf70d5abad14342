//! The form in which a point set's hot records go onto the GPU.

use pointray_kernels::{PatchHot, PatchUnpacked};
use serde::{Deserialize, Serialize};

/// Packed records (`PatchHot`, 32 bytes a patch) or records unpacked at upload
/// (`PatchUnpacked`, 64 bytes), which the intersection shader reads without decoding. The
/// Vulkan backend gives each form its own hit groups, so that neither carries the other's
/// code; the CPU renderer reads the packed records whatever the setting.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum HotRecords {
    #[default]
    Packed,
    Unpacked,
}

/// The names a scene file and `--hot-records` accept.
pub const HOT_RECORDS_NAMES: [&str; 2] = ["packed", "unpacked"];

impl HotRecords {
    /// The form's name, as a scene file spells it.
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

impl std::str::FromStr for HotRecords {
    type Err = String;

    fn from_str(text: &str) -> Result<Self, Self::Err> {
        match text.trim() {
            "packed" => Ok(Self::Packed),
            "unpacked" => Ok(Self::Unpacked),
            _ => Err(format!("unknown hot records `{text}`; the forms are {HOT_RECORDS_NAMES:?}")),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_parse_back_to_their_forms() {
        for name in HOT_RECORDS_NAMES {
            assert_eq!(name.parse::<HotRecords>().unwrap().name(), name);
        }
        assert!("compressed".parse::<HotRecords>().unwrap_err().contains("packed"));
    }
}
