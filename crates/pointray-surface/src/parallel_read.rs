//! Reading large binary files (patch stores) on every core. A 100M-point store is 7 GB:
//! reading it whole into one buffer and then copying each section out held it twice and
//! ran on one core. Here each section is read straight into its typed records, in pieces
//! that every core reads and checksums at once.

use std::fs::File;
use std::os::unix::fs::FileExt;

use bytemuck::Pod;
use crc32fast::Hasher;
use rayon::prelude::*;

/// Bytes each worker reads or checksums at a time: large enough that the split costs
/// nothing, small enough to spread a store's sections over every core.
const PIECE_BYTES: usize = 8 << 20;

/// The CRC-32 (IEEE) of `bytes`, as `crc32fast::hash` gives it, computed in parallel pieces
/// and combined.
pub fn checksum(bytes: &[u8]) -> u32 {
    bytes.par_chunks(PIECE_BYTES).map(piece_hasher).reduce(Hasher::new, joined).finalize()
}

/// The `length` bytes of `file` at `offset` as records of `T` (a partial record at the end
/// is not read), and a hasher that has seen those bytes in order.
pub fn read_records<T: Pod + Send + Sync>(
    file: &File,
    offset: u64,
    length: u64,
) -> std::io::Result<(Vec<T>, Hasher)> {
    let count = usize::try_from(length).map_err(std::io::Error::other)? / size_of::<T>();
    let mut records: Vec<T> = bytemuck::zeroed_vec(count);
    let target: &mut [u8] = bytemuck::cast_slice_mut(&mut records);
    let hasher = target
        .par_chunks_mut(PIECE_BYTES)
        .enumerate()
        .map(|(index, piece)| {
            file.read_exact_at(piece, offset + (index * PIECE_BYTES) as u64)?;
            Ok::<_, std::io::Error>(piece_hasher(piece))
        })
        .try_reduce(Hasher::new, |before, after| Ok(joined(before, after)))?;
    Ok((records, hasher))
}

fn piece_hasher(piece: &[u8]) -> Hasher {
    let mut hasher = Hasher::new();
    hasher.update(piece);
    hasher
}

/// The hasher of `before`'s bytes followed by `after`'s.
fn joined(mut before: Hasher, after: Hasher) -> Hasher {
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
    fn records_read_in_pieces_are_the_bytes_in_order_with_their_checksum() {
        let bytes = test_bytes();
        let folder = tempfile::tempdir().unwrap();
        let path = folder.path().join("bytes");
        std::fs::write(&path, &bytes).unwrap();
        let file = File::open(&path).unwrap();
        for (offset, length) in [(0, bytes.len()), (3, 2 * PIECE_BYTES + 9), (100, 0), (5, 6)] {
            let (records, hasher) = read_records::<u32>(&file, offset as u64, length as u64).unwrap();
            let read = &bytes[offset..offset + length / 4 * 4];
            assert_eq!(bytemuck::cast_slice::<u32, u8>(&records), read, "{length} bytes at {offset}");
            assert_eq!(hasher.finalize(), crc32fast::hash(read), "{length} bytes at {offset}");
        }
        let beyond = read_records::<u32>(&file, bytes.len() as u64 - 8, 16);
        assert!(beyond.is_err(), "a read past the end must fail");
    }
}
