//! Exact arithmetic on floating-point expansions (Shewchuk 1997), used when a predicate's
//! filter cannot decide. An expansion is a sum of non-overlapping `f64`s in increasing order
//! of magnitude; its sign is the sign of its last component.
//!
//! Why not `robust`'s exact path: it zero-fills fixed stack buffers of about 100 KB per call,
//! which made the rare exactly-degenerate in-sphere tests (mirror-symmetric meshes are full of
//! exactly cocircular points) cost more than all other work of a tetrahedralization.

/// `a + b = x + y` exactly.
#[inline]
fn two_sum(a: f64, b: f64) -> (f64, f64) {
    let x = a + b;
    let bv = x - a;
    let av = x - bv;
    (x, (a - av) + (b - bv))
}

/// `a + b = x + y` exactly, given `|a| >= |b|`.
#[inline]
fn fast_two_sum(a: f64, b: f64) -> (f64, f64) {
    let x = a + b;
    (x, b - (x - a))
}

#[inline]
fn split(a: f64) -> (f64, f64) {
    const SPLITTER: f64 = 134_217_729.0; // 2^27 + 1
    let c = SPLITTER * a;
    let hi = c - (c - a);
    (hi, a - hi)
}

/// `a * b = x + y` exactly.
#[inline]
fn two_product(a: f64, b: f64) -> (f64, f64) {
    let x = a * b;
    let (ahi, alo) = split(a);
    let (bhi, blo) = split(b);
    let err = x - ahi * bhi - alo * bhi - ahi * blo;
    (x, alo * blo - err)
}

/// A stack of expansions in one reusable buffer. An expansion is a range of the buffer; every
/// operation appends its result, so nothing is freed until [`Arena::clear`], and nothing is
/// allocated once the buffer has grown to the largest predicate seen (it lives in a
/// thread-local, see [`insphere_sign`]).
#[derive(Default)]
pub struct Arena {
    buf: Vec<f64>,
}

/// An expansion in an [`Arena`]: `start..start + len`.
#[derive(Clone, Copy, Debug)]
pub struct Exp {
    start: usize,
    len: usize,
}

impl Arena {
    /// Forgets every expansion (keeps the capacity).
    pub fn clear(&mut self) {
        self.buf.clear();
    }

    fn slice(&self, x: Exp) -> &[f64] {
        &self.buf[x.start..x.start + x.len]
    }

    fn begin(&self) -> usize {
        self.buf.len()
    }

    fn end(&self, start: usize) -> Exp {
        Exp {
            start,
            len: self.buf.len() - start,
        }
    }

    /// The exact value of `a`.
    pub fn from(&mut self, a: f64) -> Exp {
        let s = self.begin();
        if a != 0.0 {
            self.buf.push(a);
        }
        self.end(s)
    }

    /// The exact value of `a − b`.
    pub fn diff(&mut self, a: f64, b: f64) -> Exp {
        let x = a - b;
        let bv = a - x;
        let av = x + bv;
        let y = (a - av) + (bv - b);
        let s = self.begin();
        if y != 0.0 {
            self.buf.push(y);
        }
        if x != 0.0 {
            self.buf.push(x);
        }
        self.end(s)
    }

    /// Sign of `x`: -1, 0 or 1.
    pub fn sign(&self, x: Exp) -> f64 {
        match self.slice(x).last() {
            Some(&v) if v > 0.0 => 1.0,
            Some(&v) if v < 0.0 => -1.0,
            _ => 0.0,
        }
    }

    /// Approximate value of `x`.
    pub fn estimate(&self, x: Exp) -> f64 {
        self.slice(x).iter().sum()
    }

    /// `-x`.
    pub fn neg(&mut self, x: Exp) -> Exp {
        let s = self.begin();
        for i in x.start..x.start + x.len {
            let v = self.buf[i];
            self.buf.push(-v);
        }
        self.end(s)
    }

