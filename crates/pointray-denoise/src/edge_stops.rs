//! How much a neighbour may lend a pixel its value: alike in what was hit (the same object,
//! a similar depth and normal) and in its filtered colour so far.

use glam::Vec3;

/// One pixel's guides, from its render's AOVs.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Guide {
    pub(crate) instance: u32,
    pub(crate) depth: f32,
    pub(crate) normal: Vec3,
}

/// Widths of the edge stops; see `DenoiseSettings`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Sigmas {
    pub(crate) luminance: f32,
    pub(crate) normal_power: i32,
    pub(crate) relative_depth: f32,
}

/// 0 across an object's outline; otherwise falling with the difference in depth (relative
/// to the pixel's own, so that it holds at any scene scale) and in normal.
pub(crate) fn geometry_weight(pixel: &Guide, neighbour: &Guide, sigmas: &Sigmas) -> f32 {
    if pixel.instance != neighbour.instance {
        return 0.0;
    }
    let depth = (pixel.depth - neighbour.depth).abs() / (sigmas.relative_depth * pixel.depth.abs().max(1e-6));
    let normal = pixel.normal.dot(neighbour.normal).max(0.0).powi(sigmas.normal_power);
    (-depth).exp() * normal
}

/// What the colour stop compares: luminance after `x / (1 + x)`, so that a firefly does not
/// stop every neighbour from averaging it away.
pub(crate) fn compressed_luminance(color: Vec3) -> f32 {
    (color / (Vec3::ONE + color)).dot(Vec3::new(0.2126, 0.7152, 0.0722))
}

/// Falls with the difference in compressed luminance, measured in standard deviations of the
/// pixel's own noise (`deviation`), as in SVGF (Schied et al. 2017): noise is averaged away,
/// a real edge in the lighting (a shadow's) is kept.
pub(crate) fn color_weight(pixel: f32, neighbour: f32, deviation: f32, sigma: f32) -> f32 {
    (-(pixel - neighbour).abs() / (sigma * deviation + 1e-4)).exp()
}

#[cfg(test)]
mod tests {
    use super::*;

    const SIGMAS: Sigmas = Sigmas { luminance: 4.0, normal_power: 32, relative_depth: 0.05 };

    fn guide(instance: u32, depth: f32, normal: Vec3) -> Guide {
        Guide { instance, depth, normal }
    }

    #[test]
    fn another_object_lends_nothing_and_a_twin_lends_everything() {
        let here = guide(1, 2.0, Vec3::Z);
        assert_eq!(geometry_weight(&here, &guide(2, 2.0, Vec3::Z), &SIGMAS), 0.0);
        assert_eq!(geometry_weight(&here, &here, &SIGMAS), 1.0);
        assert_eq!(color_weight(0.5, 0.5, 0.1, 4.0), 1.0);
    }

    #[test]
    fn weights_fall_with_depth_normal_and_colour() {
        let here = guide(1, 2.0, Vec3::Z);
        let nearer = geometry_weight(&here, &guide(1, 2.02, Vec3::Z), &SIGMAS);
        let farther = geometry_weight(&here, &guide(1, 2.2, Vec3::Z), &SIGMAS);
        assert!(1.0 > nearer && nearer > farther, "{nearer} {farther}");
        let tilted = geometry_weight(&here, &guide(1, 2.0, Vec3::new(0.0, 0.5, 1.0).normalize()), &SIGMAS);
        assert!(tilted < 0.1, "{tilted}");
        assert!(color_weight(0.5, 0.55, 0.01, 4.0) > color_weight(0.5, 0.7, 0.01, 4.0));
        assert!(
            color_weight(0.5, 0.7, 0.1, 4.0) > color_weight(0.5, 0.7, 0.01, 4.0),
            "noisier pixels average more"
        );
        assert!(compressed_luminance(Vec3::splat(1e6)) < 1.0);
    }
}
