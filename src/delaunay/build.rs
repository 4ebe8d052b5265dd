//! Building a tetrahedralization: the insertion order (BRIO + Hilbert, the first simplex
//! first), the serial insertions, and the hand-over to the parallel phases. The
//! [`Builder`] holds what only the build needs (cavity marks, the workers, the hook) apart
//! from the result.

use super::cavity::{Outcome, Worker};
use super::cell::{Cell, Tets, NONE, UNSEEN};
use super::hook::EdgeHook;
use super::parallel::{grow, owner_of, Parallel, MIXED};
use super::{Delaunay, DelaunayError, FACE, INFINITE};
use crate::geom::hilbert::brio_order;
use crate::geom::predicates::{collinear, orient3d};
use glam::DVec3;

/// A tetrahedralization being built.
pub(super) struct Builder<'h, H> {
    pub result: Delaunay,
    /// Cavity marks, one per record (all `UNSEEN` between insertions).
    pub mark: Vec<u8>,
    /// The serial insertion's worker.
    pub serial: Worker,
    /// Present during the parallel phases.
    pub par: Option<Box<Parallel>>,
    pub hook: &'h H,
}

/// Tetrahedralizes `points` with the parallel phases starting at insertion
/// `first_parallel` (none when it is `points.len()` or more); the hook is made from the
/// input index of each point in insertion order and told of every edge.
pub(super) fn build<H: EdgeHook>(
    points: &[DVec3],
    progress: &dyn Fn(f64),
    idle: &(dyn Fn() -> bool + Sync),
    first_parallel: usize,
    make_hook: impl FnOnce(&[u32]) -> H,
) -> Result<(Delaunay, H), DelaunayError> {
    let n = points.len();
    if n < 4 {
        return Err(DelaunayError::TooFew(n));
    }
    if n >= (u32::MAX / 2) as usize {
        return Err(DelaunayError::TooMany(n));
    }
    if let Some(i) = points.iter().position(|p| !p.is_finite()) {
        return Err(DelaunayError::NonFinite(i));
    }
    let mut order = brio_order(points, 0x5EED_CAFE);
    let p0 = points[order[0] as usize];
    let k1 = order
        .iter()
        .position(|&i| points[i as usize] != p0)
        .ok_or(DelaunayError::Flat("identical"))?;
    let p1 = points[order[k1] as usize];
    let k2 = order
        .iter()
        .position(|&i| !collinear(p0, p1, points[i as usize]))
        .ok_or(DelaunayError::Flat("collinear"))?;
    let p2 = points[order[k2] as usize];
    let k3 = order
        .iter()
        .position(|&i| orient3d(p0, p1, p2, points[i as usize]) != 0.0)
        .ok_or(DelaunayError::Flat("coplanar"))?;
    // Move the first simplex to the front, keep the rest in BRIO order.
    let first = [order[0], order[k1], order[k2], order[k3]];
    let mut rest: Vec<u32> = Vec::with_capacity(n);
    rest.extend_from_slice(&first);
    for (k, &i) in order.iter().enumerate() {
        if k != 0 && k != k1 && k != k2 && k != k3 {
            rest.push(i);
        }
    }
    order = rest;

    let hook = make_hook(&order);
    let mut b = Builder {
        result: Delaunay {
            pts: order.iter().map(|&i| points[i as usize]).collect(),
            input_id: order,
            // The parallel phases leave some slots unused: 8 per point is enough for the
            // inputs measured (only address space until used).
            cells: Vec::with_capacity(8 * n),
            duplicate_of: vec![NONE; n],
            free: 0,
            #[cfg(test)]
            deferred: 0,
            #[cfg(test)]
            sorted_links: 0,
        },
        mark: Vec::with_capacity(8 * n),
        serial: Worker::new(MIXED, 0x1234_5678, n),
        par: None,
        hook: &hook,
    };
    b.init_simplex([0, 1, 2, 3]);
    let step = (n / 64).max(1 << 14);
    let serial_end = first_parallel.clamp(4, n);
    for k in 4..serial_end {
        b.insert(k as u32);
        if k % step == 0 {
            progress(k as f64 / n as f64);
        }
    }
    if serial_end < n {
        b.start_parallel();
        let mut lo = serial_end;
        while lo < n {
            // Doubling phases; a last one of less than half the previous joins it.
            let hi = if 3 * lo > n { n } else { 2 * lo };
            b.phase(lo, hi, idle);
            progress(hi as f64 / n as f64);
            lo = hi;
        }
        b.end_parallel();
    }
    progress(1.0);
    let mut result = b.result;
    result.free = b.serial.free.len();
    #[cfg(test)]
    {
        result.sorted_links += b.serial.sorted_links;
    }
    Ok((result, hook))
}

