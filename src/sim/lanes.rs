//! Eight `f32` lanes, the kernel's unit of work: one AVX2 register ([`Avx`]) or a plain array
//! ([`Portable`]). The kernel is written once, generic over [`Lanes`], and compiled for both.
//!
//! Every operation is one IEEE-754 operation per lane (`+ − × ÷ √`, comparisons, selects), with
//! no fused multiply-add and no approximate reciprocal, so both implementations give
//! bit-identical results (tested).

use std::ops::{Add, Div, Mul, Sub};

/// Number of lanes.
pub(super) const LANES: usize = 8;

/// A vector in lanes.
#[derive(Clone, Copy)]
pub(super) struct V3<V> {
    pub(super) x: V,
    pub(super) y: V,
    pub(super) z: V,
}

/// Eight `f32` lanes.
pub(super) trait Lanes:
    Copy + Add<Output = Self> + Sub<Output = Self> + Mul<Output = Self> + Div<Output = Self>
{
    fn splat(x: f32) -> Self;
    #[cfg(test)]
    fn from_array(a: [f32; LANES]) -> Self;
    fn to_array(self) -> [f32; LANES];
    /// `s[at..at + 8]`.
    fn load(s: &[f32], at: usize) -> Self;
    /// `s[idx[lane]]` for each lane.
    fn gather(s: &[f32], idx: &[u32; LANES]) -> Self;
    /// `x, y, z` of `s[idx[lane]]` for each lane.
    fn gather3(s: &[[f32; 4]], idx: &[u32; LANES]) -> [Self; 3];
    /// [`Lanes::gather3`] by offsets counted in `f32` (`4 × index`), without bounds checks.
    ///
    /// # Safety
    /// Every `offset[lane] + 4` must be at most `4 * s.len()`.
    unsafe fn gather3_unchecked(s: &[[f32; 4]], offset: &[u32; LANES]) -> [Self; 3];
    /// Lane by lane `self > b ? self : b` (what `vmaxps` computes, NaN included).
    fn max(self, b: Self) -> Self;
    /// `x, y, z` of `s[at..at + 8]`.
    fn load3(s: &[[f32; 4]], at: usize) -> [Self; 3];
    /// Writes `s[at..at + 8]` (the fourth `f32` of each point 0).
    fn store3(v: [Self; 3], s: &mut [[f32; 4]], at: usize);
    fn sqrt(self) -> Self;
    /// `self > 0 ? a : 0`, lane by lane.
    fn positive_or_zero(self, a: Self) -> Self;
    /// `self <= b ? x : y`, lane by lane.
    fn le_select(self, b: Self, x: Self, y: Self) -> Self;

    // Masks: lanes with every bit set (true) or none (false).
    /// Every lane `set`.
    fn mask(set: bool) -> Self;
    /// `self > b`.
    fn gt(self, b: Self) -> Self;
    /// `self < b`.
    fn lt(self, b: Self) -> Self;
    /// `self <= b`.
    fn le(self, b: Self) -> Self;
    /// `self & b`.
    fn and(self, b: Self) -> Self;
    /// `!self & b`.
    fn and_not(self, b: Self) -> Self;
    /// `self | b`.
    fn or(self, b: Self) -> Self;
    /// `mask ? a : b`, lane by lane (`self` is the mask).
    fn select(self, a: Self, b: Self) -> Self;
    /// Is any lane of the mask true?
    fn any(self) -> bool;
    /// `−self`, exact (the sign bit flipped).
    fn neg(self) -> Self;
}

/// The portable implementation: a plain array.
#[derive(Clone, Copy, Debug)]
pub(super) struct Portable([f32; LANES]);

macro_rules! portable_op {
    ($tr:ident, $f:ident, $op:tt) => {
        impl $tr for Portable {
            type Output = Portable;
            #[inline(always)]
            fn $f(self, o: Portable) -> Portable {
                Portable(std::array::from_fn(|l| self.0[l] $op o.0[l]))
            }
        }
    };
}
portable_op!(Add, add, +);
portable_op!(Sub, sub, -);
portable_op!(Mul, mul, *);
portable_op!(Div, div, /);

