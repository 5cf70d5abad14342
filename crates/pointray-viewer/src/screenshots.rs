//! Saving frames: the `P` key's numbered screenshots, the scripted screenshot and the
//! turntable sequence. `write_image` writes atomically (temporary file, then rename).

use std::path::{Path, PathBuf};

use pointray_scene::{AovSelection, RenderedImage, write_image};

use crate::error::ViewerError;

pub(crate) fn save(frame: &RenderedImage, path: &Path) -> Result<(), ViewerError> {
    write_image(frame, path, &AovSelection::default())
        .map(|_| ())
        .map_err(|source| ViewerError::Screenshot { path: path.to_path_buf(), source: Box::new(source) })
}

/// `DIR/frame-00012.png`: zero-padded so the files sort in frame order.
pub fn sequence_path(dir: &Path, index: u32) -> PathBuf {
    dir.join(format!("frame-{index:05}.png"))
}

/// The first `pointray-view-NNN.png` in `dir` that does not exist yet, so no file is replaced.
pub(crate) fn next_screenshot_path(dir: &Path) -> PathBuf {
    (1u32..)
        .map(|n| dir.join(format!("pointray-view-{n:03}.png")))
        .find(|path| !path.exists())
        .expect("some number is free")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn screenshot_names_skip_existing_files() {
        let dir = tempfile::tempdir().unwrap();
        let first = next_screenshot_path(dir.path());
        std::fs::write(&first, b"taken").unwrap();
        let second = next_screenshot_path(dir.path());
        assert_ne!(first, second);
        assert!(sequence_path(dir.path(), 7).ends_with("frame-00007.png"));
    }
}
