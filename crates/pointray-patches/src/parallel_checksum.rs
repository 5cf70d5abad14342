//! Checksumming large binary files (patch stores) on every core: a 100M-point store is
//! 7 GB, which one core hashes in seconds.

use crc32fast::Hasher;
use rayon::prelude::*;

/// Bytes each worker checksums at a time: large enough that the split costs
/// nothing, small enough to spread a store's sections over every core.
const PIECE_BYTES: usize = 8 << 20;

/// The CRC-32 (IEEE) of `bytes`, as `crc32fast::hash` gives it, computed in parallel pieces
/// and combined.
pub fn checksum(bytes: &[u8]) -> u32 {
    bytes.par_chunks(PIECE_BYTES).map(piece_hasher).reduce(Hasher::new, joined).finalize()
}

/// The hasher of `count` zero bytes (the unwritten room of a file), in as many steps as
/// `count` has bits.
pub(crate) fn zeros_hasher(count: u64) -> Hasher {
    let (mut zeros, mut power, mut remaining) = (Hasher::new(), piece_hasher(&[0]), count);
    while remaining > 0 {
        if remaining & 1 == 1 {
            zeros = joined(zeros, power.clone());
        }
        power = joined(power.clone(), power);
        remaining >>= 1;
    }
    zeros
}

/// The hasher of one piece's bytes, to be joined in order with its neighbours'.
pub(crate) fn piece_hasher(piece: &[u8]) -> Hasher {
    let mut hasher = Hasher::new();
    hasher.update(piece);
    hasher
}

/// The hasher of `before`'s bytes followed by `after`'s.
pub(crate) fn joined(mut before: Hasher, after: Hasher) -> Hasher {
    before.combine(&after);
    before
}

#[cfg(test)]
mod tests {
    use super::*;

    fn test_bytes() -> Vec<u8> {
        (0..3 * PIECE_BYTES + 12_345).map(|i| (i * 7 + i / 251) as u8).collect()
    }

    #[test]
    fn the_parallel_checksum_is_the_serial_one() {
        let bytes = test_bytes();
        for length in [0, 1, PIECE_BYTES, PIECE_BYTES + 1, bytes.len()] {
            assert_eq!(checksum(&bytes[..length]), crc32fast::hash(&bytes[..length]), "{length} bytes");
        }
    }

    #[test]
    fn zeros_hash_as_written_zeros() {
        for count in [0, 1, 2, 3, 16, 1000, PIECE_BYTES + 7] {
            let mut bytes = test_bytes()[..100].to_vec();
            let mut hasher = piece_hasher(&bytes);
            hasher.combine(&zeros_hasher(count as u64));
            bytes.resize(100 + count, 0);
            assert_eq!(hasher.finalize(), crc32fast::hash(&bytes), "{count} zeros");
        }
    }
}
