//! Scan lines from the order of a spinning sensor's sweep.
//!
//! Files such as KITTI's `.bin` keep the order in which the sensor delivered its returns: one
//! beam after another, each beam one turn of the head. Along a beam the azimuth advances by
//! one column step at a time (more where returns were dropped); a new beam starts where the
//! azimuth steps back, or where one more step would close a full turn. Elevations cannot
//! separate those beams: lasers mounted off the sensor's centre see a beam's elevation drift by
//! a degree and more with range, farther than the beams lie apart.

use std::f64::consts::TAU;

use glam::DVec3;

use crate::median::median;

/// Fewer returns than this are not a sweep whose order can be trusted.
const MIN_RETURNS: usize = 1_000;

/// Column steps of spinning sensors lie between these (degrees): 0.08° for a 4500-column head,
/// 0.7° for a 512-column one. Steps outside them are not a sweep's order.
const PLAUSIBLE_STEP_DEGREES: std::ops::RangeInclusive<f64> = 0.01..=2.0;

/// A sweep's order turns one way: at least this share of steps must advance the azimuth. A
/// shuffled or spatially sorted cloud advances about half of them.
const MIN_FORWARD_SHARE: f64 = 0.95;

/// Beams a spinning sensor may have.
const PLAUSIBLE_LINES: std::ops::RangeInclusive<usize> = 2..=1024;

/// The median line must turn at least this far (radians); shorter runs are not beams.
const MIN_MEDIAN_TURN: f64 = std::f64::consts::PI;

/// Per return, its line, numbered in the order the sweep delivers them; `None` when the
/// order is not a sweep's (too few returns, no steady rotation, an implausible line count).
pub fn lines_from_sweep_order(positions: &[DVec3]) -> Option<Vec<u16>> {
    if positions.len() < MIN_RETURNS {
        return None;
    }
    let steps = azimuth_steps(positions);
    let column_step = steady_column_step(&steps)?;
    let (lines, turns) = split_into_turns(&steps, column_step);
    let line_count = usize::from(*lines.last()?) + 1;
    (PLAUSIBLE_LINES.contains(&line_count) && median(turns)? >= MIN_MEDIAN_TURN).then_some(lines)
}

/// The azimuth change from each return to the next, wrapped into (-π, π].
fn azimuth_steps(positions: &[DVec3]) -> Vec<f64> {
    positions
        .windows(2)
        .map(|pair| {
            let step = pair[1].y.atan2(pair[1].x) - pair[0].y.atan2(pair[0].x);
            step - TAU * (step / TAU).round()
        })
        .collect()
}

/// The signed column step of a steady rotation, or `None` when the order does not turn
/// steadily one way.
fn steady_column_step(steps: &[f64]) -> Option<f64> {
    let column_step = median(steps.to_vec())?;
    let degrees = column_step.abs().to_degrees();
    if !PLAUSIBLE_STEP_DEGREES.contains(&degrees) {
        return None;
    }
    let forward = steps.iter().filter(|&&step| step * column_step.signum() > 0.0).count();
    (forward as f64 >= MIN_FORWARD_SHARE * steps.len() as f64).then_some(column_step)
}

/// Each return's line, and how far each line turned (radians). A line ends where the
/// azimuth steps back by more than half a column, or where the next step would close a turn.
fn split_into_turns(steps: &[f64], column_step: f64) -> (Vec<u16>, Vec<f64>) {
    let half_column = column_step.abs() / 2.0;
    let mut lines = Vec::with_capacity(steps.len() + 1);
    let mut turns = Vec::new();
    let (mut line, mut turned) = (0u16, 0.0);
    lines.push(line);
    for &step in steps {
        let step = step * column_step.signum();
        if step < -half_column || turned + step >= TAU - half_column {
            turns.push(turned);
            line = line.saturating_add(1);
            turned = 0.0;
        } else {
            turned += step;
        }
        lines.push(line);
    }
    turns.push(turned);
    (lines, turns)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `beams` beams of `columns` returns each, in sweep order, each beam starting `skew`
    /// columns later than the one before, on a cylinder whose radius varies with azimuth.
    fn sweep(beams: usize, columns: usize, skew: usize) -> Vec<DVec3> {
        (0..beams)
            .flat_map(|beam| {
                (0..columns).map(move |column| {
                    let azimuth = ((column + beam * skew) % columns) as f64 / columns as f64 * TAU;
                    let elevation = (beam as f64 * 0.4 - 10.0).to_radians();
                    let range = 10.0 + 3.0 * (azimuth * 3.0).sin();
                    DVec3::new(azimuth.cos(), azimuth.sin(), elevation.tan()) * range
                })
            })
            .collect()
    }

    #[test]
    fn each_beam_is_one_turn_of_the_order() {
        let positions = sweep(64, 1000, 0);
        let lines = lines_from_sweep_order(&positions).expect("a sweep's order");
        assert_eq!(usize::from(*lines.last().unwrap()) + 1, 64);
        assert!(lines.iter().enumerate().all(|(i, &line)| usize::from(line) == i / 1000));
    }

    #[test]
    fn dropped_returns_and_a_start_that_moves_keep_the_lines() {
        let positions: Vec<DVec3> =
            sweep(32, 1024, 7).into_iter().enumerate().filter(|(i, _)| i % 5 != 3).map(|(_, p)| p).collect();
        let lines = lines_from_sweep_order(&positions).expect("a sweep's order");
        assert_eq!(usize::from(*lines.last().unwrap()) + 1, 32);
    }

    #[test]
    fn a_shuffled_cloud_has_no_sweep_order() {
        let mut positions = sweep(16, 500, 0);
        let len = positions.len();
        for i in 0..len {
            positions.swap(i, (i * 7919) % len);
        }
        assert!(lines_from_sweep_order(&positions).is_none());
    }
}