impl<H: EdgeHook> Builder<'_, H> {
    fn init_simplex(&mut self, v: [u32; 4]) {
        let [a, b, mut c, mut d] = v;
        let p = |v: u32| self.result.pts[v as usize];
        if orient3d(p(a), p(b), p(c), p(d)) < 0.0 {
            std::mem::swap(&mut c, &mut d);
        }
        let t0 = [a, b, c, d];
        let mut ids = vec![self.push(t0)];
        for f in FACE {
            let (x, y, z) = (t0[f[0]], t0[f[1]], t0[f[2]]);
            ids.push(self.push([x, z, y, INFINITE]));
        }
        for &t in &ids {
            for i in 0..4 {
                let face = self.result.face_key(t, i);
                for &u in &ids {
                    if u == t {
                        continue;
                    }
                    for j in 0..4 {
                        if self.result.face_key(u, j) == face {
                            self.result.cells[t as usize].n[i] = u;
                        }
                    }
                }
            }
        }
        self.serial.hint = ids[0];
        // The first edges are made here, not by an insertion.
        for (i, &a) in t0.iter().enumerate() {
            for &b in &t0[i + 1..] {
                // SAFETY: nothing else runs.
                unsafe { self.hook.edge(&self.result.pts, a, b) };
            }
        }
    }

    fn push(&mut self, v: [u32; 4]) -> u32 {
        self.result.cells.push(Cell { v, n: [NONE; 4] });
        self.mark.push(UNSEEN);
        (self.result.cells.len() - 1) as u32
    }

    /// Inserts internal point `p` on this thread.
    pub fn insert(&mut self, p: u32) {
        loop {
            let tets = Tets::new(&mut self.result.cells, &mut self.mark);
            // SAFETY: no other thread runs, and the arrays are not touched otherwise
            // during the call.
            let outcome = unsafe {
                self.serial
                    .insert::<false, H>(tets, &[], &self.result.pts, self.hook, p)
            };
            match outcome {
                Outcome::Inserted => {
                    if let Some(par) = &mut self.par {
                        for &t in &self.serial.created {
                            let v = self.result.cells[t as usize].v;
                            par.owner[t as usize] = owner_of(&par.side, v);
                        }
                    }
                    return;
                }
                Outcome::Duplicate(v) => {
                    let result = &mut self.result;
                    result.duplicate_of[result.input_id[p as usize] as usize] =
                        result.input_id[v as usize];
                    return;
                }
                Outcome::NeedSlots(k) => {
                    // Between parallel rounds, from the workers' spare slots first: free,
                    // and relabelled above once used. Growing could move the whole array.
                    if let Some(par) = &mut self.par {
                        let [a, b] = &mut par.workers;
                        let spare = if a.free.len() >= b.free.len() { a } else { b };
                        if spare.free.len() >= k {
                            let at = spare.free.len() - k.max(256).min(spare.free.len());
                            self.serial.free.splice(0..0, spare.free.drain(at..));
                            continue;
                        }
                    }
                    // Grow in chunks (few retries); the new slots go under the freed ones,
                    // which are reused first.
                    let add = k.max(self.result.cells.len() / 64).max(256);
                    let owner = self.par.as_mut().map(|par| &mut par.owner);
                    let start =
                        grow(&mut self.result.cells, &mut self.mark, owner, add, MIXED) as u32;
                    let fresh = (start..start + add as u32).rev();
                    self.serial.free.splice(0..0, fresh);
                }
                Outcome::Blocked => return, // only with CHECKED
            }
        }
    }
}
