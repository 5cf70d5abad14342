//! The programs' allocator: the system's for small blocks, and for large ones mappings of
//! their own, backed by transparent huge pages.
//!
//! Prep fills buffers of hundreds of megabytes, tile after tile, and each fresh buffer is
//! faulted in a page at a time. With 4 KiB pages a 100M-point prep on 16 cores took 22 million
//! faults, and the kernel's share of its processor time was a seventh; 2 MiB pages make the
//! faults a hundred times fewer. The advice must come before a block's first touch, which the
//! system allocator's growth by copying would precede, so large blocks are mapped, grown and
//! unmapped here (Linux 6.7 and later place mappings of whole huge pages on huge-page
//! boundaries; on older kernels a block's partial huge pages at its ends stay small).

use std::alloc::{GlobalAlloc, Layout, System};
use std::ptr;

/// The size of a transparent huge page with 4 KiB base pages (x86-64, and most arm64 kernels).
/// Elsewhere the advice covers fewer whole huge pages, and only speed differs.
const HUGE_PAGE: usize = 2 << 20;

/// Blocks at least this large get mappings of their own: a mapping is rounded up to whole
/// huge pages, a small share of the block. Smaller blocks stay in the system's heaps, which
/// reuse freed memory without faulting it in again.
const LARGE_BLOCK: usize = 16 * HUGE_PAGE;

/// Blocks in the system's heaps at least this large ask for huge pages over the part of them
/// that spans whole huge pages. The advice comes after the system allocator has placed the
/// block (and, for `calloc` or a copying `realloc`, touched it), and it stays with that part
/// of the heap after the block is freed: it never changes contents, and the blocks placed
/// there later fault in 2 MiB at a time as well.
const HEAP_ADVICE_BLOCK: usize = 2 * HUGE_PAGE;

/// The system allocator, with every large block mapped on its own and backed by huge pages.
pub struct HugePageAllocator;

/// The alignment every mapping has: the smallest page size of the platforms with huge pages.
const MAPPING_ALIGN: usize = 4096;

/// Whether a block of this size and alignment is one of this allocator's own mappings.
fn is_mapped(size: usize, align: usize) -> bool {
    cfg!(target_os = "linux") && size >= LARGE_BLOCK && align <= MAPPING_ALIGN
}

// SAFETY: a block is mapped here exactly when `is_mapped` holds for its layout, which its
// caller passes back unchanged, so every block returns to the allocator it came from.
unsafe impl GlobalAlloc for HugePageAllocator {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        if is_mapped(layout.size(), layout.align()) {
            map(layout.size())
        } else {
            // SAFETY: the caller's contract for `alloc` is passed on unchanged.
            advised(unsafe { System.alloc(layout) }, layout.size())
        }
    }

    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        if is_mapped(layout.size(), layout.align()) {
            // A fresh anonymous mapping reads as zeros.
            map(layout.size())
        } else {
            // SAFETY: as for `alloc`.
            advised(unsafe { System.alloc_zeroed(layout) }, layout.size())
        }
    }

    unsafe fn dealloc(&self, block: *mut u8, layout: Layout) {
        if is_mapped(layout.size(), layout.align()) {
            // SAFETY: the block is a mapping made by `map` for this size.
            unsafe { unmap(block, layout.size()) }
        } else {
            // SAFETY: the caller's contract for `dealloc` is passed on unchanged.
            unsafe { System.dealloc(block, layout) }
        }
    }

    unsafe fn realloc(&self, block: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        let was_mapped = is_mapped(layout.size(), layout.align());
        let is_to_be_mapped = is_mapped(new_size, layout.align());
        match (was_mapped, is_to_be_mapped) {
            // SAFETY: the block is a mapping made by `map` for its old size.
            (true, true) => unsafe { remap(block, layout.size(), new_size) },
            // SAFETY: the caller's contract for `realloc` is passed on unchanged.
            (false, false) => advised(unsafe { System.realloc(block, layout, new_size) }, new_size),
            // SAFETY: the block is valid for its old size, and the new layout is valid since
            // the caller guarantees `new_size`, rounded up to the alignment, fits an isize.
            _ => unsafe { moved(self, block, layout, new_size) },
        }
    }
}

/// A block of `new_size` bytes holding the start of `block`, which is then freed.
///
/// # Safety
/// As for `GlobalAlloc::realloc`.
unsafe fn moved(allocator: &HugePageAllocator, block: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
    // SAFETY: see the caller.
    unsafe {
        let new_layout = Layout::from_size_align_unchecked(new_size, layout.align());
        let new_block = allocator.alloc(new_layout);
        if !new_block.is_null() {
            ptr::copy_nonoverlapping(block, new_block, layout.size().min(new_size));
            allocator.dealloc(block, layout);
        }
        new_block
    }
}

/// `block`, a block of the system's heaps, once the huge pages wholly inside it have been
/// asked for if it is large enough to hold some.
fn advised(block: *mut u8, size: usize) -> *mut u8 {
    if cfg!(target_os = "linux") && !block.is_null() && size >= HEAP_ADVICE_BLOCK {
        let first = (block as usize).next_multiple_of(HUGE_PAGE);
        let end = (block as usize + size) / HUGE_PAGE * HUGE_PAGE;
        if end > first {
            advise_huge_pages(first as *mut u8, end - first);
        }
    }
    block
}

fn mapping_size(size: usize) -> usize {
    size.next_multiple_of(HUGE_PAGE)
}

