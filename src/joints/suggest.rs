//! Joints suggested from the skeleton: cuts where the protrusions of a mesh (limbs, neck,
//! tail, ears, fingers) leave the body and where they narrow, organised as a section tree
//! (shoulder → elbow → wrist).
//!
//! 1. **The body and a distance from it.** Two sweeps of shortest paths find two far tips;
//!    the thickest skeletal point on the middle fifth of the path between them is the root.
//!    The body's core is every vertex whose skeletal point lies in the root's medial ball,
//!    grown through vertices nearly as thick ([`CORE`]) within a few radii of it
//!    ([`CORE_REACH`]: a long body is all core, fingers as thick as the palm are not). `g(v)` is the shortest path from
//!    the core to `v` over the surface, each edge counted in units of the local skeletal
//!    distance: one unit is about one local radius, so a fat body is crossed in a few units
//!    and limbs stand out, and the level sets of `g` are close to cross-sections of a limb.
//! 2. **Protrusions.** The vertices are added from the largest `g` down, joined by mesh
//!    edges (a union-find sweep: the join tree of `g`). Every local maximum (a tip) starts a
//!    component; where two or more reaching [`ELONGATED`] radii meet (a fork) a new segment
//!    starts; shorter ones (bumps) fold into the longest.
//! 3. **Cuts.** A segment that hangs from a fork, is narrower than the trunk below it
//!    ([`THINNER`], by the rings' sizes) and longer than wide is a *limb*: it is cut at its
//!    base. A part as wide as the body with two or more limbs of its own, each at most
//!    [`SLENDER`] of its width (a head with ears and horns, a hand with fingers, not a palm
//!    with its wrist), is cut at its base too ([`HEAD`]). Inside a part, cuts go where the
//!    medial radius or the ring's size narrows between wider parts ([`DIP`]: an elbow, a
//!    knee, a neck); where a limb widens into an extremity that limbs grow from (a wrist);
//!    along a digit (a tip among four or more of one extremity) at 45 % and 72 % of its
//!    length; and in the middle of a limb's stretch longer than [`LONG`] radii without a
//!    joint.
//! 4. **Sections.** Each cut is a connected plane through the ring's centre, across the
//!    limb's axis there, its pivot on the axis; cuts apply parent-first, are named by their
//!    place in the tree (`joint 2`, `joint 2.1`, …), and one that would leave a section of
//!    fewer than [`SMALLEST`] of the vertices, or whose plane takes more than twice what
//!    lies past it in the join tree (it slipped past the limb into the body), is dropped.

use super::{Cut, Joints};
use crate::mesh::Mesh;
use crate::skeleton::Skeleton;
use glam::DVec3;
use std::cmp::Ordering;
use std::collections::BinaryHeap;

/// The body's core reaches as far as its skeletal distance stays this share of the root's,
/// and no farther than this many of the root's radii from its centre.
const CORE: f64 = 0.85;
const CORE_REACH: f64 = 2.5;
/// A limb must be at most this share of the width where it hangs from.
const THINNER: f64 = 0.75;
/// A limb is cut this many of its radii out from the fork.
const BASE: f64 = 0.5;
/// A limb or a bump must be at least this many of its radii long.
const ELONGATED: f64 = 1.6;
/// A narrowing is a joint when the radius dips by at least this share below the thinner of
/// the thicker parts on either side (and an extremity is that much wider than its wrist).
const DIP: f64 = 0.06;
/// A digit (a tip among several that grow from one extremity) at least this many of its
/// radii long gets its two joints.
const DIGIT: f64 = 6.0;
/// A stretch of a limb this many of its radii long with no joint bends in the middle.
const LONG: f64 = 10.0;
/// A part as thick as the body with limbs of its own turns at its base when it reaches
/// this many radii out.
const HEAD: f64 = 3.0;
/// ... and every limb it has is at most this share of its width.
const SLENDER: f64 = 0.5;
/// Sections smaller than this share of the vertices (or 12 vertices) are not suggested.
const SMALLEST: f64 = 0.002;

