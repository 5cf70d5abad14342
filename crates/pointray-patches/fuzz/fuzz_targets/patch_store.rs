//! The patch store reader on arbitrary bytes. Random bytes almost never pass the checksum, so
//! unless the first byte is odd the harness re-seals the input with a correct CRC-32, to reach
//! the checks behind it (section table, records, ranges). Any result is fine; a panic, or a
//! store that reads but holds numbers no renderer can build on, is not.
#![no_main]

use std::path::Path;

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let mut bytes = data.to_vec();
    if bytes.len() >= 4 && data[0] % 2 == 0 {
        let body = bytes.len() - 4;
        let checksum = crc32fast::hash(&bytes[..body]);
        bytes[body..].copy_from_slice(&checksum.to_le_bytes());
    }
    if let Ok(patches) = pointray_patches::patch_store::read_from(&bytes, Path::new("fuzz.patches")) {
        assert_eq!(patches.check(), Ok(()), "a store that reads must pass the renderers' checks");
    }
});
