//! Half-edges by vertex: for each vertex `v`, the directed edges `v → w` of its faces (as
//! compressed rows sorted by `w`), each with the face's third vertex, so that "how many
//! faces have the edge `a → b`" is a short search and walking around a vertex never leaves
//! its row. Validation, orientation repair and hole filling read them.

use rayon::prelude::*;

/// Vertices per block when the rows are sorted and scanned in parallel.
const BLOCK: usize = 4096;

/// The directed edges of a triangle list, grouped by their first vertex.
pub(super) struct HalfEdges {
    /// Row of vertex `v`: `start[v]..start[v + 1]`.
    start: Vec<u32>,
    /// `(w << 32) | x` for each half-edge `v → w` of a face `(v, w, x)`, sorted within a row.
    edge: Vec<u64>,
    /// The face of each half-edge.
    face: Vec<u32>,
}

/// The far end of a half-edge entry.
#[inline]
pub(super) fn target(e: u64) -> u32 {
    (e >> 32) as u32
}

/// The third vertex of a half-edge entry's face (after the far end).
#[inline]
pub(super) fn third(e: u64) -> u32 {
    e as u32
}

/// What the undirected edges of a mesh are like.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(super) struct EdgeCensus {
    /// Unique undirected edges.
    pub edges: usize,
    /// Edges of one face.
    pub boundary: usize,
    /// Edges of more than two faces.
    pub nonmanifold: usize,
    /// Edges of two faces that run the same way along it.
    pub inconsistent: usize,
    /// The smallest example `(a, b)`, `a < b`, of each kind (boundary, non-manifold,
    /// inconsistent).
    pub examples: [Option<(u32, u32)>; 3],
}

impl EdgeCensus {
    /// Every edge is shared by two faces running opposite ways.
    #[cfg(test)]
    pub fn is_clean(&self) -> bool {
        self.boundary == 0 && self.nonmanifold == 0 && self.inconsistent == 0
    }

    fn merge(mut self, o: EdgeCensus) -> EdgeCensus {
        self.edges += o.edges;
        self.boundary += o.boundary;
        self.nonmanifold += o.nonmanifold;
        self.inconsistent += o.inconsistent;
        for k in 0..3 {
            self.examples[k] = match (self.examples[k], o.examples[k]) {
                (Some(a), Some(b)) => Some(a.min(b)),
                (a, b) => a.or(b),
            };
        }
        self
    }

    fn note(&mut self, kind: usize, key: (u32, u32)) {
        match kind {
            0 => self.boundary += 1,
            1 => self.nonmanifold += 1,
            _ => self.inconsistent += 1,
        }
        let e = &mut self.examples[kind];
        *e = Some(e.map_or(key, |old| old.min(key)));
    }
}

impl HalfEdges {
    /// The half-edges of `triangles` over `n` vertices.
    ///
    /// Each thread owns a range of vertices and reads every face, keeping the half-edges
    /// that leave its own vertices: no two threads write the same place.
    pub fn new(n: usize, triangles: &[[u32; 3]]) -> HalfEdges {
        let threads = rayon::current_num_threads().clamp(1, 16);
        let threads = if triangles.len() < 100_000 {
            1
        } else {
            threads
        };
        let ranges: Vec<(u32, u32)> = (0..threads)
            .map(|k| ((n * k / threads) as u32, (n * (k + 1) / threads) as u32))
            .collect();
        // Half-edges leaving each vertex, counted per range.
        let mut start = vec![0u32; n + 1];
        {
            let mut rest = &mut start[1..];
            let mut pieces = Vec::with_capacity(threads);
            for &(lo, hi) in &ranges {
                let (piece, tail) = rest.split_at_mut((hi - lo) as usize);
                pieces.push((lo, hi, piece));
                rest = tail;
            }
            pieces.into_par_iter().for_each(|(lo, hi, piece)| {
                for t in triangles {
                    for &v in t {
                        if v >= lo && v < hi {
                            piece[(v - lo) as usize] += 1;
                        }
                    }
                }
            });
        }
        for i in 0..n {
            start[i + 1] += start[i];
        }
        let mut edge = vec![0u64; triangles.len() * 3];
        let mut face = vec![0u32; triangles.len() * 3];
        {
            let (mut rest_e, mut rest_f) = (&mut edge[..], &mut face[..]);
            let mut pieces = Vec::with_capacity(threads);
            for &(lo, hi) in &ranges {
                let len = (start[hi as usize] - start[lo as usize]) as usize;
                let (e, te) = rest_e.split_at_mut(len);
                let (f, tf) = rest_f.split_at_mut(len);
                pieces.push((lo, hi, e, f));
                (rest_e, rest_f) = (te, tf);
            }
            let start = &start;
            pieces.into_par_iter().for_each(|(lo, hi, e, f)| {
                let base = start[lo as usize];
                let mut fill: Vec<u32> = start[lo as usize..hi as usize]
                    .iter()
                    .map(|&s| s - base)
                    .collect();
                for (k, t) in triangles.iter().enumerate() {
                    for c in 0..3 {
                        let a = t[c];
                        if a >= lo && a < hi {
                            let slot = &mut fill[(a - lo) as usize];
                            e[*slot as usize] =
                                (u64::from(t[(c + 1) % 3]) << 32) | u64::from(t[(c + 2) % 3]);
                            f[*slot as usize] = k as u32;
                            *slot += 1;
                        }
                    }
                }
            });
        }
        // Sort each row by (entry, face): a block of rows per task.
        let mut blocks = Vec::with_capacity(n / BLOCK + 1);
        let (mut rest_e, mut rest_f) = (&mut edge[..], &mut face[..]);
        let mut v = 0;
        while v < n {
            let end = (v + BLOCK).min(n);
            let len = (start[end] - start[v]) as usize;
            let (e, te) = rest_e.split_at_mut(len);
            let (f, tf) = rest_f.split_at_mut(len);
            blocks.push((v, end, e, f));
            (rest_e, rest_f) = (te, tf);
            v = end;
        }
        blocks.into_par_iter().for_each(|(first, end, e, f)| {
            let base = start[first] as usize;
            let mut pairs = Vec::new();
            for v in first..end {
                let (lo, hi) = (start[v] as usize - base, start[v + 1] as usize - base);
                if hi - lo < 2 {
                    continue;
                }
                pairs.clear();
                pairs.extend(e[lo..hi].iter().copied().zip(f[lo..hi].iter().copied()));
                pairs.sort_unstable();
                for (k, &(x, y)) in pairs.iter().enumerate() {
                    e[lo + k] = x;
                    f[lo + k] = y;
                }
            }
        });
        HalfEdges { start, edge, face }
    }

