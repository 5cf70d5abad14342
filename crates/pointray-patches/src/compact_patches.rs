//! The patch store's compact records (format 8): a patch's GPU record (`PatchHot`, 32 bytes)
//! and cold record (`PatchCold`, 12 bytes) in 28 bytes, plus 6 for colour and intensity
//! where the cloud has them. Patches are cut into blocks of `BLOCK_PATCHES` consecutive
//! patches, which are in Morton order and so cover a compact region; each block keeps the box
//! its origins span and the power of two its radii are scaled by (`BlockFrame`).
//!
//! What each field keeps, against the records prep made:
//! - the origin: 21 bits an axis on a grid over the block's box whose step is a power of two,
//!   under `2 extent / (2^21 - 2)` along an axis of the block's extent, so it moves by at most
//!   `extent / (2^21 - 2)`; decoded origins lie on the grid, so a second round trip keeps
//!   them, and an origin already on it (a step finer than its f32 spacing) is kept exactly;
//! - `d_u` and the colour reach: half floats of the value times the block's power of two, so
//!   the relative error is at most 2^-11 for values within 2^28 of the block's largest;
//! - the normal and tangent angle, `d_v / d_u` and `c1 .. c5`: the GPU record's own bits,
//!   unchanged (the renderers read no more than these);
//! - the colour: unchanged; the intensity (in [0, 1]): unorm16, off by at most half a step, 1 / 131070;
//! - the box: not stored, made again from the decoded patch (`patch_bounds`), so it bounds
//!   the patch the renderers see.

use bytemuck::{Pod, Zeroable};
use half::f16;
use pointray_kernels::{Aabb, PatchCold, PatchHot};
use rayon::prelude::*;

use crate::patch_bounds::patch_box;
use crate::patch_set::PatchSet;
use crate::prep_settings::BoxKind;

/// Patches a block holds (the last block of a store may hold fewer).
pub const BLOCK_PATCHES: usize = 1024;

/// The steps an origin coordinate takes within its block's box, along each axis.
const POSITION_BITS: u32 = 21;
const POSITION_STEPS: u32 = (1 << POSITION_BITS) - 1;

/// The scaled largest radius of a block lies in [2^14, 2^15): within a half float's range,
/// with 28 binades of normal numbers below it.
const LARGEST_SCALED_BINADE: u32 = 14;

/// How a block's patches are quantised. 32 bytes.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct BlockFrame {
    /// The low corner of the box the block's origins span.
    pub min: [f32; 3],
    /// The length of one position step along each axis (0 where the box is flat).
    pub step: [f32; 3],
    /// Radii are stored as half floats of `radius * 2^-radius_exponent`.
    pub radius_exponent: i32,
    pub reserved: u32,
}

/// One patch's geometry and colour reach. 28 bytes.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct CompactPatch {
    /// The origin's steps from the block's low corner: x in bits 0..21, y in 21..42, z in
    /// 42..63 of the little-endian 64-bit number these two words make.
    pub position: [u32; 2],
    /// `PatchHot::frame`, `aspect_c1` and `coefficients` as they are.
    pub frame: u32,
    pub aspect_c1: u32,
    pub coefficients: [u32; 2],
    /// `d_u` (low half) and the colour reach (high half), scaled half floats.
    pub radii: u32,
}

/// One patch's colour (RGBA8, r first) and intensity (unorm16, little-endian). 6 bytes.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct CompactColor {
    pub rgba: [u8; 4],
    pub intensity: [u8; 2],
}

/// The frame of the block of `hot` records and their `cold` ones. Its grid is that of the
/// origins as a first grid over them places them (`snapped`): the grid a round trip of the
/// decoded block finds again, so that a store of decoded patches has the same bytes.
pub fn block_frame(hot: &[PatchHot], cold: &[PatchCold]) -> BlockFrame {
    let axes = grids(&snapped(hot));
    let largest =
        hot.iter().map(|h| h.radius).chain(cold.iter().map(|c| c.color_reach)).fold(0.0f32, f32::max);
    BlockFrame {
        min: axes.map(|(start, _)| start),
        step: axes.map(|(_, step)| step),
        radius_exponent: radius_exponent(largest),
        reserved: 0,
    }
}

