//! LAS/LAZ reader on arbitrary bytes: any result is fine, a panic or a runaway allocation is not.
#![no_main]

use std::io::Cursor;
use std::path::Path;

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let _ = pointray_io::formats::las::read_las_from(Cursor::new(data.to_vec()), Path::new("fuzz.las"));
});
