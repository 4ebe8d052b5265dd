//! Repairs of what downloaded meshes often get wrong, each run only when the edge census
//! shows it is needed:
//!
//! * **duplicate faces**: a face over the same three vertices as an earlier one is dropped;
//!   a two-sided flap (a face written both ways round, hanging off the surface by an edge
//!   no other face uses) goes whole;
//! * **fins**: a piece of open surface hanging off an edge that three or more faces share
//!   (a fin, a flap left by a modeller) is dropped when a larger piece shares that edge;
//! * **open seams**: boundary vertices almost on top of another boundary vertex (closer
//!   than a tenth of their shortest edge: a gap no modeller meant) are welded;
//! * **inconsistent orientation**: faces are turned to agree with their neighbours, part by
//!   part, from each part's first face (the part's outward side is settled later by the sign
//!   of its volume); a part that cannot be oriented (a Möbius strip) is left as it is;
//! * **holes**: a boundary loop of at most the given number of edges (by default every
//!   one) is closed with well-shaped triangles faired to continue the surface
//!   ([`super::fill`]; a fan around the loop's centre where its projection folds). Loops
//!   through a vertex with more than one boundary (two holes touching) are left.

use super::edges::{target, HalfEdges};
use super::weld::remap;
use super::Mesh;

/// Drops the faces written more than once over the same three vertices, keeping the first;
/// a *flap* (a face written both ways round with an edge no other face uses: a two-sided
/// triangle hanging off the surface) goes whole. Returns how many faces were dropped.
pub(super) fn drop_duplicate_faces(mesh: &mut Mesh) -> usize {
    use std::collections::HashMap;
    let way = |t: &[u32; 3]| {
        let k = (0..3).min_by_key(|&k| t[k]).unwrap_or(0);
        usize::from(t[(k + 1) % 3] < t[(k + 2) % 3])
    };
    let key = |t: &[u32; 3]| {
        let mut k = *t;
        k.sort_unstable();
        k
    };
    // Copies of each vertex set, each way round; faces on each edge.
    let mut copies: HashMap<[u32; 3], [u32; 2]> = HashMap::with_capacity(mesh.triangles.len());
    let mut on_edge: HashMap<(u32, u32), u32> = HashMap::new();
    for t in &mesh.triangles {
        copies.entry(key(t)).or_default()[way(t)] += 1;
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            *on_edge.entry((a.min(b), a.max(b))).or_default() += 1;
        }
    }
    let flap = |k: &[u32; 3], n: [u32; 2]| {
        n[0] > 0
            && n[1] > 0
            && [(k[0], k[1]), (k[1], k[2]), (k[0], k[2])]
                .iter()
                .any(|e| on_edge.get(e).copied().unwrap_or(0) <= n[0] + n[1])
    };
    let mut kept = std::collections::HashSet::with_capacity(mesh.triangles.len());
    let before = mesh.triangles.len();
    mesh.triangles.retain(|t| {
        let k = key(t);
        copies.get(&k).is_some_and(|&n| !flap(&k, n)) && kept.insert(k)
    });
    before - mesh.triangles.len()
}

/// Drops the faces joined to no other along any of their three edges (a stray triangle
/// left where a seam came apart: filled, it would close into a solid of no volume whose
/// vertices have no normal), unless every face is one (a file of lone triangles keeps them,
/// and the check says what they lack). Returns how many were dropped.
pub(super) fn drop_lone_faces(mesh: &mut Mesh) -> usize {
    use std::collections::HashMap;
    let edge = |a: u32, b: u32| (a.min(b), a.max(b));
    let mut on_edge: HashMap<(u32, u32), u32> = HashMap::with_capacity(mesh.triangles.len());
    for t in &mesh.triangles {
        for k in 0..3 {
            *on_edge.entry(edge(t[k], t[(k + 1) % 3])).or_default() += 1;
        }
    }
    let joined = |t: &[u32; 3]| (0..3).any(|k| on_edge[&edge(t[k], t[(k + 1) % 3])] > 1);
    if !mesh.triangles.iter().any(joined) {
        return 0;
    }
    let before = mesh.triangles.len();
    mesh.triangles.retain(joined);
    before - mesh.triangles.len()
}

/// A piece hanging off an edge is a fin, dropped, while it has at most this many faces (a
/// stray flap); a larger one (a skirt, trousers, a cape) is a piece of its own.
pub(super) const FIN: usize = 16;

