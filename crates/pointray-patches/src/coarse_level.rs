//! A point set's coarse level (METHOD.md §2.9): its patches merged about sixteen to one, so
//! that a renderer whose GPU memory cannot hold a tile in full draws the tile from these
//! instead of leaving it out.
//!
//! The patches are merged within each block of `BLOCK_PATCHES` consecutive patches, the
//! blocks the compact store quantises in, so that a tile (a run of patches, `patch_tiles`)
//! finds its coarse patches by the blocks it touches whatever its length. A block is cut in
//! two at the middle of its patches' longest side, again and again, until each part holds
//! at most `CLUSTER_PATCHES`: the parts are compact in space even where the Morton order
//! jumps within a block. Each part becomes one patch through the area-weighted mean of its
//! origins, facing their mean normal, on an ellipse along their spread that holds every
//! part's patch projected onto it (the coarse patches cover what the fine ones covered), and
//! whose quadratic fits their origins and normals.

use std::ops::Range;

use glam::{Vec2, Vec3, Vec4};
use pointray_kernels::tangent_frame::normal_basis;
use pointray_kernels::{Aabb, PackedTangentFrame, PatchCold, PatchHot};
use rayon::prelude::*;

use crate::compact_patches::BLOCK_PATCHES;
use crate::patch_bounds::patch_box;
use crate::patch_set::PatchSet;

/// The most patches one coarse patch stands for. Cutting at the middle leaves parts of
/// about two thirds of this on average: a coarse level of about 6% of the patches. Under a
/// budget that holds a tenth of a set in full, finer parts draw a close view better though
/// fewer of its tiles fit in full, coarser ones worse (bench/RESULTS.md).
pub const CLUSTER_PATCHES: usize = 24;

/// The coarse patches of a set, block after block, and where each block's begin.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct CoarseLevel {
    /// The coarse patches, with the fine set's settings and offset and no colour neighbours:
    /// a hit on one takes its own colour, the mean of its part's. Made on every core at about
    /// 300 ns a fine patch of one core, which is why the patch store holds them.
    pub patches: PatchSet,
    /// The first coarse patch of each block, and one past the last of the last block.
    block_starts: Vec<usize>,
}

impl CoarseLevel {
    /// The coarse level of `fine`, made a block at a time on every core.
    pub fn of(fine: &PatchSet) -> Self {
        let blocks: Vec<Vec<(PatchHot, PatchCold)>> = (0..fine.len().div_ceil(BLOCK_PATCHES))
            .into_par_iter()
            .map(|block| {
                let range = block * BLOCK_PATCHES..((block + 1) * BLOCK_PATCHES).min(fine.len());
                coarse_block(&fine.hot[range.clone()], &fine.cold[range])
            })
            .collect();
        let counts: Vec<u32> = blocks.iter().map(|block| block.len() as u32).collect();
        let (hot, cold) = blocks.into_iter().flatten().unzip();
        Self { patches: coarse_set(fine, hot, cold), block_starts: block_starts(&counts) }
    }

    /// The level of `patches`, of which each block of the fine set has the next `counts`;
    /// `None` where the counts do not add up to the patches.
    pub fn of_blocks(patches: PatchSet, counts: &[u32]) -> Option<Self> {
        let block_starts = block_starts(counts);
        (block_starts.last() == Some(&patches.len())).then_some(Self { patches, block_starts })
    }

    /// The coarse patches that stand for the fine patches in `fine`: those of every block it
    /// touches, so two tiles that share a block both draw that block's coarse patches.
    pub fn covering(&self, fine: Range<usize>) -> Range<usize> {
        if fine.is_empty() {
            return 0..0;
        }
        let start = |block: usize| {
            let last = self.block_starts.len().saturating_sub(1);
            self.block_starts.get(block.min(last)).copied().unwrap_or(0)
        };
        start(fine.start / BLOCK_PATCHES)..start(fine.end.div_ceil(BLOCK_PATCHES))
    }
}

/// The first coarse patch of each block of `counts` coarse patches, and one past the last
/// (saturated: a sum past `usize` is no set's length).
fn block_starts(counts: &[u32]) -> Vec<usize> {
    let mut starts = Vec::with_capacity(counts.len() + 1);
    starts.push(0usize);
    for &count in counts {
        starts.push(starts[starts.len() - 1].saturating_add(count as usize));
    }
    starts
}