impl Lanes for Portable {
    #[inline(always)]
    fn splat(x: f32) -> Self {
        Portable([x; LANES])
    }
    #[cfg(test)]
    #[inline(always)]
    fn from_array(a: [f32; LANES]) -> Self {
        Portable(a)
    }
    #[inline(always)]
    fn to_array(self) -> [f32; LANES] {
        self.0
    }
    #[inline(always)]
    fn load(s: &[f32], at: usize) -> Self {
        let mut a = [0.0; LANES];
        a.copy_from_slice(&s[at..at + LANES]);
        Portable(a)
    }
    #[inline(always)]
    fn gather(s: &[f32], idx: &[u32; LANES]) -> Self {
        Portable(std::array::from_fn(|l| s[idx[l] as usize]))
    }
    #[inline(always)]
    fn gather3(s: &[[f32; 4]], idx: &[u32; LANES]) -> [Self; 3] {
        let p: [[f32; 4]; LANES] = std::array::from_fn(|l| s[idx[l] as usize]);
        std::array::from_fn(|c| Portable(std::array::from_fn(|l| p[l][c])))
    }
    #[inline(always)]
    unsafe fn gather3_unchecked(s: &[[f32; 4]], offset: &[u32; LANES]) -> [Self; 3] {
        let s = s.as_flattened();
        let p: [&[f32]; LANES] = std::array::from_fn(|l| &s[offset[l] as usize..]);
        std::array::from_fn(|c| Portable(std::array::from_fn(|l| p[l][c])))
    }
    #[inline(always)]
    fn max(self, b: Self) -> Self {
        Portable(std::array::from_fn(|l| {
            if self.0[l] > b.0[l] {
                self.0[l]
            } else {
                b.0[l]
            }
        }))
    }
    #[inline(always)]
    fn load3(s: &[[f32; 4]], at: usize) -> [Self; 3] {
        let p = &s[at..at + LANES];
        std::array::from_fn(|c| Portable(std::array::from_fn(|l| p[l][c])))
    }
    #[inline(always)]
    fn store3(v: [Self; 3], s: &mut [[f32; 4]], at: usize) {
        for (l, q) in s[at..at + LANES].iter_mut().enumerate() {
            *q = [v[0].0[l], v[1].0[l], v[2].0[l], 0.0];
        }
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        Portable(self.0.map(f32::sqrt))
    }
    #[inline(always)]
    fn positive_or_zero(self, a: Self) -> Self {
        Portable(std::array::from_fn(|l| {
            if self.0[l] > 0.0 {
                a.0[l]
            } else {
                0.0
            }
        }))
    }
    #[inline(always)]
    fn le_select(self, b: Self, x: Self, y: Self) -> Self {
        Portable(std::array::from_fn(|l| {
            if self.0[l] <= b.0[l] {
                x.0[l]
            } else {
                y.0[l]
            }
        }))
    }
    #[inline(always)]
    fn mask(set: bool) -> Self {
        Portable::mask_where(|_| set)
    }
    #[inline(always)]
    fn gt(self, b: Self) -> Self {
        Portable::mask_where(|l| self.0[l] > b.0[l])
    }
    #[inline(always)]
    fn lt(self, b: Self) -> Self {
        Portable::mask_where(|l| self.0[l] < b.0[l])
    }
    #[inline(always)]
    fn le(self, b: Self) -> Self {
        Portable::mask_where(|l| self.0[l] <= b.0[l])
    }
    #[inline(always)]
    fn and(self, b: Self) -> Self {
        self.bits(b, |x, y| x & y)
    }
    #[inline(always)]
    fn and_not(self, b: Self) -> Self {
        self.bits(b, |x, y| !x & y)
    }
    #[inline(always)]
    fn or(self, b: Self) -> Self {
        self.bits(b, |x, y| x | y)
    }
    #[inline(always)]
    fn select(self, a: Self, b: Self) -> Self {
        // What `vblendvps` looks at: the sign bit of the mask.
        Portable(std::array::from_fn(|l| {
            if self.0[l].is_sign_negative() {
                a.0[l]
            } else {
                b.0[l]
            }
        }))
    }
    #[inline(always)]
    fn any(self) -> bool {
        self.0.iter().any(|m| m.is_sign_negative())
    }
    #[inline(always)]
    fn neg(self) -> Self {
        Portable(self.0.map(|x| -x))
    }
}

impl Portable {
    #[inline(always)]
    fn bits(self, b: Self, f: impl Fn(u32, u32) -> u32) -> Self {
        Portable(std::array::from_fn(|l| {
            f32::from_bits(f(self.0[l].to_bits(), b.0[l].to_bits()))
        }))
    }

    #[inline(always)]
    fn mask_where(c: impl Fn(usize) -> bool) -> Self {
        Portable(std::array::from_fn(|l| {
            f32::from_bits(if c(l) { !0 } else { 0 })
        }))
    }
}

#[cfg(target_arch = "x86_64")]
pub(super) use avx::Avx;

#[cfg(target_arch = "x86_64")]
mod avx {
    //! # Safety
    //! [`Avx`] values are only made inside code compiled with `target_feature(enable =
    //! "avx2")` that runs after `is_x86_feature_detected!("avx2")` said yes (the kernel's
    //! dispatch), so every intrinsic below runs on a CPU that has it. The methods are
    //! `inline(always)`: they are inlined into that AVX2 code.
    use super::{Lanes, LANES};
    use std::arch::x86_64::*;
    use std::ops::{Add, Div, Mul, Sub};