/// What [`drop_fins`] did.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub(super) struct Fins {
    /// Faces dropped (fins).
    pub dropped: usize,
    /// Pieces given their own copies of the vertices they shared.
    pub detached: usize,
    /// Those copies (vertex numbers after the mesh's own).
    pub copies: Vec<u32>,
}

/// Drops the *fins*: the faces of a piece that hangs off an edge shared by an odd number
/// of faces (three or more), when the piece is open (it has an edge of one face), a
/// larger piece shares that edge, and the piece has at most [`FIN`] faces. A larger open
/// piece hanging so (a character's trousers or skirt meeting its body along the waist)
/// is a piece of its own: it gets its own copies of the vertices it shares, its
/// holes are then filled like any other, and it is attached where it meets the body
/// (`attachments`). Where that leaves more than two faces on such an edge (or on an edge
/// of four or more faces that [`super::split::split_sheets`] cannot pair), the smallest
/// closed piece there gets its own copies too, then the next, until two faces are left (a
/// low-poly eye set into a ring of the head, its buried half a third piece). Where more
/// than two faces of one piece are still left (a face folded over its neighbours' edge),
/// the smallest of those running the edge the way more of them do is dropped, until as many
/// run each way. Pieces are faces joined across edges of exactly two faces. Leaves the mesh
/// untouched when there is nothing to do.
pub(super) fn drop_fins(mesh: &mut Mesh) -> Fins {
    use std::collections::HashMap;
    let n = mesh.triangles.len();
    let mut on_edge: HashMap<(u32, u32), Vec<u32>> = HashMap::new();
    for (f, t) in mesh.triangles.iter().enumerate() {
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            on_edge
                .entry((a.min(b), a.max(b)))
                .or_default()
                .push(f as u32);
        }
    }
    // Each face on the edge `a`–`b` (`a < b`) and whether it runs along it from `a`.
    let ways = |&(a, b): &(u32, u32), faces: &[u32]| -> Vec<(u32, bool)> {
        faces
            .iter()
            .map(|&f| {
                let t = mesh.triangles[f as usize];
                (f, (0..3).any(|k| t[k] == a && t[(k + 1) % 3] == b))
            })
            .collect()
    };
    // An edge of three or more faces that `split_sheets` cannot pair: an odd number, or
    // faces that do not run half each way or do not pair about the edge.
    let unpaired = |e: &(u32, u32), f: &Vec<u32>| {
        f.len() > 2
            && (f.len() % 2 == 1
                || super::split::pair_around(mesh, e.0, e.1, &ways(e, f)).is_none())
    };
    if !on_edge.iter().any(|(e, f)| unpaired(e, f)) {
        return Fins::default();
    }
    // Pieces: faces joined across edges of two faces.
    let mut parent: Vec<u32> = (0..n as u32).collect();
    fn find(parent: &mut [u32], mut x: u32) -> u32 {
        while parent[x as usize] != x {
            parent[x as usize] = parent[parent[x as usize] as usize];
            x = parent[x as usize];
        }
        x
    }
    for faces in on_edge.values() {
        if let [f, g] = faces[..] {
            let (a, b) = (find(&mut parent, f), find(&mut parent, g));
            parent[a.max(b) as usize] = a.min(b);
        }
    }
    let roots: Vec<u32> = (0..n as u32).map(|f| find(&mut parent, f)).collect();
    let mut size: HashMap<u32, usize> = HashMap::new();
    for &r in &roots {
        *size.entry(r).or_default() += 1;
    }
    let mut open: std::collections::HashSet<u32> = std::collections::HashSet::new();
    for faces in on_edge.values() {
        if let [f] = faces[..] {
            open.insert(roots[f as usize]);
        }
    }
    let mut drop: std::collections::HashSet<u32> = std::collections::HashSet::new();
    let mut detach: std::collections::BTreeSet<u32> = std::collections::BTreeSet::new();
    let mut keys: Vec<(u32, u32)> = on_edge
        .iter()
        .filter(|(e, f)| unpaired(e, f))
        .map(|(e, _)| *e)
        .collect();
    keys.sort_unstable_by_key(|e| &on_edge[e]);
    let edges: Vec<&Vec<u32>> = keys.iter().map(|e| &on_edge[e]).collect();
    for faces in &edges {
        let largest = faces
            .iter()
            .map(|&f| size[&roots[f as usize]])
            .max()
            .unwrap_or(0);
        for &f in faces.iter() {
            let r = roots[f as usize];
            if open.contains(&r) && size[&r] < largest {
                if size[&r] <= FIN {
                    drop.insert(r);
                } else {
                    detach.insert(r);
                }
            }
        }
    }
    // Where more than two faces are left on such an edge, the smallest closed piece there
    // goes its own way, then the next, until two are left (an eye set into a ring of the
    // head keeps its visible cap joined to the head; its buried half closes on its own).
    for faces in &edges {
        loop {
            let left: Vec<u32> = faces
                .iter()
                .map(|&f| roots[f as usize])
                .filter(|r| !drop.contains(r) && !detach.contains(r))
                .collect();
            if left.len() <= 2 {
                break;
            }
            let largest = left.iter().map(|r| size[r]).max().unwrap_or(0);
            match left
                .iter()
                .filter(|r| size[*r] < largest)
                .min_by_key(|r| (size[*r], **r))
            {
                Some(&r) => {
                    detach.insert(r);
                }
                None => break,
            }
        }
    }
    // Where more than two faces are still left on an edge, all of one piece (a face folded
    // over its neighbours' edge, joined to them elsewhere), the smallest of those running
    // the edge the way more of them do goes, until as many run each way: its gap is then
    // a hole like any other.
    let mut stray: std::collections::BTreeSet<u32> = std::collections::BTreeSet::new();
    let area = |f: u32| {
        let [a, b, c] = mesh.triangles[f as usize].map(|v| mesh.positions[v as usize]);
        (b - a).cross(c - a).length()
    };
    for e in &keys {
        let left: Vec<(u32, bool)> = ways(e, &on_edge[e])
            .into_iter()
            .filter(|&(f, _)| {
                let r = roots[f as usize];
                !drop.contains(&r) && !detach.contains(&r) && !stray.contains(&f)
            })
            .collect();
        let one_piece = left
            .iter()
            .all(|w| roots[w.0 as usize] == roots[left[0].0 as usize]);
        if left.len() <= 2 || !one_piece {
            continue;
        }
        let forward = left.iter().filter(|w| w.1).count();
        let more = forward * 2 > left.len();
        let mut more_way: Vec<u32> = left.iter().filter(|w| w.1 == more).map(|w| w.0).collect();
        more_way.sort_by(|&f, &g| area(f).total_cmp(&area(g)).then(f.cmp(&g)));
        let excess = more_way.len() - (left.len() - more_way.len());
        stray.extend(more_way.iter().take(excess));
    }
    // A piece both dropped (off one edge) and detached (off another) is dropped.
    detach.retain(|r| !drop.contains(r));
    let copies = if detach.is_empty() {
        Vec::new()
    } else {
        own_copies(mesh, &roots, &detach)
    };
    let mut f = 0;
    mesh.triangles.retain(|_| {
        f += 1;
        !drop.contains(&roots[f - 1]) && !stray.contains(&(f as u32 - 1))
    });
    Fins {
        dropped: n - mesh.triangles.len(),
        detached: detach.len(),
        copies,
    }
}