    /// `e + f` in linear time (Shewchuk's `fast_expansion_sum_zeroelim`).
    pub fn add(&mut self, e: Exp, f: Exp) -> Exp {
        let s = self.begin();
        if e.len == 0 || f.len == 0 {
            let x = if e.len == 0 { f } else { e };
            for i in x.start..x.start + x.len {
                let v = self.buf[i];
                self.buf.push(v);
            }
            return self.end(s);
        }
        self.buf.reserve(e.len + f.len);
        let (mut ei, mut fi) = (0, 0);
        let at = |buf: &Vec<f64>, x: Exp, i: usize| buf[x.start + i];
        let smaller = |a: f64, b: f64| (b > a) == (b > -a); // |a| < |b| (or equal, then a)
        let mut q;
        let (enow, fnow) = (at(&self.buf, e, 0), at(&self.buf, f, 0));
        if smaller(enow, fnow) {
            q = enow;
            ei += 1;
        } else {
            q = fnow;
            fi += 1;
        }
        let mut first = true;
        while ei < e.len && fi < f.len {
            let (enow, fnow) = (at(&self.buf, e, ei), at(&self.buf, f, fi));
            let next = if smaller(enow, fnow) {
                ei += 1;
                enow
            } else {
                fi += 1;
                fnow
            };
            let (nq, h) = if first {
                fast_two_sum(next, q)
            } else {
                two_sum(q, next)
            };
            first = false;
            q = nq;
            if h != 0.0 {
                self.buf.push(h);
            }
        }
        // At most one of the two has components left.
        let (rest, from) = if ei < e.len { (e, ei) } else { (f, fi) };
        for i in from..rest.len {
            let (nq, h) = two_sum(q, at(&self.buf, rest, i));
            q = nq;
            if h != 0.0 {
                self.buf.push(h);
            }
        }
        if q != 0.0 {
            self.buf.push(q);
        }
        self.end(s)
    }

    /// `e − f`.
    pub fn sub(&mut self, e: Exp, f: Exp) -> Exp {
        let nf = self.neg(f);
        self.add(e, nf)
    }

    /// `e * b` for a single double (Shewchuk's `scale_expansion_zeroelim`).
    pub fn scale(&mut self, e: Exp, b: f64) -> Exp {
        let s = self.begin();
        if e.len == 0 || b == 0.0 {
            return self.end(s);
        }
        self.buf.reserve(2 * e.len);
        let (mut q, h) = two_product(self.buf[e.start], b);
        if h != 0.0 {
            self.buf.push(h);
        }
        for i in e.start + 1..e.start + e.len {
            let (t1, t0) = two_product(self.buf[i], b);
            let (sum, h) = two_sum(q, t0);
            if h != 0.0 {
                self.buf.push(h);
            }
            let (nq, h) = fast_two_sum(t1, sum);
            q = nq;
            if h != 0.0 {
                self.buf.push(h);
            }
        }
        if q != 0.0 {
            self.buf.push(q);
        }
        self.end(s)
    }

    /// `e * f`: the sum of `e` scaled by each component of the shorter `f`.
    pub fn mul(&mut self, e: Exp, f: Exp) -> Exp {
        let (long, short) = if e.len >= f.len { (e, f) } else { (f, e) };
        let mut acc = self.from(0.0);
        for i in short.start..short.start + short.len {
            let b = self.buf[i];
            let part = self.scale(long, b);
            acc = self.add(acc, part);
        }
        acc
    }
}

thread_local! {
    static ARENA: std::cell::RefCell<Arena> = std::cell::RefCell::new(Arena::default());
}

/// Exact sign of the in-sphere determinant in Shewchuk's convention (positive when `e` is
/// inside the sphere through `a, b, c, d` for his positive orientation).
///
/// Two paths: in integers when the coordinates allow it (`insphere_integer`, every case
/// seen on real meshes), otherwise on the differences `p − e` as expansions in a
/// thread-local [`Arena`] (no allocation once warm).
pub fn insphere_sign(a: [f64; 3], b: [f64; 3], c: [f64; 3], d: [f64; 3], e: [f64; 3]) -> f64 {
    ARENA.with(|arena| match arena.try_borrow_mut() {
        Ok(mut ar) => insphere_in(&mut ar, a, b, c, d, e),
        // Re-entered on this thread (cannot happen today): use a fresh arena.
        Err(_) => insphere_in(&mut Arena::default(), a, b, c, d, e),
    })
}

