//! E57 reader on arbitrary bytes: any result is fine, a panic or a runaway allocation is not.
#![no_main]

use std::io::Cursor;
use std::path::Path;

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let _ = pointray_io::formats::e57::read_e57_from(Cursor::new(data), Path::new("fuzz.e57"));
});
