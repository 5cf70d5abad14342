//! Radiance (`.hdr`) and OpenEXR (`.exr`) bytes through `read_linear_image_within`, the reader
//! of `compare`'s images and of environment maps, under a budget of 256 MiB: the first byte
//! picks the format, the rest is the file. Any `Ok` or `Err` is fine; a panic, a sanitizer
//! report, an image whose pixels do not match its size, or an allocation past libFuzzer's
//! `-malloc_limit_mb` (run with 1024: the budget plus the decoder's own working room) is a
//! failure.

#![no_main]

use libfuzzer_sys::fuzz_target;
use pointray_io::{MemoryBudget, read_linear_image_within};

const BUDGET: MemoryBudget = MemoryBudget { bytes: 256 << 20 };

fuzz_target!(|data: &[u8]| {
    let Some((&format, bytes)) = data.split_first() else { return };
    let extension = if format & 1 == 0 { "hdr" } else { "exr" };
    let dir = tempfile::tempdir().expect("a temporary folder");
    let path = dir.path().join(format!("input.{extension}"));
    std::fs::write(&path, bytes).expect("the input is written");
    if let Ok(image) = read_linear_image_within(&path, BUDGET, |_, _| Ok(())) {
        assert_eq!(image.pixels.len(), image.width as usize * image.height as usize);
    }
});
