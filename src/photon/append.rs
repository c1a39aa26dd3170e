//! Appending records to one large array in parallel.

use rayon::prelude::*;

/// Appends `parts`, in order, to `dst`, copying them in parallel (in pieces of at most
/// `PIECE` records). The array grows once by exactly what is added; past the allocator's
/// mmap threshold that growth moves pages rather than records, and only the pages written
/// are taken.
pub(crate) fn append_parallel<P: Copy + Send + Sync>(dst: &mut Vec<P>, parts: &[&[P]]) {
    const PIECE: usize = 1 << 16;
    let len = dst.len();
    let added: usize = parts.iter().map(|p| p.len()).sum();
    dst.reserve(added);
    let mut slots = &mut dst.spare_capacity_mut()[..added];
    let mut jobs = Vec::new();
    for piece in parts.iter().flat_map(|p| p.chunks(PIECE)) {
        let (place, rest) = std::mem::take(&mut slots).split_at_mut(piece.len());
        jobs.push((place, piece));
        slots = rest;
    }
    jobs.into_par_iter().for_each(|(place, piece)| {
        for (slot, ph) in place.iter_mut().zip(piece) {
            slot.write(*ph);
        }
    });
    // SAFETY: the `added` slots after `len` were each written above: the pieces split them
    // exactly, one slot per record of `parts`.
    unsafe { dst.set_len(len + added) };
}