/// The set of the coarse patches `hot` and `cold` of `fine`: its settings and offset, boxes
/// made from the patches (as the compact store's are), and no colour neighbours, since a
/// hit on a coarse patch takes its own colour.
pub fn coarse_set(fine: &PatchSet, hot: Vec<PatchHot>, cold: Vec<PatchCold>) -> PatchSet {
    let aabbs: Vec<Aabb> = hot.par_iter().map(|patch| patch_box(patch, fine.settings.boxes)).collect();
    let (settings, offset) = (fine.settings, fine.offset);
    PatchSet {
        settings,
        offset,
        aabbs: aabbs.into(),
        hot: hot.into(),
        cold: cold.into(),
        ..PatchSet::default()
    }
}

/// The coarse patches of one block's fine patches (`hot`, `cold`), one a part.
pub fn coarse_block(hot: &[PatchHot], cold: &[PatchCold]) -> Vec<(PatchHot, PatchCold)> {
    let origins: Vec<Vec3> = hot.iter().map(PatchHot::origin).collect();
    let (order, parts) = parts(&origins);
    parts
        .into_iter()
        .map(|part| {
            let members = &order[part];
            let patch = merged_patch(members.iter().map(|&i| &hot[i]));
            let color = merged_color(members.iter().map(|&i| (&hot[i], &cold[i])), patch.radius);
            (patch, color)
        })
        .collect()
}

/// The patches of `origins` ordered so that each part is a run, and the runs: each part's
/// origins lie on one side of the middle of its parent's longest side, and none holds more
/// than `CLUSTER_PATCHES`.
fn parts(origins: &[Vec3]) -> (Vec<usize>, Vec<Range<usize>>) {
    let mut order: Vec<usize> = (0..origins.len()).collect();
    let (mut parts, mut pending) = (Vec::new(), Vec::new());
    pending.push(0..origins.len());
    while let Some(range) = pending.pop() {
        if range.len() <= CLUSTER_PATCHES {
            parts.push(range);
            continue;
        }
        let near = cut_at_middle(origins, &mut order[range.clone()]);
        pending.push(range.start + near..range.end);
        pending.push(range.start..range.start + near);
    }
    (order, parts)
}

/// Puts the patches of `members` nearer than the middle of their longest side first, and
/// says how many they are; where none lies nearer (their coordinates coincide along that
/// side), the first half by count.
fn cut_at_middle(origins: &[Vec3], members: &mut [usize]) -> usize {
    let (min, max) = members.iter().fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(min, max), &i| {
        (min.min(origins[i]), max.max(origins[i]))
    });
    let axis = (max - min).max_position();
    let middle = 0.5 * (min[axis] + max[axis]);
    let mut near = 0;
    for next in 0..members.len() {
        if origins[members[next]][axis] < middle {
            members.swap(next, near);
            near += 1;
        }
    }
    if near == 0 || near == members.len() { members.len() / 2 } else { near }
}

/// One patch over `part`'s patches: through their mean origin, facing their mean normal
/// (each weighted by its support's area), on an ellipse along their spread (`spread`) just
/// large enough to hold each patch's support projected onto it, and with the quadratic that
/// fits their origins and normals (`fitted_surface`), so that its shading turns as theirs
/// did.
fn merged_patch<'a>(part: impl Iterator<Item = &'a PatchHot> + Clone) -> PatchHot {
    let area = |patch: &PatchHot| patch.radius() * patch.radius();
    let total = part.clone().map(area).sum::<f32>().max(f32::MIN_POSITIVE);
    let centre = part.clone().map(|patch| area(patch) * patch.origin()).sum::<Vec3>() / total;
    let normal = mean_normal(part.clone().map(|patch| (patch.normal(), area(patch))));
    let plane = PackedTangentFrame::new(normal, normal_basis(normal).0).decode();
    let (major, _) =
        spread(part.clone().map(|patch| (plane.to_local(patch.origin() - centre), patch.radius())));
    let packed = PackedTangentFrame::new(normal, major.x * plane.t1 + major.y * plane.t2);
    // Measured in the frame as stored, which the renderers see.
    let frame = packed.decode();
    let (_, shape) =
        spread(part.clone().map(|patch| (frame.to_local(patch.origin() - centre), patch.radius())));
    let radii = covering_radii(
        part.clone().map(|patch| (frame.to_local(patch.origin() - centre), patch.radius())),
        shape,
    );
    let samples = part.map(|patch| {
        let local = frame.to_local(patch.origin() - centre);
        let normal = frame.to_local(patch.normal());
        (local, normal * normal.z.signum(), area(patch))
    });
    PatchHot::new(centre, packed, radii, fitted_surface(samples, radii.x))
}

