//! A left and a right cut that nearly mirror each other, made to mirror each other exactly.

use super::other_side;
use crate::joints::suggest::rules::PAIRED;
use crate::joints::Cut;
use crate::mesh::orientation::{image, reflect, Frame};
use crate::mesh::Mesh;
use glam::DVec3;
use std::collections::HashMap;

/// A left and a right cut that nearly mirror each other, and the ways to make them mirror
/// each other exactly, in order of preference.
pub(super) struct Pair {
    pub(super) left: usize,
    pub(super) right: usize,
    pub(super) ways: Vec<(Cut, Cut)>,
}

/// The pairs of cuts named alike but for `L` and `R` whose pivots already lie within
/// [`PAIRED`] of the mesh's size of each other's mirror image; each can be moved to the
/// mean of the one and the other's image, or one to the other's image.
pub(super) fn mirror_pairs(cuts: &[Cut], frame: &Frame, mesh: &Mesh) -> Vec<Pair> {
    let Some((n, o)) = frame.mirror else {
        return Vec::new();
    };
    let point = |p: DVec3| image((n, o), p);
    let vector = |v: DVec3| reflect(n, v);
    let size = mesh.longest_side();
    let index: HashMap<&str, usize> = cuts
        .iter()
        .enumerate()
        .map(|(k, c)| (c.name.as_str(), k))
        .collect();
    // `a` moved to (point, normal, pivot), and `b` to its image.
    let placed = |a: &Cut, b: &Cut, at: DVec3, normal: DVec3, pivot: DVec3| {
        (
            Cut {
                point: at,
                normal,
                pivot: Some(pivot),
                ..a.clone()
            }
            .rounded(),
            Cut {
                point: point(at),
                normal: vector(normal),
                pivot: Some(point(pivot)),
                ..b.clone()
            }
            .rounded(),
        )
    };
    let mut out = Vec::new();
    for (i, a) in cuts.iter().enumerate() {
        if !a.name.split('.').any(|w| w == "L") {
            continue;
        }
        let Some(other) = other_side(&a.name) else {
            continue;
        };
        let Some(&j) = index.get(other.as_str()) else {
            continue;
        };
        let b = &cuts[j];
        let (pa, pb) = (a.pivot.unwrap_or(a.point), b.pivot.unwrap_or(b.point));
        if pa.distance(point(pb)) > PAIRED * size {
            continue;
        }
        let mean = placed(
            a,
            b,
            0.5 * (a.point + point(b.point)),
            (a.normal + vector(b.normal)).normalize_or(a.normal),
            0.5 * (pa + point(pb)),
        );
        let left = placed(a, b, a.point, a.normal, pa);
        let (b2, a2) = placed(b, a, b.point, b.normal, pb);
        out.push(Pair {
            left: i,
            right: j,
            ways: vec![mean, left, (a2, b2)],
        });
    }
    out
}
