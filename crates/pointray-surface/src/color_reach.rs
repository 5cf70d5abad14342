//! How far each point's colour reaches in `interpolate_color`, for one patch set.
//!
//! The blend was tuned with the paper's radii: point `j`'s colour reaches
//! `COLOR_SUPPORT_SCALE d_j`, about 1.3 point spacings. The cell radius and disk scales below 1
//! store smaller radii, and a reach tied to them left gaps that one faint weight filled: a
//! rendered gradient stepped by 0.046 where the paper's radii gave under 0.02. So the set
//! stores one scale that takes its radii back to the paper's on the whole. It is one number
//! for the set, not one per point, so that a point's weight still depends only on the hit and
//! that point, and every patch hit at one place blends to the same colour.

use pointray_kernels::interpolate_color::COLOR_SUPPORT_SCALE;

/// `COLOR_SUPPORT_SCALE` times the median of `paper_i / stored_i`; `COLOR_SUPPORT_SCALE` when
/// there is nothing to compare.
pub fn color_reach_scale(paper: &[f32], stored: &[f32]) -> f32 {
    let mut ratios: Vec<f32> =
        paper.iter().zip(stored).filter(|(_, s)| **s > 0.0).map(|(p, s)| p / s).collect();
    if ratios.is_empty() {
        return COLOR_SUPPORT_SCALE;
    }
    let middle = ratios.len() / 2;
    let (_, median, _) = ratios.select_nth_unstable_by(middle, f32::total_cmp);
    COLOR_SUPPORT_SCALE * *median
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_papers_radii_keep_the_tuned_scale() {
        let radii = [0.2, 0.3, 0.25];
        assert_eq!(color_reach_scale(&radii, &radii), COLOR_SUPPORT_SCALE);
    }

    #[test]
    fn halved_radii_double_the_scale_and_outliers_do_not_move_it() {
        let paper = [2.0, 2.0, 2.0, 2.0, 2.0];
        let stored = [1.0, 1.0, 1.0, 0.01, 2.0];
        assert_eq!(color_reach_scale(&paper, &stored), 2.0 * COLOR_SUPPORT_SCALE);
    }

    #[test]
    fn no_radii_give_the_tuned_scale() {
        assert_eq!(color_reach_scale(&[], &[]), COLOR_SUPPORT_SCALE);
        assert_eq!(color_reach_scale(&[1.0], &[0.0]), COLOR_SUPPORT_SCALE);
    }
}