/// Gives each piece in `detach` (by its root in `roots`, one per face) its own copy of
/// every vertex a face outside it uses too; returns the copies, in order.
fn own_copies(
    mesh: &mut Mesh,
    roots: &[u32],
    detach: &std::collections::BTreeSet<u32>,
) -> Vec<u32> {
    use std::collections::HashMap;
    let mut users: HashMap<u32, Vec<u32>> = HashMap::new();
    for (f, t) in mesh.triangles.iter().enumerate() {
        for &v in t {
            let list = users.entry(v).or_default();
            if !list.contains(&roots[f]) {
                list.push(roots[f]);
            }
        }
    }
    let mut copies: HashMap<(u32, u32), u32> = HashMap::new();
    for (f, t) in mesh.triangles.iter_mut().enumerate() {
        let r = roots[f];
        if !detach.contains(&r) {
            continue;
        }
        for v in t.iter_mut() {
            if users[v].len() > 1 {
                *v = *copies.entry((*v, r)).or_insert_with(|| {
                    mesh.positions.push(mesh.positions[*v as usize]);
                    (mesh.positions.len() - 1) as u32
                });
            }
        }
    }
    let mut copies: Vec<u32> = copies.into_values().collect();
    copies.sort_unstable();
    copies
}

/// Welds boundary vertices closer than a tenth of the shortest edge at either, but none
/// from `apart` (the copies [`drop_fins`] gave a detached piece). Two joined by an edge
/// count it out: they weld only where it is a sliver's, a tenth of every other edge at
/// both (two faces folded over a 0.9 mm edge of a low-poly alpaca), and the faces over it
/// go. Returns how many vertices were merged (0 leaves the mesh untouched).
pub(super) fn weld_seams(mesh: &mut Mesh, half: &HalfEdges, apart: &[u32]) -> usize {
    let n = mesh.positions.len();
    // Boundary vertices and their two shortest incident edges (the first with the vertex
    // at its other end).
    let mut reach = vec![(f64::INFINITY, u32::MAX, f64::INFINITY); n];
    let mut note = |v: u32, other: u32, len: f64| {
        let r = &mut reach[v as usize];
        if other == r.1 {
            return;
        }
        if len < r.0 {
            *r = (len, other, r.0);
        } else if len < r.2 {
            r.2 = len;
        }
    };
    let mut boundary = Vec::new();
    for a in 0..n as u32 {
        let mut on_boundary = false;
        for &e in half.row(a) {
            let b = target(e);
            let len = mesh.positions[a as usize].distance(mesh.positions[b as usize]);
            note(a, b, len);
            note(b, a, len);
            if half.count(b, a) == 0 {
                on_boundary = true;
            }
        }
        if on_boundary {
            boundary.push(a);
        }
    }
    // Also the end of a boundary half-edge (its own row may have no boundary edge).
    let mut is_boundary = vec![false; n];
    for &a in &boundary {
        is_boundary[a as usize] = true;
        for &e in half.row(a) {
            let b = target(e);
            if half.count(b, a) == 0 {
                is_boundary[b as usize] = true;
            }
        }
    }
    for &v in apart {
        if let Some(b) = is_boundary.get_mut(v as usize) {
            *b = false;
        }
    }
    let mut list: Vec<u32> = (0..n as u32).filter(|&v| is_boundary[v as usize]).collect();
    if list.len() < 2 {
        return 0;
    }
    list.sort_by(|&a, &b| {
        mesh.positions[a as usize]
            .x
            .total_cmp(&mesh.positions[b as usize].x)
            .then(a.cmp(&b))
    });
    // A tenth of `v`'s shortest edge other than one to `to`.
    let tol = |v: u32, to: u32| {
        let (len, other, next) = reach[v as usize];
        0.1 * if other == to { next } else { len }
    };
    let mut pairs = Vec::new();
    for (k, &a) in list.iter().enumerate() {
        let pa = mesh.positions[a as usize];
        // The widest this vertex's tolerance can be (its edge to the other excepted).
        let widest = 0.1 * reach[a as usize].2;
        for &b in &list[k + 1..] {
            let pb = mesh.positions[b as usize];
            if pb.x - pa.x > widest {
                break;
            }
            let t = tol(a, b).min(tol(b, a));
            // Two ends of one edge only where that edge is a sliver's (a tenth of every
            // other edge at both ends): collapsing it drops the faces folded over it.
            if pa.distance(pb) <= t {
                pairs.push((a.max(b), a.min(b)));
            }
        }
    }
    pairs.sort_unstable();
    let mut rep: Vec<u32> = (0..n as u32).collect();
    // The faces at each vertex, those of a vertex welded to it included.
    let mut faces_of: Vec<Vec<u32>> = vec![Vec::new(); n];
    for (f, t) in mesh.triangles.iter().enumerate() {
        for &v in t {
            faces_of[v as usize].push(f as u32);
        }
    }
    let mut merged = 0;
    for (i, j) in pairs {
        if rep[i as usize] == i && rep[j as usize] == j && !overfills(mesh, &rep, &faces_of, i, j) {
            rep[i as usize] = j;
            let moved = std::mem::take(&mut faces_of[i as usize]);
            faces_of[j as usize].extend(moved);
            merged += 1;
        }
    }
    if merged > 0 {
        remap(mesh, &rep);
    }
    merged
}

