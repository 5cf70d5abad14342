//! The scan structure prep found in a cloud, as the patch store records it: the scan lines
//! its patches followed, or the one-line reason it prepped the scan as unstructured points.

use std::fmt;

/// Bytes the store gives the reason's text; a longer reason is cut at a character boundary.
pub const REASON_BYTES: usize = 128;

#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub enum ScanStructure {
    /// The store's writer did not say (a store written by a library call, or merged from tiles).
    #[default]
    NotRecorded,
    /// Prep looked for no scan structure: the cloud has no sensor, or scan mode was off.
    NotSought,
    /// The patches followed scan lines (over all stations together).
    Lines { lines: u64, returns_on_lines: u64, patches: u64, surface_patches: u64 },
    /// A scan with a sensor, prepped as unstructured points for this reason.
    Unstructured { reason: String },
}

impl ScanStructure {
    /// The share of returns on lines, in [0, 1], where lines were followed.
    pub fn share_on_lines(&self) -> Option<f64> {
        match self {
            Self::Lines { returns_on_lines, patches, .. } => {
                Some(*returns_on_lines as f64 / (*patches).max(1) as f64)
            }
            _ => None,
        }
    }

    /// `reason` as the store holds it: at most `REASON_BYTES` bytes of UTF-8, zero-padded.
    pub(crate) fn reason_bytes(&self) -> [u8; REASON_BYTES] {
        let mut bytes = [0; REASON_BYTES];
        if let Self::Unstructured { reason } = self {
            let mut end = reason.len().min(REASON_BYTES);
            while !reason.is_char_boundary(end) {
                end -= 1;
            }
            bytes[..end].copy_from_slice(&reason.as_bytes()[..end]);
        }
        bytes
    }

    /// The reason held in `bytes`, or why they hold none.
    pub(crate) fn reason_of(bytes: &[u8; REASON_BYTES]) -> Result<String, &'static str> {
        let end = bytes.iter().position(|&b| b == 0).unwrap_or(REASON_BYTES);
        if bytes[end..].iter().any(|&b| b != 0) {
            return Err("the scan reason has bytes after its end");
        }
        String::from_utf8(bytes[..end].to_vec()).map_err(|_| "the scan reason is not UTF-8 text")
    }
}

impl fmt::Display for ScanStructure {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::NotRecorded => write!(f, "not recorded"),
            Self::NotSought => write!(f, "none sought (no sensor, or scan mode off)"),
            Self::Lines { lines, surface_patches, .. } => write!(
                f,
                "{lines} scan lines, {:.1} % of returns on them, {surface_patches} surface patches",
                100.0 * self.share_on_lines().unwrap_or(0.0)
            ),
            Self::Unstructured { reason } => write!(f, "unstructured: {reason}"),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_long_reason_is_cut_at_a_character_boundary() {
        let reason = "é".repeat(100);
        let bytes = ScanStructure::Unstructured { reason }.reason_bytes();
        assert_eq!(ScanStructure::reason_of(&bytes).unwrap(), "é".repeat(64));
        let mut bad = [0u8; REASON_BYTES];
        bad[3] = 7;
        assert!(ScanStructure::reason_of(&bad).is_err());
        bad[0] = b'a';
        bad[1..3].copy_from_slice(&[0xff, 0xfe]);
        assert!(ScanStructure::reason_of(&bad).is_err());
    }

    #[test]
    fn the_share_is_of_the_patches() {
        let lines =
            ScanStructure::Lines { lines: 64, returns_on_lines: 900, patches: 1000, surface_patches: 800 };
        assert_eq!(lines.share_on_lines(), Some(0.9));
        assert_eq!(lines.to_string(), "64 scan lines, 90.0 % of returns on them, 800 surface patches");
    }
}