/// The origins of `hot` on the grid over them: where a first round trip puts them. Every one
/// lies on the grid of these too, whose step is no coarser, so they are what is stored.
fn snapped(hot: &[PatchHot]) -> Vec<[f32; 3]> {
    let origins: Vec<[f32; 3]> = hot.iter().map(|h| h.origin).collect();
    let axes = grids(&origins);
    origins.iter().map(|o| std::array::from_fn(|a| on_grid(position_steps(o[a], axes[a]), axes[a]))).collect()
}

/// The box of the origins of `hot` as a store keeps them, blocks from its first: the same for
/// decoded patches as for those they were decoded from.
pub fn stored_origin_bounds(hot: &[PatchHot]) -> Option<Aabb> {
    let block_box = |block: &[PatchHot]| {
        let origins = snapped(block).into_iter().map(glam::Vec3::from_array);
        origins.fold(None, |bounds: Option<Aabb>, o| {
            Some(bounds.map_or(Aabb::new(o, o), |b| b.union(&Aabb::new(o, o))))
        })
    };
    hot.par_chunks(BLOCK_PATCHES).filter_map(block_box).reduce_with(|a, b| a.union(&b))
}

/// The grid (first line, step) along each axis of `origins`.
fn grids(origins: &[[f32; 3]]) -> [(f32, f32); 3] {
    let (low, high) = origins.iter().fold(([f32::INFINITY; 3], [f32::NEG_INFINITY; 3]), |(low, high), o| {
        (std::array::from_fn(|a| low[a].min(o[a])), std::array::from_fn(|a| high[a].max(o[a])))
    });
    std::array::from_fn(|a| if origins.is_empty() { (0.0, 0.0) } else { grid(low[a], high[a]) })
}

/// The coordinate `steps` steps along `(start, step)`.
fn on_grid(steps: u64, (start, step): (f32, f32)) -> f32 {
    (f64::from(start) + steps as f64 * f64::from(step)) as f32
}

/// The grid a block's coordinates in `[low, high]` are stored on: its first line, a multiple
/// of the step, and the step, the smallest power of two at least `(high - low) / (2^21 - 2)`,
/// so that `2^21 - 1` steps from the first line reach `high`. Decoded coordinates lie on the
/// grid and are f32 numbers, so a second round trip changes nothing.
fn grid(low: f32, high: f32) -> (f32, f32) {
    if high <= low {
        return (low, 0.0);
    }
    let (low, high) = (f64::from(low), f64::from(high));
    let mut step = ((high - low) / f64::from(POSITION_STEPS - 1)).log2().ceil().exp2();
    loop {
        let start = (low / step).floor() * step;
        let reaches = start + f64::from(POSITION_STEPS) * step >= high;
        if reaches && f64::from(start as f32) == start {
            return (start as f32, step as f32);
        }
        step *= 2.0;
    }
}

/// The power of two radii are divided by: the block's largest value becomes a half float in
/// [2^14, 2^15), after rounding, so that decoded radii give the same exponent again.
fn radius_exponent(largest: f32) -> i32 {
    if !(largest > 0.0 && largest.is_finite()) {
        return 0;
    }
    let scaled = |exponent: i32| f16::from_f64(f64::from(largest) * (-f64::from(exponent)).exp2()).to_f64();
    let (low, high) = (f64::from(1u32 << LARGEST_SCALED_BINADE), f64::from(2u32 << LARGEST_SCALED_BINADE));
    // The logarithm of a value near a power of two may round across it, and rounding to a
    // half float may carry the value up to the next power.
    let exponent = largest.log2().floor() as i32 - LARGEST_SCALED_BINADE as i32;
    match scaled(exponent) {
        s if s >= high => exponent + 1,
        s if s < low => exponent - 1,
        _ => exponent,
    }
}

