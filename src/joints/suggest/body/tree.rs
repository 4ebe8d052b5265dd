//! The join tree of `g` (stage 2, see the module docs): the root and the body's core, `g`
//! (the distance from the core in local radii), and the union-find sweep from the largest
//! `g` down that cuts the mesh into segments, protrusions hanging from forks.

use super::graph::{farthest, Graph};
use crate::joints::suggest::rules::{CORE, CORE_REACH, ELONGATED, THICK};
use crate::joints::suggest::union_find::UnionFind;
use crate::mesh::Mesh;
use crate::skeleton::Skeleton;
use glam::DVec3;

/// A segment of the join tree: the vertices added between two events of the sweep.
#[derive(Clone, Debug)]
pub(crate) struct Segment {
    /// The segment the sweep continued into below this one's lowest vertex (`None` for the
    /// last one, the root's).
    pub(crate) parent: Option<usize>,
    /// Its vertices, from the largest `g` down.
    pub(crate) vertices: Vec<u32>,
}

/// The join tree of `g` with what the cuts need.
pub(crate) struct Tree<'a> {
    pub(crate) mesh: &'a Mesh,
    pub(crate) skeleton: &'a Skeleton,
    pub(crate) g: Vec<f64>,
    pub(crate) segments: Vec<Segment>,
    /// Each segment's children (the segments whose parent it is).
    pub(crate) children: Vec<Vec<usize>>,
    /// The root's medial ball: the body's core is at least this.
    pub(crate) core: (DVec3, f64),
    /// The longest side of the mesh's bounding box.
    pub(crate) size_of_mesh: f64,
    /// Rooted on a flat base the body stands on: the body is what stands there.
    pub(crate) standing: bool,
    /// The mesh's edges in local radii (see `graph`).
    pub(crate) graph: Graph,
}