    /// The AVX2 implementation: one `__m256`.
    #[derive(Clone, Copy, Debug)]
    pub(in crate::sim) struct Avx(__m256);

    macro_rules! avx_op {
        ($tr:ident, $f:ident, $intr:ident) => {
            impl $tr for Avx {
                type Output = Avx;
                #[inline(always)]
                fn $f(self, o: Avx) -> Avx {
                    // SAFETY: see the module docs.
                    Avx(unsafe { $intr(self.0, o.0) })
                }
            }
        };
    }
    avx_op!(Add, add, _mm256_add_ps);
    avx_op!(Sub, sub, _mm256_sub_ps);
    avx_op!(Mul, mul, _mm256_mul_ps);
    avx_op!(Div, div, _mm256_div_ps);

    /// `x, y, z` in lanes from four registers holding points `l` (low half) and `l + 4`
    /// (high half), `l = 0..4`.
    #[inline(always)]
    unsafe fn transpose_in(r: [__m256; 4]) -> [Avx; 3] {
        let t0 = _mm256_unpacklo_ps(r[0], r[1]); // x0 x1 y0 y1 | x4 x5 y4 y5
        let t1 = _mm256_unpackhi_ps(r[0], r[1]); // z0 z1 w0 w1 | z4 z5 w4 w5
        let t2 = _mm256_unpacklo_ps(r[2], r[3]); // x2 x3 y2 y3 | x6 x7 y6 y7
        let t3 = _mm256_unpackhi_ps(r[2], r[3]); // z2 z3 w2 w3 | z6 z7 w6 w7
        [
            Avx(_mm256_shuffle_ps::<0x44>(t0, t2)),
            Avx(_mm256_shuffle_ps::<0xEE>(t0, t2)),
            Avx(_mm256_shuffle_ps::<0x44>(t1, t3)),
        ]
    }

