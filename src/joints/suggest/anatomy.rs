//! Step 5 of the module docs: which way is up, front and left, and names by role.
//!
//! * **Mirror plane.** The mesh is mirrored through the plane across each axis through its
//!   centroid; the plane is kept where the mirrored vertices land, at the median, within
//!   [`MIRRORED`] of the mesh's size of a vertex (a character in T-pose or on all fours; a
//!   curled tail or a raised arm moves few vertices).
//! * **Up.** Given (`--up`, the rig file's `up`), or found: of the axis directions along
//!   the mirror plane, the one opposite to where the tips of the root's limbs off the
//!   plane lie from the mesh's centre, the legs hanging down, each limb counted as much as
//!   it is thick (legs carry the body; an armadillo's ears and raised arm say less).
//!   With no mirror plane or no limb off it, a flat base at the mesh's far end along an
//!   axis ([`BASE`] of its area: a bust's, a statue's) faces down, if that axis lies along
//!   the plane. Else, when the limbs do not clearly hang, and two pairs or more all end
//!   within [`FEET`] of the mesh's far end along one axis only, that way is down (a
//!   lizard's, an insect's sprawled feet on the ground). Else, without a plane, when +y
//!   does nearly as well, or when the limbs do not clearly hang along it, +y (the OBJ and
//!   glTF convention), unless +y is across the plane.
//!   Clearly: the root's limbs off the plane on the whole, or those that point that way at
//!   all when one of them reaches the mesh's far end that way (a biped's legs stand on the
//!   ground while its arms are held out and its ears raised; a lizard's sprawled hind legs
//!   reach no farther back than its tail).
//! * **Front.** Across up and the mirror plane: the end of the body that the part on the
//!   plane most like a head grows from (with ears on the body, the one nearest them), away
//!   from another part on the plane, a tail ([`FRONT_END`]: a cat stretching looks up and
//!   back); else the way that part leans, else the way the feet point, else the convention
//!   (+z for y up, −y for z up).
//!   **Left** = up × front: a character's own left, as `.L` in Blender's names.
//! * **Roles.** The root's limbs off the mirror plane: pointing up from above the root's
//!   centre, ears, unless its root's mirror image lies by an arm's or a leg's, at most half
//!   as far as by another ear's (an arm raised higher than the other), and one above the
//!   centre whose root's mirror image lies by an ear's, at most half as far as by another
//!   limb's, is an ear too (the far ear of a head turned aside); of the others, when
//!   one pair stands on the ground ([`GROUND`]) and the rest do not, a biped: the standing
//!   pair are legs and the largest raised limb on each side an arm (arms held out or
//!   hanging down); when all stand, pairs from the front: arms (forelegs) and legs,
//!   numbered legs from three pairs on. A part on the plane hanging down with two or more
//!   off it (a pelvis the legs hang from, cut at a waist) is the `hips`, and those parts
//!   count as the root's limbs. On the plane, of those not growing from the back
//!   end and ending no thinner than any limb off the plane, the one whose far half is
//!   thickest (a head ends in a bulb, a tail in a point), leaning up, counted twice when it
//!   carries parts off the plane (ears, antennae), is the neck (or the head if nothing
//!   follows it); one pointing back or growing from the back end is the tail (a
//!   scorpion's, raised over its back), or the abdomen when it ends as thick as the head;
//!   with no head, a short one (a snout on a head not cut from the body) is no joint.
//!   Down a limb the names go on: `arm`, `forearm`, `hand`; `leg`, `shin`, `foot`; `neck`,
//!   `head`; four or five digits of a hand are `thumb`, `index`, `middle`, `ring`,
//!   `little` (the thumb the one turned most from the others), of a foot `toe1`….
//!   A neck's one short part with none of its own, thin beside it (a snout, a beak turned
//!   aside), is the head's end, no joint, and the neck is the `head`.
//!   A head's parts off the plane are ears; with two on a side, the one pointing most up
//!   is a horn; one long and round (`ANTENNA`) is an antenna.
//!   Side suffixes come from the side of the mirror plane; what fits no role keeps a
//!   number.

use super::rules::{ANTENNA, SLENDER, SNOUT};
use crate::joints::Joints;
use crate::mesh::Mesh;
use glam::DVec3;

/// A cut's pivot this share of the mesh's size from the mirror plane is on one side.
const OFF_PLANE: f64 = 0.03;
/// A limb that reaches this share of the height above the mesh's lowest point stands on
/// the ground.
const GROUND: f64 = 0.1;
/// Two pairs of limbs or more that all end within this share of the height above the mesh's
/// lowest point are feet on the ground (a lizard's, an insect's sprawled legs), when they do
/// so along one axis only.
const FEET: f64 = 0.2;
/// A head whose root lies this share of the mesh's size ahead of another part's on the
/// mirror plane (a tail's) marks the front; a part on the plane whose root lies as far
/// behind the centre is a tail.
const FRONT_END: f64 = 0.15;
/// A flat face of the mesh at its far end along an axis (faces within 5° of the axis and
/// within 1 % of the mesh's size of that end) covering at least this share of its area is
/// a base it stands on (a bust's, a statue's): where no limb off the mirror plane says
/// which way is down, that way is. (Characters measured: at most 1.3 %, a flank's or a
/// sole's flat patch; busts 6–11 %.)
const BASE: f64 = 0.04;

/// An axis direction a mesh is modelled with as up: `+y` (OBJ's and glTF's convention),
/// `+z` (CAD's and Blender's)…, written `x`, `+x` or `-x`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Deserialize)]
#[serde(try_from = "String")]
pub enum Up {
    /// `+x`.
    PosX,
    /// `-x`.
    NegX,
    /// `+y`.
    PosY,
    /// `-y`.
    NegY,
    /// `+z`.
    PosZ,
    /// `-z`.
    NegZ,
}

impl Up {
    /// The axis direction nearest `v`.
    pub fn nearest(v: DVec3) -> Up {
        let a = v.abs();
        if a.x >= a.y && a.x >= a.z {
            if v.x < 0.0 {
                Up::NegX
            } else {
                Up::PosX
            }
        } else if a.y >= a.z {
            if v.y < 0.0 {
                Up::NegY
            } else {
                Up::PosY
            }
        } else if v.z < 0.0 {
            Up::NegZ
        } else {
            Up::PosZ
        }
    }

    /// The unit vector.
    pub fn vector(self) -> DVec3 {
        match self {
            Up::PosX => DVec3::X,
            Up::NegX => DVec3::NEG_X,
            Up::PosY => DVec3::Y,
            Up::NegY => DVec3::NEG_Y,
            Up::PosZ => DVec3::Z,
            Up::NegZ => DVec3::NEG_Z,
        }
    }
}

impl std::str::FromStr for Up {
    type Err = String;
    fn from_str(s: &str) -> Result<Up, String> {
        Ok(match s.trim().to_ascii_lowercase().as_str() {
            "x" | "+x" => Up::PosX,
            "-x" => Up::NegX,
            "y" | "+y" => Up::PosY,
            "-y" => Up::NegY,
            "z" | "+z" => Up::PosZ,
            "-z" => Up::NegZ,
            _ => return Err(format!("'{s}' is not one of +x, -x, +y, -y, +z, -z")),
        })
    }
}

impl TryFrom<String> for Up {
    type Error = String;
    fn try_from(s: String) -> Result<Up, String> {
        s.parse()
    }
}

impl std::fmt::Display for Up {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Up::PosX => "+x",
            Up::NegX => "-x",
            Up::PosY => "+y",
            Up::NegY => "-y",
            Up::PosZ => "+z",
            Up::NegZ => "-z",
        })
    }
}

/// The mirrored vertices lie within this share of the mesh's size of a vertex (median).
const MIRRORED: f64 = 0.012;

