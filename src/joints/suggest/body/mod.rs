//! Stages 1 and 2 of the suggestion: the body it cuts, and the tree of its protrusions.
//!
//! Stage 1 reads the body apart from its riders (props and eyes with no skeleton of their
//! own, [`crate::mesh::Parts`]), which go with their hosts; its cues (mirror plane, flat
//! base: [`crate::mesh::orientation::Cues`]) are the body's, since a prop lying apart says
//! nothing of its symmetry. Stage 2 roots the tree:
//!
//! * **The root and a distance from it.** Two sweeps of shortest paths find two far tips;
//!   of the points on the middle three fifths of the path between them at least `THICK`
//!   of the thickest there, the root is the one nearest the centroid of the enclosed
//!   volume (the body the limbs hang from, not a big head on it). The body's core is every
//!   vertex whose skeletal point lies in the root's medial ball, grown through vertices
//!   nearly as thick (`CORE`) within a few radii of it (`CORE_REACH`: a long body is all
//!   core, fingers as thick as the palm are not). `g(v)` is the shortest path from the
//!   core to `v` over the surface, each edge counted in units of the local skeletal
//!   distance: one unit is about one local radius, so a fat body is crossed in a few units
//!   and limbs stand out, and the level sets of `g` are close to cross-sections of a limb.
//!   When a limb of that root has more tips than all the root's other limbs and is as
//!   thick inside (`BODY_TIPS`, `BODY_THICK`: a body hanging by its neck from a head
//!   bigger than it, with the arms and legs), the tree is built again from that limb's
//!   thickest point, and the head turns at the neck cut the other way round. A mesh with
//!   a flat base (a bust) is rooted at its thickest point within `STANDING` of its height
//!   above the base: the head on it turns at its neck.
//! * **Protrusions.** The vertices are added from the largest `g` down, joined by mesh
//!   edges (a union-find sweep: the join tree of `g`). Every local maximum (a tip) starts a
//!   component; where two or more reaching `ELONGATED` radii meet (a fork) a new segment
//!   starts; shorter ones (bumps) fold into the longest.
//!
//! * `graph`: the mesh's edges in local radii, shortest paths;
//! * `tree`: the root, the core, `g` and the join tree.

mod graph;
mod tree;

pub(crate) use tree::Tree;

use super::rules::STANDING;
use crate::mesh::orientation::Cues;
use crate::mesh::Mesh;
use crate::skeleton::Skeleton;
use glam::DVec3;
use std::borrow::Cow;

/// Stage 1's output: what the suggestion cuts.
pub(crate) struct Body<'a> {
    /// The body without its riders (the whole mesh when it has none): its limbs are cut.
    pub(crate) mesh: Cow<'a, Mesh>,
    /// Its skeleton.
    pub(crate) skeleton: Cow<'a, Skeleton>,
    /// Per vertex of the whole mesh, the body vertex its rider rides on (empty or all
    /// `None` without riders).
    pub(crate) hosts: Vec<Option<u32>>,
    /// The character's shape for naming: the whole mesh with each rider where its host is
    /// (a prop lying apart from the body would stretch its size and move its centre).
    pub(crate) character: Cow<'a, Mesh>,
    /// The body's mirror plane and flat base.
    pub(crate) cues: Cues,
    /// Where the body's separate parts meet ([`crate::mesh::attachments`]), by body vertex.
    pub(crate) attachments: Vec<(u32, u32)>,
}

impl<'a> Body<'a> {
    /// The body of `mesh`, whose skeleton is `skeleton` and whose separate parts meet at
    /// `attachments` ([`crate::mesh::attachments`]: between body parts only), standing
    /// along `up` where that is given (its mirror plane then holds up: [`Cues::of`]).
    pub(crate) fn of(
        mesh: &'a Mesh,
        skeleton: &'a Skeleton,
        attachments: &[(u32, u32)],
        up: Option<DVec3>,
    ) -> Body<'a> {
        if skeleton.riders == 0 {
            return Body {
                mesh: Cow::Borrowed(mesh),
                skeleton: Cow::Borrowed(skeleton),
                hosts: Vec::new(),
                character: Cow::Borrowed(mesh),
                cues: Cues::of(mesh, up),
                attachments: attachments.to_vec(),
            };
        }
        let parts = crate::mesh::Parts::of(mesh);
        let (body, old) = parts.body(mesh);
        let body_skeleton = Skeleton {
            distance: old.iter().map(|&v| skeleton.distance[v as usize]).collect(),
            points: old.iter().map(|&v| skeleton.points[v as usize]).collect(),
            riders: 0,
            ..skeleton.clone()
        };
        let hosts = parts.hosts(&mesh.positions);
        let character = if hosts.iter().any(Option::is_some) {
            Cow::Owned(Mesh {
                positions: (0..mesh.positions.len())
                    .map(|v| mesh.positions[hosts[v].map_or(v, |h| h as usize)])
                    .collect(),
                triangles: mesh.triangles.clone(),
            })
        } else {
            Cow::Borrowed(mesh)
        };
        let cues = Cues::of(&body, up);
        // The body keeps the whole's vertices in their order, less the riders'.
        let mut index = vec![u32::MAX; mesh.positions.len()];
        for (new, &v) in old.iter().enumerate() {
            index[v as usize] = new as u32;
        }
        let attachments = attachments
            .iter()
            .map(|&(a, b)| {
                let at = |v: u32| index.get(v as usize).copied().unwrap_or(u32::MAX);
                (at(a), at(b))
            })
            .filter(|&(a, b)| a != u32::MAX && b != u32::MAX)
            .collect();
        Body {
            mesh: Cow::Owned(body),
            skeleton: Cow::Owned(body_skeleton),
            hosts,
            character,
            cues,
            attachments,
        }
    }

    /// Stage 2: the tree of the body's protrusions, rooted on its flat base when it stands
    /// on one ([`STANDING`]), else at the root found.
    pub(crate) fn tree(&self) -> Tree<'_> {
        let root = self
            .cues
            .base
            .and_then(|down| on_the_base(&self.mesh, &self.skeleton.distance, down));
        let graph = graph::Graph::new(
            &self.mesh,
            &self.attachments,
            &self.mesh.positions,
            &self.skeleton.distance,
        );
        let mut tree = Tree::rooted(&self.mesh, &self.skeleton, graph, root);
        tree.standing = root.is_some();
        tree
    }
}