/// Cuts where the protrusions of `mesh` narrow, organised parent-first as a section tree
/// under the root section `root`. Every cut applies, in order, to joints without cuts.
pub fn suggest(mesh: &Mesh, skeleton: &Skeleton, root: &str) -> Vec<Cut> {
    // Riders have no skeleton: the limbs are the body's, and riders go with their hosts.
    let (limbs, hosts) = if skeleton.riders > 0 {
        let parts = crate::mesh::Parts::of(mesh);
        let (body, old) = parts.body(mesh);
        let body_skeleton = Skeleton {
            distance: old.iter().map(|&v| skeleton.distance[v as usize]).collect(),
            points: old.iter().map(|&v| skeleton.points[v as usize]).collect(),
            riders: 0,
            ..skeleton.clone()
        };
        let limbs = Tree::new(&body, &body_skeleton).limbs();
        (limbs, parts.hosts(&mesh.positions))
    } else {
        (Tree::new(mesh, skeleton).limbs(), Vec::new())
    };
    // Apply them in order; one that cannot apply (a side left empty) is dropped and what
    // hangs from it hangs from its parent instead.
    let mut joints = Joints::with_mesh(&skeleton.points, &mesh.triangles, &hosts, root);
    let mut applied: Vec<Option<String>> = Vec::with_capacity(limbs.len());
    let mut count: std::collections::HashMap<String, usize> = Default::default();
    let mut cuts = Vec::new();
    for limb in &limbs {
        // The nearest ancestor that applied, or the root.
        let mut parent = limb.parent;
        let section = loop {
            match parent {
                Some(p) => match &applied[p] {
                    Some(name) => break name.clone(),
                    None => parent = limbs[p].parent,
                },
                None => break root.to_string(),
            }
        };
        let k = count.entry(section.clone()).or_default();
        *k += 1;
        let name = if section == root {
            format!("joint {k}")
        } else {
            format!("{section}.{k}")
        };
        let cut = Cut {
            name: name.clone(),
            section,
            point: limb.point,
            normal: limb.normal,
            pivot: Some(limb.pivot),
            connected: true,
            band: None,
            shape: super::Shape::Plane,
            shared_pivot: false,
        };
        // Too small a piece, or too little left, is no joint worth a section.
        let smallest = (SMALLEST * skeleton.points.len() as f64).max(12.0) as usize;
        let big_enough = joints.find(&cut.section).is_some_and(|s| {
            let taken = joints.preview(s, &cut).iter().filter(|&&t| t).count();
            taken >= smallest
                && joints.sections()[s].vertices - taken >= smallest
                && taken <= 2 * limb.expected + smallest
        });
        if !big_enough {
            *count.entry(cut.section).or_default() -= 1;
            applied.push(None);
            continue;
        }
        match joints.add_cut(cut.clone()) {
            Ok(_) => {
                applied.push(Some(name));
                cuts.push(cut);
            }
            Err(e) => {
                log::debug!("suggested joint dropped: {e}");
                *count.entry(cut.section).or_default() -= 1;
                applied.push(None);
            }
        }
    }
    cuts
}

/// A mesh's skeletal graph: `S`'s edges as a CSR with their lengths.
struct Graph {
    start: Vec<u32>,
    to: Vec<u32>,
    len: Vec<f64>,
}

impl Graph {
    /// The mesh's edges, each as long as it is in units of the skeletal distance at its
    /// ends: a step of one is about one local radius, across a fat body or a thin finger.
    fn new(mesh: &Mesh, points: &[DVec3], distance: &[f64]) -> Graph {
        let n = points.len();
        let mut sorted: Vec<f64> = distance.iter().copied().filter(|d| *d > 0.0).collect();
        sorted.sort_by(f64::total_cmp);
        let floor = 1e-3 * sorted.get(sorted.len() / 2).copied().unwrap_or(1.0);
        let (start, to) = crate::mesh::neighbours(n, &crate::mesh::unique_edges(&mesh.triangles));
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

    fn neighbours(&self, v: usize) -> impl Iterator<Item = (usize, f64)> + '_ {
        let (a, b) = (self.start[v] as usize, self.start[v + 1] as usize);
        self.to[a..b]
            .iter()
            .zip(&self.len[a..b])
            .map(|(&t, &l)| (t as usize, l))
    }

    /// Shortest-path lengths from `source` (infinite where unreachable), and each vertex's
    /// predecessor on its path.
    fn distances(&self, source: usize) -> (Vec<f64>, Vec<u32>) {
        self.distances_from(&[(source as u32, 0.0)])
    }

