//! The parallel phases: after a serial start, two workers insert the points in doubling
//! phases, one per side of a median plane, each touching only tetrahedra whose vertices
//! are all on its side; what would touch anything else is deferred and inserted serially
//! after the phase (see [`super::Delaunay`] for why the result does not depend on the
//! thread count or on timing).

use super::build::Builder;
use super::cavity::{Outcome, Worker};
use super::cell::{Cell, Tets, FREE, UNSEEN};
use super::hook::EdgeHook;
use super::{Delaunay, INFINITE};
use glam::DVec3;
use rayon::prelude::*;
use std::sync::atomic::{AtomicBool, Ordering};

/// Owner of a slot in the parallel phases: a side (0 or 1) when every finite vertex of its
/// tetrahedron lies on that side of the split plane, `MIXED` otherwise (and for free slots
/// that belong to no worker).
pub(super) const MIXED: u8 = 2;

/// Below this many points the insertion is serial: the phases would cost more than they
/// save.
const PARALLEL_MIN: usize = 1 << 15;

/// The owner label of a tetrahedron with vertices `v`, given each vertex's side.
pub(super) fn owner_of(side: &[u8], v: [u32; 4]) -> u8 {
    if v[0] == FREE {
        return MIXED;
    }
    let sides = v
        .iter()
        .filter(|&&x| x != INFINITE)
        .fold(0u8, |acc, &x| acc | 1 << side[x as usize]);
    match sides {
        1 => 0,
        2 => 1,
        _ => MIXED,
    }
}

/// Appends `add` free records (labelled `label` when labels are kept); returns the first.
pub(super) fn grow(
    cells: &mut Vec<Cell>,
    mark: &mut Vec<u8>,
    owner: Option<&mut Vec<u8>>,
    add: usize,
    label: u8,
) -> usize {
    let start = cells.len();
    cells.resize(start + add, Cell::FREE);
    mark.resize(start + add, UNSEEN);
    if let Some(owner) = owner {
        owner.resize(start + add, label);
    }
    start
}

/// Is `t` a live finite tetrahedron?
pub(super) fn live_finite(cells: &[Cell], t: u32) -> bool {
    cells.get(t as usize).is_some_and(Cell::is_live_finite)
}

/// Where the parallel phases start for `n` points: after the first sixteenth, or never
/// below [`PARALLEL_MIN`].
pub(super) fn first_parallel(n: usize) -> usize {
    if n >= PARALLEL_MIN {
        n / 16
    } else {
        n
    }
}

/// The side of each point of `pts` of the plane through their median along `axis`: side 1
/// when the coordinate is at least the median.
fn median_sides(pts: &[DVec3], axis: usize) -> Vec<u8> {
    let mut coords: Vec<f64> = pts.iter().map(|p| p[axis]).collect();
    let mid = coords.len() / 2;
    let split = match coords.is_empty() {
        true => 0.0,
        false => *coords.select_nth_unstable_by(mid, f64::total_cmp).1,
    };
    pts.par_iter().map(|p| u8::from(p[axis] >= split)).collect()
}

/// State of the parallel phases: the points are split by a plane into two sides; a worker
/// per side inserts that side's points, touching only tetrahedra whose finite vertices are
/// all on its side.
pub(super) struct Parallel {
    /// Side of each point (internal ids) of the median plane chosen by
    /// `Builder::start_parallel` (see [`median_sides`]).
    pub side: Vec<u8>,
    /// Owner label of each slot (see [`MIXED`]); as long as the records.
    pub owner: Vec<u8>,
    pub workers: [Worker; 2],
}