/// A character's directions.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Frame {
    /// Up (unit).
    pub up: DVec3,
    /// The way the character faces (unit, across up).
    pub front: DVec3,
    /// The character's own left: up × front.
    pub left: DVec3,
    /// The mirror plane (unit normal, offset along it), if the mesh has one.
    pub mirror: Option<(DVec3, f64)>,
}

impl Default for Frame {
    fn default() -> Self {
        Frame {
            up: DVec3::Y,
            front: DVec3::Z,
            left: DVec3::X,
            mirror: None,
        }
    }
}

/// The mirror image of the point `p` in the plane of unit normal `n` and offset `o`
/// (the points `q` with `q·n = o`).
pub fn image((n, o): (DVec3, f64), p: DVec3) -> DVec3 {
    p - n * 2.0 * (p.dot(n) - o)
}

/// The mirror image of the direction `v` in a plane of unit normal `n`.
pub fn reflect(n: DVec3, v: DVec3) -> DVec3 {
    v - n * 2.0 * v.dot(n)
}

/// The mirror plane across one of the axes, if the mesh has one (see the module docs).
pub fn mirror_plane(positions: &[DVec3]) -> Option<(DVec3, f64)> {
    if positions.len() < 8 {
        return None;
    }
    let (lo, hi) = crate::mesh::bounds(positions);
    let size = (hi - lo).max_element();
    if size <= 0.0 || !size.is_finite() {
        return None;
    }
    let centroid = positions.iter().sum::<DVec3>() / positions.len() as f64;
    let grid = Grid::new(positions, lo, size / 48.0);
    let step = (positions.len() / 1500).max(1);
    let mut best: Option<(f64, DVec3, f64)> = None;
    for n in [DVec3::X, DVec3::Y, DVec3::Z] {
        let mut offset = centroid.dot(n);
        let mut median = f64::INFINITY;
        // Twice: the second time through the plane the first pairs put halfway.
        for _ in 0..2 {
            let mut gaps = Vec::new();
            let mut shifts = Vec::new();
            for p in positions.iter().step_by(step) {
                let m = image((n, offset), *p);
                let (q, d) = grid.nearest(positions, m);
                gaps.push(d);
                shifts.push((q - m).dot(n));
            }
            median = crate::stats::median(&mut gaps).unwrap_or(f64::INFINITY);
            offset += 0.5 * crate::stats::median(&mut shifts).unwrap_or(f64::INFINITY);
        }
        if best.is_none_or(|b| median < b.0) {
            best = Some((median, n, offset));
        }
    }
    let (median, n, offset) = best?;
    (median <= MIRRORED * size).then_some((n, offset))
}

/// A grid of vertices for nearest-vertex queries within a cell or two: the vertices of
/// each cell, in index order, as one flat list indexed by cell, so a query reads 27 slices
/// and hashes nothing.
struct Grid {
    lo: DVec3,
    cell: f64,
    /// Cells along each axis.
    dims: [i64; 3],
    /// The vertices of cell `c` are `vertices[start[c]..start[c + 1]]`.
    start: Vec<u32>,
    vertices: Vec<u32>,
}

impl Grid {
    /// (`cell` is a 48th of the bounds' longest side: at most 49³ cells.)
    fn new(positions: &[DVec3], lo: DVec3, cell: f64) -> Grid {
        let (_, hi) = crate::mesh::bounds(positions);
        let dims = (((hi - lo) / cell).floor().as_i64vec3() + 1).to_array();
        let mut grid = Grid {
            lo,
            cell,
            dims,
            start: vec![0; (dims[0] * dims[1] * dims[2]) as usize + 1],
            vertices: vec![0; positions.len()],
        };
        let cells: Vec<usize> = positions
            .iter()
            .map(|&p| grid.index(grid.key(p)).unwrap_or(0))
            .collect();
        for &c in &cells {
            grid.start[c + 1] += 1;
        }
        for c in 1..grid.start.len() {
            grid.start[c] += grid.start[c - 1];
        }
        let mut fill = grid.start.clone();
        for (i, &c) in cells.iter().enumerate() {
            grid.vertices[fill[c] as usize] = i as u32;
            fill[c] += 1;
        }
        grid
    }

    fn key(&self, p: DVec3) -> [i64; 3] {
        ((p - self.lo) / self.cell).floor().as_i64vec3().to_array()
    }

    /// The cell's place in `start`, if it is in the grid.
    fn index(&self, k: [i64; 3]) -> Option<usize> {
        let inside = (0..3).all(|a| (0..self.dims[a]).contains(&k[a]));
        inside.then(|| ((k[2] * self.dims[1] + k[1]) * self.dims[0] + k[0]) as usize)
    }

    /// The nearest vertex within about two cells, and its distance (two cells when none).
    fn nearest(&self, positions: &[DVec3], p: DVec3) -> (DVec3, f64) {
        let k = self.key(p);
        let mut best = (p, 2.0 * self.cell);
        for dx in -1..=1 {
            for dy in -1..=1 {
                for dz in -1..=1 {
                    let Some(c) = self.index([k[0] + dx, k[1] + dy, k[2] + dz]) else {
                        continue;
                    };
                    let list = &self.vertices[self.start[c] as usize..self.start[c + 1] as usize];
                    for &i in list {
                        let d = positions[i as usize].distance(p);
                        if d < best.1 {
                            best = (positions[i as usize], d);
                        }
                    }
                }
            }
        }
        best
    }
}

