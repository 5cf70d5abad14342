//! The colour at a hit point, blended from the points around it (no blocky seams
//! between patches). Twin of `shaders/interpolate_color.glsl`.
//!
//! Each point `j` spreads its colour over the ball of radius `COLOR_SUPPORT_SCALE * d_j`
//! around `p_j` with the Wendland weight, where `d_j` is the paper's radius, stored in the cold
//! record as the point's colour reach whatever radius its patch has (a smaller radius, as the
//! cell radius gives, would leave gaps in the blend), and the colour at `x` is the weighted mean over
//! the points whose ball holds `x`. A point's weight depends only on `x` and on that point,
//! never on the patch that was hit, so this is one continuous field over the surface,
//! provided that every patch hit at `x` sums over the same points.
//!
//! Patches overlap, so `x` may lie as far as `d_i` from the hit patch's point `p_i`, where
//! `p_i`'s neighbour list no longer holds all the points that weigh at `x`. So the blend
//! first walks the neighbour graph from `p_i` to the point nearest `x` (the same point
//! whichever patch was hit) and sums over that point and its neighbours. Measured on a
//! jittered height field of 3,600 points against 3,000 vertical rays, hitting every patch
//! that each ray meets: with 8 neighbours and no walk the patches hit at one point disagreed
//! by 0.024 on average (0.086 with one colour per patch); with 12 neighbours and the walk
//! (reach 0.5 to 0.75 d_j), by under 0.0001, within the 8-bit rounding.
//!
//! Cost, measured with `pointray bench` on an NVIDIA H200 (300 frames after 30, the Autzen
//! scan, 110,002 patches, 800x600): against the same build reading one colour per patch, the
//! median trace went from 0.330 to 0.356 ms (+8%) for `scenes/autzen.toml` and from 0.544
//! to 0.589 ms (+8%) with its field of view narrowed to 8 degrees. Reading colours only for
//! the settled scan's weighted points was slower (0.377 and 0.627 ms). The neighbour lists
//! add 48 bytes a patch: the bench reported 18.5 MiB of GPU buffers for Autzen before them and
//! 23.5 MiB after (on an H100).

use glam::Vec3;

use crate::layout::{PatchCold, PatchHot};

/// Neighbours kept per patch for the blend (the nearest, excluding the patch itself).
pub const COLOR_NEIGHBORS: usize = 12;

/// Marks an unused neighbour slot.
pub const NO_NEIGHBOR: u32 = u32::MAX;

/// Point `j`'s colour reaches this multiple of its support radius `d_j` (about 1.3 point
/// spacings for the default `k = 9`). At 0.6 the gaps of a jittered grid were barely
/// reached, and a rendered gradient plane stepped by 0.02 between pixels where only one
/// faint weight was left; at 0.75 it followed the gradient. Larger blurs colour detail.
pub const COLOR_SUPPORT_SCALE: f32 = 0.75;

/// Scans of a point and its neighbours, walking toward the point nearest the hit, before
/// the blend settles for the last one (the walk almost always ends in one or two).
pub const COLOR_WALK_SCANS: u32 = 3;

/// The colour at `position` (in the patches' space) on patch `hit`, as linear RGBA8.
/// `neighbors` holds `COLOR_NEIGHBORS` patch indices per patch, or nothing, when the blend
/// is over the hit patch alone. Where no point reaches `position`, the colour of the point
/// nearest it. Packed, as the GPU's hit payload carries it, so that both renderers round the
/// same way. Indices out of range count as `NO_NEIGHBOR`.
pub fn interpolate_color(
    position: Vec3,
    hit: u32,
    hot: &[PatchHot],
    cold: &[PatchCold],
    neighbors: &[u32],
) -> u32 {
    let mut centre = hit;
    let mut scan = ColorScan::default();
    for _ in 0..COLOR_WALK_SCANS {
        scan = ColorScan::around(position, centre, hot, cold, neighbors);
        if scan.nearest == centre {
            break;
        }
        centre = scan.nearest;
    }
    if scan.total_weight <= 0.0 {
        return cold.get(scan.nearest as usize).map_or(PatchCold::default().color_rgba8, |c| c.color_rgba8);
    }
    color_to_rgba8(scan.weighted_color / scan.total_weight)
}

/// One pass over a point and its neighbours: their weighted colours, and which of them lies
/// nearest the hit.
#[derive(Default)]
struct ColorScan {
    weighted_color: Vec3,
    total_weight: f32,
    nearest: u32,
}

