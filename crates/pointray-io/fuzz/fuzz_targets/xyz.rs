//! Text reader on arbitrary bytes. The first line doubles as a column spec, so the spec
//! parser and the spec-driven layout are fuzzed too.
#![no_main]

use std::path::Path;

use libfuzzer_sys::fuzz_target;
use pointray_io::formats::xyz::{ColumnSpec, read_xyz_from};

fuzz_target!(|data: &[u8]| {
    let origin = Path::new("fuzz.xyz");
    let _ = read_xyz_from(data, origin, None);
    let first_line = data.split(|&b| b == b'\n').next().unwrap_or_default();
    if let Ok(Ok(spec)) = std::str::from_utf8(first_line).map(ColumnSpec::parse) {
        let _ = read_xyz_from(data, origin, Some(&spec));
    }
});
