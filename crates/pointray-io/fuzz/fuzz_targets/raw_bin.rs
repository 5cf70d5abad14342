//! Raw .bin sweep reader on arbitrary bytes, as KITTI and as nuScenes: any result is fine,
//! a panic is not.
#![no_main]

use std::path::Path;

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    for name in ["fuzz.bin", "fuzz.pcd.bin"] {
        let _ = pointray_io::formats::raw_bin::read_raw_bin_from(data, Path::new(name), None);
    }
});
