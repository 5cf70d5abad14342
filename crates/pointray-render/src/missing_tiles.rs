//! What an image of a streamed scene lacks or draws coarse, in the words both programs'
//! edges print.

use pointray_vulkan::TileResidency;

/// What the image lacks where the GPU memory budget holds not even the coarse level of
/// tiles the camera sees, or of tiles out of view (they cast no shadows and show in no
/// reflections); else which tiles it draws coarse; `None` when every tile is on the GPU in
/// full.
pub fn missing_tiles(residency: &TileResidency) -> Option<String> {
    let unseen = residency.missing_in_view();
    if unseen > 0 {
        return Some(format!(
            "{unseen} tiles in or beside the view do not fit the GPU memory budget even coarse: the image \
             may lack them (raise the budget, or render on the CPU backend)"
        ));
    }
    let left_out = residency.missing();
    if left_out > 0 {
        return Some(format!(
            "the {left_out} tiles out of view that do not fit the GPU memory budget even coarse cast no \
             shadows and show in no reflections"
        ));
    }
    (residency.coarse > 0).then(|| {
        format!(
            "{} tiles ({} of the {} in view) are drawn from their coarse level, as the GPU memory budget \
             does not hold them in full",
            residency.coarse, residency.in_view_coarse, residency.in_view
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tiles_missing_in_view_warn_and_tiles_missing_out_of_view_or_drawn_coarse_note() {
        let all =
            TileResidency { tiles: 8, resident: 8, in_view: 3, in_view_resident: 3, ..Default::default() };
        assert_eq!(missing_tiles(&all), None);
        let unseen = TileResidency { resident: 5, in_view_resident: 2, ..all };
        assert!(missing_tiles(&unseen).is_some_and(|text| text.starts_with("1 tiles in or beside the view")));
        let out_of_view = TileResidency { resident: 5, ..all };
        assert!(missing_tiles(&out_of_view).is_some_and(|text| text.starts_with("the 3 tiles out of view")));
        let coarse = TileResidency { resident: 5, coarse: 3, in_view_resident: 2, in_view_coarse: 1, ..all };
        assert_eq!(coarse.missing_in_view(), 0);
        let note = missing_tiles(&coarse).expect("a note on the coarse tiles");
        assert!(note.starts_with("3 tiles (1 of the 3 in view) are drawn from their coarse level"), "{note}");
    }
}