/// `hot` and `cold` (one block, of the same length as `out`) in `frame`, into `out`.
pub fn encode_patches(frame: &BlockFrame, hot: &[PatchHot], cold: &[PatchCold], out: &mut [CompactPatch]) {
    let scale = (-f64::from(frame.radius_exponent)).exp2();
    for (((h, c), origin), record) in hot.iter().zip(cold).zip(snapped(hot)).zip(out) {
        let steps: [u64; 3] =
            std::array::from_fn(|a| position_steps(origin[a], (frame.min[a], frame.step[a])));
        let packed = steps[0] | steps[1] << POSITION_BITS | steps[2] << (2 * POSITION_BITS);
        let radius = positive_half(f64::from(h.radius) * scale);
        let reach = f16::from_f64(f64::from(c.color_reach) * scale).to_bits();
        *record = CompactPatch {
            position: [packed as u32, (packed >> 32) as u32],
            frame: h.frame,
            aspect_c1: h.aspect_c1,
            coefficients: h.coefficients,
            radii: u32::from(radius) | u32::from(reach) << 16,
        };
    }
}

/// The nearest step of `value` along the grid `(start, step)`, within the block's steps.
fn position_steps(value: f32, (start, step): (f32, f32)) -> u64 {
    if step <= 0.0 {
        return 0;
    }
    ((f64::from(value) - f64::from(start)) / f64::from(step)).round().clamp(0.0, f64::from(POSITION_STEPS))
        as u64
}

/// The half float nearest `value`, but never 0 for a positive value: a support radius of 0
/// would make the patch vanish.
fn positive_half(value: f64) -> u16 {
    let bits = f16::from_f64(value.min(f64::from(f16::MAX))).to_bits();
    if bits == 0 && value > 0.0 { 1 } else { bits }
}

/// The cold records' colours and intensities, into `out`.
pub fn encode_colors(cold: &[PatchCold], out: &mut [CompactColor]) {
    for (c, record) in cold.iter().zip(out) {
        let intensity = (c.intensity.clamp(0.0, 1.0) * 65535.0).round() as u16;
        *record = CompactColor { rgba: c.color_rgba8.to_le_bytes(), intensity: intensity.to_le_bytes() };
    }
}

/// Whether the colour and intensity of `record` are those of a point without either, which
/// a store without colour columns gives every patch.
pub fn is_plain(record: &PatchCold) -> bool {
    record.color_rgba8 == PatchCold::default().color_rgba8 && record.intensity == 0.0
}

/// The frames of the blocks of `hot` and `cold`, whose first patch starts a block.
pub fn frames_of(hot: &[PatchHot], cold: &[PatchCold]) -> Vec<BlockFrame> {
    hot.par_chunks(BLOCK_PATCHES)
        .zip(cold.par_chunks(BLOCK_PATCHES))
        .map(|(h, c)| block_frame(h, c))
        .collect()
}

/// The compact patches of `hot` and `cold` in the blocks of `frames`, on every core.
pub fn patches_of(frames: &[BlockFrame], hot: &[PatchHot], cold: &[PatchCold]) -> Vec<CompactPatch> {
    let mut out = vec![CompactPatch::default(); hot.len()];
    out.par_chunks_mut(BLOCK_PATCHES)
        .zip(hot.par_chunks(BLOCK_PATCHES).zip(cold.par_chunks(BLOCK_PATCHES)))
        .zip(frames)
        .for_each(|((out, (hot, cold)), frame)| encode_patches(frame, hot, cold, out));
    out
}

/// The colour records of `cold`, on every core.
pub fn colors_of(cold: &[PatchCold]) -> Vec<CompactColor> {
    let mut out = vec![CompactColor::default(); cold.len()];
    out.par_chunks_mut(BLOCK_PATCHES)
        .zip(cold.par_chunks(BLOCK_PATCHES))
        .for_each(|(out, cold)| encode_colors(cold, out));
    out
}

/// Why `cold` cannot be stored compactly, with colour columns when `colors`, if it cannot:
/// an intensity outside [0, 1], or a colour where the store keeps none.
pub fn cold_problem(cold: &[PatchCold], colors: bool) -> Option<String> {
    if let Some(i) = cold.par_iter().position_first(|c| !(0.0..=1.0).contains(&c.intensity)) {
        return Some(format!("cold record {i} has intensity {}, outside [0, 1]", cold[i].intensity));
    }
    let coloured = if colors { None } else { cold.par_iter().position_first(|c| !is_plain(c)) };
    coloured.map(|i| {
        format!("cold record {i} has a colour or intensity, but the store keeps none (no colour neighbours)")
    })
}