/// The outward normal of the mesh's flat base, if it has one: of the six axis directions,
/// the one whose flat faces at the mesh's far end that way cover the most area, when that
/// is at least [`BASE`] of the whole.
pub(super) fn flat_base(mesh: &Mesh) -> Option<DVec3> {
    let (lo, hi) = crate::mesh::bounds(&mesh.positions);
    let size = (hi - lo).max_element();
    if !(size > 0.0 && size.is_finite()) {
        return None;
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
    let k = (0..6).max_by(|&a, &b| area[a].total_cmp(&area[b]))?;
    (total > 0.0 && area[k] >= BASE * total).then_some(AXES[k])
}

/// The six axis directions.
const AXES: [DVec3; 6] = [
    DVec3::X,
    DVec3::NEG_X,
    DVec3::Y,
    DVec3::NEG_Y,
    DVec3::Z,
    DVec3::NEG_Z,
];

/// One of the root's limbs: where it is cut, and its tip.
#[derive(Clone, Copy, Debug)]
pub struct Reach {
    /// Its cut's pivot.
    pub pivot: DVec3,
    /// Its point farthest from the pivot.
    pub tip: DVec3,
    /// How thick its far half is: the largest skeletal distance there (a head ends in a
    /// bulb, a tail in a point).
    pub end: f64,
    /// It carries a part of its own off the mirror plane (a head's ears, horns, antennae).
    pub paired: bool,
}

impl Reach {
    fn direction(&self) -> DVec3 {
        (self.tip - self.pivot).normalize_or_zero()
    }

    /// It points up (along `up`) from above `centre`: an ear, when off the mirror plane.
    fn raised(&self, up: DVec3, centre: DVec3) -> bool {
        self.direction().dot(up) > 0.5 && (self.pivot - centre).dot(up) > 0.0
    }

    /// It reaches at most [`SNOUT`] times its far half's thickness: a snout, a muzzle, a
    /// nose, not a limb's length.
    fn short(&self) -> bool {
        self.tip.distance(self.pivot) <= SNOUT * self.end
    }

    /// How much it looks like a head, leaning along `towards`: its far half's thickness,
    /// more when it leans that way, twice that when it carries parts of its own off the
    /// mirror plane (an ant's head with its antennae, not the thicker abdomen).
    fn head_score(&self, towards: DVec3) -> f64 {
        let pair = if self.paired { 2.0 } else { 1.0 };
        pair * self.end * (1.0 + self.direction().dot(towards))
    }
}

/// The frame of a mesh with the mirror plane `mirror` ([`mirror_plane`]) whose root has
/// `limbs` (see the module docs); `up` when given; `base`, the outward normal of its flat
/// base if it has one ([`flat_base`]).
pub fn frame(
    positions: &[DVec3],
    mirror: Option<(DVec3, f64)>,
    limbs: &[Reach],
    up: Option<DVec3>,
    base: Option<DVec3>,
) -> Frame {
    let size = crate::mesh::longest_side(positions);
    let centre = positions.iter().sum::<DVec3>() / positions.len().max(1) as f64;
    let axes = AXES;
    // The root's limbs off the mirror plane (none without one).
    let off_plane =
        |l: &Reach| mirror.is_some_and(|(n, o)| (l.pivot.dot(n) - o).abs() >= OFF_PLANE * size);
    let off: Vec<&Reach> = limbs.iter().filter(|l| off_plane(l)).collect();
    // Up from a flat base, along the mirror plane.
    let base_up = base
        .map(|b| -b)
        .filter(|u| mirror.is_none_or(|(n, _)| u.dot(n).abs() < 0.5));
    let up = match (up, mirror) {
        (Some(u), _) => u.normalize_or(DVec3::Y),
        (None, None) => base_up.unwrap_or(DVec3::Y),
        (None, Some(_)) if base_up.is_some() && off.is_empty() => base_up.unwrap_or(DVec3::Y),
        (None, Some((n, _))) => {
            // How well each direction across the plane does as down, by where the tips
            // of the limbs off the plane lie from the mesh's centre (legs and arms; a tail
            // or a neck says nothing about up). From the centre, not from the limb's own
            // cut: a stubby leg cut at its ankle is a foot pointing forward.
            // Each limb says as much as it is thick (the legs carry the body; ears and a
            // raised arm's thin hand say less).
            let thickest = off.iter().map(|l| l.end).fold(0.0, f64::max);
            let weight = |l: &Reach| {
                if thickest > 0.0 {
                    l.end / thickest
                } else {
                    1.0
                }
            };
            let down = |d: DVec3| -> f64 {
                off.iter()
                    .map(|l| {
                        weight(l) * (l.tip - centre).normalize_or_zero().dot(d).max(0.0).powi(2)
                    })
                    .sum()
            };
            let best = axes
                .iter()
                .copied()
                .filter(|a| a.dot(n).abs() < 0.5)
                .max_by(|a, b| down(*a).total_cmp(&down(*b)))
                .unwrap_or(DVec3::NEG_Y);
            // Those that point way `d` at all (legs hanging; not arms held out, nor ears),
            // and whether one of them reaches the mesh's far end that way (stands on the
            // ground, [`GROUND`]: sprawled legs hang back no farther than a tail).
            let hanging = |d: DVec3| -> Vec<&Reach> {
                off.iter()
                    .copied()
                    .filter(|l| (l.tip - centre).dot(d) > 0.0)
                    .collect()
            };
            // The mesh's extent along `d`, near end and far end.
            let span = |d: DVec3| {
                positions
                    .iter()
                    .map(|p| p.dot(d))
                    .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| {
                        (a.min(x), b.max(x))
                    })
            };
            let stands = |d: DVec3| {
                let (near, far) = span(d);
                hanging(d)
                    .iter()
                    .any(|l| far - l.tip.dot(d) <= GROUND * (far - near))
            };
            // (Only limbs that clearly hang along it move up off +y: sprawled legs say
            // little; all the root's limbs doing so, or those that point that way at all
            // and stand on the ground (a biped's legs, its arms held out).)
            let best_stands = stands(best);
            let votes = |of: &[&Reach]| of.iter().map(|l| weight(l)).sum::<f64>();
            let clearly = down(best) >= 0.5 * votes(&off)
                || (best_stands && down(best) >= 0.5 * votes(&hanging(best)));
            // (+y does nearly as well, unless only the other stands on the ground: a
            // sitting animal's forelegs reach forward as far as its legs hang.)
            let y_as_well =
                down(DVec3::NEG_Y) >= 0.67 * down(best) && (stands(DVec3::NEG_Y) || !best_stands);
            // (Sprawled legs that say little of up still all end on the ground, one way
            // only: a lizard, an insect or a scorpion modelled with any axis up.)
            let grounded = |d: DVec3| {
                let (near, far) = span(d);
                off.len() >= 4
                    && off
                        .iter()
                        .all(|l| far - l.tip.dot(d) <= FEET * (far - near))
            };
            let on_the_ground: Vec<DVec3> = axes
                .iter()
                .copied()
                .filter(|a| a.dot(n).abs() < 0.5 && grounded(*a))
                .collect();
            // (+y across the mirror plane cannot be up: a character lying on its side, or
            // modelled with x or z up, has only its limbs to say.)
            let y_along = DVec3::Y.dot(n).abs() < 0.5;
            if let (false, [down]) = (clearly, on_the_ground.as_slice()) {
                -*down
            } else if y_along && (y_as_well || !clearly) {
                DVec3::Y
            } else {
                -best
            }
        }
    };
    // Front: across up and the plane's normal (or the convention without a plane).
    let convention = if up.y.abs() >= 0.5 {
        DVec3::Z
    } else {
        DVec3::NEG_Y
    };
    let axis = match mirror {
        Some((n, _)) => up.cross(n).normalize_or(convention),
        None => (convention - up * convention.dot(up)).normalize_or(DVec3::Z),
    };
    let on_plane = |l: &Reach| !off_plane(l);
    // The part on the plane most like a head grows from the other end of the body than the
    // tail (a cat stretching looks up and back; a penguin), or leans forward; else the feet
    // point forward. Most like a head: with ears on the body (a head not cut from it), of
    // two or more parts on the plane the one nearest them; else [`head_of`].
    let midline: Vec<&Reach> = limbs.iter().filter(|l| on_plane(l)).collect();
    let ears: Vec<DVec3> = limbs
        .iter()
        .filter(|l| !on_plane(l) && l.raised(up, centre))
        .map(|l| l.pivot)
        .collect();
    let head = if ears.is_empty() || midline.len() < 2 {
        head_of(&midline, 0.0, up).map(|h| midline[h])
    } else {
        let at = ears.iter().sum::<DVec3>() / ears.len() as f64;
        midline
            .iter()
            .copied()
            .min_by(|a, b| a.pivot.distance(at).total_cmp(&b.pivot.distance(at)))
    };
    // (With no other part on the plane there is nothing to tell a head from a tail by:
    // a scorpion's raised tail.)
    let placed = head.map_or(0.0, |h| {
        let along = |l: &Reach| (h.pivot - l.pivot).dot(axis);
        midline
            .iter()
            .map(|l| along(l))
            .max_by(|a, b| a.abs().total_cmp(&b.abs()))
            .unwrap_or(0.0)
    });
    let lean = head.map_or(0.0, |h| h.direction().dot(axis));
    let feet: f64 = limbs
        .iter()
        .filter(|l| l.direction().dot(up) < -0.5)
        .map(|l| (l.tip - l.pivot).dot(axis))
        .sum();
    let sign = if placed.abs() > FRONT_END * size {
        placed.signum()
    } else if lean.abs() > 0.3 {
        lean.signum()
    } else if feet.abs() > 1e-9 {
        feet.signum()
    } else if axis.dot(convention) < 0.0 {
        -1.0
    } else {
        1.0
    };
    let front = axis * sign;
    // (Plus zero: an axis turned over is written `0`, not `-0`, in `--json`.)
    Frame {
        up: up + DVec3::ZERO,
        front: front + DVec3::ZERO,
        left: up.cross(front) + DVec3::ZERO,
        mirror,
    }
}