fn insphere_in(
    ar: &mut Arena,
    a: [f64; 3],
    b: [f64; 3],
    c: [f64; 3],
    d: [f64; 3],
    e: [f64; 3],
) -> f64 {
    if let Some(sign) = insphere_integer([a, b, c, d], e) {
        return sign;
    }
    ar.clear();
    let mut rel = |p: [f64; 3]| [0, 1, 2].map(|k| ar.diff(p[k], e[k]));
    let (ae, be, ce, de) = (rel(a), rel(b), rel(c), rel(d));
    let minor = |ar: &mut Arena, p: &[Exp; 3], q: &[Exp; 3]| {
        let x = ar.mul(p[0], q[1]);
        let y = ar.mul(q[0], p[1]);
        ar.sub(x, y)
    };
    let ab = minor(ar, &ae, &be);
    let bc = minor(ar, &be, &ce);
    let cd = minor(ar, &ce, &de);
    let da = minor(ar, &de, &ae);
    let ac = minor(ar, &ae, &ce);
    let bd = minor(ar, &be, &de);
    // x*p + y*q + z*r with signs folded into the minors.
    let triple = |ar: &mut Arena, terms: [(Exp, Exp, bool); 3]| {
        let mut acc = ar.from(0.0);
        for (x, m, negative) in terms {
            let mut t = ar.mul(x, m);
            if negative {
                t = ar.neg(t);
            }
            acc = ar.add(acc, t);
        }
        acc
    };
    let abc = triple(
        ar,
        [(ae[2], bc, false), (be[2], ac, true), (ce[2], ab, false)],
    );
    let bcd = triple(
        ar,
        [(be[2], cd, false), (ce[2], bd, true), (de[2], bc, false)],
    );
    let cda = triple(
        ar,
        [(ce[2], da, false), (de[2], ac, false), (ae[2], cd, false)],
    );
    let dab = triple(
        ar,
        [(de[2], ab, false), (ae[2], bd, false), (be[2], da, false)],
    );
    let lift = |ar: &mut Arena, p: &[Exp; 3]| {
        let x = ar.mul(p[0], p[0]);
        let y = ar.mul(p[1], p[1]);
        let z = ar.mul(p[2], p[2]);
        let xy = ar.add(x, y);
        ar.add(xy, z)
    };
    let (la, lb, lc, ld) = (lift(ar, &ae), lift(ar, &be), lift(ar, &ce), lift(ar, &de));
    let t1 = ar.mul(ld, abc);
    let t2 = ar.mul(lc, dab);
    let t3 = ar.mul(lb, cda);
    let t4 = ar.mul(la, bcd);
    let u = ar.sub(t1, t2);
    let v = ar.sub(t3, t4);
    let det = ar.add(u, v);
    ar.sign(det)
}

/// A signed 384-bit integer in two's complement, little-endian limbs. Arithmetic wraps
/// modulo 2^384, which is exact for every value [`insphere_integer`] forms (at most 2^330).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct I384([u64; 6]);

impl I384 {
    fn from_i128(x: i128) -> Self {
        let fill = if x < 0 { u64::MAX } else { 0 };
        I384([x as u64, (x >> 64) as u64, fill, fill, fill, fill])
    }

    fn add(self, o: Self) -> Self {
        let mut r = [0u64; 6];
        let mut carry = false;
        for (k, rk) in r.iter_mut().enumerate() {
            let (s1, c1) = self.0[k].overflowing_add(o.0[k]);
            let (s2, c2) = s1.overflowing_add(carry as u64);
            *rk = s2;
            carry = c1 || c2;
        }
        I384(r)
    }

    fn neg(self) -> Self {
        let mut r = self.0.map(|x| !x);
        for x in r.iter_mut() {
            let (s, c) = x.overflowing_add(1);
            *x = s;
            if !c {
                break;
            }
        }
        I384(r)
    }

    /// Product modulo 2^384 (schoolbook, the limbs above 384 bits dropped).
    fn mul(self, o: Self) -> Self {
        let mut r = [0u64; 6];
        for i in 0..6 {
            if self.0[i] == 0 {
                continue;
            }
            let mut carry = 0u128;
            for j in 0..6 - i {
                let t = self.0[i] as u128 * o.0[j] as u128 + r[i + j] as u128 + carry;
                r[i + j] = t as u64;
                carry = t >> 64;
            }
        }
        I384(r)
    }

    fn signum(self) -> f64 {
        if self.0[5] >> 63 == 1 {
            -1.0
        } else if self.0.iter().all(|&x| x == 0) {
            0.0
        } else {
            1.0
        }
    }
}

