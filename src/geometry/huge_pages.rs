//! Transparent huge pages for the large arrays of the acceleration structure.
//!
//! The BVH nodes and the leaf-ordered triangles of a big mesh are read at random: with
//! 4 KiB pages nearly every node visit of an incoherent ray also misses the TLB. On Linux,
//! [`advise`] marks a vector's unused capacity with `madvise(MADV_HUGEPAGE)` before it is
//! filled, so that the kernel backs it with 2 MiB pages where it can (it does so when
//! `/sys/kernel/mm/transparent_hugepage/enabled` is `always` or `madvise`). Elsewhere, and
//! for vectors under 4 MiB, it does nothing. The advice changes no result.

/// Vectors with less capacity than this are left alone.
const MIN_BYTES: usize = 4 << 20;

#[cfg(target_os = "linux")]
mod sys {
    use std::ffi::{c_int, c_void};

    pub const MADV_HUGEPAGE: c_int = 14;
    pub const HUGE_PAGE: usize = 2 << 20;

    extern "C" {
        pub fn madvise(addr: *mut c_void, length: usize, advice: c_int) -> c_int;
    }
}

/// Advises huge pages for the 2 MiB-aligned part of `v`'s allocation (see the module
/// documentation). Call it on an empty vector right after reserving its capacity.
pub(crate) fn advise<T>(v: &mut Vec<T>) {
    let bytes = v.capacity() * std::mem::size_of::<T>();
    if bytes < MIN_BYTES {
        return;
    }
    #[cfg(target_os = "linux")]
    {
        let start = v.as_mut_ptr() as usize;
        let lo = start.next_multiple_of(sys::HUGE_PAGE);
        let hi = (start + bytes) / sys::HUGE_PAGE * sys::HUGE_PAGE;
        if hi > lo {
            // SAFETY: the range lies within the vector's allocation; MADV_HUGEPAGE only
            // changes how the kernel backs the pages, never their contents. A failure (an
            // old kernel, THP disabled) leaves the pages as they were and is ignored.
            unsafe {
                sys::madvise(lo as *mut std::ffi::c_void, hi - lo, sys::MADV_HUGEPAGE);
            }
        }
    }
}