/// Which of the parts on the mirror plane `midline` is most like a head (or the neck it
/// ends): of those ending at least `thickest` thick, the one ending widest, leaning up.
fn head_of(midline: &[&Reach], thickest: f64, up: DVec3) -> Option<usize> {
    (0..midline.len())
        .filter(|&m| midline[m].end >= thickest)
        .max_by(|&a, &b| {
            midline[a]
                .head_score(up)
                .total_cmp(&midline[b].head_score(up))
        })
}

/// The sections of a suggestion as [`roles`] reads them.
pub struct Roles {
    /// Per section, its name by role (index 0 is the root and keeps its name); `None`
    /// where no role fits.
    pub names: Vec<Option<String>>,
    /// The frame they were named in.
    pub frame: Frame,
    /// Sections that are the end of their parent, no joint (a head's snout): their cuts
    /// are taken back.
    pub ends: Vec<usize>,
}

/// Role names for the sections of `joints`, in the frame found for them. `radius` is each
/// vertex's skeletal distance, `mirror` the mesh's mirror plane ([`mirror_plane`]) and
/// `base` the outward normal of its flat base ([`flat_base`]).
pub fn roles(
    mesh: &Mesh,
    radius: &[f64],
    joints: &Joints,
    up: Option<DVec3>,
    mirror: Option<(DVec3, f64)>,
    base: Option<DVec3>,
) -> Roles {
    let sections = joints.sections();
    let n = sections.len();
    let mut children = vec![Vec::new(); n];
    for (s, sec) in sections.iter().enumerate() {
        if let Some(p) = sec.parent {
            children[p].push(s);
        }
    }
    // Each section's subtree: the vertices in it and in what hangs from it.
    let mut within: Vec<Vec<usize>> = vec![Vec::new(); n];
    for (v, &s) in joints.section_of().iter().enumerate() {
        let mut t = Some(s as usize);
        while let Some(at) = t {
            within[at].push(v);
            t = sections[at].parent;
        }
    }
    let mut naming = Naming {
        mesh,
        radius,
        sections,
        children,
        within,
        // The mirror plane first: a limb's reach says whether it carries parts off it.
        frame: Frame {
            mirror,
            ..Frame::default()
        },
        names: vec![None; n],
        ends: Vec::new(),
        size: mesh.longest_side().max(1e-12),
        base,
    };
    let limbs: Vec<(usize, Reach)> = naming.children[0]
        .iter()
        .map(|&s| (s, naming.reach(s)))
        .collect();
    let reaches: Vec<Reach> = limbs.iter().map(|l| l.1).collect();
    naming.frame = frame(&mesh.positions, mirror, &reaches, up, base);
    naming.root(&limbs);
    Roles {
        names: naming.names,
        frame: naming.frame,
        ends: naming.ends,
    }
}

/// What naming the sections needs: the section tree, each subtree's vertices, the frame.
struct Naming<'a> {
    mesh: &'a Mesh,
    /// Each vertex's skeletal distance.
    radius: &'a [f64],
    sections: &'a [crate::joints::Section],
    children: Vec<Vec<usize>>,
    within: Vec<Vec<usize>>,
    frame: Frame,
    names: Vec<Option<String>>,
    /// Sections that are no joint (see [`Roles::ends`]).
    ends: Vec<usize>,
    /// The mesh's size (the longest side of its bounding box).
    size: f64,
    /// The outward normal of its flat base ([`flat_base`]), if it has one.
    base: Option<DVec3>,
}