/// Whether welding vertex `i` to `j` (each vertex already welded to `rep[v]`; the faces at
/// each in `faces_of`) would leave an edge at `j` with more than two faces where it had
/// fewer: a seam welded across a gap that a dropped fin left beside it (a stag's head,
/// whose midline kept one face of three), which the hole's filling closes instead.
fn overfills(mesh: &Mesh, rep: &[u32], faces_of: &[Vec<u32>], i: u32, j: u32) -> bool {
    use std::collections::HashMap;
    let (fi, fj) = (&faces_of[i as usize], &faces_of[j as usize]);
    // Per other end of an edge at `j`: its faces before the weld and after.
    let mut count: HashMap<u32, (usize, usize)> = HashMap::new();
    for (k, &f) in fi.iter().chain(fj).enumerate() {
        if k >= fi.len() && fi.contains(&f) {
            continue;
        }
        let before = mesh.triangles[f as usize].map(|v| rep[v as usize]);
        let after = before.map(|v| if v == i { j } else { v });
        for (t, at) in [(before, 0), (after, 1)] {
            if t[0] == t[1] || t[1] == t[2] || t[0] == t[2] {
                continue;
            }
            for k in 0..3 {
                let (a, b) = (t[k], t[(k + 1) % 3]);
                let other = if a == j {
                    b
                } else if b == j {
                    a
                } else {
                    continue;
                };
                let c = count.entry(other).or_default();
                if at == 0 {
                    c.0 += 1;
                } else {
                    c.1 += 1;
                }
            }
        }
    }
    count
        .values()
        .any(|&(before, after)| after > 2 && after > before)
}

