//! Two or more characters in one file (a scene, a pair side by side): each gets its own
//! suggestion, with its own mirror plane, up and names.

use super::union_find::UnionFind;
use crate::mesh::{Mesh, Parts};
use crate::skeleton::Skeleton;
use glam::DVec3;

/// One character of a mesh in pieces: its mesh and its skeleton.
pub(super) struct Character {
    pub(super) mesh: Mesh,
    pub(super) skeleton: Skeleton,
}

/// The characters of `mesh`, largest first, when there are two or more: its body parts (not
/// riders) grouped where their bounding boxes overlap or they are attached (an arm
/// modelled apart and pushed into the torso is the torso's; two characters holding hands
/// are one), each with the riders on its parts; `attachments`, where its separate parts
/// meet ([`crate::mesh::attachments`]). `None` for one character.
pub(super) fn of(
    mesh: &Mesh,
    skeleton: &Skeleton,
    attachments: &[(u32, u32)],
) -> Option<Vec<Character>> {
    let parts = Parts::of(mesh);
    let body = parts.body_parts();
    if body.len() < 2 {
        return None;
    }
    // Each body part's bounding box.
    let mut boxes = vec![(DVec3::INFINITY, DVec3::NEG_INFINITY); parts.len()];
    for (v, p) in mesh.positions.iter().enumerate() {
        let b = &mut boxes[parts.part_of[v] as usize];
        *b = (b.0.min(*p), b.1.max(*p));
    }
    let mut groups = UnionFind::new(parts.len());
    for (i, &a) in body.iter().enumerate() {
        for &b in &body[i + 1..] {
            let (p, q) = (boxes[a], boxes[b]);
            if p.0.cmple(q.1).all() && q.0.cmple(p.1).all() {
                groups.union(a, b);
            }
        }
    }
    // Attached parts are one character, whatever their boxes (a foot just below its shin).
    for &(a, b) in attachments {
        groups.union(
            parts.part_of[a as usize] as usize,
            parts.part_of[b as usize] as usize,
        );
    }
    let mut of_part: Vec<Option<usize>> = vec![None; parts.len()];
    let mut roots: Vec<usize> = Vec::new();
    for &k in &body {
        let r = groups.find(k);
        let g = roots.iter().position(|&x| x == r).unwrap_or_else(|| {
            roots.push(r);
            roots.len() - 1
        });
        of_part[k] = Some(g);
    }
    if roots.len() < 2 {
        return None;
    }
    // A rider goes with the character its host vertex is on.
    let hosts = parts.hosts(&mesh.positions);
    for (v, host) in hosts.iter().enumerate() {
        let part = parts.part_of[v] as usize;
        if let (Some(h), None) = (host, of_part[part]) {
            of_part[part] = of_part[parts.part_of[*h as usize] as usize];
        }
    }
    let mut out: Vec<Character> = (0..roots.len())
        .map(|g| {
            let keep: Vec<bool> = of_part.iter().map(|&o| o == Some(g)).collect();
            let (sub, old) = parts.select_parts(mesh, &keep);
            let riders = old
                .iter()
                .filter(|&&v| parts.is_rider_vertex(v as usize))
                .count();
            let skeleton = Skeleton {
                distance: old.iter().map(|&v| skeleton.distance[v as usize]).collect(),
                points: old.iter().map(|&v| skeleton.points[v as usize]).collect(),
                riders,
                ..skeleton.clone()
            };
            Character {
                mesh: sub,
                skeleton,
            }
        })
        .collect();
    out.sort_by_key(|c| std::cmp::Reverse(c.mesh.positions.len()));
    Some(out)
}

/// The name of a cut of character `k` (0 the largest): the first keeps its names, the
/// others' take `.001`, `.002`… as a copy's do in Blender (`arm.L.001`); `root` stays.
pub(super) fn name(name: &str, k: usize, root: &str) -> String {
    if k == 0 || name == root {
        name.to_string()
    } else {
        format!("{name}.{k:03}")
    }
}

/// A cut's name taken apart into the name its role gives and the character it is of (0
/// the largest): `("arm.L", 1)` for `arm.L.001` (see [`name`]).
pub fn role(name: &str) -> (&str, usize) {
    match name.rsplit_once('.') {
        Some((role, k)) if k.len() == 3 && k.bytes().all(|b| b.is_ascii_digit()) => {
            (role, k.parse().unwrap_or(0))
        }
        _ => (name, 0),
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn a_copy_s_names_carry_its_number_and_the_same_roles() {
        assert_eq!(super::name("arm.L", 0, "root"), "arm.L");
        assert_eq!(super::name("arm.L", 1, "root"), "arm.L.001");
        assert_eq!(super::name("root", 2, "root"), "root");
        assert_eq!(super::role("arm.L.001"), ("arm.L", 1));
        assert_eq!(super::role("hand.2.R"), ("hand.2.R", 0));
        assert_eq!(super::role("tail.2"), ("tail.2", 0));
        assert_eq!(super::role("tail.2.012"), ("tail.2", 12));
    }
}
