//! The CPU renderer's refinement on the host: passes that continue one another
//! (`RenderSettings::first_sample`) averaged into the image the window shows.

use pointray_scene::{RenderSettings, RenderedImage};

/// `pass` (samples `first_sample..first_sample + samples_per_pixel`) added to `earlier`, the
/// mean of the samples before it; a pass from sample 0, or of another size, starts anew.
pub(crate) fn continue_mean(
    earlier: Option<RenderedImage>,
    pass: RenderedImage,
    settings: &RenderSettings,
) -> RenderedImage {
    let Some(mut mean) = earlier else { return pass };
    if settings.first_sample == 0 || (mean.width, mean.height) != (pass.width, pass.height) {
        return pass;
    }
    let before = settings.first_sample as f32;
    let total = before + settings.samples_per_pixel as f32;
    for (sum, new) in mean.color.iter_mut().zip(&pass.color) {
        *sum = (*sum * before + *new * settings.samples_per_pixel as f32) / total;
    }
    mean
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    fn flat(width: u32, height: u32, value: f32) -> RenderedImage {
        let count = (width * height) as usize;
        RenderedImage {
            width,
            height,
            color: vec![Vec3::splat(value); count],
            depth: vec![1.0; count],
            normal: vec![Vec3::Z; count],
            instance_id: vec![0; count],
            primitive_id: vec![0; count],
            albedo: None,
        }
    }

    #[test]
    fn passes_are_averaged_by_their_sample_counts_and_sample_zero_starts_anew() {
        let settings = |first_sample, samples_per_pixel| RenderSettings {
            first_sample,
            samples_per_pixel,
            ..RenderSettings::default()
        };
        let first = continue_mean(None, flat(2, 2, 1.0), &settings(0, 1));
        let second = continue_mean(Some(first), flat(2, 2, 4.0), &settings(1, 3));
        assert_eq!(second.color, vec![Vec3::splat(3.25); 4]);
        let restarted = continue_mean(Some(second.clone()), flat(2, 2, 0.5), &settings(0, 1));
        assert_eq!(restarted.color, vec![Vec3::splat(0.5); 4]);
        let resized = continue_mean(Some(second), flat(3, 1, 2.0), &settings(4, 4));
        assert_eq!(resized.color, vec![Vec3::splat(2.0); 3]);
    }
}
