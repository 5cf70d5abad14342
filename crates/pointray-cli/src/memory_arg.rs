//! A memory size on the command line: bytes, or a number with a binary unit (`512M`,
//! `1.5G`, `64MiB`).

use pointray_io::MemoryBudget;

/// Parses `SIZE[K|M|G|T][iB|B]`; units are powers of 1024.
pub fn parse_memory(text: &str) -> Result<MemoryBudget, String> {
    let trimmed = text.trim();
    let lower = trimmed.to_ascii_lowercase();
    let without_b = lower.strip_suffix("ib").or_else(|| lower.strip_suffix('b')).unwrap_or(&lower);
    let (number, shift) = match without_b.chars().last() {
        Some('k') => (&without_b[..without_b.len() - 1], 10),
        Some('m') => (&without_b[..without_b.len() - 1], 20),
        Some('g') => (&without_b[..without_b.len() - 1], 30),
        Some('t') => (&without_b[..without_b.len() - 1], 40),
        _ => (without_b, 0),
    };
    let value: f64 = number
        .trim()
        .parse()
        .map_err(|_| format!("'{trimmed}' is not a memory size (e.g. 512M, 4G or a byte count)"))?;
    let bytes = value * (1u64 << shift) as f64;
    if !bytes.is_finite() || bytes < 1.0 || bytes > u64::MAX as f64 {
        return Err(format!("'{trimmed}' is not a usable memory size"));
    }
    Ok(MemoryBudget { bytes: bytes as u64 })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_take_binary_units() {
        assert_eq!(parse_memory("1G").unwrap().bytes, 1 << 30);
        assert_eq!(parse_memory("64MiB").unwrap().bytes, 64 << 20);
        assert_eq!(parse_memory("1.5g").unwrap().bytes, 3 << 29);
        assert_eq!(parse_memory("4096").unwrap().bytes, 4096);
        for bad in ["", "G", "-1G", "lots", "1e400"] {
            assert!(parse_memory(bad).is_err(), "{bad}");
        }
    }
}
