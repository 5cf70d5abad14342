//! One section of per-patch records, held in memory (prep's output, a store read from bytes)
//! or mapped from a patch store file. A mapped store takes no memory of the process's own:
//! its pages are the page cache's, read as the renderers touch them and dropped by the system
//! when memory runs short, so a store larger than the machine's free memory still loads and
//! uploads.

use std::fmt;
use std::ops::{Deref, DerefMut, Range};
use std::sync::Arc;

use bytemuck::Pod;
use memmap2::Mmap;

pub struct PatchRecords<T> {
    storage: Storage<T>,
}

enum Storage<T> {
    Owned(Vec<T>),
    /// The bytes of `range` within `map`, whose start and length fit `T` (checked by
    /// `PatchRecords::mapped`).
    Mapped {
        map: Arc<Mmap>,
        range: Range<usize>,
    },
}

impl<T: Pod> PatchRecords<T> {
    /// The records in `map[range]`, or `None` where the range lies outside the map or does
    /// not hold whole, aligned records.
    pub(crate) fn mapped(map: Arc<Mmap>, range: Range<usize>) -> Option<Self> {
        bytemuck::try_cast_slice::<u8, T>(map.get(range.clone())?).ok()?;
        Some(Self { storage: Storage::Mapped { map, range } })
    }

    /// Whether the records are mapped from a store file rather than held in memory.
    pub fn is_mapped(&self) -> bool {
        matches!(self.storage, Storage::Mapped { .. })
    }

    /// The records as a vector of their own: a mapped section is copied into memory first,
    /// once, as `Cow::to_mut` does.
    pub fn to_mut(&mut self) -> &mut Vec<T> {
        if let Storage::Mapped { .. } = self.storage {
            self.storage = Storage::Owned(self.to_vec());
        }
        match &mut self.storage {
            Storage::Owned(records) => records,
            Storage::Mapped { .. } => unreachable!("a mapped section was copied just above"),
        }
    }
}

impl<T: Pod> Deref for PatchRecords<T> {
    type Target = [T];

    fn deref(&self) -> &[T] {
        match &self.storage {
            Storage::Owned(records) => records,
            Storage::Mapped { map, range } => bytemuck::cast_slice(&map[range.clone()]),
        }
    }
}

impl<T: Pod> DerefMut for PatchRecords<T> {
    fn deref_mut(&mut self) -> &mut [T] {
        self.to_mut()
    }
}

impl<T> From<Vec<T>> for PatchRecords<T> {
    fn from(records: Vec<T>) -> Self {
        Self { storage: Storage::Owned(records) }
    }
}

impl<T> Default for PatchRecords<T> {
    fn default() -> Self {
        Vec::new().into()
    }
}

impl<T: Clone> Clone for PatchRecords<T> {
    fn clone(&self) -> Self {
        let storage = match &self.storage {
            Storage::Owned(records) => Storage::Owned(records.clone()),
            Storage::Mapped { map, range } => Storage::Mapped { map: map.clone(), range: range.clone() },
        };
        Self { storage }
    }
}

impl<T: Pod + PartialEq> PartialEq for PatchRecords<T> {
    fn eq(&self, other: &Self) -> bool {
        **self == **other
    }
}

impl<T: Pod + fmt::Debug> fmt::Debug for PatchRecords<T> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_list().entries(self.iter()).finish()
    }
}

impl<'a, T: Pod> IntoIterator for &'a PatchRecords<T> {
    type Item = &'a T;
    type IntoIter = std::slice::Iter<'a, T>;

    fn into_iter(self) -> Self::IntoIter {
        self.iter()
    }
}

impl<T: Pod> FromIterator<T> for PatchRecords<T> {
    fn from_iter<I: IntoIterator<Item = T>>(iter: I) -> Self {
        iter.into_iter().collect::<Vec<T>>().into()
    }
}

#[cfg(test)]
mod tests {
    use std::io::Write;

    use super::*;

    fn map_of(bytes: &[u8]) -> Arc<Mmap> {
        let mut file = tempfile::tempfile().expect("a temporary file");
        file.write_all(bytes).expect("written");
        // SAFETY: the file is this test's own and nothing changes it while it is mapped.
        Arc::new(unsafe { Mmap::map(&file) }.expect("mapped"))
    }

    #[test]
    fn a_mapped_section_reads_as_its_records_and_copies_once_on_change() {
        let values: Vec<u32> = (0..64).collect();
        let map = map_of(bytemuck::cast_slice(&values));
        let mut records = PatchRecords::<u32>::mapped(map, 16..64).expect("whole, aligned records");
        assert!(records.is_mapped());
        assert_eq!(&*records, &values[4..16]);
        records[0] = 99;
        assert!(!records.is_mapped());
        assert_eq!(records[0], 99);
        assert_eq!(&records[1..], &values[5..16]);
    }

    #[test]
    fn a_mapped_clone_shares_the_map_and_equals_the_same_records_in_memory() {
        let values: Vec<u32> = (0..16).collect();
        let mapped = PatchRecords::<u32>::mapped(map_of(bytemuck::cast_slice(&values)), 0..64).unwrap();
        let clone = mapped.clone();
        assert!(clone.is_mapped());
        assert_eq!(clone, PatchRecords::from(values));
        let empty = PatchRecords::<u32>::mapped(map_of(&[0u8; 8]), 8..8).expect("an empty section");
        assert!(empty.is_empty() && empty.is_mapped());
        assert_eq!(empty, PatchRecords::default());
    }

    #[test]
    fn partial_misaligned_or_outside_ranges_are_refused() {
        let map = map_of(&[0u8; 64]);
        assert!(PatchRecords::<u32>::mapped(map.clone(), 0..6).is_none());
        assert!(PatchRecords::<u32>::mapped(map.clone(), 2..10).is_none());
        assert!(PatchRecords::<u32>::mapped(map, 32..96).is_none());
    }
}
