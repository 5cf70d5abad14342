//! PCD reader on arbitrary bytes: any result is fine, a panic or a runaway allocation is not.
#![no_main]

use std::path::Path;

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let _ = pointray_io::formats::pcd::read_pcd_from(data, Path::new("fuzz.pcd"));
});
