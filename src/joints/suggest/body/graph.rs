//! The skeletal graph the suggestion walks: the mesh's edges, each as long as it is in
//! local medial radii, and shortest paths over it (Dijkstra).

use crate::mesh::Mesh;
use glam::DVec3;
use std::cmp::Ordering;
use std::collections::BinaryHeap;

/// A mesh's skeletal graph: `S`'s edges as a CSR with their lengths.
#[derive(Clone)]
pub(crate) struct Graph {
    pub(crate) start: Vec<u32>,
    pub(crate) to: Vec<u32>,
    pub(crate) len: Vec<f64>,
}

impl Graph {
    /// The mesh's edges and its `attachments` (where its separate parts meet:
    /// [`crate::mesh::attachments`]), each as long as it is in units of the skeletal
    /// distance at its ends: a step of one is about one local radius, across a fat body or
    /// a thin finger.
    pub(crate) fn new(
        mesh: &Mesh,
        attachments: &[(u32, u32)],
        points: &[DVec3],
        distance: &[f64],
    ) -> Graph {
        let n = points.len();
        let mut positive: Vec<f64> = distance.iter().copied().filter(|d| *d > 0.0).collect();
        let floor = 1e-3 * crate::stats::median(&mut positive).unwrap_or(1.0);
        // The mesh's edges, and where its separate parts meet.
        let mut edges = crate::mesh::unique_edges(&mesh.triangles);
        edges.extend_from_slice(attachments);
        let (start, to) = crate::mesh::neighbours(n, &edges);
        let mut len = vec![0.0; to.len()];
        for a in 0..n {
            for k in start[a] as usize..start[a + 1] as usize {
                let b = to[k] as usize;
                let thickness = 0.5 * (distance[a] + distance[b]);
                len[k] = points[a].distance(points[b]) / thickness.max(floor);
            }
        }
        Graph { start, to, len }
    }

    pub(crate) fn neighbours(&self, v: usize) -> impl Iterator<Item = (usize, f64)> + '_ {
        let (a, b) = (self.start[v] as usize, self.start[v + 1] as usize);
        self.to[a..b]
            .iter()
            .zip(&self.len[a..b])
            .map(|(&t, &l)| (t as usize, l))
    }

    /// Shortest-path lengths from `source` (infinite where unreachable), and each vertex's
    /// predecessor on its path.
    pub(crate) fn distances(&self, source: usize) -> (Vec<f64>, Vec<u32>) {
        self.distances_from(&[(source as u32, 0.0)])
    }

    /// Shortest-path lengths from several sources, each starting at its own distance.
    pub(crate) fn distances_from(&self, sources: &[(u32, f64)]) -> (Vec<f64>, Vec<u32>) {
        let n = self.start.len() - 1;
        let mut dist = vec![f64::INFINITY; n];
        let mut pred = vec![u32::MAX; n];
        let mut heap = BinaryHeap::new();
        for &(v, d) in sources {
            if d < dist[v as usize] {
                dist[v as usize] = d;
                heap.push(Item(d, v));
            }
        }
        while let Some(Item(d, v)) = heap.pop() {
            let v = v as usize;
            if d > dist[v] {
                continue;
            }
            for (w, l) in self.neighbours(v) {
                let nd = d + l;
                if nd < dist[w] {
                    dist[w] = nd;
                    pred[w] = v as u32;
                    heap.push(Item(nd, w as u32));
                }
            }
        }
        (dist, pred)
    }
}

/// A heap entry ordered by smallest distance first.
#[derive(PartialEq)]
struct Item(f64, u32);

impl Eq for Item {}

impl PartialOrd for Item {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

impl Ord for Item {
    fn cmp(&self, other: &Self) -> Ordering {
        other.0.total_cmp(&self.0).then(other.1.cmp(&self.1))
    }
}

/// The farthest reachable vertex.
pub(crate) fn farthest(dist: &[f64]) -> usize {
    (0..dist.len())
        .filter(|&v| dist[v].is_finite())
        .max_by(|&a, &b| dist[a].total_cmp(&dist[b]))
        .unwrap_or(0)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::shapes;

    #[test]
    fn edges_are_measured_in_local_radii() {
        let mesh = shapes::icosphere(2.0, 1);
        let n = mesh.positions.len();
        // Every skeletal distance 0.5: an edge of length l is 2 l long.
        let graph = Graph::new(&mesh, &[], &mesh.positions, &vec![0.5; n]);
        for v in 0..n {
            for (w, l) in graph.neighbours(v) {
                let want = mesh.positions[v].distance(mesh.positions[w]) / 0.5;
                assert!((l - want).abs() < 1e-12, "{v}-{w}: {l} vs {want}");
            }
        }
    }

    #[test]
    fn shortest_paths_are_shortest_and_follow_their_predecessors() {
        let mesh = shapes::icosphere(1.0, 2);
        let n = mesh.positions.len();
        let graph = Graph::new(&mesh, &[], &mesh.positions, &vec![1.0; n]);
        let (dist, pred) = graph.distances(0);
        assert_eq!(dist[0], 0.0);
        for v in 1..n {
            // Each distance is its predecessor's plus the edge between them, and no
            // neighbour offers a shorter one (Bellman's optimality).
            let p = pred[v] as usize;
            let edge = graph.neighbours(p).find(|&(w, _)| w == v).unwrap().1;
            assert!((dist[v] - (dist[p] + edge)).abs() < 1e-12);
            for (w, l) in graph.neighbours(v) {
                assert!(dist[v] <= dist[w] + l + 1e-12);
            }
        }
        // The farthest vertex from a pole of the sphere is near the other pole.
        let far = farthest(&dist);
        assert!(mesh.positions[far].distance(-mesh.positions[0]) < 0.5);
        // Several sources: each vertex's distance is the nearest source's.
        let (two, _) = graph.distances_from(&[(0, 0.0), (far as u32, 0.0)]);
        let (other, _) = graph.distances(far);
        for v in 0..n {
            assert_eq!(two[v], dist[v].min(other[v]));
        }
    }

    #[test]
    fn unreachable_vertices_are_infinitely_far() {
        let graph = Graph {
            start: vec![0, 1, 2, 2],
            to: vec![1, 0],
            len: vec![1.0, 1.0],
        };
        let (dist, _) = graph.distances(0);
        assert_eq!(dist, vec![0.0, 1.0, f64::INFINITY]);
        assert_eq!(farthest(&dist), 1);
    }
}
