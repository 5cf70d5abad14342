//! What only shading reads per patch (METHOD.md §2.7): the cold record (colour and
//! intensity) and the neighbours whose colours a hit blends.

use pointray_kernels::{COLOR_NEIGHBORS, NO_NEIGHBOR, PatchCold};

use crate::neighbors::Neighbors;

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

/// Each patch's `COLOR_NEIGHBORS` nearest neighbours, padded with `NO_NEIGHBOR` where the
/// table is narrower; empty for points with no colour (nor intensity to colour them by),
/// where blending would only repeat white and the list would add half to the patch set's
/// memory (48 bytes a patch beside 96). A table exactly `COLOR_NEIGHBORS` wide becomes the
/// list as it is, without a copy.
pub fn color_neighbor_table(neighbors: Neighbors, has_colors: bool) -> Vec<u32> {
    if !has_colors {
        return Vec::new();
    }
    if neighbors.k == COLOR_NEIGHBORS {
        return neighbors.indices;
    }
    (0..neighbors.point_count())
        .flat_map(|i| {
            let row = neighbors.of(i);
            (0..COLOR_NEIGHBORS).map(move |slot| row.get(slot).copied().unwrap_or(NO_NEIGHBOR))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn colour_neighbours_are_the_nearest_padded_and_only_with_colours() {
        let wide = Neighbors { k: 16, indices: (0..32).collect(), distances: vec![0.0; 32] };
        let table = color_neighbor_table(wide.clone(), true);
        assert_eq!(table.len(), 2 * COLOR_NEIGHBORS);
        assert_eq!(&table[COLOR_NEIGHBORS..], &(16..16 + COLOR_NEIGHBORS as u32).collect::<Vec<_>>()[..]);
        let narrow = Neighbors { k: 3, indices: vec![4, 5, 6], distances: vec![0.0; 3] };
        let padded = color_neighbor_table(narrow, true);
        assert_eq!(&padded[..4], &[4, 5, 6, NO_NEIGHBOR]);
        assert!(padded[3..].iter().all(|&j| j == NO_NEIGHBOR));
        assert!(color_neighbor_table(wide.clone(), false).is_empty());
        let mut exact = wide;
        exact.narrow(COLOR_NEIGHBORS);
        assert_eq!(color_neighbor_table(exact, true), table, "a table of the list's width is the list");
    }

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