/// Turns faces to agree with their neighbours across two-face edges, part by part from the
/// part's first face. Returns how many faces were turned (in each part, the smaller of the
/// two sides), or `None` when some part cannot be oriented (nothing changes then).
pub(super) fn orient(mesh: &mut Mesh, half: &HalfEdges) -> Option<usize> {
    let f = mesh.triangles.len();
    let mut flip: Vec<Option<bool>> = vec![None; f];
    let mut turned = 0;
    let mut queue = Vec::new();
    let mut members = Vec::new();
    for seed in 0..f {
        if flip[seed].is_some() {
            continue;
        }
        flip[seed] = Some(false);
        queue.push(seed as u32);
        members.clear();
        while let Some(face) = queue.pop() {
            members.push(face);
            let me = flip[face as usize] == Some(true);
            let t = mesh.triangles[face as usize];
            for k in 0..3 {
                let (a, b) = (t[k], t[(k + 1) % 3]);
                let mut same = half.faces(a, b).filter(|&g| g != face);
                let mut opposite = half.faces(b, a);
                // Only a two-face edge has a neighbour to agree with. One running the same
                // way along the edge must be turned relative to this face.
                let (g, relative) =
                    match (same.next(), same.next(), opposite.next(), opposite.next()) {
                        (Some(g), None, None, None) => (g, true),
                        (None, None, Some(g), None) => (g, false),
                        _ => continue,
                    };
                let want = me ^ relative;
                match flip[g as usize] {
                    None => {
                        flip[g as usize] = Some(want);
                        queue.push(g);
                    }
                    Some(have) if have != want => return None,
                    Some(_) => {}
                }
            }
        }
        let flipped = members
            .iter()
            .filter(|&&g| flip[g as usize] == Some(true))
            .count();
        if 2 * flipped > members.len() {
            // Fewer changes the other way round (the volume decides the outside later).
            for &g in &members {
                flip[g as usize] = flip[g as usize].map(|x| !x);
            }
        }
        turned += flipped.min(members.len() - flipped);
    }
    for (t, fl) in mesh.triangles.iter_mut().zip(&flip) {
        if *fl == Some(true) {
            t.swap(1, 2);
        }
    }
    Some(turned)
}

/// A boundary loop that was or was not closed.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(super) struct Holes {
    /// Loops closed.
    pub filled: usize,
    /// Faces added to close them.
    pub faces: usize,
    /// Vertices added inside them.
    pub vertices: usize,
    /// Loops whose projection folded, closed with a fan.
    pub fans: usize,
    /// Loops left open because they are longer than the limit.
    pub too_large: usize,
    /// Edges of the longest loop left open.
    pub largest_left: usize,
}