/// The least `d_v / d_u` a coarse patch takes: a part cut at its middles is seldom longer.
const MIN_ASPECT: f32 = 0.25;

/// The direction in the plane along which the disks of `disks` (local offsets from the
/// centre, radii) spread most, and their spread (the root of the second moment of the union
/// of the disks, each weighted by its area) along it and across it, the latter at least
/// `MIN_ASPECT` of the former.
fn spread(disks: impl Iterator<Item = (Vec3, f32)>) -> (Vec2, Vec2) {
    let (mut uu, mut uv, mut vv, mut total) = (0.0f32, 0.0f32, 0.0f32, 0.0f32);
    for (offset, radius) in disks {
        let (weight, own) = (radius * radius, 0.25 * radius * radius);
        uu += weight * (offset.x * offset.x + own);
        uv += weight * offset.x * offset.y;
        vv += weight * (offset.y * offset.y + own);
        total += weight;
    }
    let total = total.max(f32::MIN_POSITIVE);
    let (uu, uv, vv) = (uu / total, uv / total, vv / total);
    let angle = 0.5 * (2.0 * uv).atan2(uu - vv);
    let middle = 0.5 * (uu + vv);
    let half_gap = (0.25 * (uu - vv) * (uu - vv) + uv * uv).sqrt();
    let along = (middle + half_gap).max(f32::MIN_POSITIVE).sqrt();
    let across = (middle - half_gap).max(0.0).sqrt().clamp(MIN_ASPECT * along, along);
    (Vec2::new(angle.cos(), angle.sin()), Vec2::new(along, across))
}

/// The radii `(d_u, d_v)` of the ellipse of `shape`'s proportions that holds every disk of
/// `disks` (local offsets, radii): in units of the shape, a disk's centre lies within its
/// norm, and its rim within `radius / shape.y` more, as `shape.y <= shape.x`. `d_v` is
/// rounded up past what the stored ratio to `d_u` loses.
fn covering_radii(disks: impl Iterator<Item = (Vec3, f32)>, shape: Vec2) -> Vec2 {
    let reach = |(offset, radius): (Vec3, f32)| (offset.truncate() / shape).length() + radius / shape.y;
    let scale = disks.map(reach).fold(0.0f32, f32::max);
    let radii = scale * shape;
    Vec2::new(radii.x, (radii.y * (1.0 + ASPECT_ROUNDING)).min(radii.x))
}

/// More than the relative error of `d_v` stored as a unorm16 ratio to `d_u` of at least
/// `MIN_ASPECT`.
const ASPECT_ROUNDING: f32 = 1.0 / 8192.0;