/// Whether a store of `patches` keeps colour columns: where they have colour neighbours, or
/// any colour or intensity.
pub fn keeps_colors(patches: &PatchSet) -> bool {
    !patches.color_neighbors.is_empty() || patches.cold.par_iter().any(|c| !is_plain(c))
}

/// Why `frame` cannot be decoded, if it cannot.
pub fn frame_problem(frame: &BlockFrame) -> Option<&'static str> {
    let finite = frame.min.iter().chain(&frame.step).all(|v| v.is_finite());
    if !finite || frame.step.iter().any(|&s| s < 0.0) {
        return Some("a block's box is not finite");
    }
    // Radii beyond 2^150 or below 2^-170 are no f32; the exponent's range is far wider than
    // any that a cloud within the coordinate range needs.
    (!(-170..=150).contains(&frame.radius_exponent)).then_some("a block's radius scale is out of range")
}

/// The records of one block: its hot records, their boxes of `kind`, and cold records with
/// the `colors` given (white and intensity 0 where none are).
pub fn decode_block(
    frame: &BlockFrame,
    patches: &[CompactPatch],
    colors: Option<&[CompactColor]>,
    kind: BoxKind,
    (hot, aabbs, cold): (&mut [PatchHot], &mut [Aabb], &mut [PatchCold]),
) {
    let scale = f64::from(frame.radius_exponent).exp2();
    for (i, record) in patches.iter().enumerate() {
        let packed = u64::from(record.position[0]) | u64::from(record.position[1]) << 32;
        let origin = std::array::from_fn(|a| {
            let steps = (packed >> (a as u32 * POSITION_BITS)) & u64::from(POSITION_STEPS);
            on_grid(steps, (frame.min[a], frame.step[a]))
        });
        let half = |bits: u32| (f64::from(f16::from_bits(bits as u16)) * scale) as f32;
        hot[i] = PatchHot {
            origin,
            radius: half(record.radii),
            frame: record.frame,
            aspect_c1: record.aspect_c1,
            coefficients: record.coefficients,
        };
        aabbs[i] = patch_box(&hot[i], kind);
        let plain = PatchCold { color_reach: half(record.radii >> 16), ..PatchCold::default() };
        cold[i] = colors.map_or(plain, |colors| PatchCold {
            color_rgba8: u32::from_le_bytes(colors[i].rgba),
            intensity: f32::from(u16::from_le_bytes(colors[i].intensity)) / 65535.0,
            ..plain
        });
    }
}

#[cfg(test)]
mod tests {
    use glam::{Vec2, Vec3};
    use pointray_kernels::PackedTangentFrame;

    use super::*;

    fn patch(origin: Vec3, radius: f32) -> PatchHot {
        let n = Vec3::new(0.2, 0.4, 1.0).normalize();
        let frame = PackedTangentFrame::new(n, n.any_orthonormal_vector());
        PatchHot::new(origin, frame, Vec2::new(radius, 0.6 * radius), [0.0, 0.1, -0.2, 3.0, 1.0, -2.0])
    }

    fn round_trip(hot: &[PatchHot], cold: &[PatchCold]) -> (BlockFrame, Vec<PatchHot>, Vec<PatchCold>) {
        let frame = block_frame(hot, cold);
        let mut patches = vec![CompactPatch::default(); hot.len()];
        encode_patches(&frame, hot, cold, &mut patches);
        let mut colors = vec![CompactColor::default(); hot.len()];
        encode_colors(cold, &mut colors);
        let n = hot.len();
        let (mut out_hot, mut aabbs, mut out_cold) =
            (vec![PatchHot::default(); n], vec![Aabb::default(); n], vec![PatchCold::default(); n]);
        decode_block(
            &frame,
            &patches,
            Some(&colors),
            BoxKind::Cube,
            (&mut out_hot, &mut aabbs, &mut out_cold),
        );
        assert_eq!(aabbs[0], patch_box(&out_hot[0], BoxKind::Cube));
        (frame, out_hot, out_cold)
    }

