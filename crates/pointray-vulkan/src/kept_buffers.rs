//! GPU buffers kept between traces and made anew only when they no longer serve.

use crate::error::VulkanError;

/// `slot`'s buffers when `serve` says they do, else new ones from `make`. The old ones go
/// first, so that a resize never holds both at once.
pub(crate) fn kept_or_made<T>(
    slot: &mut Option<T>,
    serve: impl FnOnce(&T) -> bool,
    make: impl FnOnce() -> Result<T, VulkanError>,
) -> Result<&mut T, VulkanError> {
    if !slot.as_ref().is_some_and(serve) {
        *slot = None;
        *slot = Some(make()?);
    }
    Ok(slot.as_mut().expect("made just above"))
}