/// The height field `f(u,v) = c0 + c1 u + c2 v + c3 u² + c4 uv + c5 v²` (in a frame whose
/// normal is the samples' mean) that fits each sample's position and the slope of its
/// normal, weighted, by least squares over lengths in units of `scale`, with a slight pull
/// towards the flat disk that keeps it defined for a sample or two. Flat where the samples'
/// normals lie near the plane or the fit fails.
fn fitted_surface(samples: impl Iterator<Item = (Vec3, Vec3, f32)>, scale: f32) -> [f32; 6] {
    let mut system = [[0.0f64; 7]; 6];
    let mut add = |row: [f64; 6], value: f64, weight: f64| {
        for i in 0..6 {
            for j in 0..6 {
                system[i][j] += weight * row[i] * row[j];
            }
            system[i][6] += weight * row[i] * value;
        }
    };
    let scale = f64::from(scale.max(f32::MIN_POSITIVE));
    for (position, normal, weight) in samples {
        if normal.z < MIN_NORMAL_Z {
            return [0.0; 6];
        }
        let (u, v, h) =
            (f64::from(position.x) / scale, f64::from(position.y) / scale, f64::from(position.z) / scale);
        let (slope_u, slope_v) = (f64::from(-normal.x / normal.z), f64::from(-normal.y / normal.z));
        let weight = f64::from(weight);
        add([1.0, u, v, u * u, u * v, v * v], h, weight);
        add([0.0, 1.0, 0.0, 2.0 * u, v, 0.0], slope_u, weight);
        add([0.0, 0.0, 1.0, 0.0, u, 2.0 * v], slope_v, weight);
    }
    let pull = FLAT_PULL * (0..6).map(|i| system[i][i]).sum::<f64>().max(f64::MIN_POSITIVE);
    (0..6).for_each(|i| system[i][i] += pull);
    let Some([c0, c1, c2, c3, c4, c5]) = solve(system) else { return [0.0; 6] };
    // Back from units of `scale`: f(u, v) = scale f'(u / scale, v / scale).
    let coefficients = [c0 * scale, c1, c2, c3 / scale, c4 / scale, c5 / scale].map(|c| c as f32);
    if coefficients.iter().all(|c| c.is_finite()) { coefficients } else { [0.0; 6] }
}

/// The least a sample's normal may face along the part's: below it the part folds over
/// and no height field over its plane holds it.
const MIN_NORMAL_Z: f32 = 0.2;

/// How strongly the fit is pulled towards the flat disk, as a share of its equations'
/// mean weight on each coefficient.
const FLAT_PULL: f64 = 1e-3 / 6.0;

/// The solution of six linear equations (`system`'s rows, each ending in its right-hand
/// side) by Gaussian elimination with partial pivoting; `None` where they are singular.
fn solve(mut system: [[f64; 7]; 6]) -> Option<[f64; 6]> {
    for column in 0..6 {
        let pivot =
            (column..6).max_by(|&a, &b| system[a][column].abs().total_cmp(&system[b][column].abs()))?;
        if system[pivot][column].abs() < 1e-12 {
            return None;
        }
        system.swap(column, pivot);
        let (above, below) = system.split_at_mut(column + 1);
        let pivot_row = &above[column];
        for row in below {
            let factor = row[column] / pivot_row[column];
            row.iter_mut().zip(pivot_row).skip(column).for_each(|(value, pivot)| *value -= factor * pivot);
        }
    }
    let mut solution = [0.0; 6];
    for row in (0..6).rev() {
        let known: f64 = (row + 1..6).map(|k| system[row][k] * solution[k]).sum();
        solution[row] = (system[row][6] - known) / system[row][row];
    }
    Some(solution)
}

/// The area-weighted mean of unit `normals`, each turned to the side of the first: prep
/// orients normals, but a thin part may hold both sides of a surface. The first where they
/// cancel.
fn mean_normal(mut normals: impl Iterator<Item = (Vec3, f32)>) -> Vec3 {
    let Some((first, weight)) = normals.next() else { return Vec3::Z };
    let sum = normals
        .fold(first * weight, |sum, (normal, weight)| sum + normal * weight * normal.dot(first).signum());
    sum.try_normalize().unwrap_or(first)
}