    /// Shortest-path lengths from several sources, each starting at its own distance.
    fn distances_from(&self, sources: &[(u32, f64)]) -> (Vec<f64>, Vec<u32>) {
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
fn farthest(dist: &[f64]) -> usize {
    (0..dist.len())
        .filter(|&v| dist[v].is_finite())
        .max_by(|&a, &b| dist[a].total_cmp(&dist[b]))
        .unwrap_or(0)
}

/// A segment of the join tree: the vertices added between two events of the sweep.
#[derive(Clone, Debug)]
struct Segment {
    /// The segment the sweep continued into below this one's lowest vertex (`None` for the
    /// last one, the root's).
    parent: Option<usize>,
    /// Its vertices, from the largest `g` down.
    vertices: Vec<u32>,
}

/// The join tree of `g` with what the cuts need.
struct Tree<'a> {
    mesh: &'a Mesh,
    skeleton: &'a Skeleton,
    g: Vec<f64>,
    segments: Vec<Segment>,
    /// Each segment's children (the segments whose parent it is).
    children: Vec<Vec<usize>>,
}

impl<'a> Tree<'a> {
    fn new(mesh: &'a Mesh, skeleton: &'a Skeleton) -> Tree<'a> {
        let points = &skeleton.points;
        let n = points.len();
        let graph = Graph::new(mesh, &mesh.positions, &skeleton.distance);
        let mut tree = Tree {
            mesh,
            skeleton,
            g: Vec::new(),
            segments: Vec::new(),
            children: Vec::new(),
        };
        if n < 4 {
            return tree;
        }
        // 1. The root: the thickest point on the middle fifth of the path between two far
        // tips (the middle of the body, not its thickest end).
        let (d0, _) = graph.distances(0);
        let a = farthest(&d0);
        let (da, pred) = graph.distances(a);
        let b = farthest(&da);
        // The path from b back to a is a shortest path: along it, the distance from b is
        // the span less the distance from a.
        let span = da[b];
        let mut root = b;
        let mut best = f64::NEG_INFINITY;
        let mut v = b;
        while v != a && pred[v] != u32::MAX {
            let along = 1.0 - da[v] / span.max(f64::MIN_POSITIVE);
            if (0.4..=0.6).contains(&along) && skeleton.distance[v] > best {
                best = skeleton.distance[v];
                root = v;
            }
            v = pred[v] as usize;
        }
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
        tree.segments = tree.sweep(&graph);
        tree.children = tree.children();
        tree
    }