    /// Number of vertices.
    pub fn vertices(&self) -> usize {
        self.start.len() - 1
    }

    fn range(&self, v: u32) -> std::ops::Range<usize> {
        self.start[v as usize] as usize..self.start[v as usize + 1] as usize
    }

    /// The half-edges leaving `v` (see [`target`], [`third`]), sorted.
    pub fn row(&self, v: u32) -> &[u64] {
        &self.edge[self.range(v)]
    }

    /// The entries of `a → b` within `a`'s row.
    fn span(&self, a: u32, b: u32) -> std::ops::Range<usize> {
        let row = self.row(a);
        let from = row.partition_point(|&e| target(e) < b);
        let to = from + row[from..].iter().take_while(|&&e| target(e) == b).count();
        from..to
    }

    /// Faces with the directed edge `a → b`.
    pub fn faces(&self, a: u32, b: u32) -> impl Iterator<Item = u32> + '_ {
        let base = self.range(a).start;
        self.span(a, b).map(move |k| self.face[base + k])
    }

    /// Number of faces with the directed edge `a → b`.
    pub fn count(&self, a: u32, b: u32) -> usize {
        self.span(a, b).len()
    }

    /// Do the faces around `v` form one fan? Follows "the face after" from the first
    /// half-edge (face `(v, a, b)` is followed by the one with `v → b`); edges must be
    /// manifold and consistently oriented.
    pub fn single_fan(&self, v: u32) -> bool {
        let row = self.row(v);
        let Some(&first) = row.first() else {
            return true;
        };
        let mut cur = first;
        for steps in 1..=row.len() {
            let b = third(cur);
            let at = row.partition_point(|&e| target(e) < b);
            match row.get(at) {
                Some(&e) if target(e) == b => cur = e,
                _ => return false,
            }
            if cur == first {
                return steps == row.len();
            }
        }
        false
    }

    /// Number of half-edges.
    pub fn len(&self) -> usize {
        self.edge.len()
    }

    /// Is every edge shared by exactly two faces running opposite ways, and every vertex's
    /// faces one fan? One pass over the rows, each vertex on its own: a row without repeated
    /// targets whose fan walk closes over all of it has, for every face `(v, a, b)`, the
    /// neighbour across `v-b` running the other way; with no repeats anywhere, no edge has a
    /// third face. When this says no, [`HalfEdges::census`] and [`HalfEdges::single_fan`]
    /// say what is wrong.
    pub fn is_closed_manifold(&self) -> bool {
        let n = self.vertices();
        (0..n.div_ceil(BLOCK)).into_par_iter().all(|b| {
            ((b * BLOCK) as u32..((b + 1) * BLOCK).min(n) as u32).all(|v| {
                let row = self.row(v);
                row.windows(2).all(|w| target(w[0]) != target(w[1])) && self.single_fan(v)
            })
        })
    }

    /// Classifies every undirected edge whose first vertex passes `keep` (in parallel).
    ///
    /// Each edge is looked up from its smaller end only; the half-edges this cannot see
    /// (those from the larger end when none runs back) are counted, and only when there
    /// are some does a second pass find them.
    pub fn census(&self, keep: &(dyn Fn(u32) -> bool + Sync)) -> EdgeCensus {
        let n = self.vertices();
        let (census, seen) = (0..n.div_ceil(BLOCK))
            .into_par_iter()
            .map(|b| {
                let mut c = EdgeCensus::default();
                let mut seen = 0usize;
                let mut kept = 0usize;
                for a in (b * BLOCK) as u32..((b + 1) * BLOCK).min(n) as u32 {
                    if !keep(a) {
                        continue;
                    }
                    let row = self.row(a);
                    kept += row.len();
                    let mut k = 0;
                    while k < row.len() {
                        let w = target(row[k]);
                        let run = row[k..].iter().take_while(|&&e| target(e) == w).count();
                        k += run;
                        if w < a {
                            continue;
                        }
                        let back = self.count(w, a);
                        seen += run + back;
                        c.edges += 1;
                        if let Some(kind) = kind(run, back) {
                            c.note(kind, (a, w));
                        }
                    }
                }
                (c, (seen, kept))
            })
            .reduce(
                || (EdgeCensus::default(), (0, 0)),
                |x, y| (x.0.merge(y.0), (x.1 .0 + y.1 .0, x.1 .1 + y.1 .1)),
            );
        if seen.0 == seen.1 {
            return census;
        }
        // Edges seen only from their larger end: a → w, w < a, with nothing from w to a.
        (0..n.div_ceil(BLOCK))
            .into_par_iter()
            .map(|b| {
                let mut c = EdgeCensus::default();
                for a in (b * BLOCK) as u32..((b + 1) * BLOCK).min(n) as u32 {
                    if !keep(a) {
                        continue;
                    }
                    let row = self.row(a);
                    let mut k = 0;
                    while k < row.len() {
                        let w = target(row[k]);
                        let run = row[k..].iter().take_while(|&&e| target(e) == w).count();
                        k += run;
                        if w < a && self.count(w, a) == 0 {
                            c.edges += 1;
                            if let Some(kind) = kind(run, 0) {
                                c.note(kind, (w, a));
                            }
                        }
                    }
                }
                c
            })
            .reduce(|| census, EdgeCensus::merge)
    }
}