#[cfg(target_os = "linux")]
fn map(size: usize) -> *mut u8 {
    // SAFETY: a new private anonymous mapping touches no memory the process holds.
    let mapping = unsafe {
        libc::mmap(
            ptr::null_mut(),
            mapping_size(size),
            libc::PROT_READ | libc::PROT_WRITE,
            libc::MAP_PRIVATE | libc::MAP_ANONYMOUS,
            -1,
            0,
        )
    };
    if mapping == libc::MAP_FAILED {
        return ptr::null_mut();
    }
    advise_huge_pages(mapping.cast(), mapping_size(size));
    mapping.cast()
}

/// # Safety
/// `block` must be a mapping made by `map` for `size` bytes, or grown by `remap` to them.
#[cfg(target_os = "linux")]
unsafe fn remap(block: *mut u8, size: usize, new_size: usize) -> *mut u8 {
    // SAFETY: see the function's contract.
    let mapping = unsafe {
        libc::mremap(block.cast(), mapping_size(size), mapping_size(new_size), libc::MREMAP_MAYMOVE)
    };
    if mapping == libc::MAP_FAILED {
        return ptr::null_mut();
    }
    advise_huge_pages(mapping.cast(), mapping_size(new_size));
    mapping.cast()
}

/// # Safety
/// As for `remap`.
#[cfg(target_os = "linux")]
unsafe fn unmap(block: *mut u8, size: usize) {
    // SAFETY: see the function's contract.
    let result = unsafe { libc::munmap(block.cast(), mapping_size(size)) };
    debug_assert_eq!(result, 0, "a block freed as a mapping was not one");
}

/// Asks for huge pages over `length` bytes at `start`, a range this process holds. A kernel
/// without them refuses, and small pages serve as before.
#[cfg(target_os = "linux")]
fn advise_huge_pages(start: *mut u8, length: usize) {
    // SAFETY: the range is memory this process holds; the advice changes no contents.
    unsafe { libc::madvise(start.cast(), length, libc::MADV_HUGEPAGE) };
}

#[cfg(not(target_os = "linux"))]
fn advise_huge_pages(_start: *mut u8, _length: usize) {}

#[cfg(not(target_os = "linux"))]
fn map(_size: usize) -> *mut u8 {
    unreachable!("large blocks are mapped only on Linux")
}

#[cfg(not(target_os = "linux"))]
unsafe fn remap(_block: *mut u8, _size: usize, _new_size: usize) -> *mut u8 {
    unreachable!("large blocks are mapped only on Linux")
}

#[cfg(not(target_os = "linux"))]
unsafe fn unmap(_block: *mut u8, _size: usize) {
    unreachable!("large blocks are mapped only on Linux")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[global_allocator]
    static ALLOCATOR: HugePageAllocator = HugePageAllocator;

    const SIZES: [usize; 7] =
        [1, 4096, HEAP_ADVICE_BLOCK + 4097, LARGE_BLOCK - 1, LARGE_BLOCK, 3 * LARGE_BLOCK + 12345, 40];

    fn pattern(offset: usize) -> u8 {
        (offset % 251) as u8
    }

    /// Grows or shrinks a patterned block from `size` to `new_size` and checks what it kept.
    ///
    /// # Safety
    /// `block` must come from `HugePageAllocator` with `layout`, patterned over its size.
    unsafe fn resize_keeping_pattern(block: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        // SAFETY: see the function's contract.
        unsafe {
            let resized = HugePageAllocator.realloc(block, layout, new_size);
            assert!(!resized.is_null());
            for offset in (0..layout.size().min(new_size)).step_by(997) {
                assert_eq!(*resized.add(offset), pattern(offset), "{} -> {new_size}", layout.size());
            }
            resized
        }
    }

    #[test]
    fn blocks_keep_their_contents_across_every_size_change() {
        for size in SIZES {
            for new_size in SIZES {
                let layout = Layout::from_size_align(size, 64).unwrap();
                // SAFETY: every block is used within its size and freed with its last layout.
                unsafe {
                    let block = HugePageAllocator.alloc_zeroed(layout);
                    assert!(!block.is_null());
                    let zeroed = std::slice::from_raw_parts(block, size);
                    assert!(zeroed.iter().all(|&byte| byte == 0), "{size} bytes not zeroed");
                    for offset in (0..size).step_by(997) {
                        *block.add(offset) = pattern(offset);
                    }
                    let resized = resize_keeping_pattern(block, layout, new_size);
                    let new_layout = Layout::from_size_align(new_size, 64).unwrap();
                    HugePageAllocator.dealloc(resized, new_layout);
                }
            }
        }
    }

    #[test]
    fn large_blocks_keep_their_alignment_whoever_maps_them() {
        for align in [MAPPING_ALIGN, 2 * MAPPING_ALIGN, HUGE_PAGE] {
            let layout = Layout::from_size_align(LARGE_BLOCK + 1, align).unwrap();
            // SAFETY: the layout has a non-zero size, and the block is freed with it.
            unsafe {
                let block = HugePageAllocator.alloc(layout);
                assert!(!block.is_null());
                assert_eq!(block as usize % align, 0, "aligned to {align}");
                HugePageAllocator.dealloc(block, layout);
            }
        }
    }

    #[test]
    fn vectors_grow_through_the_large_sizes() {
        let mut values: Vec<u64> = Vec::new();
        for value in 0..(3 * LARGE_BLOCK as u64 / 8) {
            values.push(value);
        }
        assert!(values.iter().enumerate().all(|(index, &value)| index as u64 == value));
        values.truncate(10);
        values.shrink_to_fit();
        assert_eq!(values, (0..10).collect::<Vec<u64>>());
    }
}
