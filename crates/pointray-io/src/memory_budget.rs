//! How much memory a request may take: a request is estimated before anything is allocated
//! and refused, with what would fit, when it exceeds the memory available, instead of
//! allocating until the process aborts.

use std::fmt;
use std::str::FromStr;

/// The memory a request may use, in bytes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct MemoryBudget {
    pub bytes: u64,
}

/// Assumed where the system does not say how much memory is available.
const FALLBACK_BYTES: u64 = 8 << 30;

/// A request that does not fit: what it needs, what there is, and how many of its items fit.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("{what} need about {} of memory, but {} is available: at most about {fitting} fit", Bytes(*needed), Bytes(*available))]
pub struct MemoryShortfall {
    /// The request, e.g. "10000000000 points at 48 bytes each".
    pub what: String,
    pub needed: u64,
    pub available: u64,
    /// How many of the request's items the budget holds.
    pub fitting: u64,
}

impl MemoryBudget {
    /// The memory the system reports available now (Linux: `MemAvailable`), else 8 GiB.
    pub fn of_this_machine() -> Self {
        Self { bytes: available_memory().unwrap_or(FALLBACK_BYTES) }
    }

    /// Half the memory the machine has (Linux: `MemTotal`), else half of 8 GiB: a default
    /// that leaves room for the rest of the machine's work.
    pub fn half_of_this_machine() -> Self {
        Self { bytes: meminfo("MemTotal:").unwrap_or(FALLBACK_BYTES) / 2 }
    }

    /// Whether `count` items of `bytes_each` fit; `items` names them in the message.
    pub fn check(&self, count: u64, bytes_each: u64, items: &str) -> Result<(), MemoryShortfall> {
        let needed = count.saturating_mul(bytes_each);
        if needed <= self.bytes {
            return Ok(());
        }
        Err(MemoryShortfall {
            what: format!("{count} {items} at {bytes_each} bytes each"),
            needed,
            available: self.bytes,
            fitting: self.bytes / bytes_each.max(1),
        })
    }
}

/// A size as people write it: bytes, or a number with a binary unit (`512M`, `1.5G`,
/// `64MiB`).
impl FromStr for MemoryBudget {
    type Err = String;

    /// Parses `SIZE[K|M|G|T][iB|B]`; units are powers of 1024.
    fn from_str(text: &str) -> Result<Self, Self::Err> {
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
        Ok(Self { bytes: bytes as u64 })
    }
}

/// The memory the system reports available now (Linux: `MemAvailable`), in bytes; `None`
/// where it does not say.
pub fn available_memory() -> Option<u64> {
    meminfo("MemAvailable:")
}

/// A `/proc/meminfo` field, in bytes.
fn meminfo(field: &str) -> Option<u64> {
    let text = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = text.lines().find(|line| line.starts_with(field))?;
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    kib.checked_mul(1024)
}

/// A byte count in the largest binary unit that keeps it at 1 or more.
struct Bytes(u64);

impl fmt::Display for Bytes {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let units = ["bytes", "KiB", "MiB", "GiB", "TiB", "PiB", "EiB"];
        let mut value = self.0 as f64;
        let mut unit = 0;
        while value >= 1024.0 && unit + 1 < units.len() {
            value /= 1024.0;
            unit += 1;
        }
        if unit == 0 { write!(f, "{} bytes", self.0) } else { write!(f, "{value:.1} {}", units[unit]) }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_request_within_the_budget_passes_and_one_beyond_says_what_fits() {
        let budget = MemoryBudget { bytes: 1 << 30 };
        budget.check(1000, 48, "points").unwrap();
        let shortfall = budget.check(10_000_000_000, 48, "points").unwrap_err();
        assert_eq!(shortfall.fitting, (1 << 30) / 48);
        let message = shortfall.to_string();
        assert!(message.contains("447.0 GiB") && message.contains("1.0 GiB is available"), "{message}");
        assert!(message.contains("at most about 22369621 fit"), "{message}");
        assert!(budget.check(u64::MAX, u64::MAX, "points").is_err(), "no overflow");
    }

    #[test]
    fn this_machine_reports_some_memory() {
        assert!(MemoryBudget::of_this_machine().bytes > 0);
        assert!(MemoryBudget::half_of_this_machine().bytes > 0);
    }

    #[test]
    fn sizes_take_binary_units() {
        assert_eq!(MemoryBudget::from_str("1G").unwrap().bytes, 1 << 30);
        assert_eq!(MemoryBudget::from_str("64MiB").unwrap().bytes, 64 << 20);
        assert_eq!(MemoryBudget::from_str("1.5g").unwrap().bytes, 3 << 29);
        assert_eq!(MemoryBudget::from_str("4096").unwrap().bytes, 4096);
        for bad in ["", "G", "-1G", "lots", "1e400"] {
            assert!(MemoryBudget::from_str(bad).is_err(), "{bad}");
        }
    }
}