    impl Lanes for Avx {
        #[inline(always)]
        fn splat(x: f32) -> Self {
            // SAFETY: see the module docs.
            Avx(unsafe { _mm256_set1_ps(x) })
        }
        #[cfg(test)]
        #[inline(always)]
        fn from_array(a: [f32; LANES]) -> Self {
            // SAFETY: see the module docs; `a` is 8 readable floats.
            Avx(unsafe { _mm256_loadu_ps(a.as_ptr()) })
        }
        #[inline(always)]
        fn to_array(self) -> [f32; LANES] {
            let mut a = [0.0; LANES];
            // SAFETY: see the module docs; `a` is 8 writable floats.
            unsafe { _mm256_storeu_ps(a.as_mut_ptr(), self.0) };
            a
        }
        #[inline(always)]
        fn load(s: &[f32], at: usize) -> Self {
            let s = &s[at..at + LANES];
            // SAFETY: see the module docs; `s` is 8 readable floats.
            Avx(unsafe { _mm256_loadu_ps(s.as_ptr()) })
        }
        #[inline(always)]
        fn gather(s: &[f32], idx: &[u32; LANES]) -> Self {
            let g = |l: usize| s[idx[l] as usize];
            // SAFETY: see the module docs.
            Avx(unsafe { _mm256_setr_ps(g(0), g(1), g(2), g(3), g(4), g(5), g(6), g(7)) })
        }
        #[inline(always)]
        fn gather3(s: &[[f32; 4]], idx: &[u32; LANES]) -> [Self; 3] {
            assert!(idx.iter().all(|&i| (i as usize) < s.len()));
            // SAFETY: every index was just checked, so every `4 × index + 4 <= 4 × s.len()`.
            unsafe { Self::gather3_unchecked(s, &idx.map(|i| 4 * i)) }
        }
        #[inline(always)]
        unsafe fn gather3_unchecked(s: &[[f32; 4]], offset: &[u32; LANES]) -> [Self; 3] {
            // SAFETY: see the module docs; the caller promises every `offset[l] + 4 <= 4 ×
            // s.len()`, so `p(l)` reads 4 floats inside `s`.
            unsafe {
                let base = s.as_ptr() as *const f32;
                let p = |l: usize| _mm_loadu_ps(base.add(offset[l] as usize));
                transpose_in([
                    _mm256_insertf128_ps::<1>(_mm256_castps128_ps256(p(0)), p(4)),
                    _mm256_insertf128_ps::<1>(_mm256_castps128_ps256(p(1)), p(5)),
                    _mm256_insertf128_ps::<1>(_mm256_castps128_ps256(p(2)), p(6)),
                    _mm256_insertf128_ps::<1>(_mm256_castps128_ps256(p(3)), p(7)),
                ])
            }
        }
        #[inline(always)]
        fn load3(s: &[[f32; 4]], at: usize) -> [Self; 3] {
            let s = &s[at..at + LANES];
            // SAFETY: see the module docs; `s` is 8 points, 32 readable floats.
            unsafe {
                let p = s.as_ptr() as *const f32;
                let q = |l: usize| _mm256_loadu2_m128(p.add(4 * (l + 4)), p.add(4 * l));
                transpose_in([q(0), q(1), q(2), q(3)])
            }
        }
        #[inline(always)]
        fn store3(v: [Self; 3], s: &mut [[f32; 4]], at: usize) {
            let s = &mut s[at..at + LANES];
            // SAFETY: see the module docs; `s` is 8 points, 32 writable floats.
            unsafe {
                let w = _mm256_setzero_ps();
                let t0 = _mm256_unpacklo_ps(v[0].0, v[1].0);
                let t1 = _mm256_unpackhi_ps(v[0].0, v[1].0);
                let t2 = _mm256_unpacklo_ps(v[2].0, w);
                let t3 = _mm256_unpackhi_ps(v[2].0, w);
                let r = [
                    _mm256_shuffle_ps::<0x44>(t0, t2),
                    _mm256_shuffle_ps::<0xEE>(t0, t2),
                    _mm256_shuffle_ps::<0x44>(t1, t3),
                    _mm256_shuffle_ps::<0xEE>(t1, t3),
                ];
                let p = s.as_mut_ptr() as *mut f32;
                for (l, r) in r.into_iter().enumerate() {
                    _mm256_storeu2_m128(p.add(4 * (l + 4)), p.add(4 * l), r);
                }
            }
        }
        #[inline(always)]
        fn max(self, b: Self) -> Self {
            // SAFETY: see the module docs.
            Avx(unsafe { _mm256_max_ps(self.0, b.0) })
        }
        #[inline(always)]
        fn sqrt(self) -> Self {
            // SAFETY: see the module docs.
            Avx(unsafe { _mm256_sqrt_ps(self.0) })
        }
        #[inline(always)]
        fn positive_or_zero(self, a: Self) -> Self {
            // SAFETY: see the module docs.
            unsafe {
                let m = _mm256_cmp_ps::<_CMP_GT_OQ>(self.0, _mm256_setzero_ps());
                Avx(_mm256_and_ps(m, a.0))
            }
        }
        #[inline(always)]
        fn le_select(self, b: Self, x: Self, y: Self) -> Self {
            // SAFETY: see the module docs.
            unsafe {
                let m = _mm256_cmp_ps::<_CMP_LE_OQ>(self.0, b.0);
                Avx(_mm256_blendv_ps(y.0, x.0, m))
            }
        }
        #[inline(always)]
        fn mask(set: bool) -> Self {
            Self::splat(f32::from_bits(if set { !0 } else { 0 }))
        }
        #[inline(always)]
        fn gt(self, b: Self) -> Self {
            // SAFETY: see the module docs.
            Avx(unsafe { _mm256_cmp_ps::<_CMP_GT_OQ>(self.0, b.0) })
        }
        #[inline(always)]
        fn lt(self, b: Self) -> Self {
            // SAFETY: see the module docs.
            Avx(unsafe { _mm256_cmp_ps::<_CMP_LT_OQ>(self.0, b.0) })
        }
        #[inline(always)]
        fn le(self, b: Self) -> Self {
            // SAFETY: see the module docs.
            Avx(unsafe { _mm256_cmp_ps::<_CMP_LE_OQ>(self.0, b.0) })
        }
        #[inline(always)]
        fn and(self, b: Self) -> Self {
            // SAFETY: see the module docs.
            Avx(unsafe { _mm256_and_ps(self.0, b.0) })
        }
        #[inline(always)]
        fn and_not(self, b: Self) -> Self {
            // SAFETY: see the module docs.
            Avx(unsafe { _mm256_andnot_ps(self.0, b.0) })
        }
        #[inline(always)]
        fn or(self, b: Self) -> Self {
            // SAFETY: see the module docs.
            Avx(unsafe { _mm256_or_ps(self.0, b.0) })
        }
        #[inline(always)]
        fn select(self, a: Self, b: Self) -> Self {
            // SAFETY: see the module docs.
            Avx(unsafe { _mm256_blendv_ps(b.0, a.0, self.0) })
        }
        #[inline(always)]
        fn any(self) -> bool {
            // SAFETY: see the module docs.
            unsafe { _mm256_movemask_ps(self.0) != 0 }
        }
        #[inline(always)]
        fn neg(self) -> Self {
            // SAFETY: see the module docs.
            Avx(unsafe { _mm256_xor_ps(self.0, _mm256_set1_ps(-0.0)) })
        }
    }
}
