//! What an image of a streamed scene lacks, in the words both programs' edges print.

use pointray_vulkan::TileResidency;

/// What the image lacks where tiles the camera sees did not fit the GPU memory budget, or
/// where tiles out of view did not (they cast no shadows and show in no reflections); `None`
/// when every tile is on the GPU.
pub fn missing_tiles(residency: &TileResidency) -> Option<String> {
    let unseen = residency.missing_in_view();
    if unseen > 0 {
        return Some(format!(
            "{unseen} tiles in or beside the view do not fit the GPU memory budget: the image may lack \
             them (raise the budget, or render on the CPU backend)"
        ));
    }
    let left_out = residency.tiles - residency.resident;
    (left_out > 0).then(|| {
        format!(
            "the {left_out} tiles out of view that do not fit the GPU memory budget cast no \
             shadows and show in no reflections"
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tiles_missing_in_view_warn_and_tiles_missing_out_of_view_note() {
        let all =
            TileResidency { tiles: 8, resident: 8, in_view: 3, in_view_resident: 3, ..Default::default() };
        assert_eq!(missing_tiles(&all), None);
        let unseen = TileResidency { resident: 5, in_view_resident: 2, ..all };
        assert!(missing_tiles(&unseen).is_some_and(|text| text.starts_with("1 tiles in or beside the view")));
        let out_of_view = TileResidency { resident: 5, ..all };
        assert!(missing_tiles(&out_of_view).is_some_and(|text| text.starts_with("the 3 tiles out of view")));
    }
}
