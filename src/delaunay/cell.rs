//! The tetrahedron records: one 32-byte, 32-aligned [`Cell`] per tetrahedron (four vertex
//! ids and the neighbour opposite each: one cache line visit, not two), a byte of cavity
//! mark per record, and [`Tets`], the raw view through which the two workers of a parallel
//! phase write their own records of the same arrays. The only `unsafe` of the
//! tetrahedralization is here and in the callers of [`Tets`].

use super::INFINITE;

/// A free record's vertices.
pub(super) const FREE: u32 = u32::MAX - 1;
/// No tetrahedron (a neighbour not yet linked).
pub(super) const NONE: u32 = u32::MAX;

/// Cavity marks (reset to `UNSEEN` after every insertion).
pub(super) const UNSEEN: u8 = 0;
pub(super) const IN: u8 = 1;
pub(super) const OUT: u8 = 2;

/// One tetrahedron: its vertices (internal ids) and the neighbour opposite each vertex.
#[derive(Clone, Copy)]
#[repr(C, align(32))]
pub(super) struct Cell {
    pub v: [u32; 4],
    pub n: [u32; 4],
}

impl Cell {
    /// A free record.
    pub const FREE: Cell = Cell {
        v: [FREE; 4],
        n: [NONE; 4],
    };

    /// A live (not free) tetrahedron without the vertex at infinity.
    pub fn is_live_finite(&self) -> bool {
        self.v[0] != FREE && !self.v.contains(&INFINITE)
    }
}

/// The tetrahedron records and their cavity marks as raw pointers, so that the two workers
/// of a parallel phase can each write their own slots of the same arrays. Every access is
/// bounds-checked; what keeps the accesses free of data races is the ownership rule stated
/// on `Worker::insert`.
#[derive(Clone, Copy)]
pub(super) struct Tets {
    cells: *mut Cell,
    mark: *mut u8,
    pub len: usize,
}

// SAFETY: a `Tets` is only dereferenced under the ownership rule of `Worker::insert`: while
// several threads hold it, each reads and writes only slots that no other thread touches.
unsafe impl Send for Tets {}
unsafe impl Sync for Tets {}

impl Tets {
    /// A view of `cells` and `mark`, valid until either is touched through the `Vec`s again.
    pub fn new(cells: &mut Vec<Cell>, mark: &mut Vec<u8>) -> Self {
        assert_eq!(cells.len(), mark.len());
        Tets {
            cells: cells.as_mut_ptr(),
            mark: mark.as_mut_ptr(),
            len: cells.len(),
        }
    }

    /// # Safety
    /// The arrays are alive and no other thread writes slot `t` meanwhile.
    #[inline(always)]
    pub unsafe fn get(self, t: u32) -> Cell {
        assert!((t as usize) < self.len);
        *self.cells.add(t as usize)
    }

    /// # Safety
    /// The arrays are alive and no other thread reads or writes slot `t` meanwhile.
    #[inline(always)]
    pub unsafe fn set(self, t: u32, cell: Cell) {
        assert!((t as usize) < self.len);
        *self.cells.add(t as usize) = cell;
    }

    /// Sets neighbour `j` of `t`.
    ///
    /// # Safety
    /// As [`Tets::set`].
    #[inline(always)]
    pub unsafe fn set_n(self, t: u32, j: usize, n: u32) {
        assert!((t as usize) < self.len);
        (*self.cells.add(t as usize)).n[j & 3] = n;
    }

    /// Asks for slot `t`'s record and mark to be brought into cache (a hint: no access).
    #[inline(always)]
    pub fn prefetch(self, t: u32) {
        #[cfg(target_arch = "x86_64")]
        if (t as usize) < self.len {
            use std::arch::x86_64::{_mm_prefetch, _MM_HINT_T0};
            // SAFETY: a prefetch never faults and reads nothing; the addresses are in bounds.
            unsafe {
                _mm_prefetch::<_MM_HINT_T0>(self.cells.add(t as usize) as *const i8);
                _mm_prefetch::<_MM_HINT_T0>(self.mark.add(t as usize) as *const i8);
            }
        }
        #[cfg(not(target_arch = "x86_64"))]
        let _ = (self, t);
    }

    /// Prefetches the four neighbours of `t` ([`Tets::prefetch`]).
    ///
    /// # Safety
    /// As [`Tets::get`].
    #[inline(always)]
    pub unsafe fn prefetch_neighbours(self, t: u32) {
        for n in self.get(t).n {
            self.prefetch(n);
        }
    }

    /// # Safety
    /// As [`Tets::get`].
    #[inline(always)]
    pub unsafe fn mark(self, t: u32) -> u8 {
        assert!((t as usize) < self.len);
        *self.mark.add(t as usize)
    }

    /// # Safety
    /// As [`Tets::set`].
    #[inline(always)]
    pub unsafe fn set_mark(self, t: u32, m: u8) {
        assert!((t as usize) < self.len);
        *self.mark.add(t as usize) = m;
    }
}