impl<'a> Tree<'a> {
    /// The tree from vertex `root`'s medial ball, or from the root found when `None`;
    /// `graph`, the mesh's ([`Graph::new`]).
    pub(crate) fn rooted(
        mesh: &'a Mesh,
        skeleton: &'a Skeleton,
        graph: Graph,
        root: Option<usize>,
    ) -> Tree<'a> {
        let points = &skeleton.points;
        let n = points.len();
        let mut tree = Tree {
            mesh,
            skeleton,
            g: Vec::new(),
            segments: Vec::new(),
            children: Vec::new(),
            core: (DVec3::ZERO, 0.0),
            size_of_mesh: mesh.longest_side(),
            standing: false,
            graph,
        };
        if n < 4 {
            return tree;
        }
        let graph = &tree.graph;
        // 1. The root: the thickest point on the middle fifth of the path between two far
        // tips (the middle of the body, not its thickest end).
        let (d0, _) = graph.distances(0);
        let a = farthest(&d0);
        let (da, pred) = graph.distances(a);
        let b = farthest(&da);
        // The path from b back to a is a shortest path: along it, the distance from b is
        // the span less the distance from a.
        // Of the points on its middle three fifths nearly as thick as the thickest there
        // (a big head and a body), the one nearest the mesh's centroid: the body that
        // the limbs hang from, not the head on it.
        let span = da[b];
        let mut middle = Vec::new();
        let mut v = b;
        while v != a && pred[v] != u32::MAX {
            let along = 1.0 - da[v] / span.max(f64::MIN_POSITIVE);
            if (0.2..=0.8).contains(&along) {
                middle.push(v);
            }
            v = pred[v] as usize;
        }
        let thickest = middle
            .iter()
            .map(|&v| skeleton.distance[v])
            .fold(0.0, f64::max);
        let centroid = mesh.volume_centroid();
        let found = middle
            .iter()
            .copied()
            .filter(|&v| skeleton.distance[v] >= THICK * thickest)
            .min_by(|&p, &q| {
                points[p]
                    .distance(centroid)
                    .total_cmp(&points[q].distance(centroid))
            })
            .unwrap_or(b);
        let root = root.filter(|&r| r < n).unwrap_or(found);
        // g: over the surface, from the body's core: the vertices whose skeletal point lies
        // in the root's medial ball, and with them every vertex joined to them through
        // vertices nearly as thick (a long body is all core; its limbs start where it ends).
        let centre = points[root];
        let reach = skeleton.distance[root];
        let thick = CORE * reach;
        let mut in_core: Vec<bool> = (0..n)
            .map(|v| points[v].distance(centre) <= reach)
            .collect();
        let mut stack: Vec<usize> = (0..n).filter(|&v| in_core[v]).collect();
        while let Some(v) = stack.pop() {
            for (w, _) in graph.neighbours(v) {
                if !in_core[w]
                    && skeleton.distance[w] >= thick
                    && points[w].distance(centre) <= CORE_REACH * reach
                {
                    in_core[w] = true;
                    stack.push(w);
                }
            }
        }
        let core: Vec<(u32, f64)> = (0..n)
            .filter(|&v| in_core[v])
            .map(|v| (v as u32, 0.0))
            .collect();
        let (g, _) = graph.distances_from(&core);
        tree.g = g;
        tree.core = (centre, reach);
        tree.segments = tree.sweep(&tree.graph);
        tree.children = tree.children();
        tree
    }

    /// The union-find sweep from the largest `g` down (see the module docs): segments and
    /// their parents. Where components meet, only those reaching at least [`ELONGATED`]
    /// radii above the meeting point count: when fewer than two do, the others are bumps and
    /// the sweep goes on in the longest one's segment.
    pub(crate) fn sweep(&self, graph: &Graph) -> Vec<Segment> {
        let g = &self.g;
        let n = g.len();
        let mut order: Vec<u32> = (0..n as u32)
            .filter(|&v| g[v as usize].is_finite())
            .collect();
        order.sort_by(|&a, &b| g[b as usize].total_cmp(&g[a as usize]).then(a.cmp(&b)));
        let mut set = UnionFind::new(n);
        // Per component (by its union-find root): its open segment and its largest `g`.
        let mut open: Vec<u32> = vec![u32::MAX; n];
        let mut top = vec![0.0f64; n];
        let mut added = vec![false; n];
        let mut segments: Vec<Segment> = Vec::new();
        for &v in &order {
            let v = v as usize;
            added[v] = true;
            let mut roots: Vec<usize> = graph
                .neighbours(v)
                .filter(|&(w, _)| added[w])
                .map(|(w, _)| set.find(w))
                .collect();
            roots.sort_unstable();
            roots.dedup();
            let (segment, reach) = match roots.len() {
                0 => {
                    segments.push(Segment {
                        parent: None,
                        vertices: Vec::new(),
                    });
                    (segments.len() - 1, g[v])
                }
                _ => {
                    // The longest component goes on; the others end here.
                    let elder = roots
                        .iter()
                        .copied()
                        .max_by(|&a, &b| top[a].total_cmp(&top[b]).then(b.cmp(&a)))
                        .unwrap_or(roots[0]);
                    let significant = roots
                        .iter()
                        .filter(|&&r| top[r] - g[v] >= ELONGATED)
                        .count();
                    let segment = if significant >= 2 {
                        segments.push(Segment {
                            parent: None,
                            vertices: Vec::new(),
                        });
                        segments.len() - 1
                    } else {
                        open[elder] as usize
                    };
                    for &r in &roots {
                        let s = open[r] as usize;
                        if s != segment {
                            segments[s].parent = Some(segment);
                        }
                    }
                    (segment, top[elder])
                }
            };
            for &r in &roots {
                set.union(r, v);
            }
            let r = set.find(v);
            open[r] = segment as u32;
            top[r] = reach;
            segments[segment].vertices.push(v as u32);
        }
        segments
    }

    /// The smallest `g` of `vertices` (infinite for none).
    pub(crate) fn lowest(&self, vertices: &[u32]) -> f64 {
        vertices
            .iter()
            .map(|&v| self.g[v as usize])
            .fold(f64::INFINITY, f64::min)
    }

    /// The largest `g` of `vertices` (minus infinity for none).
    pub(crate) fn highest(&self, vertices: &[u32]) -> f64 {
        vertices
            .iter()
            .map(|&v| self.g[v as usize])
            .fold(f64::NEG_INFINITY, f64::max)
    }

    /// A ring of a segment: its vertices with `g` in `[lo, hi)`.
    pub(crate) fn ring(&self, segment: &[u32], lo: f64, hi: f64) -> Vec<u32> {
        segment
            .iter()
            .copied()
            .filter(|&v| (lo..hi).contains(&self.g[v as usize]))
            .collect()
    }

    /// The row of a segment's vertices just past the level `at` of `g`: those at or above
    /// it with a neighbour below it (none when the segment does not reach across `at`).
    /// On a low-poly limb, whose edges span more than a radius each, a window of `g`
    /// narrower than an edge ([`Tree::ring`]) can hold no vertex where this row does.
    pub(crate) fn past_level(&self, segment: &[u32], at: f64) -> Vec<u32> {
        if !(self.lowest(segment)..=self.highest(segment)).contains(&at) {
            return Vec::new();
        }
        let g = &self.g;
        segment
            .iter()
            .copied()
            .filter(|&v| {
                g[v as usize] >= at && self.graph.neighbours(v as usize).any(|(w, _)| g[w] < at)
            })
            .collect()
    }

    /// Median skeletal distance of `vertices`.
    pub(crate) fn radius(&self, vertices: &[u32]) -> f64 {
        let mut d: Vec<f64> = vertices
            .iter()
            .map(|&v| self.skeleton.distance[v as usize])
            .collect();
        crate::stats::median(&mut d).unwrap_or(0.0)
    }

    /// The size of a ring: the mean distance of its surface points from their centre.
    pub(crate) fn size(&self, vertices: &[u32]) -> f64 {
        let (c, _) = self.centre(vertices);
        vertices
            .iter()
            .map(|&v| (self.mesh.positions[v as usize] - c).length())
            .sum::<f64>()
            / vertices.len().max(1) as f64
    }

    /// Mean surface position and mean skeletal point of `vertices`.
    pub(crate) fn centre(&self, vertices: &[u32]) -> (DVec3, DVec3) {
        let k = vertices.len().max(1) as f64;
        let p = vertices
            .iter()
            .map(|&v| self.mesh.positions[v as usize])
            .sum::<DVec3>()
            / k;
        let s = vertices
            .iter()
            .map(|&v| self.skeleton.points[v as usize])
            .sum::<DVec3>()
            / k;
        (p, s)
    }

    pub(crate) fn children(&self) -> Vec<Vec<usize>> {
        let mut children = vec![Vec::new(); self.segments.len()];
        for (k, s) in self.segments.iter().enumerate() {
            if let Some(p) = s.parent {
                children[p].push(k);
            }
        }
        children
    }

    /// All vertices of segment `k` and of the segments above it.
    pub(crate) fn subtree(&self, k: usize, children: &[Vec<usize>]) -> Vec<u32> {
        let mut out = Vec::new();
        let mut stack = vec![k];
        while let Some(s) = stack.pop() {
            out.extend_from_slice(&self.segments[s].vertices);
            stack.extend_from_slice(&children[s]);
        }
        out
    }

    /// The vertices with `g` in `[lo, hi)` of segment `k` and the segments below it.
    pub(crate) fn trunk_ring(&self, mut k: usize, lo: f64, hi: f64) -> Vec<u32> {
        let mut out = Vec::new();
        loop {
            let seg = &self.segments[k].vertices;
            out.extend(self.ring(seg, lo, hi));
            let bottom = self.lowest(seg);
            match self.segments[k].parent {
                Some(p) if bottom > lo => k = p,
                _ => return out,
            }
        }
    }
}
