//! What says how a body stands before its limbs are cut (the suggestion's first stage):
//! its mirror plane, its flat base, and how much finer one half of it is modelled than
//! the other.

use super::{mirror_plane, AXES, BASE_AREA, SOLES};
use crate::mesh::Mesh;
use glam::DVec3;

/// Per axis direction (in [`AXES`]' order), the share of the mesh's area in flat faces at
/// its far end that way: faces within 5° of facing along it and within 1 % of the mesh's
/// size of that end (a bust's base, a statue's plinth, the soles of feet; 0 for a mesh
/// with no area).
pub fn flat_ends(mesh: &Mesh) -> [f64; 6] {
    let (lo, hi) = crate::mesh::bounds(&mesh.positions);
    let size = (hi - lo).max_element();
    if !(size > 0.0 && size.is_finite()) {
        return [0.0; 6];
    }
    let cos = 5f64.to_radians().cos();
    let mut area = [0.0; 6];
    let mut total = 0.0;
    for t in &mesh.triangles {
        let [a, b, c] = t.map(|v| mesh.positions[v as usize]);
        let cross = (b - a).cross(c - a);
        let twice = cross.length();
        if !(twice > 0.0 && twice.is_finite()) {
            continue;
        }
        total += 0.5 * twice;
        let (normal, centre) = (cross / twice, (a + b + c) / 3.0);
        for (k, d) in AXES.iter().enumerate() {
            let end = if d.max_element() > 0.0 {
                hi.dot(*d)
            } else {
                lo.dot(*d)
            };
            if normal.dot(*d) > cos && (end - centre.dot(*d)).abs() < 0.01 * size {
                area[k] += 0.5 * twice;
            }
        }
    }
    if total > 0.0 {
        area.map(|a| a / total)
    } else {
        [0.0; 6]
    }
}

/// Is the end along `AXES[k]` flat as soles are ([`SOLES`] of the area at least, the
/// opposite end a third of that or less)? `flat` as [`flat_ends`] gives it.
pub(super) fn soled(flat: &[f64; 6], k: usize) -> bool {
    flat[k] >= SOLES && flat[k ^ 1] <= flat[k] / 3.0
}

/// The way down where exactly one axis direction's end is flat as soles are ([`soled`]).
pub fn soles(flat: &[f64; 6]) -> Option<DVec3> {
    let mut ends = (0..6).filter(|&k| soled(flat, k));
    match (ends.next(), ends.next()) {
        (Some(k), None) => Some(AXES[k]),
        _ => None,
    }
}

/// The outward normal of the mesh's flat base, if it has one: of the six axis directions,
/// the one whose flat faces at the mesh's far end that way cover the most area
/// ([`flat_ends`]), when that is at least [`BASE_AREA`] of the whole.
pub fn flat_base(mesh: &Mesh) -> Option<DVec3> {
    base_of(&flat_ends(mesh))
}

/// [`flat_base`] from the shares [`flat_ends`] gives.
fn base_of(flat: &[f64; 6]) -> Option<DVec3> {
    let k = (0..6).max_by(|&a, &b| flat[a].total_cmp(&flat[b]))?;
    (flat[k] >= BASE_AREA).then_some(AXES[k])
}

/// What says how a body stands before its limbs are cut: its mirror plane and its flat
/// base (the suggestion's first stage; up and front come from the limbs, [`super::frame`]).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Cues {
    /// The mirror plane (unit normal, offset along it), if the mesh has one
    /// ([`mirror_plane`]).
    pub mirror: Option<(DVec3, f64)>,
    /// The outward normal of its flat base, if it has one ([`flat_base`]).
    pub base: Option<DVec3>,
    /// Per axis direction, the share of its area flat at its far end that way
    /// ([`flat_ends`]: soles, a base).
    pub flat: [f64; 6],
    /// Where its volume lies: the centre of mass of the solid it encloses, if it encloses
    /// any ([`bulk`]).
    pub bulk: Option<DVec3>,
    /// Per axis (x, y, z), how much finer the surface is made in the half of the mesh on
    /// the axis's positive side than in the other ([`detail`]): 0 where alike or unknown.
    pub detail: [f64; 3],
}