impl Naming<'_> {
    /// Section `s`'s pivot, its tip (the farthest point from the pivot of it and what hangs
    /// from it; of a part on the mirror plane, not what it carries off it: a head's ears or
    /// antennae) and how thick its far half is.
    fn reach(&self, s: usize) -> Reach {
        let pivot = self.sections[s].pivot;
        // A part on the mirror plane with parts of its own off it (a head's ears).
        let midline = self.side(pivot).is_none();
        let off: Vec<usize> = self.children[s]
            .iter()
            .copied()
            .filter(|&c| midline && self.side(self.sections[c].pivot).is_some())
            .collect();
        let mut aside = Vec::new();
        if !off.is_empty() {
            aside = vec![false; self.mesh.positions.len()];
            for &c in &off {
                for &v in &self.within[c] {
                    aside[v] = true;
                }
            }
        }
        let own = || {
            self.within[s]
                .iter()
                .copied()
                .filter(|&v| !aside.get(v).copied().unwrap_or(false))
        };
        let tip = own()
            .map(|v| self.mesh.positions[v])
            .max_by(|a, b| a.distance(pivot).total_cmp(&b.distance(pivot)))
            .unwrap_or(pivot);
        let reach = tip.distance(pivot);
        let end = own()
            .filter(|&v| self.mesh.positions[v].distance(pivot) >= 0.5 * reach)
            .map(|v| self.radius[v])
            .fold(0.0, f64::max);
        Reach {
            pivot,
            tip,
            end,
            paired: !off.is_empty(),
        }
    }

    /// On a flat base (a bust), the root's part that holds the mesh's top: its head on its
    /// neck, whichever way it faces.
    fn on_the_bust(&self) -> Option<usize> {
        self.base?;
        let up = self.frame.up;
        let top = (0..self.mesh.positions.len()).max_by(|&a, &b| {
            let height = |v: usize| self.mesh.positions[v].dot(up);
            height(a).total_cmp(&height(b))
        })?;
        self.children[0]
            .iter()
            .copied()
            .find(|&c| self.within[c].contains(&top))
    }

    /// The side of the mirror plane `p` is on (`None` on the plane, or with no plane).
    fn side(&self, p: DVec3) -> Option<&'static str> {
        let (n, o) = self.frame.mirror?;
        let d = p.dot(n) - o;
        if d.abs() < OFF_PLANE * self.size {
            return None;
        }
        Some(if d * n.dot(self.frame.left) > 0.0 {
            "L"
        } else {
            "R"
        })
    }

    /// Names the root's limbs and what hangs from them.
    fn root(&mut self, limbs: &[(usize, Reach)]) {
        let frame = self.frame;
        if frame.mirror.is_none() {
            // No mirror plane: a hand on its own, or a creature posed off its symmetry;
            // on a flat base, a bust sculpted off its symmetry, whose one part holding its
            // top is its head on its neck.
            self.digits(0, "");
            if let Some(head) = self.on_the_bust() {
                self.chain(head, Family::Neck, "");
            }
            return;
        }
        let within = &self.within[0];
        let centre = within
            .iter()
            .map(|&v| self.mesh.positions[v])
            .sum::<DVec3>()
            / within.len().max(1) as f64;
        // On the mirror plane; off it pointing up from above the centre (ears); the rest
        // (arms and legs).
        let mut midline: Vec<(usize, Reach)> = Vec::new();
        let mut ears: Vec<(usize, Reach)> = Vec::new();
        let mut legs: Vec<(usize, Reach)> = Vec::new();
        // A part on the plane hanging down with two or more parts off it (a pelvis both
        // legs hang from, cut as one with a loincloth) is the hips: its parts are the
        // body's limbs.
        let mut parts: Vec<(usize, Reach)> = Vec::new();
        for &(s, r) in limbs {
            let carried: Vec<usize> = self.children[s]
                .iter()
                .copied()
                .filter(|&c| self.side(self.sections[c].pivot).is_some())
                .collect();
            if self.side(r.pivot).is_none()
                && r.direction().dot(frame.up) < -0.5
                && carried.len() >= 2
            {
                self.names[s] = Some("hips".into());
                parts.extend(carried.into_iter().map(|c| (c, self.reach(c))));
            } else {
                parts.push((s, r));
            }
        }
        for &(s, r) in &parts {
            if self.side(r.pivot).is_none() {
                midline.push((s, r));
            } else if r.raised(frame.up, centre) {
                ears.push((s, r));
            } else {
                legs.push((s, r));
            }
        }
        // A limb pointing up whose root's mirror image lies by an arm's or a leg's, at most
        // half as far from it as from another ear's, is that limb's pair (an arm raised
        // higher than the other), not an ear.
        if let Some(plane) = frame.mirror {
            let nearest = |p: DVec3, of: &[(usize, Reach)]| {
                of.iter()
                    .map(|l| l.1.pivot.distance(p))
                    .fold(f64::INFINITY, f64::min)
            };
            let (raised, kept): (Vec<_>, Vec<_>) = ears.iter().partition(|(s, r)| {
                let image = image(plane, r.pivot);
                let others: Vec<(usize, Reach)> =
                    ears.iter().copied().filter(|e| e.0 != *s).collect();
                !others.is_empty() && nearest(image, &legs) < 0.5 * nearest(image, &others)
            });
            legs.extend(raised);
            ears = kept;
            // And the other way: a limb above the centre whose root's mirror image lies by
            // an ear's, at most half as far from it as from any other limb's, is that
            // ear's pair (the far ear of a head turned aside, its section reaching down the
            // side of the head).
            let (turned, kept): (Vec<_>, Vec<_>) = legs.iter().partition(|(s, r)| {
                let image = image(plane, r.pivot);
                let others: Vec<(usize, Reach)> =
                    legs.iter().copied().filter(|l| l.0 != *s).collect();
                (r.pivot - centre).dot(frame.up) > 0.0
                    && nearest(image, &ears) < 0.5 * nearest(image, &others)
            });
            ears.extend(turned);
            legs = kept;
        }
        // A lone pair that does not hang down, from above the centre, and short (an ear's
        // flap, not an arm's length) is a head's ears: the root is the head (a monkey's
        // head modelled on its own), and a part on the plane is its face, no neck.
        let flaps = |l: &(usize, Reach)| {
            l.1.direction().dot(frame.up) > -0.5
                && (l.1.pivot - centre).dot(frame.up) > 0.0
                && l.1.short()
        };
        if ears.is_empty()
            && legs.len() == 2
            && legs.iter().all(flaps)
            && self.side(legs[0].1.pivot) != self.side(legs[1].1.pivot)
        {
            ears.append(&mut legs);
        }
        let only_a_head = legs.is_empty() && !ears.is_empty();
        // Midline: the head ([`head_of`]), not growing from the back end, ending no thinner
        // than any part off the plane (a head ends in a bulb; a snout on a head not cut from
        // the body does not, nor does a tail); the tail points back, or grows from the back
        // end (a scorpion's, raised over its back).
        let back = -FRONT_END * self.size;
        let behind = |r: &Reach| (r.pivot - centre).dot(frame.front) < back;
        let head = {
            let ahead: Vec<(usize, Reach)> =
                midline.iter().copied().filter(|l| !behind(&l.1)).collect();
            let on: Vec<&Reach> = ahead.iter().map(|l| &l.1).collect();
            let thickest = legs
                .iter()
                .chain(&ears)
                .map(|l| l.1.end)
                .fold(0.0, f64::max);
            let bust = self
                .on_the_bust()
                .and_then(|b| midline.iter().copied().find(|l| l.0 == b));
            bust.or_else(|| head_of(&on, thickest, frame.up).map(|h| ahead[h]))
                .filter(|_| !only_a_head)
        };
        for &(s, r) in &midline {
            let behind = behind(&r);
            if Some(s) == head.map(|h| h.0) {
                self.chain(s, Family::Neck, "");
            } else if head.is_none() && r.short() && self.children[s].is_empty() && !behind {
                // A short bump on the plane (a snout on a head not cut from the body) is
                // no joint.
                self.ends.push(s);
            } else if r.direction().dot(frame.front) < -0.3 || behind {
                // Ending as thick as the head: an abdomen; thinner, a tail.
                let thick = head.is_some_and(|h| r.end >= h.1.end);
                let family = if thick { Family::Abdomen } else { Family::Tail };
                self.chain(s, family, "");
            }
        }
        let height = |p: DVec3| p.dot(frame.up);
        let lowest = |s: usize| {
            self.within[s]
                .iter()
                .map(|&v| height(self.mesh.positions[v]))
                .fold(f64::INFINITY, f64::min)
        };
        let (floor, top) = self
            .mesh
            .positions
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &p| {
                (lo.min(height(p)), hi.max(height(p)))
            });
        // A biped: one pair stands on the ground and the rest do not (arms hanging down
        // or held out), legs and arms; of the raised limbs, one per side (the largest) is
        // an arm, and the others keep their numbers.
        let stands: Vec<bool> = legs
            .iter()
            .map(|l| lowest(l.0) <= floor + GROUND * (top - floor))
            .collect();
        let standing = stands.iter().filter(|&&st| st).count();
        if (1..=2).contains(&standing) && standing < legs.len() {
            let side = |r: &Reach| self.side(r.pivot).unwrap_or("L");
            let arms: Vec<usize> = ["L", "R"]
                .iter()
                .filter_map(|&lr| {
                    legs.iter()
                        .zip(&stands)
                        .filter(|(l, &st)| !st && side(&l.1) == lr)
                        .max_by_key(|(l, _)| self.within[l.0].len())
                        .map(|(l, _)| l.0)
                })
                .collect();
            // Of the other raised limbs, one above its side's arm, and smaller, is an ear
            // (a head not cut from the body: it sits on the shoulders as wide as its neck).
            let arm_on = |lr: &str| {
                legs.iter()
                    .find(|l| arms.contains(&l.0) && side(&l.1) == lr)
                    .copied()
            };
            let ear = |s: usize, r: &Reach| {
                arm_on(side(r)).is_some_and(|(a, ar)| {
                    height(r.pivot) > height(ar.pivot) + ar.end
                        && self.within[s].len() < self.within[a].len()
                })
            };
            let families: Vec<(usize, Option<Family>, &str)> = legs
                .iter()
                .zip(&stands)
                .map(|(&(s, r), &st)| {
                    let family = if st {
                        Some(Family::Leg)
                    } else if arms.contains(&s) {
                        Some(Family::Arm)
                    } else if ear(s, &r) {
                        Some(Family::Ear)
                    } else {
                        None
                    };
                    (s, family, side(&r))
                })
                .collect();
            for (s, family, lr) in families {
                if let Some(family) = family {
                    self.chain(s, family, lr);
                }
            }
        } else {
            self.limbs_from_the_front(&mut legs, centre);
        }
        for &(s, r) in &ears {
            let lr = self.side(r.pivot).unwrap_or("L");
            self.chain(s, Family::Ear, lr);
        }
    }

    /// Names limbs that all stand (or none does) in pairs from the front: arms (forelegs)
    /// and legs, or numbered legs from three pairs on; with two pairs, one pointing down
    /// and one not, legs and arms.
    fn limbs_from_the_front(&mut self, legs: &mut [(usize, Reach)], centre: DVec3) {
        let frame = self.frame;
        let along = |r: &Reach| (r.pivot - centre).dot(frame.front);
        legs.sort_by(|a, b| along(&b.1).total_cmp(&along(&a.1)));
        let pairs = legs.len().div_ceil(2);
        let downward = |r: &Reach| r.direction().dot(frame.up) < -0.5;
        let biped = legs.iter().filter(|l| downward(&l.1)).count() == 2 && pairs <= 2;
        for (k, &(s, r)) in legs.iter().enumerate() {
            let lr = self.side(r.pivot).unwrap_or("L");
            let rank = k / 2;
            let family = if biped {
                if downward(&r) {
                    Family::Leg
                } else {
                    Family::Arm
                }
            } else if pairs >= 3 {
                Family::Numbered(rank + 1)
            } else if pairs == 2 && rank == 0 {
                Family::Arm
            } else if downward(&r) || pairs == 2 {
                Family::Leg
            } else {
                Family::Arm
            };
            self.chain(s, family, lr);
        }
    }

    /// Names section `s` and the single chain that follows it with `family`'s names (side
    /// `tag`), then what branches from the chain: digits of a hand or foot, ears of a head.
    fn chain(&mut self, s: usize, family: Family, tag: &str) {
        let list = family.names();
        let mut at = s;
        let mut k = 0;
        loop {
            let base = if k < list.len() {
                list[k].clone()
            } else {
                format!("{}.{}", list[list.len() - 1], k - list.len() + 2)
            };
            self.names[at] = Some(tagged(&base, tag));
            match self.children[at].as_slice() {
                [] => return,
                // A lone part with none of its own, at most SLENDER as thick as the limb it
                // hangs from, is a digit on it (a thumb on an arm whose hand is not cut),
                // not the limb's next stretch.
                [only] if self.lone_digit(at, *only, family) => {
                    let digit = if family == Family::Arm {
                        "thumb"
                    } else {
                        "toe"
                    };
                    self.names[*only] = Some(tagged(digit, tag));
                    return;
                }
                // A neck's one short part with none of its own, at most SLENDER as thick as
                // the neck (a snout, a beak turned aside, not a head), is the head's end,
                // no joint: the neck is the head.
                [only]
                    if family == Family::Neck
                        && self.children[*only].is_empty()
                        && self.reach(*only).short()
                        && self.reach(*only).end <= SLENDER * self.reach(at).end =>
                {
                    self.ends.push(*only);
                    self.names[at] = Some(tagged("head", tag));
                    return;
                }
                [only] if !(family == Family::Neck && k + 1 >= list.len()) => {
                    at = *only;
                    k += 1;
                }
                _ => break,
            }
        }
        if family != Family::Neck {
            self.digits(at, tag);
            return;
        }
        // A neck whose head has no cut of its own is the head.
        if k == 0 && self.children[at].len() >= 2 {
            self.names[at] = Some(tagged("head", tag));
        }
        // Off the plane: ears; on it, below the head: a jaw. A head's one short part on the
        // plane (a snout, a muzzle, a nose: at most SNOUT of its own thickness long) is its
        // end, no joint; a jaw is one of two (an open mouth).
        let kids = self.children[at].clone();
        let on_plane: Vec<usize> = kids
            .iter()
            .copied()
            .filter(|&c| self.side(self.sections[c].pivot).is_none())
            .collect();
        // With two or more parts on one side (ears and horns), the one pointing most
        // up is a horn.
        let up = self.frame.up;
        let horns: Vec<usize> = ["L", "R"]
            .iter()
            .filter_map(|&lr| {
                let mine: Vec<usize> = kids
                    .iter()
                    .copied()
                    .filter(|&c| self.side(self.sections[c].pivot) == Some(lr))
                    .collect();
                if mine.len() < 2 {
                    return None;
                }
                mine.into_iter()
                    .map(|c| (c, self.reach(c).direction().dot(up)))
                    .max_by(|a, b| a.1.total_cmp(&b.1))
                    .map(|(c, _)| c)
            })
            .collect();
        for c in kids {
            match self.side(self.sections[c].pivot) {
                Some(lr) if horns.contains(&c) => self.chain(c, Family::Horn, lr),
                Some(lr) if self.feeler(c) => self.chain(c, Family::Antenna, lr),
                Some(lr) => self.chain(c, Family::Ear, lr),
                None => {
                    if on_plane.len() == 1 && self.reach(c).short() && self.children[c].is_empty() {
                        self.ends.push(c);
                        continue;
                    }
                    self.chain(c, Family::Jaw, "");
                }
            }
        }
    }

    /// Whether `c`, the only part of limb section `at` (of `family`), is a digit on it: an
    /// arm's or a leg's (an insect's numbered legs' digits are its feet's `toe1`…), with no
    /// parts of its own, its far half at most [`SLENDER`] as
    /// thick as the far half of the limb with it.
    fn lone_digit(&self, at: usize, c: usize, family: Family) -> bool {
        matches!(family, Family::Arm | Family::Leg)
            && self.children[c].is_empty()
            && self.reach(c).end <= SLENDER * self.reach(at).end
    }

    /// Whether head part `c` is a feeler (an insect's antenna, not an ear or a horn): at
    /// least [`ANTENNA`] times as long as its far half is thick, and that far half round,
    /// no wider across than thick (a big flat ear is long against its thickness too).
    fn feeler(&self, c: usize) -> bool {
        let r = self.reach(c);
        let reach = r.tip.distance(r.pivot);
        if reach < ANTENNA * r.end {
            return false;
        }
        // The far half's spread across its long axis: the root mean square of its points'
        // distances from that axis, per direction across (a round tube of radius `t`
        // spreads 0.71 t; a flat ear as much as it is wide).
        let far: Vec<DVec3> = self.within[c]
            .iter()
            .map(|&v| self.mesh.positions[v])
            .filter(|p| p.distance(r.pivot) >= 0.5 * reach)
            .collect();
        let mean = far.iter().sum::<DVec3>() / far.len().max(1) as f64;
        let axis = super::trunk::long_axis(far.iter().map(|&p| p - mean));
        let across = far
            .iter()
            .map(|&p| (p - mean).reject_from_normalized(axis).length_squared())
            .sum::<f64>()
            / (2 * far.len()).max(1) as f64;
        across.sqrt() <= r.end
    }

    /// Names the branches of section `at`: four or five digits as fingers (thumb first) or
    /// toes; each digit's chain goes on with `.2`, `.3`…. A branch of the root pointing
    /// away from the digits (a forearm below a palm) is the forearm.
    fn digits(&mut self, at: usize, tag: &str) {
        let kids = self.children[at].clone();
        if kids.len() < 2 {
            return;
        }
        let dirs: Vec<DVec3> = kids.iter().map(|&c| self.reach(c).direction()).collect();
        let mean = dirs.iter().sum::<DVec3>().normalize_or_zero();
        let digits: Vec<usize> = (0..kids.len())
            .filter(|&i| dirs[i].dot(mean) > 0.0)
            .collect();
        let toes = self.names[at]
            .as_deref()
            .is_some_and(|n| n.starts_with("foot"));
        // A hand not cut at its wrist: of two parts, one with two or more digits of its
        // own and one with none, the first is the hand and the other its thumb.
        if !toes && at != 0 && digits.len() == 2 {
            let (a, b) = (kids[digits[0]], kids[digits[1]]);
            let palm = |c: usize| self.children[c].len() >= 2;
            let bare = |c: usize| self.children[c].is_empty();
            let pair = if palm(a) && bare(b) {
                Some((a, b))
            } else if palm(b) && bare(a) {
                Some((b, a))
            } else {
                None
            };
            if let Some((hand, thumb)) = pair {
                self.names[hand] = Some(tagged("hand", tag));
                self.digit(thumb, &tagged("thumb", tag));
                self.digits(hand, tag);
                return;
            }
        }
        if !toes && (4..=5).contains(&digits.len()) {
            // The thumb is the digit turned most from the others; the rest by distance
            // from it.
            let others = |i: usize| {
                digits
                    .iter()
                    .filter(|&&j| j != i)
                    .map(|&j| dirs[j])
                    .sum::<DVec3>()
                    .normalize_or_zero()
            };
            let thumb = digits
                .iter()
                .copied()
                .min_by(|&a, &b| dirs[a].dot(others(a)).total_cmp(&dirs[b].dot(others(b))))
                .unwrap_or(digits[0]);
            let base = self.sections[kids[thumb]].pivot;
            let mut order = digits.clone();
            order.sort_by(|&a, &b| {
                let d = |i: usize| self.sections[kids[i]].pivot.distance(base);
                d(a).total_cmp(&d(b))
            });
            let fingers = ["thumb", "index", "middle", "ring", "little"];
            let skip = 5 - digits.len();
            for (rank, &i) in order.iter().enumerate() {
                let name = if rank == 0 {
                    fingers[0]
                } else {
                    fingers[rank + skip]
                };
                self.digit(kids[i], &tagged(name, tag));
            }
        } else if digits.len() >= 2 {
            let base = if toes { "toe" } else { "finger" };
            for (rank, &i) in digits.iter().enumerate() {
                self.digit(kids[i], &tagged(&format!("{base}{}", rank + 1), tag));
            }
        }
        if at == 0 {
            for (i, &c) in kids.iter().enumerate() {
                if !digits.contains(&i) && self.names[c].is_none() {
                    self.digit(c, &tagged("forearm", tag));
                }
            }
        }
    }

    /// Names a digit's chain: `index`, `index.2`, `index.3`….
    fn digit(&mut self, s: usize, name: &str) {
        let mut at = s;
        let mut k = 1;
        loop {
            self.names[at] = Some(if k == 1 {
                name.to_string()
            } else {
                format!("{name}.{k}")
            });
            match self.children[at].as_slice() {
                [only] => {
                    at = *only;
                    k += 1;
                }
                _ => return,
            }
        }
    }
}