impl<H: EdgeHook> Builder<'_, H> {
    /// Splits the points by a median plane and labels every slot (see [`Parallel`]); the
    /// insertions keep the labels up to date from then on.
    ///
    /// Of the three axes, the plane cuts the fewest tetrahedra inserted so far: a point
    /// whose cavity meets a cut tetrahedron is deferred, and the cuts so far predict the
    /// later ones.
    pub fn start_parallel(&mut self) {
        let n = self.result.pts.len();
        let cells = &self.result.cells;
        let cut = |side: &[u8]| {
            cells
                .par_iter()
                .filter(|c| c.v[0] != FREE && owner_of(side, c.v) == MIXED)
                .count()
        };
        let side = (0..3)
            .map(|axis| median_sides(&self.result.pts, axis))
            .min_by_key(|side| cut(side))
            .unwrap_or_default();
        let owner = self
            .result
            .cells
            .par_iter()
            .map(|c| owner_of(&side, c.v))
            .collect();
        self.par = Some(Box::new(Parallel {
            side,
            owner,
            workers: [
                Worker::new(0, 0x0A11_CE00, n),
                Worker::new(1, 0x0B0B_0000, n),
            ],
        }));
    }

    /// Inserts the points `lo..hi` (internal ids): a parallel round split by the median
    /// plane of all points, then the deferred ones serially (a second parallel round for
    /// them, split across the first plane, defers too many of them again to pay).
    pub fn phase(&mut self, lo: usize, hi: usize, idle: &(dyn Fn() -> bool + Sync)) {
        let deferred = self.round((lo as u32..hi as u32).collect(), idle);
        #[cfg(test)]
        {
            self.result.deferred += deferred.len();
        }
        let clock = std::time::Instant::now();
        for &p in &deferred {
            self.insert(p);
        }
        log::debug!(
            "delaunay: phase {lo}..{hi}: {} serial, {:.1} ms",
            deferred.len(),
            clock.elapsed().as_secs_f64() * 1e3
        );
    }

    /// Inserts the points `seq` (internal ids, in insertion order) on both workers by the
    /// current labels; returns the deferred ones, in insertion order. Leaves the serial
    /// walk's hint on a live tetrahedron. Runs `idle` while waiting for the other worker.
    fn round(&mut self, points: Vec<u32>, idle: &(dyn Fn() -> bool + Sync)) -> Vec<u32> {
        let Builder {
            result:
                Delaunay {
                    pts,
                    input_id,
                    cells,
                    duplicate_of,
                    ..
                },
            mark,
            serial,
            par,
            hook,
            ..
        } = self;
        let hook: &H = hook;
        let Some(par) = par.as_deref_mut() else {
            return points;
        };
        let count = points.len();
        let mut seq: [Vec<u32>; 2] = [Vec::new(), Vec::new()];
        for p in points {
            seq[par.side[p as usize] as usize].push(p);
        }
        let mut deferred = Vec::new();
        for (s, seq) in seq.iter_mut().enumerate() {
            let worker = &mut par.workers[s];
            // Enough free slots labelled with this side (about 6.5 new tetrahedra per point
            // on average; a worker that runs out defers the rest).
            let need = 8 * seq.len() + 1024;
            if worker.free.len() < need {
                let add = need - worker.free.len();
                let start = grow(cells, mark, Some(&mut par.owner), add, s as u8) as u32;
                worker.free.splice(0..0, (start..start + add as u32).rev());
            }
            // Walks start from a tetrahedron of this side.
            let ours = |t: u32| live_finite(cells, t) && par.owner[t as usize] == s as u8;
            if !ours(worker.hint) {
                match (0..cells.len() as u32).rev().find(|&t| ours(t)) {
                    Some(t) => worker.hint = t,
                    None => deferred.append(seq), // nothing of this side yet
                }
            }
        }
        let tets = Tets::new(cells, mark);
        let owner = &par.owner[..];
        let run = |w: &mut Worker, seq: &[u32]| {
            let (mut deferred, mut duplicates) = (Vec::new(), Vec::new());
            for &p in seq {
                // SAFETY: both workers hold `tets` over the same live arrays, which nothing
                // else touches until both return; `owner` labels every slot as
                // `Worker::insert` requires (set by `start_parallel`, kept up to date by
                // `Builder::insert` and by the workers, the fresh slots above labelled with
                // their worker's side), and each worker has its own side and free list.
                match unsafe { w.insert::<true, H>(tets, owner, pts, hook, p) } {
                    Outcome::Inserted => {}
                    Outcome::Duplicate(v) => duplicates.push((p, v)),
                    Outcome::Blocked | Outcome::NeedSlots(_) => deferred.push(p),
                }
            }
            (deferred, duplicates)
        };
        let [w0, w1] = &mut par.workers;
        let clock = std::time::Instant::now();
        // Side 1 runs on another thread if one takes it, else after side 0 on this one.
        let (started, finished) = (AtomicBool::new(false), AtomicBool::new(false));
        let ((d0, u0), (d1, u1)) = rayon::join(
            || {
                let done = run(w0, &seq[0]);
                while started.load(Ordering::Relaxed) && !finished.load(Ordering::Relaxed) {
                    if !idle() {
                        break;
                    }
                }
                done
            },
            || {
                started.store(true, Ordering::Relaxed);
                let done = run(w1, &seq[1]);
                finished.store(true, Ordering::Relaxed);
                done
            },
        );
        for (p, v) in u0.into_iter().chain(u1) {
            duplicate_of[input_id[p as usize] as usize] = input_id[v as usize];
        }
        deferred.extend(d0.into_iter().chain(d1));
        deferred.sort_unstable();
        log::debug!(
            "delaunay: {count} points in parallel, {:.1} ms, {} deferred",
            clock.elapsed().as_secs_f64() * 1e3,
            deferred.len()
        );
        // The serial walk starts from a tetrahedron still alive.
        let hint = [serial.hint, w0.hint, w1.hint]
            .into_iter()
            .find(|&t| live_finite(cells, t))
            .or_else(|| (0..cells.len() as u32).find(|&t| live_finite(cells, t)));
        serial.hint = hint.unwrap_or(0);
        deferred
    }

    /// Ends the parallel phases: the workers' free slots go to the serial list.
    pub fn end_parallel(&mut self) {
        if let Some(par) = self.par.take() {
            for w in par.workers {
                self.serial.free.extend(w.free);
                #[cfg(test)]
                {
                    self.result.sorted_links += w.sorted_links;
                }
            }
        }
    }
}