impl Cues {
    /// The cues of `mesh`, standing along `up` where that is given: its mirror plane then
    /// holds up, and is read against the surface (see the module docs). Where up is not
    /// given and no plane is found, soles at one end only ([`SOLES`]) stand for it.
    pub fn of(mesh: &Mesh, up: Option<DVec3>) -> Cues {
        let surface: &[[u32; 3]] = if up.is_some() { &mesh.triangles } else { &[] };
        let flat = flat_ends(mesh);
        // Without up and without a plane, soles at one end only stand for up: the two
        // planes that hold it are tried against the surface (a low-poly animal with its
        // head turned has its plane).
        let mirror = mirror_plane(&mesh.positions, surface, up).or_else(|| match up {
            None => soles(&flat)
                .and_then(|down| mirror_plane(&mesh.positions, &mesh.triangles, Some(-down))),
            Some(_) => None,
        });
        Cues {
            mirror,
            base: base_of(&flat),
            flat,
            bulk: bulk(mesh),
            detail: detail(mesh),
        }
    }
}

/// Per axis, the natural log of the ratio of the triangles per unit of area in the half of
/// the mesh's box on the axis's positive side (by where each triangle's centroid lies) to
/// those in the other half: where an artist modelled a face (eyes, a mouth, a muzzle's
/// nostrils), triangles are smaller than over a rump or a back (0 where a half has no
/// area).
pub fn detail(mesh: &Mesh) -> [f64; 3] {
    let (lo, hi) = crate::mesh::bounds(&mesh.positions);
    let mid = (lo + hi) * 0.5;
    // Per axis and side: triangles and their area.
    let mut count = [[0.0f64; 2]; 3];
    let mut area = [[0.0f64; 2]; 3];
    for t in &mesh.triangles {
        let [Some(a), Some(b), Some(c)] = t.map(|v| mesh.positions.get(v as usize).copied()) else {
            continue;
        };
        let size = 0.5 * (b - a).cross(c - a).length();
        if !(size > 0.0 && size.is_finite()) {
            continue;
        }
        let centroid = (a + b + c) / 3.0;
        for axis in 0..3 {
            let side = usize::from(centroid[axis] > mid[axis]);
            count[axis][side] += 1.0;
            area[axis][side] += size;
        }
    }
    std::array::from_fn(|axis| {
        let [n0, n1] = count[axis];
        let [a0, a1] = area[axis];
        if a0 > 0.0 && a1 > 0.0 && n0 > 0.0 && n1 > 0.0 {
            ((n1 / a1) / (n0 / a0)).ln()
        } else {
            0.0
        }
    })
}

/// The centre of mass of the solid the mesh encloses (uniform density: the signed
/// tetrahedra from a point inside its box to each face), `None` where it encloses no
/// volume. A fish's or a dinosaur's lies toward its head: the body thickest near the front,
/// tapering to a tail.
pub fn bulk(mesh: &Mesh) -> Option<DVec3> {
    let (lo, hi) = crate::mesh::bounds(&mesh.positions);
    let o = (lo + hi) * 0.5;
    let (mut volume, mut moment) = (0.0, DVec3::ZERO);
    for t in &mesh.triangles {
        let [Some(a), Some(b), Some(c)] = t.map(|v| mesh.positions.get(v as usize).copied()) else {
            continue;
        };
        let (a, b, c) = (a - o, b - o, c - o);
        let v = a.dot(b.cross(c)) / 6.0;
        volume += v;
        moment += v * (a + b + c) / 4.0;
    }
    let centre = o + moment / volume;
    (volume > 0.0 && centre.is_finite()).then_some(centre)
}