/// What a chain of cuts down one limb is called.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Family {
    Arm,
    Leg,
    /// Legs numbered from the front (an insect's).
    Numbered(usize),
    Neck,
    Tail,
    /// A head's part on the mirror plane below it, one of two (an open mouth).
    Jaw,
    /// A part pointing back that ends as thick as the head (an insect's).
    Abdomen,
    Ear,
    Horn,
    /// A head's long thin part off the plane (an insect's feeler).
    Antenna,
}

impl Family {
    /// The names down the chain, base first.
    fn names(self) -> Vec<String> {
        match self {
            Family::Arm => vec!["arm".into(), "forearm".into(), "hand".into()],
            Family::Leg => vec!["leg".into(), "shin".into(), "foot".into()],
            Family::Numbered(k) => vec![format!("leg{k}"), format!("shin{k}"), format!("foot{k}")],
            Family::Neck => vec!["neck".into(), "head".into()],
            Family::Tail => vec!["tail".into()],
            Family::Jaw => vec!["jaw".into()],
            Family::Abdomen => vec!["abdomen".into()],
            Family::Ear => vec!["ear".into()],
            Family::Horn => vec!["horn".into()],
            Family::Antenna => vec!["antenna".into()],
        }
    }
}

/// The name of the same role on the other side: `index.R.2` for `index.L.2`; `None` for a
/// name with no side.
pub fn other_side(name: &str) -> Option<String> {
    let words: Vec<&str> = name.split('.').collect();
    if !words.iter().any(|&w| w == "L" || w == "R") {
        return None;
    }
    let swapped: Vec<&str> = words
        .iter()
        .map(|&w| match w {
            "L" => "R",
            "R" => "L",
            w => w,
        })
        .collect();
    Some(swapped.join("."))
}