/// The part's colour and intensity, area-weighted means of its patches'; its colour reaches
/// over the coarse patch's `radius`.
fn merged_color<'a>(part: impl Iterator<Item = (&'a PatchHot, &'a PatchCold)>, radius: f32) -> PatchCold {
    let (mut sum, mut total) = (Vec4::ZERO, 0.0f32);
    for (hot, cold) in part {
        let weight = hot.radius() * hot.radius();
        sum += weight * cold.color().extend(cold.intensity);
        total += weight;
    }
    let mean = sum / total.max(f32::MIN_POSITIVE);
    let byte = |value: f32| (value * 255.0).round().clamp(0.0, 255.0) as u8;
    PatchCold {
        intensity: mean.w,
        color_reach: radius,
        ..PatchCold::from_rgb8([byte(mean.x), byte(mean.y), byte(mean.z)], 0.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A `side` x `side` grid of round patches a unit apart in the plane z = 0, of `radius`.
    fn grid(side: usize, radius: f32) -> PatchSet {
        let hot: Vec<PatchHot> = (0..side * side)
            .map(|i| Vec3::new((i % side) as f32, (i / side) as f32, 0.0))
            .map(|origin| PatchHot::isotropic(origin, Vec3::X, Vec3::Z, [0.0; 6], radius))
            .collect();
        let aabbs = hot.iter().map(|patch| Aabb::cube(patch.origin(), patch.radius())).collect();
        PatchSet {
            aabbs,
            cold: vec![PatchCold::default(); hot.len()].into(),
            hot: hot.into(),
            ..PatchSet::default()
        }
    }

    #[test]
    fn a_tile_takes_the_coarse_patches_of_every_block_it_touches() {
        let level = CoarseLevel { block_starts: vec![0, 40, 90, 120], ..CoarseLevel::default() };
        assert_eq!(level.covering(0..BLOCK_PATCHES), 0..40);
        assert_eq!(level.covering(10..BLOCK_PATCHES + 1), 0..90);
        assert_eq!(level.covering(BLOCK_PATCHES..3 * BLOCK_PATCHES - 5), 40..120);
        assert_eq!(level.covering(5..5), 0..0);
        assert_eq!(level.covering(0..10 * BLOCK_PATCHES), 0..120, "past the last block");
    }

    #[test]
    fn a_flat_grid_merges_to_a_few_percent_whose_disks_cover_every_fine_disk() {
        let fine = grid(100, 0.8);
        let level = CoarseLevel::of(&fine);
        let coarse = &level.patches;
        let share = coarse.len() as f64 / fine.len() as f64;
        assert!((0.02..0.08).contains(&share), "{} coarse patches of {}", coarse.len(), fine.len());
        assert_eq!(level.covering(0..fine.len()), 0..coarse.len());
        assert!(coarse.check().is_ok(), "{:?}", coarse.check());
        for patch in coarse.hot.iter() {
            assert!(patch.normal().dot(Vec3::Z).abs() > 0.9999, "{:?}", patch.normal());
            assert!(patch.origin().z.abs() < 1e-6 && patch.radius() < 8.0, "{patch:?}");
            let radii = patch.decode().radii;
            assert!(radii.y >= MIN_ASPECT * radii.x * 0.999, "{radii}");
        }
        // Points on the rim of every fine disk lie within a coarse disk.
        for patch in fine.hot.iter() {
            for angle in (0..8).map(|k| k as f32 * std::f32::consts::FRAC_PI_4) {
                let rim = patch.origin() + patch.radius() * 0.999 * Vec3::new(angle.cos(), angle.sin(), 0.0);
                let covered = coarse.hot.iter().map(PatchHot::decode).any(|c| {
                    let local = c.frame.to_local(rim - c.origin);
                    local.z.abs() < 1e-4 && c.supports(local.truncate())
                });
                assert!(covered, "{rim} is on no coarse disk");
            }
        }
    }

    #[test]
    fn a_block_whose_patches_lie_apart_merges_each_group_apart_with_its_colour() {
        let mut fine = grid(10, 0.5);
        let far = Vec3::new(1000.0, 0.0, 0.0);
        let (hot, cold) = (fine.hot.to_mut(), fine.cold.to_mut());
        for i in (1..hot.len()).step_by(2) {
            hot[i] = PatchHot::isotropic(hot[i].origin() + far, Vec3::X, -Vec3::Z, [0.0; 6], 0.5);
            cold[i] = PatchCold::from_rgb8([255, 0, 0], 0.5);
        }
        let level = CoarseLevel::of(&fine);
        for (patch, color) in level.patches.hot.iter().zip(level.patches.cold.iter()) {
            assert!(patch.radius() < 20.0, "{patch:?} spans both groups");
            let red = patch.origin().x > 500.0;
            let expected = if red { PatchCold::from_rgb8([255, 0, 0], 0.5) } else { PatchCold::default() };
            assert_eq!(color.color_rgba8, expected.color_rgba8);
            assert!((color.intensity - expected.intensity).abs() < 1e-6, "{color:?}");
            assert!(patch.normal().z.abs() > 0.9999);
        }
    }
}