    #[test]
    fn a_block_keeps_its_records_within_the_stated_bounds() {
        let hot: Vec<PatchHot> = (0..BLOCK_PATCHES)
            .map(|i| {
                let t = i as f32 / BLOCK_PATCHES as f32;
                patch(Vec3::new(100.0 + 37.0 * t, -4.0 * t * t, 0.5 + (9.0 * t).sin()), 0.001 + 0.05 * t)
            })
            .collect();
        let cold: Vec<PatchCold> = (0..BLOCK_PATCHES)
            .map(|i| PatchCold {
                color_rgba8: 0x80ff_2040 + i as u32,
                intensity: i as f32 / BLOCK_PATCHES as f32,
                color_reach: if i % 7 == 0 { 0.0 } else { 0.03 },
            })
            .collect();
        let (frame, decoded, decoded_cold) = round_trip(&hot, &cold);
        for ((before, after), (cold_before, cold_after)) in
            hot.iter().zip(&decoded).zip(cold.iter().zip(&decoded_cold))
        {
            for a in 0..3 {
                let bound = frame.step[a] / 2.0 + f32::EPSILON * before.origin[a].abs();
                assert!((before.origin[a] - after.origin[a]).abs() <= bound, "{before:?} {after:?}");
            }
            assert!((before.radius - after.radius).abs() <= before.radius * 2f32.powi(-11));
            assert_eq!(
                (before.frame, before.aspect_c1, before.coefficients),
                (after.frame, after.aspect_c1, after.coefficients)
            );
            assert_eq!(cold_before.color_rgba8, cold_after.color_rgba8);
            assert!((cold_before.intensity - cold_after.intensity).abs() <= 0.5 / 65535.0 + f32::EPSILON);
            assert!(
                (cold_before.color_reach - cold_after.color_reach).abs()
                    <= cold_before.color_reach * 2f32.powi(-11)
            );
        }
        assert!(frame_problem(&frame).is_none());
    }

    #[test]
    fn a_second_round_trip_changes_nothing() {
        for (origin, scale) in [(Vec3::new(-3.7, 1e4, 0.001), 1.0), (Vec3::new(5e5, -2e3, 7.0), 3e3)] {
            let hot: Vec<PatchHot> = (0..BLOCK_PATCHES)
                .map(|i| {
                    let t = i as f32 / BLOCK_PATCHES as f32;
                    let radius =
                        0.01 * scale * (1.0 + (37.0 * t).sin().abs()) * if i == 9 { 2.0 } else { 1.0 };
                    patch(origin + scale * Vec3::new(t, (13.0 * t).cos(), -t * t), radius)
                })
                .collect();
            let cold: Vec<PatchCold> = (0..BLOCK_PATCHES)
                .map(|i| PatchCold { intensity: (i % 97) as f32 / 96.0, ..PatchCold::default() })
                .collect();
            let (_, once, once_cold) = round_trip(&hot, &cold);
            let (_, twice, twice_cold) = round_trip(&once, &once_cold);
            assert_eq!((&once, &once_cold), (&twice, &twice_cold));
            let encoded = |hot: &[PatchHot], cold: &[PatchCold]| {
                let frames = frames_of(hot, cold);
                (patches_of(&frames, hot, cold), frames)
            };
            assert_eq!(encoded(&hot, &cold), encoded(&once, &once_cold), "the same bytes again");
        }
    }

    #[test]
    fn tiny_radii_stay_positive_and_flat_boxes_decode() {
        let hot = [patch(Vec3::ONE, 1e3), patch(Vec3::ONE, 1e-30)];
        let (frame, decoded, _) = round_trip(&hot, &[PatchCold::default(); 2]);
        assert_eq!(frame.step, [0.0; 3]);
        assert_eq!(decoded[0].origin, [1.0; 3]);
        assert!(decoded[1].radius > 0.0, "{}", decoded[1].radius);
    }

    #[test]
    fn bad_frames_are_named() {
        let nan = BlockFrame { min: [f32::NAN, 0.0, 0.0], ..BlockFrame::default() };
        assert_eq!(frame_problem(&nan), Some("a block's box is not finite"));
        let huge = BlockFrame { radius_exponent: 900, ..BlockFrame::default() };
        assert_eq!(frame_problem(&huge), Some("a block's radius scale is out of range"));
    }
}
