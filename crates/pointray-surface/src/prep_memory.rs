//! What a prep in memory holds at its peak, and so whether a cloud is prepped in memory or
//! streamed tile by tile within a budget.
//!
//! The peak falls in the support radii (`StagePeaks` on dragon points: 218 bytes a point at
//! 2M, 213 at 5M, 216 at 100M, with the program's own memory), when these are alive at once:
//!
//! | bytes a point | what | why it is still held |
//! |---|---|---|
//! | 8 per neighbour | the neighbour table: a u32 index and an f32 distance, `max(k, normal_k)` wide | the radii read the widest rows; it is narrowed only before the fit |
//! | 12 | the recentred f32 position | every stage reads it |
//! | 4 | the input index of each point | attributes are gathered through it at the end |
//! | 12 | the normal | dropped only once the radii are chosen |
//! | 36 + 4 | the tangent frame and its packed form | the fit reads both |
//! | 8 | two radii (the chosen one and the paper's, for the colours) | the fit and the cold records |
//! | 20 | slack: the allocator's and rayon's per-task buffers | measured peaks run 2–10 over the terms above; the 4 bytes the packed frame shed in store version 6 stay here, as a 40 MiB budget's peak showed they are needed |
//! | per attribute | the input's colours, intensities, normals, rings, classes, sensor origins | the cold records gather them last |
//!
//! The f64 positions as read (24 bytes) are freed once recentred, before the peak. The
//! patches themselves (68 bytes) come after the peak, once the neighbours are narrowed.

use pointray_io::MemoryBudget;
use pointray_patches::PrepSettings;

/// A u32 neighbour index and its f32 distance.
const NEIGHBOUR_BYTES: u64 = 8;

/// Position 12, input index 4, normal 12, frame 36 + 4, radii 8, slack 20.
const POINT_BYTES: u64 = 12 + 4 + 12 + 36 + 4 + 8 + 20;

/// The program itself: its code, thread stacks and buffers, whatever the cloud.
pub const PREP_FIXED_BYTES: u64 = 32 << 20;

/// Bytes a point prep in memory holds at its peak, for a cloud whose attributes take
/// `attribute_bytes` a point.
pub fn prep_bytes_per_point(settings: &PrepSettings, attribute_bytes: u64) -> u64 {
    NEIGHBOUR_BYTES * u64::from(settings.k.max(settings.normal_k)) + POINT_BYTES + attribute_bytes
}

/// The peak bytes of prepping `points` points in memory.
pub fn in_memory_prep_bytes(points: u64, settings: &PrepSettings, attribute_bytes: u64) -> u64 {
    points.saturating_mul(prep_bytes_per_point(settings, attribute_bytes)).saturating_add(PREP_FIXED_BYTES)
}

/// How a cloud is prepped.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PrepRoute {
    /// Read whole and prepped in one pass: the faster route, when it fits.
    InMemory,
    /// Read in chunks, sorted out of core and prepped tile by tile within the budget.
    Streamed,
}

/// In memory when a single pass over `points` points fits `budget`, else streamed.
pub fn prep_route(
    points: u64,
    settings: &PrepSettings,
    attribute_bytes: u64,
    budget: MemoryBudget,
) -> PrepRoute {
    if in_memory_prep_bytes(points, settings, attribute_bytes) <= budget.bytes {
        PrepRoute::InMemory
    } else {
        PrepRoute::Streamed
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const GIB: u64 = 1 << 30;

    fn route(points: u64, attribute_bytes: u64, budget: u64) -> PrepRoute {
        prep_route(points, &PrepSettings::default(), attribute_bytes, MemoryBudget { bytes: budget })
    }

    #[test]
    fn the_estimate_is_what_prep_was_measured_to_hold() {
        // Default settings: 16 neighbours for the normals.
        assert_eq!(prep_bytes_per_point(&PrepSettings::default(), 0), 224);
        // Measured peaks: 213 to 218 bytes a point with the program's memory.
        let estimate = in_memory_prep_bytes(100_000_000, &PrepSettings::default(), 0) as f64 / 1e8;
        assert!((216.0..240.0).contains(&estimate), "{estimate}");
        let wide = PrepSettings { k: 32, normal_k: 16, ..PrepSettings::default() };
        assert_eq!(prep_bytes_per_point(&wide, 3), 224 + 128 + 3);
    }

    #[test]
    fn clouds_that_fit_are_prepped_in_memory_and_larger_ones_streamed() {
        assert_eq!(route(100_000_000, 0, 64 * GIB), PrepRoute::InMemory);
        assert_eq!(route(100_000_000, 0, 8 * GIB), PrepRoute::Streamed);
        // A 128 GiB machine's default budget, half its memory: 300M points fit (at about
        // 65 GB), more stream.
        assert_eq!(route(300_000_000, 0, 64 * GIB), PrepRoute::InMemory);
        assert_eq!(route(320_000_000, 0, 64 * GIB), PrepRoute::Streamed);
        assert_eq!(route(1_000_000_000, 0, 64 * GIB), PrepRoute::Streamed);
        // Attributes count: per-point sensor origins tip this cloud over.
        assert_eq!(route(280_000_000, 0, 64 * GIB), PrepRoute::InMemory);
        assert_eq!(route(280_000_000, 24, 64 * GIB), PrepRoute::Streamed);
        assert_eq!(route(1_000, 0, PREP_FIXED_BYTES), PrepRoute::Streamed, "the program's own memory");
        assert_eq!(route(u64::MAX, 0, u64::MAX - 1), PrepRoute::Streamed, "no overflow");
    }
}
