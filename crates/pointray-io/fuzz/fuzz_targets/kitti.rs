//! KITTI .bin reader on arbitrary bytes: any result is fine, a panic is not.
#![no_main]

use std::path::Path;

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let _ = pointray_io::formats::kitti::read_kitti_bin_from(data, Path::new("fuzz.bin"));
});