/// Closes boundary loops of at most `max_edges` edges (see module docs).
pub(super) fn fill_holes(mesh: &mut Mesh, half: &HalfEdges, max_edges: usize) -> Holes {
    let n = mesh.positions.len();
    // The boundary half-edge leaving each vertex (u32::MAX: none; MANY: more than one).
    const NONE: u32 = u32::MAX;
    const MANY: u32 = u32::MAX - 1;
    let mut next = vec![NONE; n];
    for a in 0..n as u32 {
        let row = half.row(a);
        for (k, &e) in row.iter().enumerate() {
            let b = target(e);
            if k > 0 && target(row[k - 1]) == b {
                continue;
            }
            if half.count(a, b) == 1 && half.count(b, a) == 0 {
                next[a as usize] = if next[a as usize] == NONE { b } else { MANY };
            }
        }
    }
    let mut holes = Holes::default();
    let mut done = vec![false; n];
    let mut lp = Vec::new();
    for start in 0..n {
        if done[start] || next[start] == NONE || next[start] == MANY {
            continue;
        }
        lp.clear();
        let mut v = start as u32;
        let closed = loop {
            lp.push(v);
            done[v as usize] = true;
            let w = next[v as usize];
            if w == NONE || w == MANY {
                break false;
            }
            if w == start as u32 {
                break true;
            }
            if done[w as usize] || lp.len() > n {
                break false;
            }
            v = w;
        };
        // A loop along an edge of more than two faces (a fin) is no hole to close.
        let fin = (0..lp.len()).any(|k| {
            let (a, b) = (lp[k], lp[(k + 1) % lp.len()]);
            half.count(a, b) + half.count(b, a) > 2
        });
        if !closed || fin {
            continue;
        }
        if lp.len() > max_edges {
            holes.too_large += 1;
            holes.largest_left = holes.largest_left.max(lp.len());
            continue;
        }
        // The loop runs along the faces' boundary edges a → b; new faces use b → a.
        let neighbours = |v: u32| half.row(v).iter().map(|&e| target(e)).collect();
        let base = mesh.positions.len() as u32;
        let patch = super::fill::close(&lp, &mesh.positions, &neighbours, base);
        holes.faces += patch.triangles.len();
        holes.vertices += patch.positions.len();
        holes.fans += usize::from(patch.fan);
        mesh.positions.extend(patch.positions);
        mesh.triangles.extend(patch.triangles);
        holes.filled += 1;
    }
    holes
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::shapes;
    use glam::DVec3;

    fn census(m: &Mesh) -> super::super::edges::EdgeCensus {
        HalfEdges::new(m.positions.len(), &m.triangles).census(&|_| true)
    }

    #[test]
    fn a_missing_cap_is_filled_and_closes_the_sphere() {
        let mut m = shapes::uv_sphere(1.0, 8, 12);
        // Remove the faces around the first vertex (a pole): a 12-edge hole.
        m.triangles.retain(|t| !t.contains(&0));
        let half = HalfEdges::new(m.positions.len(), &m.triangles);
        assert_eq!(census(&m).boundary, 12);
        let small = fill_holes(&mut m.clone(), &half, 11);
        assert_eq!(
            (small.filled, small.too_large, small.largest_left),
            (0, 1, 12)
        );
        let before = m.positions.len();
        let holes = fill_holes(&mut m, &half, 16);
        assert_eq!(holes.filled, 1);
        // A disc's triangles: twice the new vertices plus the loop's edges less two.
        assert_eq!(holes.faces, 2 * holes.vertices + 12 - 2);
        assert!(holes.vertices > 0 && holes.fans == 0, "{holes:?}");
        assert!(census(&m).is_clean());
        // The patch continues the sphere: it bulges past the loop's plane towards the pole
        // it replaces, and stays about on the sphere.
        let axis = m.positions[0];
        let rim = m.positions[1].dot(axis);
        let new = &m.positions[before..];
        let top = new.iter().map(|p| p.dot(axis)).fold(f64::MIN, f64::max);
        assert!(
            top > rim + 0.5 * (1.0 - rim),
            "a flat cap: {top} over a rim at {rim}"
        );
        assert!(
            new.iter()
                .all(|p| p.length() < 1.1 && p.dot(axis) > rim - 1e-9),
            "{new:?}"
        );
    }

    #[test]
    fn flipped_faces_are_turned_back() {
        let mut m = shapes::uv_sphere(1.0, 12, 8);
        let reference = m.clone();
        for k in [3, 10, 11, 40] {
            m.triangles[k].swap(1, 2);
        }
        let half = HalfEdges::new(m.positions.len(), &m.triangles);
        assert_eq!(orient(&mut m, &half), Some(4));
        assert!(census(&m).is_clean());
        assert_eq!(m, reference);
    }

    #[test]
    fn a_gap_in_a_seam_is_welded() {
        let mut m = shapes::uv_sphere(1.0, 12, 8);
        // Split vertex 5 into a copy a hair away for two of its faces.
        let copy = m.positions.len() as u32;
        m.positions.push(m.positions[5] + DVec3::splat(1e-4));
        let mut moved = 0;
        for t in &mut m.triangles {
            if moved < 2 && t.contains(&5) {
                *t = t.map(|v| if v == 5 { copy } else { v });
                moved += 1;
            }
        }
        assert!(!census(&m).is_clean());
        let half = HalfEdges::new(m.positions.len(), &m.triangles);
        assert_eq!(weld_seams(&mut m, &half, &[]), 1);
        assert!(census(&m).is_clean());
    }

    /// A gap whose two sides a sliver joins (a face over an edge a ten-thousandth long, as
    /// a low-poly alpaca's head has two): the ends of that edge are welded, the sliver goes,
    /// and the sphere is whole; an edge a tenth as long as the others is left alone.
    #[test]
    fn a_sliver_across_a_gap_is_collapsed() {
        let sphere = shapes::uv_sphere(1.0, 12, 8);
        let v = 5u32;
        let fan: Vec<usize> = (0..sphere.triangles.len())
            .filter(|&f| sphere.triangles[f].contains(&v))
            .collect();
        // The copy takes one face of the fan; the sliver joins it to the vertex, over one
        // of that face's edges (turned so the two agree there).
        let gap = |offset: f64| {
            let mut m = sphere.clone();
            let copy = m.positions.len() as u32;
            m.positions
                .push(m.positions[v as usize] + DVec3::splat(offset));
            let f = fan[0];
            let t = m.triangles[f];
            let k = t.iter().position(|&x| x == v).unwrap();
            let next = t[(k + 1) % 3];
            m.triangles[f] = t.map(|x| if x == v { copy } else { x });
            m.triangles.push([v, next, copy]);
            m
        };
        let mut m = gap(1e-4);
        assert!(!census(&m).is_clean());
        let half = HalfEdges::new(m.positions.len(), &m.triangles);
        assert_eq!(weld_seams(&mut m, &half, &[]), 1);
        assert!(census(&m).is_clean());
        assert_eq!(m.triangles.len(), sphere.triangles.len());
        let mut m = gap(0.03);
        let half = HalfEdges::new(m.positions.len(), &m.triangles);
        assert_eq!(weld_seams(&mut m, &half, &[]), 0);
    }

    /// A boundary vertex beside another, where welding them would lay a third face on an
    /// edge (a strip of two faces whose shared edge would land on a hole's rim), stays
    /// apart: the weld is for gaps that close, not for folds that make fins.
    #[test]
    fn a_seam_weld_never_puts_three_faces_on_an_edge() {
        let sphere = shapes::uv_sphere(1.0, 12, 8);
        let [a, b, c] = sphere.triangles[5];
        let mut m = sphere.clone();
        m.triangles.remove(5);
        // A strip of two faces on the edge a–i, i a hair from c.
        let i = m.positions.len() as u32;
        let (pa, pc) = (m.positions[a as usize], m.positions[c as usize]);
        m.positions.push(pc + 1e-6 * (pc - pa));
        m.positions
            .push(pc + 0.5 * (pc - pa) + DVec3::new(0.0, 0.0, 0.3));
        m.positions
            .push(pc + 0.5 * (pc - pa) - DVec3::new(0.0, 0.0, 0.3));
        m.triangles.push([a, i, i + 1]);
        m.triangles.push([i, a, i + 2]);
        let half = HalfEdges::new(m.positions.len(), &m.triangles);
        let before = m.clone();
        assert_eq!(weld_seams(&mut m, &half, &[]), 0);
        assert_eq!(m.triangles, before.triangles);
        // Where i closes the hole in c's place instead, it welds to c: the sphere is whole.
        let mut m = before.clone();
        m.triangles.truncate(m.triangles.len() - 2);
        m.triangles.push([a, b, i]);
        let half = HalfEdges::new(m.positions.len(), &m.triangles);
        assert_eq!(weld_seams(&mut m, &half, &[]), 1);
        assert!(census(&m).is_clean(), "{:?}", census(&m));
    }

    /// A lone face joined to nothing goes; a surface keeps every face, and a lone face with
    /// nothing else keeps it.
    #[test]
    fn a_lone_face_is_dropped_and_the_surface_kept() {
        let sphere = shapes::uv_sphere(1.0, 12, 8);
        let mut m = sphere.clone();
        let k = m.positions.len() as u32;
        m.positions.extend([
            DVec3::new(3.0, 0.0, 0.0),
            DVec3::new(3.0, 1.0, 0.0),
            DVec3::new(3.0, 0.0, 1.0),
        ]);
        m.triangles.push([k, k + 1, k + 2]);
        assert_eq!(drop_lone_faces(&mut m), 1);
        assert_eq!(m.triangles, sphere.triangles);
        assert_eq!(drop_lone_faces(&mut m), 0);
        // A file of one triangle keeps it (the check then names its open edges).
        let mut one = Mesh {
            positions: vec![DVec3::ZERO, DVec3::X, DVec3::Y],
            triangles: vec![[0, 1, 2]],
        };
        assert_eq!(drop_lone_faces(&mut one), 0);
    }

    /// A fin (one face hanging off an edge of a closed sphere) and a flap of two faces go;
    /// the sphere is whole again. Three equal open sheets meeting along an edge (a book)
    /// have no larger piece to keep: nothing goes, and the check names the edge.
    #[test]
    fn fins_are_dropped_and_the_surface_kept() {
        let sphere = shapes::uv_sphere(1.0, 12, 8);
        let t = sphere.triangles[5];
        let mut m = sphere.clone();
        let tip = m.positions.len() as u32;
        m.positions.push(DVec3::new(3.0, 0.0, 0.0));
        m.triangles.push([t[1], t[0], tip]);
        assert_eq!(census(&m).nonmanifold, 1);
        assert_eq!(drop_fins(&mut m).dropped, 1);
        assert_eq!(m.triangles, sphere.triangles);
        // A flap of two faces off one edge.
        let mut m = sphere.clone();
        let far = m.positions.len() as u32;
        m.positions.push(DVec3::new(3.0, 0.0, 0.0));
        m.positions.push(DVec3::new(3.0, 1.0, 0.0));
        m.triangles.push([t[1], t[0], far]);
        m.triangles.push([t[0], far + 1, far]);
        assert_eq!(drop_fins(&mut m).dropped, 2);
        assert!(census(&m).is_clean() || census(&m).boundary == 0);
        // A book: three single-face pages on one spine.
        let mut book = Mesh {
            positions: vec![
                DVec3::ZERO,
                DVec3::Y,
                DVec3::X,
                DVec3::Z,
                DVec3::new(-1.0, 0.0, 0.0),
            ],
            triangles: vec![[0, 1, 2], [1, 0, 3], [0, 1, 4]],
        };
        assert_eq!(drop_fins(&mut book), Fins::default());
        assert_eq!(book.triangles.len(), 3);
    }

    /// An open piece of more than [`FIN`] faces hanging off an edge (a character's
    /// trousers on its body) is no fin: it keeps its faces, with its own copies of the
    /// vertices it shared, and is a part of its own.
    #[test]
    fn a_large_open_piece_hanging_off_an_edge_is_detached_not_dropped() {
        let sphere = shapes::uv_sphere(1.0, 12, 8);
        let t = sphere.triangles[5];
        let mut m = sphere.clone();
        // A fan of faces off one edge of the sphere: half as many faces as the sphere.
        let base = m.positions.len() as u32;
        let count = sphere.triangles.len() / 2;
        for k in 0..=count {
            let a = k as f64 / count as f64 * std::f64::consts::PI;
            m.positions.push(DVec3::new(3.0 + a.cos(), a.sin(), 0.0));
        }
        m.triangles.push([t[1], t[0], base]);
        for k in 0..count as u32 {
            m.triangles.push([t[0], base + k + 1, base + k]);
        }
        let faces = m.triangles.len();
        let fins = drop_fins(&mut m);
        assert_eq!((fins.dropped, fins.detached, fins.copies.len()), (0, 1, 2));
        assert_eq!(m.triangles.len(), faces);
        assert_eq!(census(&m).nonmanifold, 0);
        assert_eq!(m.triangles[..sphere.triangles.len()], sphere.triangles[..]);
        assert_eq!(crate::mesh::Parts::of(&m).len(), 2);
    }
}
