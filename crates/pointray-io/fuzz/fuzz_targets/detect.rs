//! Content detection on arbitrary heads: any answer is fine, a panic is not.
#![no_main]

use std::path::Path;

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let _ = pointray_io::formats::detect::detect_format_from(data, Path::new("fuzz.dat"));
});
