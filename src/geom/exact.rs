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

/// An exact value as an expansion.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Expansion(Vec<f64>);

impl Expansion {
    /// The exact value of `a`.
    pub fn from(a: f64) -> Self {
        Expansion(if a == 0.0 { Vec::new() } else { vec![a] })
    }

    /// The exact value of `a − b`.
    pub fn diff(a: f64, b: f64) -> Self {
        let x = a - b;
        let bv = a - x;
        let av = x + bv;
        let y = (a - av) + (bv - b);
        let mut v = Vec::with_capacity(2);
        if y != 0.0 {
            v.push(y);
        }
        if x != 0.0 {
            v.push(x);
        }
        Expansion(v)
    }

    /// Sign: -1, 0 or 1.
    pub fn sign(&self) -> f64 {
        match self.0.last() {
            Some(&x) if x > 0.0 => 1.0,
            Some(&x) if x < 0.0 => -1.0,
            _ => 0.0,
        }
    }

    /// Approximate value.
    pub fn estimate(&self) -> f64 {
        self.0.iter().sum()
    }

    fn grow(&mut self, b: f64) {
        let mut q = b;
        let mut out = Vec::with_capacity(self.0.len() + 1);
        for &e in &self.0 {
            let (s, h) = two_sum(q, e);
            q = s;
            if h != 0.0 {
                out.push(h);
            }
        }
        if q != 0.0 {
            out.push(q);
        }
        self.0 = out;
    }

    /// `self + other`.
    pub fn add(&self, other: &Expansion) -> Expansion {
        let (mut acc, small) = if self.0.len() >= other.0.len() {
            (self.clone(), other)
        } else {
            (other.clone(), self)
        };
        for &b in &small.0 {
            acc.grow(b);
        }
        acc
    }

    /// `-self`.
    pub fn neg(&self) -> Expansion {
        Expansion(self.0.iter().map(|x| -x).collect())
    }

    /// `self - other`.
    pub fn sub(&self, other: &Expansion) -> Expansion {
        self.add(&other.neg())
    }

    /// `self * b` for a single double.
    pub fn scale(&self, b: f64) -> Expansion {
        let mut out = Vec::with_capacity(2 * self.0.len());
        let mut it = self.0.iter();
        let Some(&e0) = it.next() else {
            return Expansion::default();
        };
        let (mut q, h) = two_product(e0, b);
        if h != 0.0 {
            out.push(h);
        }
        for &e in it {
            let (t1, t0) = two_product(e, b);
            let (sum, h) = two_sum(q, t0);
            if h != 0.0 {
                out.push(h);
            }
            let (nq, h) = fast_two_sum(t1, sum);
            q = nq;
            if h != 0.0 {
                out.push(h);
            }
        }
        if q != 0.0 {
            out.push(q);
        }
        Expansion(out)
    }

    /// `self * other`.
    pub fn mul(&self, other: &Expansion) -> Expansion {
        let (long, short) = if self.0.len() >= other.0.len() {
            (self, other)
        } else {
            (other, self)
        };
        let mut acc = Expansion::default();
        for &b in &short.0 {
            acc = acc.add(&long.scale(b));
        }
        acc
    }
}

/// Exact sign of the in-sphere determinant in Shewchuk's convention (positive when `e` is
/// inside the sphere through `a, b, c, d` for his positive orientation).
pub fn insphere_sign(a: [f64; 3], b: [f64; 3], c: [f64; 3], d: [f64; 3], e: [f64; 3]) -> f64 {
    let rel = |p: [f64; 3]| [0, 1, 2].map(|k| Expansion::diff(p[k], e[k]));
    let (ae, be, ce, de) = (rel(a), rel(b), rel(c), rel(d));
    let minor = |p: &[Expansion; 3], q: &[Expansion; 3]| p[0].mul(&q[1]).sub(&q[0].mul(&p[1]));
    let ab = minor(&ae, &be);
    let bc = minor(&be, &ce);
    let cd = minor(&ce, &de);
    let da = minor(&de, &ae);
    let ac = minor(&ae, &ce);
    let bd = minor(&be, &de);
    let abc = ae[2].mul(&bc).sub(&be[2].mul(&ac)).add(&ce[2].mul(&ab));
    let bcd = be[2].mul(&cd).sub(&ce[2].mul(&bd)).add(&de[2].mul(&bc));
    let cda = ce[2].mul(&da).add(&de[2].mul(&ac)).add(&ae[2].mul(&cd));
    let dab = de[2].mul(&ab).add(&ae[2].mul(&bd)).add(&be[2].mul(&da));
    let lift = |p: &[Expansion; 3]| p[0].mul(&p[0]).add(&p[1].mul(&p[1])).add(&p[2].mul(&p[2]));
    let det = lift(&de)
        .mul(&abc)
        .sub(&lift(&ce).mul(&dab))
        .add(&lift(&be).mul(&cda).sub(&lift(&ae).mul(&bcd)));
    det.sign()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::hilbert::SplitMix;
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
        let a = Expansion::from(1e16).add(&Expansion::from(1.0));
        let b = a.sub(&Expansion::from(1e16));
        assert_eq!(b.estimate(), 1.0);
        let sq = Expansion::from(1.0 + f64::EPSILON).mul(&Expansion::from(1.0 - f64::EPSILON));
        // (1+e)(1-e) = 1 - e^2, not representable in one double.
        assert_eq!(sq.sub(&Expansion::from(1.0)).sign(), -1.0);
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
}