    /// The union-find sweep from the largest `g` down (see the module docs): segments and
    /// their parents. Where components meet, only those reaching at least [`ELONGATED`]
    /// radii above the meeting point count: when fewer than two do, the others are bumps and
    /// the sweep goes on in the longest one's segment.
    fn sweep(&self, graph: &Graph) -> Vec<Segment> {
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

    /// A ring of a segment: its vertices with `g` in `[lo, hi)`.
    fn ring(&self, segment: &[u32], lo: f64, hi: f64) -> Vec<u32> {
        segment
            .iter()
            .copied()
            .filter(|&v| (lo..hi).contains(&self.g[v as usize]))
            .collect()
    }

    /// Median skeletal distance of `vertices`.
    fn radius(&self, vertices: &[u32]) -> f64 {
        let mut d: Vec<f64> = vertices
            .iter()
            .map(|&v| self.skeleton.distance[v as usize])
            .collect();
        if d.is_empty() {
            return 0.0;
        }
        let mid = d.len() / 2;
        *d.select_nth_unstable_by(mid, f64::total_cmp).1
    }

    /// The size of a ring: the mean distance of its surface points from their centre.
    fn size(&self, vertices: &[u32]) -> f64 {
        let (c, _) = self.centre(vertices);
        vertices
            .iter()
            .map(|&v| (self.mesh.positions[v as usize] - c).length())
            .sum::<f64>()
            / vertices.len().max(1) as f64
    }

    /// Mean surface position and mean skeletal point of `vertices`.
    fn centre(&self, vertices: &[u32]) -> (DVec3, DVec3) {
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

    /// Every cut's place, parent-first: `parent` indexes this list.
    fn limbs(&self) -> Vec<Limb> {
        let mut out = Vec::new();
        if self.segments.is_empty() {
            return out;
        }
        let children = &self.children;
        // The segment holding the root (the smallest g).
        let Some(root) = (0..self.segments.len()).find(|&k| {
            self.segments[k].parent.is_none()
                && self.segments[k]
                    .vertices
                    .iter()
                    .any(|&v| self.g[v as usize] == 0.0)
        }) else {
            return out;
        };
        // Each segment's base cut, if it is a limb; and its owner: the nearest limb at or
        // below it (the root's segment for the body).
        let n = self.segments.len();
        let mut base: Vec<Option<Limb>> = (0..n)
            .map(|k| match self.segments[k].parent {
                Some(p) if !self.segments[k].vertices.is_empty() => self.base_cut(k, p, children),
                _ => None,
            })
            .collect();
        // A part no thinner than the body that still reaches out, with two or more limbs of
        // its own (a head with ears and horns), turns at its base too.
        for k in 0..n {
            let seg = &self.segments[k].vertices;
            if base[k].is_some() || seg.is_empty() || k == root {
                continue;
            }
            let Some(parent) = self.segments[k].parent else {
                continue;
            };
            let hanging = self.limbs_hanging(k, children, &base);
            let low = seg
                .iter()
                .map(|&v| self.g[v as usize])
                .fold(f64::INFINITY, f64::min);
            let high = self
                .subtree(k, children)
                .iter()
                .map(|&v| self.g[v as usize])
                .fold(f64::NEG_INFINITY, f64::max);
            if hanging.len() < 2 || low <= 0.0 || high - low < HEAD || parent == root {
                continue;
            }
            // Its limbs are thin beside it (ears and horns on a head, fingers on a hand):
            // where one is about as wide (a wrist below a palm), this is a stretch of the
            // body where limbs meet, not a part of its own.
            let Some(cut) = self.cut_at(k, low + BASE) else {
                continue;
            };
            if hanging.iter().all(|&w| w <= SLENDER * cut.width) {
                base[k] = Some(cut);
            }
        }
        let mut owner = vec![root; n];
        let mut stack = vec![root];
        while let Some(k) = stack.pop() {
            for &c in &children[k] {
                owner[c] = if base[c].is_some() { c } else { owner[k] };
                stack.push(c);
            }
        }
        // Limbs hanging from each owner, and those of them no limb grows from (tips).
        let hanging: Vec<(usize, usize)> = (0..n)
            .filter(|&k| base[k].is_some())
            .filter_map(|k| self.segments[k].parent.map(|p| (k, owner[p])))
            .collect();
        let mut limbs_from = vec![0usize; n];
        for &(_, o) in &hanging {
            limbs_from[o] += 1;
        }
        let mut tips_from = vec![0usize; n];
        for &(k, o) in &hanging {
            if limbs_from[k] == 0 {
                tips_from[o] += 1;
            }
        }
        let shape = Shape {
            children,
            base: &base,
            owner: &owner,
            limbs_from: &limbs_from,
            tips_from: &tips_from,
            root,
        };
        self.walk(root, None, &shape, &mut out);
        out
    }

    fn children(&self) -> Vec<Vec<usize>> {
        let mut children = vec![Vec::new(); self.segments.len()];
        for (k, s) in self.segments.iter().enumerate() {
            if let Some(p) = s.parent {
                children[p].push(k);
            }
        }
        children
    }

    /// All vertices of segment `k` and of the segments above it.
    fn subtree(&self, k: usize, children: &[Vec<usize>]) -> Vec<u32> {
        let mut out = Vec::new();
        let mut stack = vec![k];
        while let Some(s) = stack.pop() {
            out.extend_from_slice(&self.segments[s].vertices);
            stack.extend_from_slice(&children[s]);
        }
        out
    }

    /// Visits segment `k` (whose limb, the nearest cut below it, is `limb`), adding the
    /// cuts at its base and inside it, then its children.
    fn walk(&self, k: usize, limb: Option<usize>, shape: &Shape, out: &mut Vec<Limb>) {
        let mut current = limb;
        if let Some(base) = shape.base[k] {
            out.push(Limb {
                parent: limb,
                ..base
            });
            current = Some(out.len() - 1);
        }
        // An extremity: two or more limbs grow from it (a hand, a foot: cut where it
        // widens). A digit: a tip among three or more that grow from one extremity (not
        // from the body).
        // A part of the body that is no limb (a thick neck and head) may still narrow
        // (at the neck): only narrowings there.
        let limb = shape.base[k].is_some();
        let parent = self.segments[k]
            .parent
            .map_or(shape.root, |p| shape.owner[p]);
        let extremity = limb && shape.limbs_from[k] >= 2;
        let digit = limb && shape.limbs_from[k] == 0 && shape.tips_from[parent] >= 4;
        if k != shape.root {
            for inner in self.inner_cuts(k, limb, extremity, digit) {
                out.push(Limb {
                    parent: current,
                    ..inner
                });
                current = Some(out.len() - 1);
            }
        }
        // Children from the thickest down, so a section tree reads naturally.
        let mut kids = shape.children[k].clone();
        kids.sort_by(|&a, &b| {
            let (ra, rb) = (
                self.radius(&self.segments[a].vertices),
                self.radius(&self.segments[b].vertices),
            );
            rb.total_cmp(&ra)
        });
        for c in kids {
            self.walk(c, current, shape, out);
        }
    }

    /// The widths of the limbs that hang from segment `k`, directly or through forks that
    /// are no limbs.
    fn limbs_hanging(&self, k: usize, children: &[Vec<usize>], base: &[Option<Limb>]) -> Vec<f64> {
        let mut out = Vec::new();
        for &c in &children[k] {
            match base[c] {
                Some(limb) => out.push(limb.width),
                None => out.extend(self.limbs_hanging(c, children, base)),
            }
        }
        out
    }

    /// The vertices with `g` in `[lo, hi)` of segment `k` and the segments below it.
    fn trunk_ring(&self, mut k: usize, lo: f64, hi: f64) -> Vec<u32> {
        let mut out = Vec::new();
        loop {
            let seg = &self.segments[k].vertices;
            out.extend(self.ring(seg, lo, hi));
            let bottom = seg
                .iter()
                .map(|&v| self.g[v as usize])
                .fold(f64::INFINITY, f64::min);
            match self.segments[k].parent {
                Some(p) if bottom > lo => k = p,
                _ => return out,
            }
        }
    }

    /// The cut at the base of segment `k` where it hangs from `parent`, if `k` (with what
    /// grows from it) is a limb: thinner than the parent there and long enough.
    fn base_cut(&self, k: usize, parent: usize, children: &[Vec<usize>]) -> Option<Limb> {
        let seg = &self.segments[k].vertices;
        let whole = self.subtree(k, children);
        let low = seg
            .iter()
            .map(|&v| self.g[v as usize])
            .fold(f64::INFINITY, f64::min);
        let high = whole
            .iter()
            .map(|&v| self.g[v as usize])
            .fold(f64::NEG_INFINITY, f64::max);
        let r = self.radius(seg);
        if r <= 0.0 || high - low < ELONGATED {
            return None;
        }
        // Thinner than the parent just below the fork: by the rings' sizes, not their
        // medial radii (a finger is as thick as the flat palm it grows from, not as wide).
        // (Its own ring one to three radii out: at the fork itself it is not round.)
        let own = self.size(&self.ring(seg, low + 1.0, low + 3.0));
        // The trunk it grows from, one to three of its radii below the fork (through short
        // forks where other limbs join close by, like the webs between fingers).
        let below = self.trunk_ring(parent, low - 3.0, low - 1.0);
        // A limb growing right from the core (a finger from the palm) has no trunk below
        // it: the core's own vertices are only the root's ball, so the body is measured
        // beside the limb instead, by everything else as far from the core.
        let beside = || {
            let mut mine = vec![false; self.g.len()];
            for &v in &whole {
                mine[v as usize] = true;
            }
            (0..self.g.len() as u32)
                .filter(|&v| {
                    !mine[v as usize] && (low + 1.0..low + 3.0).contains(&self.g[v as usize])
                })
                .collect::<Vec<u32>>()
        };
        let parent_size = if below.is_empty() {
            self.size(&self.segments[parent].vertices)
                .max(self.size(&beside()))
        } else {
            self.size(&below)
        };
        // Thinner than its trunk, and longer than it is wide (a nose is neither).
        if own <= 0.0 || own > THINNER * parent_size || high - low < ELONGATED * own / r {
            return None;
        }
        // Through the ring a radius above the fork, across the axis there: far enough out
        // that the plane does not reach a neighbour at the fork (the other leg at the
        // crotch).
        self.cut_at(k, low + BASE)
    }

    /// The profile of segment `k` from its base up, in bins half its radius long: the
    /// median skeletal distance and the mean distance of the surface from the ring's centre
    /// of each ring (empty rings interpolated), smoothed over three bins.
    fn profile(&self, k: usize) -> Option<Profile> {
        let seg = &self.segments[k].vertices;
        let r = self.radius(seg);
        if seg.len() < 16 || r <= 0.0 {
            return None;
        }
        let low = seg
            .iter()
            .map(|&v| self.g[v as usize])
            .fold(f64::INFINITY, f64::min);
        let high = seg
            .iter()
            .map(|&v| self.g[v as usize])
            .fold(f64::NEG_INFINITY, f64::max);
        let step = 0.5;
        let bins = ((high - low) / step).floor() as usize;
        if bins < 6 {
            return None;
        }
        let mut d = vec![f64::NAN; bins];
        let mut size = vec![f64::NAN; bins];
        for b in 0..bins {
            let lo = low + b as f64 * step;
            let ring = self.ring(seg, lo, lo + step);
            if ring.len() >= 3 {
                d[b] = self.radius(&ring);
                let (c, _) = self.centre(&ring);
                size[b] = ring
                    .iter()
                    .map(|&v| (self.mesh.positions[v as usize] - c).length())
                    .sum::<f64>()
                    / ring.len() as f64;
            }
        }
        let (d, size) = (smooth(&fill(&d)?), smooth(&fill(&size)?));
        Some(Profile { low, step, d, size })
    }

    /// Cuts inside segment `k`, from its base up: at clear narrowings; where it widens into
    /// an extremity that other limbs grow from (a wrist, an ankle: `extremity`); and along
    /// a long digit (`digit`: a tip among several of an extremity) at its two joints.
    fn inner_cuts(&self, k: usize, limb: bool, extremity: bool, digit: bool) -> Vec<Limb> {
        let Some(p) = self.profile(k) else {
            return Vec::new();
        };
        let bins = p.d.len();
        // Bins of cuts; a cut keeps three bins (1.5 radii) from another and from the top,
        // and two radii from the base cut.
        let mut at: Vec<usize> = Vec::new();
        let first = if limb {
            (2.0 * (BASE + 1.5)) as usize
        } else {
            3
        };
        let free = |at: &[usize], b: usize| {
            b >= first && b + 3 <= bins && at.iter().all(|&c| c.abs_diff(b) >= 3)
        };
        // Narrowings: a minimum of the skeletal distance or of the ring's size clearly below
        // the thicker parts on either side.
        for b in 1..bins - 1 {
            let narrows = |v: &[f64]| {
                let here = v[b];
                let before = v[..b].iter().copied().fold(0.0, f64::max);
                let after = v[b + 1..].iter().copied().fold(0.0, f64::max);
                here <= v[b - 1] && here <= v[b + 1] && here <= (1.0 - DIP) * before.min(after)
            };
            if (narrows(&p.d) || narrows(&p.size)) && free(&at, b) {
                at.push(b);
            }
        }
        if !limb {
            at.sort_unstable();
            return at
                .into_iter()
                .filter_map(|b| self.cut_at(k, p.low + (b as f64 + 0.5) * p.step))
                .collect();
        }
        // Where it widens into an extremity: the narrowest ring of its last half, if the
        // extremity is clearly wider.
        if extremity {
            let half = bins / 2;
            if let Some(b) = (half..bins).min_by(|&a, &b| p.size[a].total_cmp(&p.size[b])) {
                let wider = p.size[b..].iter().copied().fold(0.0, f64::max);
                if wider >= (1.0 + DIP) * p.size[b] && free(&at, b) {
                    at.push(b);
                }
            }
        }
        // A digit's two joints, at 45 % and 72 % of its length (where a finger's bend),
        // unless narrowings already cut it.
        if digit && at.is_empty() && bins as f64 * p.step >= DIGIT {
            for share in [0.45, 0.72] {
                let b = (share * bins as f64) as usize;
                if free(&at, b) {
                    at.push(b);
                }
            }
        }
        // A long stretch with no joint (an arm whose elbow does not narrow) bends in the
        // middle.
        at.sort_unstable();
        if !digit {
            let ends: Vec<usize> = std::iter::once(first / 2)
                .chain(at.iter().copied())
                .chain(std::iter::once(bins))
                .collect();
            for w in ends.windows(2) {
                let (a, b) = (w[0], w[1]);
                if ((b - a) as f64 * p.step) >= LONG {
                    let mid = (a + b) / 2;
                    if free(&at, mid) {
                        at.push(mid);
                    }
                }
            }
            at.sort_unstable();
        }
        at.into_iter()
            .filter_map(|b| self.cut_at(k, p.low + (b as f64 + 0.5) * p.step))
            .collect()
    }

    /// A cut through the ring of `seg` at level `at`, across the axis (from the centre of
    /// the ring a radius below to the one a radius above), its pivot on the axis.
    fn cut_at(&self, k: usize, at: f64) -> Option<Limb> {
        let seg = &self.segments[k].vertices;
        let half = 0.25;
        let ring = self.ring(seg, at - half, at + half);
        let below = self.ring(seg, at - 1.0 - half, at - 1.0 + half);
        let above = self.ring(seg, at + 1.0 - half, at + 1.0 + half);
        if ring.is_empty() {
            return None;
        }
        let (point, pivot) = self.centre(&ring);
        let from = if below.is_empty() {
            point
        } else {
            self.centre(&below).0
        };
        let to = if above.is_empty() {
            point
        } else {
            self.centre(&above).0
        };
        let normal = (to - from).normalize_or_zero();
        if normal == DVec3::ZERO || !normal.is_finite() {
            return None;
        }
        // The pivot on the plane, at the axis.
        let pivot = pivot - normal * (pivot - point).dot(normal);
        let expected = self
            .subtree(k, &self.children)
            .iter()
            .filter(|&&v| self.g[v as usize] >= at)
            .count();
        Some(Limb {
            parent: None,
            expected,
            width: self.size(&ring),
            point,
            normal,
            pivot,
        })
    }
}

/// What [`Tree::limbs`] found of the tree's shape, for [`Tree::walk`].
struct Shape<'a> {
    children: &'a [Vec<usize>],
    /// Each segment's base cut, if it is a limb.
    base: &'a [Option<Limb>],
    /// The nearest limb at or below each segment (the root's segment for the body).
    owner: &'a [usize],
    /// Per owner: limbs that hang from it, and those of them no limb grows from.
    limbs_from: &'a [usize],
    tips_from: &'a [usize],
    /// The root's segment.
    root: usize,
}

/// A segment's profile (see [`Tree::profile`]).
struct Profile {
    /// `g` at its base.
    low: f64,
    /// Bin length.
    step: f64,
    /// Per bin: median skeletal distance, and mean distance from the ring's centre.
    d: Vec<f64>,
    size: Vec<f64>,
}

/// Empty bins (NaN) take the value of the nearest bins on either side; `None` if all are.
fn fill(v: &[f64]) -> Option<Vec<f64>> {
    let known: Vec<usize> = (0..v.len()).filter(|&i| v[i].is_finite()).collect();
    let (&first, &last) = (known.first()?, known.last()?);
    let mut out = v.to_vec();
    for (i, o) in out.iter_mut().enumerate() {
        if o.is_finite() {
            continue;
        }
        *o = if i < first {
            v[first]
        } else if i > last {
            v[last]
        } else {
            let a = known
                .iter()
                .rev()
                .find(|&&k| k < i)
                .copied()
                .unwrap_or(first);
            let b = known.iter().find(|&&k| k > i).copied().unwrap_or(last);
            let t = (i - a) as f64 / (b - a).max(1) as f64;
            v[a] + (v[b] - v[a]) * t
        };
    }
    Some(out)
}

/// A moving average over three bins.
fn smooth(v: &[f64]) -> Vec<f64> {
    (0..v.len())
        .map(|b| {
            let (a, c) = (b.saturating_sub(1), (b + 1).min(v.len() - 1));
            (v[a] + v[b] + v[c]) / 3.0
        })
        .collect()
}

/// A suggested cut before it is named.
#[derive(Clone, Copy, Debug)]
struct Limb {
    /// The cut below it (index in the list), `None` for one on the root.
    parent: Option<usize>,
    /// How many vertices lie past it in the join tree: a plane that takes far more has
    /// slipped past the limb into the body.
    expected: usize,
    /// The size ([`Tree::size`]) of its ring.
    width: f64,
    point: DVec3,
    normal: DVec3,
    pivot: DVec3,
}

/// Union-find with path halving.
struct UnionFind(Vec<u32>);

impl UnionFind {
    fn new(n: usize) -> Self {
        UnionFind((0..n as u32).collect())
    }

    fn find(&mut self, mut x: usize) -> usize {
        while self.0[x] as usize != x {
            self.0[x] = self.0[self.0[x] as usize];
            x = self.0[x] as usize;
        }
        x
    }

    fn union(&mut self, a: usize, b: usize) {
        let (ra, rb) = (self.find(a), self.find(b));
        if ra != rb {
            self.0[ra] = rb as u32;
        }
    }
}