/// Is `role` a limb's root that turns in a ball joint: a shoulder (`arm.L`) or a hip
/// (`leg.R`, an insect's `leg2.L`)?
pub(super) fn is_ball_joint(role: &str) -> bool {
    let base = role.split('.').next().unwrap_or("");
    base == "arm"
        || base
            .strip_prefix("leg")
            .is_some_and(|k| k.chars().all(|c| c.is_ascii_digit()))
}

/// `base` with its side: `arm.L`; `tail` on the plane.
fn tagged(base: &str, tag: &str) -> String {
    if tag.is_empty() {
        base.to_string()
    } else {
        format!("{base}.{tag}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Points on two boxes side by side, mirrored across x = 1, with a tail off to one side.
    fn figure(tail: bool) -> Vec<DVec3> {
        let mut p = Vec::new();
        for i in 0..10 {
            for j in 0..20 {
                for k in 0..6 {
                    let (x, y, z) = (i as f64 * 0.1, j as f64 * 0.1, k as f64 * 0.1);
                    p.push(DVec3::new(0.05 + x, y, z));
                    p.push(DVec3::new(1.95 - x, y, z));
                }
            }
        }
        if tail {
            for j in 0..20 {
                p.push(DVec3::new(
                    1.5 + j as f64 * 0.02,
                    0.0,
                    -0.5 - j as f64 * 0.05,
                ));
            }
        }
        p
    }

    #[test]
    fn the_mirror_plane_is_found_across_the_axis_it_mirrors() {
        let (n, o) = mirror_plane(&figure(false)).unwrap();
        assert_eq!(n, DVec3::X);
        assert!((o - 1.0).abs() < 0.02, "{o}");
        // A few points off the plane (a curled tail) move nothing.
        let (n, o) = mirror_plane(&figure(true)).unwrap();
        assert_eq!(n, DVec3::X);
        assert!((o - 1.0).abs() < 0.02, "{o}");
        // A lopsided cloud has none.
        let lopsided: Vec<DVec3> = (0..500)
            .map(|i| {
                let t = i as f64;
                DVec3::new(
                    (t * 0.37).sin().abs() * t.sqrt(),
                    (t * 0.11).cos(),
                    t * 0.01,
                )
            })
            .collect();
        assert!(mirror_plane(&lopsided).is_none());
    }

    #[test]
    fn a_bust_with_no_limbs_stands_on_its_flat_base() {
        // A ball cut flat below, modelled z-up: a bust's base at its far end along -z.
        let mut bust = crate::mesh::shapes::icosphere(1.0, 3);
        for p in &mut bust.positions {
            p.z = p.z.max(-0.6);
        }
        assert_eq!(flat_base(&bust), Some(DVec3::NEG_Z));
        // Round all over, or flat where it is not at the far end, there is none.
        assert_eq!(flat_base(&crate::mesh::shapes::icosphere(1.0, 3)), None);
        let (n, o) = mirror_plane(&bust.positions).unwrap();
        assert!(n.dot(DVec3::Z).abs() < 0.5, "{n}");
        let f = frame(&bust.positions, Some((n, o)), &[], None, flat_base(&bust));
        assert_eq!(f.up, DVec3::Z);
        // A given up wins, and without a base the convention stays.
        let given = frame(
            &bust.positions,
            Some((n, o)),
            &[],
            Some(DVec3::X),
            Some(DVec3::NEG_Z),
        );
        assert_eq!(given.up, DVec3::X);
        assert_eq!(
            frame(&bust.positions, Some((n, o)), &[], None, None).up,
            DVec3::Y
        );
    }

    #[test]
    fn the_grid_finds_the_nearest_vertex_within_its_reach() {
        let points: Vec<DVec3> = (0..2000)
            .map(|i| {
                let t = i as f64;
                DVec3::new((t * 0.37).sin(), (t * 0.11).cos() * 2.0, (t * 0.013).sin())
            })
            .collect();
        let (lo, hi) = crate::mesh::bounds(&points);
        let cell = (hi - lo).max_element() / 48.0;
        let grid = Grid::new(&points, lo, cell);
        // Queries inside the bounds and past them (a mirror image can fall outside).
        for i in 0..500 {
            let t = i as f64;
            let p = DVec3::new(
                (t * 0.7).sin() * 1.3,
                (t * 0.3).cos() * 2.4,
                (t * 0.05).cos(),
            );
            let (q, d) = grid.nearest(&points, p);
            let brute = points
                .iter()
                .map(|x| x.distance(p))
                .fold(f64::INFINITY, f64::min);
            if brute < cell {
                // Within a cell the nearest vertex is always among the 27 cells searched.
                assert_eq!(d, brute, "{p}");
                assert_eq!(q.distance(p), d);
            } else {
                // Farther: a vertex no nearer than the nearest, or none and two cells.
                let none = q == p && d == 2.0 * cell;
                assert!(
                    none || (d >= brute && d < 2.0 * cell),
                    "{p}: {d} vs {brute}"
                );
            }
        }
    }

    #[test]
    fn legs_hanging_along_an_axis_make_the_other_way_up() {
        let plane = figure(false);
        // Four legs off the plane hanging along -z: z is up, front across it and x.
        let leg = |x: f64, y: f64| Reach {
            pivot: DVec3::new(x, y, 0.0),
            tip: DVec3::new(x, y, -1.0),
            end: 0.1,
            paired: false,
        };
        let limbs = [leg(0.5, 0.2), leg(1.5, 0.2), leg(0.5, 1.8), leg(1.5, 1.8)];
        let f = frame(&plane, mirror_plane(&plane), &limbs, None, None);
        assert_eq!(f.up, DVec3::Z);
        assert!(f.front.dot(DVec3::Y).abs() > 0.99);
        assert!((f.left - f.up.cross(f.front)).length() < 1e-12);
        // Given, up is kept.
        assert_eq!(
            frame(&plane, mirror_plane(&plane), &limbs, Some(DVec3::Y), None).up,
            DVec3::Y
        );
        // Sprawled legs say little: +y stays.
        let sprawl = |x: f64, y: f64, s: f64| Reach {
            pivot: DVec3::new(x, y, 0.0),
            tip: DVec3::new(x + s, y, -0.3),
            end: 0.1,
            paired: false,
        };
        let limbs = [sprawl(0.5, 0.2, -1.0), sprawl(1.5, 0.2, 1.0)];
        assert_eq!(
            frame(&plane, mirror_plane(&plane), &limbs, None, None).up,
            DVec3::Y
        );
    }

    /// A section tree for naming: section `s` a row of `count` vertices from its pivot
    /// along its direction (`along[s]`), under `parent[s]`, each vertex of skeletal distance
    /// `radius(s)`; a section's `within` holds what hangs from it too. Named by `name`.
    fn named<T>(
        along: &[(DVec3, DVec3)],
        parent: &[Option<usize>],
        count: usize,
        radius: impl Fn(usize) -> f64,
        name: impl FnOnce(&mut Naming) -> T,
    ) -> T {
        let mut positions = Vec::new();
        let mut radii = Vec::new();
        let mut within = vec![Vec::new(); along.len()];
        for (s, &(pivot, dir)) in along.iter().enumerate() {
            for k in 0..count {
                // Into this section and every one it hangs from.
                let mut at = Some(s);
                while let Some(a) = at {
                    within[a].push(positions.len());
                    at = parent[a];
                }
                positions.push(pivot + dir * (0.02 * k as f64));
                radii.push(radius(s));
            }
        }
        let sections: Vec<crate::joints::Section> = (0..along.len())
            .map(|s| crate::joints::Section {
                name: format!("s{s}"),
                parent: parent[s],
                pivot: along[s].0,
                vertices: count,
            })
            .collect();
        let mut children = vec![Vec::new(); along.len()];
        for (s, p) in parent.iter().enumerate() {
            if let Some(p) = p {
                children[*p].push(s);
            }
        }
        let mesh = Mesh {
            positions,
            triangles: Vec::new(),
        };
        let mut naming = Naming {
            mesh: &mesh,
            radius: &radii,
            sections: &sections,
            children,
            within,
            frame: Frame::default(),
            names: vec![None; along.len()],
            ends: Vec::new(),
            size: 1.0,
            base: None,
        };
        name(&mut naming)
    }

    /// A forearm ending in two parts, one carrying fingers (a hand not cut at its wrist)
    /// and one carrying none (Homer's): the first is the hand, the other its thumb, and
    /// the hand's parts are fingers.
    #[test]
    fn a_part_carrying_fingers_beside_a_bare_one_is_a_hand_and_its_thumb() {
        // Sections: 0 the body, 1 the forearm, 2 the palm, 3 the thumb, 4–6 fingers.
        let along = [
            (DVec3::ZERO, DVec3::Y),
            (DVec3::new(0.3, 0.0, 0.0), DVec3::X),
            (DVec3::new(0.6, 0.0, 0.0), DVec3::X),
            (DVec3::new(0.55, 0.0, 0.05), DVec3::new(0.6, 0.0, 0.8)),
            (DVec3::new(0.7, 0.0, -0.03), DVec3::X),
            (DVec3::new(0.7, 0.0, 0.0), DVec3::X),
            (DVec3::new(0.7, 0.0, 0.03), DVec3::X),
        ];
        let parent = [None, Some(0), Some(1), Some(1), Some(2), Some(2), Some(2)];
        let names = named(
            &along,
            &parent,
            5,
            |_| 0.01,
            |naming| {
                naming.digits(1, "L");
                naming.names.clone()
            },
        );
        let names: Vec<Option<&str>> = names.iter().map(|n| n.as_deref()).collect();
        assert_eq!(names[2], Some("hand.L"), "{names:?}");
        assert_eq!(names[3], Some("thumb.L"), "{names:?}");
        for s in 4..7 {
            assert!(
                names[s].is_some_and(|n| n.starts_with("finger")),
                "{names:?}"
            );
        }
    }

    /// An arm whose hand is not cut, with one thin part of its own (Cheburashka's thumb
    /// sticking out, 13 and 17 vertices): that part is its thumb, not its forearm; a part
    /// as thick as the arm's far end is the forearm.
    #[test]
    fn an_arm_s_lone_thin_part_is_its_thumb() {
        let name = |thumb_radius: f64| {
            // Sections: 0 the body, 1 the arm, 2 its one part.
            let along = [
                (DVec3::ZERO, DVec3::Y),
                (DVec3::new(0.3, 0.0, 0.0), DVec3::X),
                (DVec3::new(0.45, 0.0, 0.02), DVec3::Z),
            ];
            let radius = |s: usize| if s == 2 { thumb_radius } else { 0.03 };
            named(&along, &[None, Some(0), Some(1)], 8, radius, |naming| {
                naming.chain(1, Family::Arm, "L");
                naming.names[2].clone()
            })
        };
        assert_eq!(name(0.007).as_deref(), Some("thumb.L"));
        assert_eq!(name(0.025).as_deref(), Some("forearm.L"));
    }

    #[test]
    fn up_reads_and_writes_as_an_axis() {
        for text in ["+x", "-x", "+y", "-y", "+z", "-z"] {
            let up: Up = text.parse().unwrap();
            assert_eq!(up.to_string(), text);
        }
        assert_eq!("Z".parse::<Up>().unwrap(), Up::PosZ);
        assert_eq!(Up::nearest(DVec3::new(0.1, -0.2, -0.9)), Up::NegZ);
        assert_eq!(other_side("index.L.2").as_deref(), Some("index.R.2"));
        assert_eq!(other_side("leg1.R").as_deref(), Some("leg1.L"));
        for (role, ball) in [
            ("arm.L", true),
            ("leg", true),
            ("leg2.R", true),
            ("forearm.L", false),
            ("legs", false),
            ("ear.L", false),
            ("joint 2", false),
        ] {
            assert_eq!(is_ball_joint(role), ball, "{role}");
        }
        assert_eq!(other_side("tail.2"), None);
        assert!("up".parse::<Up>().is_err());
    }
}
