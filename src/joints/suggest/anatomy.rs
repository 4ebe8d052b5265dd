//! Step 5 of the module docs: which way is up, front and left, and names by role.
//!
//! * **Mirror plane.** The mesh is mirrored through the plane across each axis through its
//!   centroid; the plane is kept where the mirrored vertices land, at the median, within
//!   [`MIRRORED`] of the mesh's size of a vertex (a character in T-pose or on all fours; a
//!   curled tail or a raised arm moves few vertices).
//! * **Up.** Given (`--up`, the rig file's `up`), or found: of the axis directions along
//!   the mirror plane, the one opposite to where the root's limbs off the plane point,
//!   the legs hanging down. Without a mirror plane, when +y does nearly as well, or when
//!   the limbs do not clearly hang along it (sprawled legs), +y (the OBJ and glTF
//!   convention).
//! * **Front.** Across up and the mirror plane: the way the head leans, else the way the
//!   feet point, else the convention (+z for y up, −y for z up). **Left** = up × front: a
//!   character's own left, as `.L` in Blender's names.
//! * **Roles.** The root's limbs: off the mirror plane and pointing down, legs (the back
//!   pair of four; numbered from the front when there are three pairs or more); off the
//!   plane otherwise, arms, or ears above the root's centre; on the plane, the one that
//!   leans most up and front is the neck (or the head if nothing follows it), one pointing
//!   back the tail. Down a limb the names go on: `arm`, `forearm`, `hand`; `leg`, `shin`,
//!   `foot`; `neck`, `head`; four or five digits of a hand are `thumb`, `index`, `middle`,
//!   `ring`, `little` (the thumb the one turned most from the others), of a foot `toe1`….
//!   Side suffixes come from the side of the mirror plane; what fits no role keeps a
//!   number.

use crate::joints::Joints;
use crate::mesh::Mesh;
use glam::DVec3;

/// A cut's pivot this share of the mesh's size from the mirror plane is on one side.
const OFF_PLANE: f64 = 0.03;

/// An axis direction a mesh is modelled with as up: `+y` (OBJ's and glTF's convention),
/// `+z` (CAD's and Blender's)…, written `x`, `+x` or `-x`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
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
                let m = *p - n * 2.0 * (p.dot(n) - offset);
                let (q, d) = grid.nearest(positions, m);
                gaps.push(d);
                shifts.push((q - m).dot(n));
            }
            median = median_of(&mut gaps);
            offset += 0.5 * median_of(&mut shifts);
        }
        if best.is_none_or(|b| median < b.0) {
            best = Some((median, n, offset));
        }
    }
    let (median, n, offset) = best?;
    (median <= MIRRORED * size).then_some((n, offset))
}

fn median_of(v: &mut [f64]) -> f64 {
    if v.is_empty() {
        return f64::INFINITY;
    }
    let mid = v.len() / 2;
    *v.select_nth_unstable_by(mid, f64::total_cmp).1
}

/// A hash grid of vertices for nearest-vertex queries within a cell or two.
struct Grid {
    lo: DVec3,
    cell: f64,
    cells: std::collections::HashMap<[i64; 3], Vec<u32>>,
}

impl Grid {
    fn new(positions: &[DVec3], lo: DVec3, cell: f64) -> Grid {
        let mut cells: std::collections::HashMap<[i64; 3], Vec<u32>> = Default::default();
        let mut grid = Grid {
            lo,
            cell,
            cells: Default::default(),
        };
        for (i, p) in positions.iter().enumerate() {
            cells.entry(grid.key(*p)).or_default().push(i as u32);
        }
        grid.cells = cells;
        grid
    }

    fn key(&self, p: DVec3) -> [i64; 3] {
        ((p - self.lo) / self.cell).floor().as_i64vec3().to_array()
    }

