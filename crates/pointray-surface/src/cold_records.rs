//! The per-patch shading record (SPEC.md §2.7): colour and intensity.

use pointray_kernels::PatchCold;

/// `PatchCold` stores linear RGB, point files carry sRGB: decode each channel once.
fn srgb_to_linear_table() -> [u8; 256] {
    std::array::from_fn(|i| {
        let c = i as f64 / 255.0;
        let linear = if c <= 0.04045 { c / 12.92 } else { ((c + 0.055) / 1.055).powf(2.4) };
        (linear * 255.0).round() as u8
    })
}

/// One cold record per patch, from the patches' colours and intensities, where present.
pub fn cold_records(colors: Option<&[[u8; 3]]>, intensities: Option<&[f32]>, count: usize) -> Vec<PatchCold> {
    let table = srgb_to_linear_table();
    (0..count)
        .map(|i| {
            let intensity = intensities.map_or(0.0, |values| values[i].clamp(0.0, 1.0));
            match colors {
                Some(colors) => PatchCold::from_rgb8(colors[i].map(|c| table[c as usize]), intensity),
                None => PatchCold { intensity, ..PatchCold::default() },
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn colours_become_linear_and_absent_ones_white() {
        let colors = [[255, 0, 188]];
        let cold = cold_records(Some(&colors), Some(&[0.25]), 1);
        let [r, g, b, a] = cold[0].color_rgba8.to_le_bytes();
        assert_eq!((r, g, b, a), (255, 0, 128, 255), "sRGB 188 is linear 0.5");
        assert_eq!(cold[0].intensity, 0.25);
        assert_eq!(cold_records(None, None, 2), vec![PatchCold::default(); 2]);
    }
}