/// The kind of problem of an edge with `run` half-edges one way and `back` the other:
/// `None` for a good edge, 0 boundary, 1 non-manifold, 2 inconsistent.
fn kind(run: usize, back: usize) -> Option<usize> {
    match (run, back) {
        (1, 1) => None,
        (1, 0) | (0, 1) => Some(0),
        (2, 0) | (0, 2) => Some(2),
        _ => Some(1),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn census_of_small_cases() {
        let tetra = [[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]];
        let h = HalfEdges::new(4, &tetra);
        let c = h.census(&|_| true);
        assert_eq!(c.edges, 6);
        assert!(c.is_clean());
        assert!(h.is_closed_manifold());
        assert_eq!(h.count(0, 2), 1);
        assert_eq!(h.faces(2, 0).collect::<Vec<_>>(), vec![2]);
        assert!((0..4).all(|v| h.single_fan(v)));
        let open = &tetra[..3];
        assert!(!HalfEdges::new(4, open).is_closed_manifold());
        let c = HalfEdges::new(4, open).census(&|_| true);
        assert_eq!((c.edges, c.boundary), (6, 3));
        assert_eq!(c.examples[0], Some((1, 2)));
        let mut flipped = tetra;
        flipped[3] = [1, 3, 2];
        assert!(!HalfEdges::new(4, &flipped).is_closed_manifold());
        let c = HalfEdges::new(4, &flipped).census(&|_| true);
        assert_eq!(c.inconsistent, 3);
        assert_eq!(c.edges, 6);
        let fin = [[0, 1, 2], [1, 0, 2], [0, 1, 3]];
        assert!(!HalfEdges::new(4, &fin).is_closed_manifold());
        let c = HalfEdges::new(4, &fin).census(&|_| true);
        assert_eq!(c.nonmanifold, 1);
        assert_eq!(c.examples[1], Some((0, 1)));
        // Two tetrahedra sharing vertex 0: two fans there.
        let mut bowtie = tetra.to_vec();
        bowtie.extend([[0, 4, 5], [0, 6, 4], [0, 5, 6], [4, 6, 5]]);
        let h = HalfEdges::new(7, &bowtie);
        assert!(h.census(&|_| true).is_clean());
        assert!(!h.is_closed_manifold());
        assert!(!h.single_fan(0));
        assert!((1..7).all(|v| h.single_fan(v)));
    }

    #[test]
    fn census_sees_edges_from_either_end() {
        // Faces whose edges run only from the larger vertex to the smaller.
        let tris = [[2, 1, 0], [3, 1, 0]];
        let c = HalfEdges::new(4, &tris).census(&|_| true);
        assert_eq!(c.edges, 5);
        assert_eq!(c.inconsistent, 1);
        assert_eq!(c.examples[2], Some((0, 1)));
        assert_eq!(c.boundary, 4);
    }
}