/// The fastest exact path of [`insphere_sign`]: when all fifteen coordinates are integer
/// multiples of one power of two `2^k` below `2^(k+61)` (typical for mesh data: similar
/// exponents), the determinant of the scaled integers (the same sign: it is homogeneous) is
/// evaluated exactly in `i64` differences, `i128` minors and lifted terms, and [`I384`].
/// `None` otherwise.
fn insphere_integer(pts: [[f64; 3]; 4], e: [f64; 3]) -> Option<f64> {
    let (mut lo, mut hi) = (i32::MAX, i32::MIN);
    for x in pts.iter().chain(std::iter::once(&e)).flatten() {
        if *x != 0.0 {
            let bits = x.to_bits();
            let biased = ((bits >> 52) & 0x7ff) as i32;
            if biased == 0 || biased == 0x7ff {
                return None; // subnormal or not finite: leave it to the expansions
            }
            let mant = (bits & ((1u64 << 52) - 1)) | (1u64 << 52);
            let exp = biased - 1075; // x = ±mant · 2^exp
            lo = lo.min(exp + mant.trailing_zeros() as i32);
            hi = hi.max(exp + 53);
        }
    }
    if lo == i32::MAX {
        return Some(0.0); // every coordinate is zero: all five points coincide
    }
    if hi - lo > 61 {
        return None;
    }
    let int = |x: f64| -> i64 {
        if x == 0.0 {
            return 0;
        }
        let bits = x.to_bits();
        let biased = ((bits >> 52) & 0x7ff) as i32;
        let mant = (bits & ((1u64 << 52) - 1)) | (1u64 << 52);
        let shift = biased - 1075 - lo;
        let m = if shift >= 0 {
            (mant << shift) as i64
        } else {
            (mant >> -shift) as i64 // only trailing zeros are shifted out
        };
        if x < 0.0 {
            -m
        } else {
            m
        }
    };
    let ei = e.map(int);
    // |coordinate| < 2^61, so every difference fits in 62 bits.
    let d = pts.map(|p| {
        let pi = p.map(int);
        [pi[0] - ei[0], pi[1] - ei[1], pi[2] - ei[2]]
    });
    let [a, b, c, dd] = d;
    let minor =
        |p: [i64; 3], r: [i64; 3]| p[0] as i128 * r[1] as i128 - r[0] as i128 * p[1] as i128;
    let ab = minor(a, b);
    let bc = minor(b, c);
    let cd = minor(c, dd);
    let da = minor(dd, a);
    let ac = minor(a, c);
    let bd = minor(b, dd);
    let big = |x: i128| I384::from_i128(x);
    let small = |x: i64| I384::from_i128(x as i128);
    let triple = |t: [(i64, i128); 3]| {
        t.iter().fold(I384::from_i128(0), |acc, &(x, m)| {
            acc.add(small(x).mul(big(m)))
        })
    };
    let abc = triple([(a[2], bc), (-b[2], ac), (c[2], ab)]);
    let bcd = triple([(b[2], cd), (-c[2], bd), (dd[2], bc)]);
    let cda = triple([(c[2], da), (dd[2], ac), (a[2], cd)]);
    let dab = triple([(dd[2], ab), (a[2], bd), (b[2], da)]);
    let lift = |p: [i64; 3]| big(p.iter().map(|&x| x as i128 * x as i128).sum::<i128>());
    let det = lift(dd)
        .mul(abc)
        .add(lift(c).mul(dab).neg())
        .add(lift(b).mul(cda))
        .add(lift(a).mul(bcd).neg());
    Some(det.signum())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::random::SplitMix;
    use robust::Coord3D;

    fn c3(p: [f64; 3]) -> Coord3D<f64> {
        Coord3D {
            x: p[0],
            y: p[1],
            z: p[2],
        }
    }

    #[test]
    fn expansion_arithmetic_is_exact() {
        let mut ar = Arena::default();
        let (big, one) = (ar.from(1e16), ar.from(1.0));
        let a = ar.add(big, one);
        let b = ar.sub(a, big);
        assert_eq!(ar.estimate(b), 1.0);
        let (x, y) = (ar.from(1.0 + f64::EPSILON), ar.from(1.0 - f64::EPSILON));
        let sq = ar.mul(x, y);
        // (1+e)(1-e) = 1 - e^2, not representable in one double.
        let d = ar.sub(sq, one);
        assert_eq!(ar.sign(d), -1.0);
        assert_eq!(ar.estimate(d), -f64::EPSILON * f64::EPSILON);
    }

    #[test]
    fn insphere_sign_matches_robust_on_degenerate_and_near_degenerate_input() {
        let mut rng = SplitMix(11);
        let mut u = || (rng.next_u64() >> 11) as f64 / (1u64 << 53) as f64 - 0.5;
        // Exactly cospherical points (Pythagorean), and tiny perturbations of them.
        let sphere = [
            [0.6, 0.8, 0.0],
            [0.0, 0.6, 0.8],
            [0.8, 0.0, 0.6],
            [-0.6, 0.8, 0.0],
            [0.0, -0.6, 0.8],
            [0.8, 0.0, -0.6],
            [-1.0, 0.0, 0.0],
        ];
        for i in 0..2000 {
            let pick = |k: usize| sphere[(i * 7 + k * 3) % sphere.len()];
            let mut e = pick(4);
            if i % 2 == 1 {
                e[i % 3] += u() * 1e-15;
            }
            let (a, b, c, d) = (pick(0), pick(1), pick(2), pick(3));
            let expect = robust::insphere(c3(a), c3(b), c3(c), c3(d), c3(e));
            let expect = if expect > 0.0 {
                1.0
            } else if expect < 0.0 {
                -1.0
            } else {
                0.0
            };
            assert_eq!(insphere_sign(a, b, c, d, e), expect, "case {i}");
        }
        for _ in 0..2000 {
            let p = [0; 5].map(|_| [u(), u(), u()]);
            let expect = robust::insphere(c3(p[0]), c3(p[1]), c3(p[2]), c3(p[3]), c3(p[4]));
            assert_eq!(insphere_sign(p[0], p[1], p[2], p[3], p[4]), expect.signum());
        }
    }

    #[test]
    fn i384_ring_arithmetic_is_signed() {
        let x = I384::from_i128(-(1i128 << 100) - 12345);
        let y = I384::from_i128((1i128 << 90) + 7);
        let p = x.mul(y).mul(x); // positive, about 2^290
        assert_eq!(p.signum(), 1.0);
        assert_eq!(x.mul(y).signum(), -1.0);
        assert_eq!(p.add(p.neg()).signum(), 0.0);
        assert_eq!(x.add(x.neg()), I384::from_i128(0));
        assert_eq!(
            I384::from_i128(-5).add(I384::from_i128(3)),
            I384::from_i128(-2)
        );
    }

    #[test]
    fn every_exact_path_agrees_with_robust_across_scales() {
        // Mixed magnitudes take the expansion paths (spread over 61 bits), uniform ones the
        // integer path; exact ties come from Pythagorean sphere points at scaled copies.
        let mut rng = SplitMix(5);
        let mut u = || (rng.next_u64() >> 11) as f64 / (1u64 << 53) as f64 - 0.5;
        let sphere = [
            [0.6, 0.8, 0.0],
            [0.0, 0.6, 0.8],
            [0.8, 0.0, 0.6],
            [-0.6, 0.8, 0.0],
            [0.0, -0.6, 0.8],
            [-1.0, 0.0, 0.0],
        ];
        let sign = |v: f64| {
            if v > 0.0 {
                1.0
            } else if v < 0.0 {
                -1.0
            } else {
                0.0
            }
        };
        let (mut ties, mut integer) = (0, 0);
        for i in 0..4000 {
            let scale = [1e-30, 1e-3, 1.0, 3.0, 1e5, 1e30][i % 6];
            let offset = [0.0, 1.0, -7.5, 1e-12][i / 6 % 4] * scale;
            let p: [[f64; 3]; 5] = if i % 3 == 0 {
                [0; 5].map(|_| [u(), u(), u()].map(|x| x * scale + offset))
            } else {
                let k = i % 6;
                [0, 1, 2, 3, 4].map(|j| sphere[(k + j) % 6].map(|x| x * scale + offset))
            };
            let mut p = p;
            if i % 5 == 1 {
                p[4][i % 3] += u() * 1e-14 * scale;
            }
            if i % 7 == 2 {
                p[1][0] = 1e-25 * u(); // a wildly different exponent
            }
            let expect = sign(robust::insphere(
                c3(p[0]),
                c3(p[1]),
                c3(p[2]),
                c3(p[3]),
                c3(p[4]),
            ));
            assert_eq!(
                insphere_sign(p[0], p[1], p[2], p[3], p[4]),
                expect,
                "case {i}: {p:?}"
            );
            ties += (expect == 0.0) as usize;
            integer += insphere_integer([p[0], p[1], p[2], p[3]], p[4]).is_some() as usize;
        }
        // Both kinds of path and exact ties were exercised.
        assert!(
            ties > 200 && integer > 1000 && integer < 3800,
            "{ties} ties, {integer} integer"
        );
    }
}