    /// The nearest vertex within about two cells, and its distance (two cells when none).
    fn nearest(&self, positions: &[DVec3], p: DVec3) -> (DVec3, f64) {
        let k = self.key(p);
        let mut best = (p, 2.0 * self.cell);
        for dx in -1..=1 {
            for dy in -1..=1 {
                for dz in -1..=1 {
                    let Some(list) = self.cells.get(&[k[0] + dx, k[1] + dy, k[2] + dz]) else {
                        continue;
                    };
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

/// One of the root's limbs: where it is cut, and its tip.
#[derive(Clone, Copy, Debug)]
pub struct Reach {
    /// Its cut's pivot.
    pub pivot: DVec3,
    /// Its point farthest from the pivot.
    pub tip: DVec3,
    /// Its vertices, with what hangs from it.
    pub vertices: usize,
}

impl Reach {
    fn direction(&self) -> DVec3 {
        (self.tip - self.pivot).normalize_or_zero()
    }
}

/// The frame of a mesh whose root has `limbs` (see the module docs); `up` when given.
pub fn frame(positions: &[DVec3], limbs: &[Reach], up: Option<DVec3>) -> Frame {
    let mirror = mirror_plane(positions);
    let (lo, hi) = crate::mesh::bounds(positions);
    let size = (hi - lo).max_element();
    let axes = [
        DVec3::X,
        DVec3::NEG_X,
        DVec3::Y,
        DVec3::NEG_Y,
        DVec3::Z,
        DVec3::NEG_Z,
    ];
    let up = match (up, mirror) {
        (Some(u), _) => u.normalize_or(DVec3::Y),
        (None, None) => DVec3::Y,
        (None, Some((n, o))) => {
            // How well each direction across the plane does as down, by the limbs off
            // the plane (legs and arms; a tail or a neck says nothing about up).
            let down = |d: DVec3| -> f64 {
                limbs
                    .iter()
                    .filter(|l| (l.pivot.dot(n) - o).abs() >= OFF_PLANE * size)
                    .map(|l| l.direction().dot(d).max(0.0).powi(2))
                    .sum()
            };
            let best = axes
                .iter()
                .copied()
                .filter(|a| a.dot(n).abs() < 0.5)
                .max_by(|a, b| down(*a).total_cmp(&down(*b)))
                .unwrap_or(DVec3::NEG_Y);
            let count = limbs
                .iter()
                .filter(|l| (l.pivot.dot(n) - o).abs() >= OFF_PLANE * size)
                .count();
            // (Only limbs that clearly hang along it move up off +y: sprawled legs and
            // a root holding ears and arms say little.)
            if down(DVec3::NEG_Y) >= 0.67 * down(best) || down(best) < 0.5 * count as f64 {
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
    let on_plane =
        |l: &Reach| mirror.is_none_or(|(n, o)| (l.pivot.dot(n) - o).abs() < OFF_PLANE * size);
    // The head leans forward (a quadruped's); else the feet point forward.
    let head = limbs.iter().filter(|l| on_plane(l)).max_by(|a, b| {
        let score = |l: &Reach| l.vertices as f64 * (1.0 + l.direction().dot(up));
        score(a).total_cmp(&score(b))
    });
    let lean = head.map_or(0.0, |h| h.direction().dot(axis));
    let feet: f64 = limbs
        .iter()
        .filter(|l| l.direction().dot(up) < -0.5)
        .map(|l| (l.tip - l.pivot).dot(axis))
        .sum();
    let sign = if lean.abs() > 0.3 {
        lean.signum()
    } else if feet.abs() > 1e-9 {
        feet.signum()
    } else if axis.dot(convention) < 0.0 {
        -1.0
    } else {
        1.0
    };
    let front = axis * sign;
    Frame {
        up,
        front,
        left: up.cross(front),
        mirror,
    }
}

/// Role names for the sections of `joints` (index 0 is the root and keeps its name), in
/// the frame found for them; `None` where no role fits. Also returns the frame.
pub fn roles(mesh: &Mesh, joints: &Joints, up: Option<DVec3>) -> (Vec<Option<String>>, Frame) {
    let sections = joints.sections();
    let n = sections.len();
    let section_of = joints.section_of();
    let mut children = vec![Vec::new(); n];
    for (s, sec) in sections.iter().enumerate() {
        if let Some(p) = sec.parent {
            children[p].push(s);
        }
    }
    // Each section's subtree: its tip (farthest from its pivot) and its vertex count.
    let mut within: Vec<Vec<usize>> = vec![Vec::new(); n];
    for (v, &s) in section_of.iter().enumerate() {
        let mut t = s as usize;
        loop {
            within[t].push(v);
            match sections[t].parent {
                Some(p) => t = p,
                None => break,
            }
        }
    }
    let reach = |s: usize| -> Reach {
        let pivot = sections[s].pivot;
        let tip = within[s]
            .iter()
            .map(|&v| mesh.positions[v])
            .max_by(|a, b| a.distance(pivot).total_cmp(&b.distance(pivot)))
            .unwrap_or(pivot);
        Reach {
            pivot,
            tip,
            vertices: within[s].len(),
        }
    };
    let limbs: Vec<usize> = children[0].clone();
    let reaches: Vec<Reach> = limbs.iter().map(|&s| reach(s)).collect();
    let frame = frame(&mesh.positions, &reaches, up);
    let mut names: Vec<Option<String>> = vec![None; n];
    let centre =
        within[0].iter().map(|&v| mesh.positions[v]).sum::<DVec3>() / within[0].len().max(1) as f64;
    let size = {
        let (lo, hi) = mesh.bounds();
        (hi - lo).max_element().max(1e-12)
    };
    let side = |p: DVec3| -> Option<&'static str> {
        let (nrm, o) = frame.mirror?;
        let d = p.dot(nrm) - o;
        if d.abs() < OFF_PLANE * size {
            return None;
        }
        Some(if d * nrm.dot(frame.left) > 0.0 {
            "L"
        } else {
            "R"
        })
    };
    // The root's limbs: on the mirror plane, off it pointing up from above the centre
    // (ears), and the rest (arms and legs).
    let mut midline: Vec<(usize, Reach)> = Vec::new();
    let mut ears: Vec<(usize, Reach)> = Vec::new();
    let mut legs: Vec<(usize, Reach)> = Vec::new();
    for (&s, r) in limbs.iter().zip(&reaches) {
        let up_dot = r.direction().dot(frame.up);
        if frame.mirror.is_some() && side(r.pivot).is_none() {
            midline.push((s, *r));
        } else if up_dot > 0.5 && (r.pivot - centre).dot(frame.up) > 0.0 {
            ears.push((s, *r));
        } else {
            legs.push((s, *r));
        }
    }
    let along = |r: &Reach| (r.pivot - centre).dot(frame.front);
    let chain = |names: &mut Vec<Option<String>>, s: usize, family: Family, tag: &str| {
        name_chain(
            names, &children, sections, &within, mesh, &frame, s, family, tag,
        );
    };
    if frame.mirror.is_some() {
        // Midline: the neck (or head) leans most up and forward; the tail points back.
        let head = midline
            .iter()
            .max_by(|a, b| {
                let score = |r: &Reach| {
                    r.vertices as f64 * (1.0 + r.direction().dot(frame.up + frame.front))
                };
                score(&a.1).total_cmp(&score(&b.1))
            })
            .map(|h| h.0);
        for &(s, r) in &midline {
            if Some(s) == head {
                chain(&mut names, s, Family::Neck, "");
            } else if r.direction().dot(frame.front) < -0.3 {
                chain(&mut names, s, Family::Tail, "");
            }
        }
        // Two pairs, one pointing down and one not: legs and arms (a biped). Else pairs
        // from the front: arms (forelegs) and legs, or numbered legs from three pairs on.
        legs.sort_by(|a, b| along(&b.1).total_cmp(&along(&a.1)));
        let pairs = legs.len().div_ceil(2);
        let downward = |r: &Reach| r.direction().dot(frame.up) < -0.5;
        let biped = legs.iter().filter(|l| downward(&l.1)).count() == 2 && pairs <= 2;
        for (k, &(s, r)) in legs.iter().enumerate() {
            let lr = side(r.pivot).unwrap_or("L");
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
            chain(&mut names, s, family, lr);
        }
        for &(s, r) in &ears {
            chain(&mut names, s, Family::Ear, side(r.pivot).unwrap_or("L"));
        }
    } else {
        // No mirror plane: a hand on its own, or a creature posed off its symmetry.
        name_digits(
            &mut names, &children, sections, &within, mesh, &frame, 0, "",
        );
    }
    (names, frame)
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
    Ear,
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
            Family::Ear => vec!["ear".into()],
        }
    }
}

/// Names section `s` and the single chain that follows it with `family`'s names (side
/// `tag`), then what branches from the chain: digits of a hand or foot, ears of a head.
#[allow(clippy::too_many_arguments)]
fn name_chain(
    names: &mut [Option<String>],
    children: &[Vec<usize>],
    sections: &[crate::joints::Section],
    within: &[Vec<usize>],
    mesh: &Mesh,
    frame: &Frame,
    s: usize,
    family: Family,
    tag: &str,
) {
    let list = family.names();
    let with_tag = |base: &str| {
        if tag.is_empty() {
            base.to_string()
        } else {
            format!("{base}.{tag}")
        }
    };
    let mut at = s;
    let mut k = 0;
    loop {
        let base = if k < list.len() {
            list[k].clone()
        } else {
            format!("{}.{}", list[list.len() - 1], k - list.len() + 2)
        };
        names[at] = Some(with_tag(&base));
        let kids = &children[at];
        match kids.len() {
            0 => return,
            1 if !(family == Family::Neck && k + 1 >= list.len()) => {
                at = kids[0];
                k += 1;
            }
            _ => break,
        }
    }
    // Branches: a neck whose head has no cut of its own is the head.
    if family == Family::Neck && k == 0 && children[at].len() >= 2 {
        names[at] = Some(with_tag("head"));
    }
    match family {
        Family::Neck => {
            // Pairs off the plane are ears (then horns), one on it below the head a jaw.
            let mut side_kids: Vec<usize> = Vec::new();
            for &c in &children[at] {
                let p = sections[c].pivot;
                let off = frame.mirror.map_or(0.0, |(n, o)| (p.dot(n) - o).abs());
                if off > OFF_PLANE * mesh_size(mesh) {
                    side_kids.push(c);
                } else {
                    name_chain(
                        names,
                        children,
                        sections,
                        within,
                        mesh,
                        frame,
                        c,
                        Family::Tail,
                        "",
                    );
                    names[c] = Some("jaw".into());
                }
            }
            for c in side_kids {
                let p = sections[c].pivot;
                let lr = frame.mirror.map_or("L", |(n, o)| {
                    if (p.dot(n) - o) * n.dot(frame.left) > 0.0 {
                        "L"
                    } else {
                        "R"
                    }
                });
                name_chain(
                    names,
                    children,
                    sections,
                    within,
                    mesh,
                    frame,
                    c,
                    Family::Ear,
                    lr,
                );
            }
        }
        _ => name_digits(names, children, sections, within, mesh, frame, at, tag),
    }
}

fn mesh_size(mesh: &Mesh) -> f64 {
    let (lo, hi) = mesh.bounds();
    (hi - lo).max_element()
}

/// Names the branches of section `at`: four or five digits as fingers (thumb first) or
/// toes; each digit's chain goes on with `.2`, `.3`….
#[allow(clippy::too_many_arguments)]
fn name_digits(
    names: &mut [Option<String>],
    children: &[Vec<usize>],
    sections: &[crate::joints::Section],
    within: &[Vec<usize>],
    mesh: &Mesh,
    frame: &Frame,
    at: usize,
    tag: &str,
) {
    let kids = &children[at];
    if kids.len() < 2 {
        return;
    }
    let direction = |c: usize| {
        let pivot = sections[c].pivot;
        let tip = within[c]
            .iter()
            .map(|&v| mesh.positions[v])
            .max_by(|a, b| a.distance(pivot).total_cmp(&b.distance(pivot)))
            .unwrap_or(pivot);
        (tip - pivot).normalize_or_zero()
    };
    let dirs: Vec<DVec3> = kids.iter().map(|&c| direction(c)).collect();
    // Digits point roughly one way; the rest of a branch (a forearm below a palm) does not.
    let mean = dirs.iter().sum::<DVec3>().normalize_or_zero();
    let digits: Vec<usize> = (0..kids.len())
        .filter(|&i| dirs[i].dot(mean) > 0.0)
        .collect();
    let toes = names[at].as_deref().is_some_and(|n| n.starts_with("foot"));
    let with_tag = |base: &str| {
        if tag.is_empty() {
            base.to_string()
        } else {
            format!("{base}.{tag}")
        }
    };
    let mut order: Vec<usize> = digits.clone();
    let finger_names = ["thumb", "index", "middle", "ring", "little"];
    if !toes && (4..=5).contains(&digits.len()) {
        // The thumb is the digit turned most from the others; the rest by distance from it.
        let others_mean = |i: usize| {
            digits
                .iter()
                .filter(|&&j| j != i)
                .map(|&j| dirs[j])
                .sum::<DVec3>()
                .normalize_or_zero()
        };
        let thumb = *digits
            .iter()
            .min_by(|&&a, &&b| {
                dirs[a]
                    .dot(others_mean(a))
                    .total_cmp(&dirs[b].dot(others_mean(b)))
            })
            .unwrap_or(&digits[0]);
        let base = sections[kids[thumb]].pivot;
        order.sort_by(|&a, &b| {
            sections[kids[a]]
                .pivot
                .distance(base)
                .total_cmp(&sections[kids[b]].pivot.distance(base))
        });
        let skip = 5 - digits.len();
        for (rank, &i) in order.iter().enumerate() {
            let name = if rank == 0 {
                "thumb"
            } else {
                finger_names[rank + skip]
            };
            name_digit(names, children, kids[i], &with_tag(name));
        }
    } else if digits.len() >= 2 {
        for (rank, &i) in order.iter().enumerate() {
            let base = if toes { "toe" } else { "finger" };
            name_digit(
                names,
                children,
                kids[i],
                &with_tag(&format!("{base}{}", rank + 1)),
            );
        }
    }
    // A branch that is no digit below an extremity (a forearm below a palm).
    for (i, &c) in kids.iter().enumerate() {
        if !digits.contains(&i) && names[c].is_none() && at == 0 {
            name_digit(names, children, c, &with_tag("forearm"));
        }
    }
    let _ = frame;
}

/// Names a digit's chain: `index`, `index.2`, `index.3`….
fn name_digit(names: &mut [Option<String>], children: &[Vec<usize>], s: usize, name: &str) {
    let mut at = s;
    let mut k = 1;
    loop {
        names[at] = Some(if k == 1 {
            name.to_string()
        } else {
            format!("{name}.{k}")
        });
        match children[at].as_slice() {
            [only] => {
                at = *only;
                k += 1;
            }
            _ => return,
        }
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
    fn legs_hanging_along_an_axis_make_the_other_way_up() {
        let plane = figure(false);
        // Four legs off the plane hanging along -z: z is up, front across it and x.
        let leg = |x: f64, y: f64| Reach {
            pivot: DVec3::new(x, y, 0.0),
            tip: DVec3::new(x, y, -1.0),
            vertices: 50,
        };
        let limbs = [leg(0.5, 0.2), leg(1.5, 0.2), leg(0.5, 1.8), leg(1.5, 1.8)];
        let f = frame(&plane, &limbs, None);
        assert_eq!(f.up, DVec3::Z);
        assert!(f.front.dot(DVec3::Y).abs() > 0.99);
        assert!((f.left - f.up.cross(f.front)).length() < 1e-12);
        // Given, up is kept.
        assert_eq!(frame(&plane, &limbs, Some(DVec3::Y)).up, DVec3::Y);
        // Sprawled legs say little: +y stays.
        let sprawl = |x: f64, y: f64, s: f64| Reach {
            pivot: DVec3::new(x, y, 0.0),
            tip: DVec3::new(x + s, y, -0.3),
            vertices: 50,
        };
        let limbs = [sprawl(0.5, 0.2, -1.0), sprawl(1.5, 0.2, 1.0)];
        assert_eq!(frame(&plane, &limbs, None).up, DVec3::Y);
    }

    #[test]
    fn up_reads_and_writes_as_an_axis() {
        for text in ["+x", "-x", "+y", "-y", "+z", "-z"] {
            let up: Up = text.parse().unwrap();
            assert_eq!(up.to_string(), text);
        }
        assert_eq!("Z".parse::<Up>().unwrap(), Up::PosZ);
        assert_eq!(Up::nearest(DVec3::new(0.1, -0.2, -0.9)), Up::NegZ);
        assert!("up".parse::<Up>().is_err());
    }
}