impl ColorScan {
    fn around(position: Vec3, centre: u32, hot: &[PatchHot], cold: &[PatchCold], neighbors: &[u32]) -> Self {
        let row = (centre as usize)
            .checked_mul(COLOR_NEIGHBORS)
            .and_then(|first| neighbors.get(first..first.checked_add(COLOR_NEIGHBORS)?));
        let mut scan = Self { nearest: centre, ..Self::default() };
        let mut nearest_distance = f32::INFINITY;
        for j in std::iter::once(centre).chain(row.into_iter().flatten().copied()) {
            let (Some(patch), Some(record)) = (hot.get(j as usize), cold.get(j as usize)) else {
                continue;
            };
            let distance = position.distance(patch.origin());
            let weight = color_weight(distance, record.color_reach);
            scan.weighted_color += weight * color_from_rgba8(record.color_rgba8);
            scan.total_weight += weight;
            if distance < nearest_distance {
                (scan.nearest, nearest_distance) = (j, distance);
            }
        }
        scan
    }
}

/// The Wendland weight `θ(r) = (1 - r)⁴ (4r + 1)` (that of the MLS fit, METHOD.md §2.6) of
/// `r = distance / reach`: smooth, 1 at `p_j`, 0 from the ball's edge on.
pub fn color_weight(distance: f32, reach: f32) -> f32 {
    if reach <= 0.0 || distance >= reach {
        return 0.0;
    }
    let r = distance / reach;
    let one_minus = 1.0 - r;
    let squared = one_minus * one_minus;
    squared * squared * (4.0 * r + 1.0)
}

/// Linear RGB in [0, 1] from RGBA8 (r in the low byte).
pub fn color_from_rgba8(rgba8: u32) -> Vec3 {
    let [r, g, b, _] = rgba8.to_le_bytes();
    Vec3::new(r as f32, g as f32, b as f32) / 255.0
}