/// The vertex with the largest skeletal distance `radius` within [`STANDING`] of the mesh's
/// height above its flat base, whose outward normal is `down`.
fn on_the_base(mesh: &Mesh, radius: &[f64], down: DVec3) -> Option<usize> {
    let height = |v: usize| -mesh.positions[v].dot(down);
    let (low, high) = (0..mesh.positions.len())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
            (lo.min(height(v)), hi.max(height(v)))
        });
    let top = low + STANDING * (high - low);
    (0..radius.len().min(mesh.positions.len()))
        .filter(|&v| height(v) <= top)
        .max_by(|&a, &b| radius[a].total_cmp(&radius[b]))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::joints::suggest::fixture;

    #[test]
    fn the_body_is_the_mesh_less_its_riders_and_its_cues_are_the_body_s() {
        // No riders: the mesh itself, mirrored across x.
        let (mesh, skeleton) = fixture::human();
        let body = Body::of(mesh, skeleton, &crate::mesh::attachments(mesh), None);
        assert!(matches!(body.mesh, Cow::Borrowed(_)));
        assert!(body.hosts.is_empty());
        let (n, _) = body.cues.mirror.expect("the human is mirrored");
        assert!(n.dot(DVec3::X).abs() > 0.99, "{n}");
        assert_eq!(body.cues.base, None);
        // The snake's eyes ride on its head: the body is the rest, the cues its own, and
        // the character for naming has each eye's vertex where its host is.
        let (mesh, skeleton) = fixture::character("tests/data/population/snake.glb");
        assert!(skeleton.riders > 0);
        let body = Body::of(mesh, skeleton, &crate::mesh::attachments(mesh), None);
        let n = mesh.positions.len();
        assert_eq!(body.mesh.positions.len(), n - skeleton.riders);
        assert_eq!(body.skeleton.points.len(), body.mesh.positions.len());
        assert_eq!(body.cues, Cues::of(&body.mesh, None));
        let riding = (0..n).filter(|&v| body.hosts[v].is_some()).count();
        assert_eq!(riding, skeleton.riders);
        for v in 0..n {
            let at = body.hosts[v].map_or(v, |h| h as usize);
            assert_eq!(body.character.positions[v], mesh.positions[at]);
        }
    }

    #[test]
    fn the_body_s_attachments_are_the_whole_s_between_its_own_vertices() {
        // A king in pieces: riders (46 small separate parts) and body parts that meet.
        // The whole's attachments, found once, moved onto the body's vertices, are what
        // the body's own mesh gives.
        let (mesh, skeleton) = fixture::character("tests/data/population/man-king.glb");
        assert!(skeleton.riders > 0);
        let body = Body::of(mesh, skeleton, &crate::mesh::attachments(mesh), None);
        assert!(!body.attachments.is_empty());
        assert_eq!(body.attachments, crate::mesh::attachments(&body.mesh));
    }

    #[test]
    fn the_tree_grows_from_a_core_in_the_trunk_and_every_vertex_is_reached() {
        let (mesh, skeleton) = fixture::human();
        let body = Body::of(mesh, skeleton, &crate::mesh::attachments(mesh), None);
        let tree = body.tree();
        assert!(!tree.standing);
        // The core's ball sits in the trunk: on the mirror plane, between hips and neck.
        let (lo, hi) = crate::mesh::bounds(&mesh.positions);
        let (centre, radius) = tree.core;
        let height = (centre.y - lo.y) / (hi.y - lo.y);
        assert!((0.45..0.8).contains(&height), "{height}");
        assert!(centre.x.abs() < 0.02 * (hi - lo).max_element(), "{centre}");
        assert!(radius > 0.0);
        // g is finite everywhere and 0 in the core; one segment (the root's) has no parent
        // and every other hangs from it through its parents.
        assert!(tree.g.iter().all(|g| g.is_finite() && *g >= 0.0));
        assert!(tree.g.contains(&0.0));
        let roots: Vec<usize> = (0..tree.segments.len())
            .filter(|&k| tree.segments[k].parent.is_none())
            .collect();
        assert_eq!(roots.len(), 1);
        for k in 0..tree.segments.len() {
            let (mut at, mut steps) = (k, 0);
            while let Some(p) = tree.segments[at].parent {
                (at, steps) = (p, steps + 1);
                assert!(steps <= tree.segments.len(), "a loop above segment {k}");
            }
            assert_eq!(at, roots[0]);
        }
        let covered: usize = tree.segments.iter().map(|s| s.vertices.len()).sum();
        assert_eq!(covered, mesh.positions.len());
    }
}