/// Linear RGB to RGBA8 with alpha 255, rounding half up (written out, not `round`, so the
/// GLSL twin rounds the same way).
pub fn color_to_rgba8(color: Vec3) -> u32 {
    let byte = |c: f32| (c.clamp(0.0, 1.0) * 255.0 + 0.5).floor() as u8;
    u32::from_le_bytes([byte(color.x), byte(color.y), byte(color.z), 255])
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Flat patches on the plane z = 0 over a jittered grid of spacing 1, each with the
    /// support radius a 9-neighbour fit gives on a grid (two spacings), coloured by `field`,
    /// and the neighbour table prep would keep.
    struct Plane {
        hot: Vec<PatchHot>,
        cold: Vec<PatchCold>,
        neighbors: Vec<u32>,
    }

    const SIDE: i32 = 13;

    impl Plane {
        fn new(field: impl Fn(Vec3) -> Vec3) -> Self {
            let points: Vec<Vec3> = (0..SIDE * SIDE)
                .map(|i| {
                    let (ix, iy) = (i % SIDE - SIDE / 2, i / SIDE - SIDE / 2);
                    let jitter = Vec3::new(
                        ((ix * 7 + iy * 3).rem_euclid(5)) as f32,
                        ((ix * 2 - iy * 5).rem_euclid(5)) as f32,
                        0.0,
                    );
                    Vec3::new(ix as f32, iy as f32, 0.0) + 0.06 * (jitter - 2.0)
                })
                .collect();
            let hot =
                points.iter().map(|&p| PatchHot::isotropic(p, Vec3::X, Vec3::Z, [0.0; 6], 2.0)).collect();
            let cold = points
                .iter()
                .map(|&p| PatchCold {
                    color_rgba8: color_to_rgba8(field(p)),
                    color_reach: COLOR_SUPPORT_SCALE * 2.0,
                    ..PatchCold::default()
                })
                .collect();
            let neighbors = (0..points.len())
                .flat_map(|i| {
                    let mut others: Vec<usize> = (0..points.len()).filter(|&j| j != i).collect();
                    others.sort_by(|&a, &b| {
                        points[a].distance(points[i]).total_cmp(&points[b].distance(points[i]))
                    });
                    others.into_iter().take(COLOR_NEIGHBORS).map(|j| j as u32)
                })
                .collect();
            Self { hot, cold, neighbors }
        }

        fn index(ix: i32, iy: i32) -> u32 {
            ((iy + SIDE / 2) * SIDE + ix + SIDE / 2) as u32
        }

        fn color(&self, position: Vec3, hit: u32) -> u32 {
            interpolate_color(position, hit, &self.hot, &self.cold, &self.neighbors)
        }
    }

    fn channel_error(a: u32, b: u32) -> f32 {
        (color_from_rgba8(a) - color_from_rgba8(b)).abs().max_element()
    }

    fn gradient(p: Vec3) -> Vec3 {
        Vec3::new(0.5 + 0.05 * p.x, 0.5 - 0.03 * p.y, 0.2)
    }

    #[test]
    fn a_linear_colour_field_is_reproduced_between_the_points() {
        let plane = Plane::new(gradient);
        let hit = Plane::index(0, 0);
        for position in [Vec3::new(0.3, 0.4, 0.0), Vec3::new(-0.5, 0.5, 0.0), Vec3::new(1.6, -1.2, 0.0)] {
            let color = plane.color(position, hit);
            // The weighted mean of a linear field is exact up to the weights' asymmetry over
            // the jittered points and 8-bit rounding; one colour per patch is off by up to 0.06.
            let error = (color_from_rgba8(color) - gradient(position)).abs().max_element();
            assert!(error < 0.01, "at {position}: {error}");
        }
    }

    #[test]
    fn every_patch_that_reaches_a_point_gives_it_the_same_colour() {
        let plane =
            Plane::new(|p| Vec3::new(0.5 + 0.4 * (p.x * 0.9).sin(), 0.5 + 0.4 * (p.y * 1.3).cos(), 0.9));
        let mut worst = 0.0f32;
        let mut worst_per_patch = 0.0f32;
        for step in 0..=40 {
            let position = Vec3::new(-1.5 + 3.0 * step as f32 / 40.0, 0.35, 0.0);
            // Every patch whose disk (radius d_i = 2) holds the point may be the one hit.
            let hits: Vec<u32> = (0..plane.hot.len() as u32)
                .filter(|&i| {
                    plane.hot[i as usize].origin().distance(position) < plane.hot[i as usize].radius()
                })
                .collect();
            assert!(hits.len() > 4, "overlapping patches");
            for &a in &hits {
                for &b in &hits {
                    worst = worst.max(channel_error(plane.color(position, a), plane.color(position, b)));
                    let own = |i: u32| plane.cold[i as usize].color_rgba8;
                    worst_per_patch = worst_per_patch.max(channel_error(own(a), own(b)));
                }
            }
        }
        assert!(worst_per_patch > 0.3, "one colour per patch shows steps: {worst_per_patch}");
        assert!(worst <= 1.0 / 255.0, "patches hit at one point disagree by {worst}");
    }

    #[test]
    fn without_neighbours_a_patch_keeps_its_own_colour() {
        let plane = Plane::new(gradient);
        let hit = Plane::index(2, -1);
        let own = plane.cold[hit as usize].color_rgba8;
        let origin = plane.hot[hit as usize].origin();
        for offset in [Vec3::ZERO, Vec3::new(0.4, 0.3, 0.0), Vec3::new(5.0, 0.0, 0.0)] {
            assert_eq!(interpolate_color(origin + offset, hit, &plane.hot, &plane.cold, &[]), own);
        }
        // Slots marked unused are skipped, and so are indices beyond the patches.
        let unused = vec![NO_NEIGHBOR; plane.neighbors.len()];
        assert_eq!(interpolate_color(origin, hit, &plane.hot, &plane.cold, &unused), own);
        let beyond = vec![u32::MAX - 1; plane.neighbors.len()];
        assert_eq!(interpolate_color(origin + Vec3::X, hit, &plane.hot, &plane.cold, &beyond), own);
    }

    #[test]
    fn where_no_point_reaches_the_nearest_colour_is_used() {
        let plane = Plane::new(gradient);
        let corner = Plane::index(SIDE / 2, SIDE / 2);
        let beyond = plane.hot[corner as usize].origin() + Vec3::new(1.5, 1.5, 0.0);
        // Hit from a patch two points away, the walk still ends at the corner.
        let from = Plane::index(SIDE / 2 - 1, SIDE / 2 - 1);
        assert_eq!(plane.color(beyond, from), plane.cold[corner as usize].color_rgba8);
    }

    #[test]
    fn nearer_points_weigh_more_and_the_ball_edge_weighs_nothing() {
        let weights: Vec<f32> = (0..=10).map(|i| color_weight(i as f32 * 0.1, 1.0)).collect();
        assert_eq!(weights[0], 1.0);
        assert!(weights.windows(2).all(|w| w[1] < w[0]));
        assert_eq!(weights[10], 0.0);
        assert_eq!(color_weight(0.0, 0.0), 0.0);
    }

    #[test]
    fn rgba8_round_trips_and_rounds_half_up() {
        for value in [0xff00_0000u32, 0xff80_4020, 0xffff_ffff, 0xff01_02fe] {
            assert_eq!(color_to_rgba8(color_from_rgba8(value)), value);
        }
        assert_eq!(color_to_rgba8(Vec3::new(0.5 / 255.0, 2.0, -1.0)).to_le_bytes(), [1, 255, 0, 255]);
    }

    #[test]
    fn the_glsl_twin_uses_the_same_constants() {
        let glsl = include_str!("../shaders/interpolate_color.glsl");
        for expected in [
            format!("const uint COLOR_NEIGHBORS = {COLOR_NEIGHBORS}u;"),
            format!("const uint COLOR_WALK_SCANS = {COLOR_WALK_SCANS}u;"),
            format!("const uint NO_NEIGHBOR = 0x{NO_NEIGHBOR:x}u;"),
        ] {
            assert!(glsl.contains(&expected), "shaders/interpolate_color.glsl must declare `{expected}`");
        }
    }
}
