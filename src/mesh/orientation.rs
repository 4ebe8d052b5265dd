//! A character's orientation: its mirror plane, its flat base, which way is up, front and
//! left (the [`Frame`]). The suggestion (`joints::suggest`) finds the mirror plane and the
//! base first (its stage 1), and up and front once the root's limbs are cut (its stage 5),
//! from how they hang ([`Reach`]); its names by role read the frame.
//!
//! * **Mirror plane** ([`crate::mesh::mirror`]). The mesh is mirrored through the plane
//!   across each axis through its centroid; the plane is kept where the mirrored vertices land, at the median, within
//!   [`MIRRORED`] of the mesh's size of a vertex (a character in T-pose or on all fours; a
//!   curled tail or a raised arm moves few vertices). With up given, only the two planes
//!   that hold it are tried, and a mirrored vertex counts as near as the surface it lands
//!   on (a low-poly side triangulated one way on the left and another on the right, a
//!   head turned a little). Without it, a vertex: the surface is the looser test, and a
//!   flat-bodied fish is nearly as alike above and below as left and right, so it could
//!   pass for a plane across up where its left and right, bent as it swims, do not.
//! * **Up.** Given (`--up`, the rig file's `up`, a glTF file's +y: `Puppet` passes it), or
//!   found: of the axis directions along the mirror plane, the one three feet or more
//!   stand on the ground along, apart, when only one has them ([`STANDING`], [`APART`]);
//!   else the one opposite to where the tips of the root's limbs off the plane lie from
//!   the mesh's centre, the legs hanging down, each limb counted as much as it is thick (legs carry the body; an armadillo's ears and raised arm say less).
//!   With no mirror plane or no limb off it, a flat base at the mesh's far end along an
//!   axis ([`BASE_AREA`] of its area: a bust's, a statue's) faces down, if that axis lies along
//!   the plane. Else, when the limbs do not clearly hang, and two pairs or more all end
//!   within [`FEET`] of the mesh's far end along one axis only, that way is down (a
//!   lizard's, an insect's sprawled feet on the ground). Else, without a plane, when +y
//!   does nearly as well, or when the limbs do not clearly hang along it, +y (the OBJ and
//!   glTF convention), unless +y is across the plane.
//!   Clearly: the root's limbs off the plane on the whole, or those that point that way at
//!   all when one of them reaches the mesh's far end that way (a biped's legs stand on the
//!   ground while its arms are held out and its ears raised; a lizard's sprawled hind legs
//!   reach no farther back than its tail).
//! * **Front.** Across up and the mirror plane: given (a rig's `front`, a glTF file's +z
//!   as the format declares, [`Axes::GLTF`]) where it lies along that line; else, where
//!   legs hang from a long body ([`LONG`]), the end of it modelled clearly finer
//!   ([`DETAIL`], [`detail`]: a face is made of smaller triangles than a rump); else the end
//!   of the body that the part on the plane most like a head grows from (with ears on the body, the one nearest them), away
//!   from another part on the plane, a tail ([`FRONT_END`]: a cat stretching looks up and
//!   back); else the way that part leans, else, with limbs hanging down, the way the soles
//!   lie ahead of the shins ([`TOES`]) or else the limbs' tips point, else the convention
//!   (+z for y up, −y for z up).
//!   **Left** = up × front: a character's own left, as `.L` in Blender's names.
pub use crate::mesh::mirror::{image, mirror_plane, reflect, MIRRORED};
use crate::mesh::Mesh;
use glam::DVec3;

/// A cut's pivot this share of the mesh's size from the mirror plane is on one side.
pub const OFF_PLANE: f64 = 0.03;
/// A limb that reaches this share of the height above the mesh's lowest point stands on
/// the ground.
pub const GROUND: f64 = 0.1;
/// This many of the root's limbs off the mirror plane or more, their tips on the ground
/// ([`GROUND`] of the mesh's far end) one way only and standing apart ([`APART`]), make
/// that way down before any other cue: a bull whose hind legs are cut with its
/// hindquarters, thick, one reaching back and up, still stands on its front legs and a
/// hind hoof. Chosen on the development half of the labelled characters: 2, 3 and 4 find
/// the same ups there (the frog's right, none lost), 5 misses the frog; 3 lies between.
pub const STANDING: usize = 3;
/// Feet stand apart when their tips spread over this share of the mesh's extent along
/// each axis across the way down (two ears and a raised hand side by side on a head's
/// top do not). On the development half any share up to 0.4 finds the same ups (0.55
/// misses the frog); the creature of `tests/suggest.rs` with ears up and an arm raised
/// high needs more than 0.05; 0.25 lies between.
pub const APART: f64 = 0.25;
/// Two pairs of limbs or more that all end within this share of the height above the mesh's
/// lowest point are feet on the ground (a lizard's, an insect's sprawled legs), when they do
/// so along one axis only.
pub const FEET: f64 = 0.2;
/// A head whose root lies this share of the mesh's size ahead of another part's on the
/// mirror plane (a tail's) marks the front; a part on the plane whose root lies as far
/// behind the centre is a tail.
pub const FRONT_END: f64 = 0.15;
/// Where neither the head's end nor its lean tells the front and limbs hang down, soles this
/// share of the mesh's size ahead of the shins do ([`toes`]), before the limbs' tips. On the development half
/// of the labelled characters that reach this cue (people, toys, a robot, a head), any
/// share above 0.0006 (the head on its own, whose "soles" are its neck) gives the same
/// fronts, all right; 0.01 is a round one in that range.
pub const TOES: f64 = 0.01;
/// The one part on the mirror plane, ending thinner than this share of the median end of
/// the root's limbs off the plane, is a tail: it leans back, not forward. (A head ends in
/// a bulb as thick as the limbs.) On the development half of the labelled characters with
/// one part on the plane, heads end at 0.51-4.3 of the limbs (a mech's small head the
/// least) and a rat's tail at 0.13; 0.25 lies between.
pub const TAIL_END: f64 = 0.25;
/// Where limbs hang down from a long body ([`LONG`]), the half of it (along the line
/// across up and the mirror plane) whose surface is made of this many times more
/// triangles per unit of area than the other's is the front, before any other cue
/// ([`detail`]: an artist models a face finer than a rump). Chosen on the development
/// half of the labelled characters: any ratio from 1.17 to 1.66 gives the same fronts
/// there, and 1.5 lies between. Fish (no limb hangs) are modelled as finely at the tail's
/// fins as at the face, and an upright figure's back (a robot's machinery, a backpack)
/// may be finer than its front, so both are left to the other cues.
pub const DETAIL: f64 = 1.5;
/// A body at least this long along the line across up and the mirror plane, for its
/// height, is long ([`DETAIL`]): on the development half, people and robots stand at most
/// 0.41 as deep as they are tall, the animals and dinosaurs at least 0.79 as long; 0.6
/// lies between.
pub const LONG: f64 = 0.6;
/// A flat face of the mesh at its far end along an axis (faces within 5° of the axis and
/// within 1 % of the mesh's size of that end) covering at least this share of its area is
/// a base it stands on (a bust's, a statue's): where no limb off the mirror plane says
/// which way is down, that way is. (Characters measured: at most 1.3 %, a flank's or a
/// sole's flat patch; busts 6–11 %.)
pub const BASE_AREA: f64 = 0.04;

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

    /// Whether `other` lies across this axis (a front across up), not along it.
    pub fn is_across(self, other: Up) -> bool {
        self.vector().dot(other.vector()) == 0.0
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

/// What a suggestion takes as given instead of finding it (each `None` to be found): up (a
/// rig file's, `--up`, a file format's), and the way the character faces (a file format's,
/// [`Axes::given`]).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Given {
    /// Up.
    pub up: Option<DVec3>,
    /// The way the character faces: taken where it lies along the line across up and the
    /// mirror plane ([`frame`]).
    pub front: Option<DVec3>,
}

impl Given {
    /// Up given, the front to be found.
    pub fn with_up(up: DVec3) -> Given {
        Given {
            up: Some(up),
            front: None,
        }
    }
}

/// The axes a file format declares its models in.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Axes {
    /// Up.
    pub up: Up,
    /// The way a model faces.
    pub front: Up,
}

impl Axes {
    /// glTF 2.0's (*Coordinate System and Units*): "glTF defines +Y as up, +Z as forward
    /// … the front of a glTF asset faces +Z".
    pub const GLTF: Axes = Axes {
        up: Up::PosY,
        front: Up::PosZ,
    };

    /// What a suggestion takes as given from a file declaring `format` and a rig (or
    /// `--up`, `--front`) giving `up` and `front`: the rig's over the file's, and the
    /// file's front only where up is the file's own (its front is declared for its up).
    pub fn given(format: Option<Axes>, up: Option<Up>, front: Option<Up>) -> Given {
        let up = up.or(format.map(|f| f.up));
        let declared = format.filter(|f| Some(f.up) == up).map(|f| f.front);
        Given {
            up: up.map(Up::vector),
            front: front.or(declared).map(Up::vector),
        }
    }
}

/// The outward normal of the mesh's flat base, if it has one: of the six axis directions,
/// the one whose flat faces at the mesh's far end that way cover the most area, when that
/// is at least [`BASE_AREA`] of the whole.
pub fn flat_base(mesh: &Mesh) -> Option<DVec3> {
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
    (total > 0.0 && area[k] >= BASE_AREA * total).then_some(AXES[k])
}

/// What says how a body stands before its limbs are cut: its mirror plane and its flat
/// base (the suggestion's first stage; up and front come from the limbs, [`frame`]).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Cues {
    /// The mirror plane (unit normal, offset along it), if the mesh has one
    /// ([`mirror_plane`]).
    pub mirror: Option<(DVec3, f64)>,
    /// The outward normal of its flat base, if it has one ([`flat_base`]).
    pub base: Option<DVec3>,
    /// Per axis (x, y, z), how much finer the surface is made in the half of the mesh on
    /// the axis's positive side than in the other ([`detail`]): 0 where alike or unknown.
    pub detail: [f64; 3],
}

impl Cues {
    /// The cues of `mesh`, standing along `up` where that is given: its mirror plane then
    /// holds up, and is read against the surface (see the module docs).
    pub fn of(mesh: &Mesh, up: Option<DVec3>) -> Cues {
        let surface: &[[u32; 3]] = if up.is_some() { &mesh.triangles } else { &[] };
        Cues {
            mirror: mirror_plane(&mesh.positions, surface, up),
            base: flat_base(mesh),
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
    /// The way the parts it carries off the mirror plane point (their mean unit direction,
    /// from each one's pivot to its tip), if it carries any: a head's ears, horns or
    /// antennae, or the legs of a body's end.
    pub carried: Option<DVec3>,
}

impl Reach {
    /// The way it points: from its pivot to its tip (unit, or zero).
    pub fn direction(&self) -> DVec3 {
        (self.tip - self.pivot).normalize_or_zero()
    }

    /// It points up (along `up`) from above `centre`: an ear, when off the mirror plane.
    pub fn raised(&self, up: DVec3, centre: DVec3) -> bool {
        self.direction().dot(up) > 0.5 && (self.pivot - centre).dot(up) > 0.0
    }

    /// How much it looks like a head, leaning along `towards` (up): its far half's
    /// thickness, more when it leans that way, twice that when it carries parts of its own
    /// off the mirror plane that do not hang down (an ant's head with its antennae, not the
    /// thicker abdomen; not a dog's hindquarters with its hind legs).
    fn head_score(&self, towards: DVec3) -> f64 {
        let pair = match self.carried {
            Some(d) if d.dot(towards) >= -0.5 => 2.0,
            _ => 1.0,
        };
        pair * self.end * (1.0 + self.direction().dot(towards))
    }
}

/// The frame of a mesh with the cues `cues` whose root has `limbs` (see the module docs);
/// up and front as far as `given`.
pub fn frame(positions: &[DVec3], cues: Cues, limbs: &[Reach], given: Given) -> Frame {
    let Cues {
        mirror,
        base,
        detail,
    } = cues;
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
    let up = match (given.up, mirror) {
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
            // (Three feet or more on the ground one way only, standing apart across it:
            // that way is down, however thick the other limbs, cut with the hindquarters,
            // or whichever way they reach. Apart: ears and a raised hand side by side on
            // a head's top are no stance.)
            let stance = |d: DVec3| {
                let (near, far) = span(d);
                let feet: Vec<DVec3> = off
                    .iter()
                    .filter(|l| far - l.tip.dot(d) <= GROUND * (far - near))
                    .map(|l| l.tip)
                    .collect();
                feet.len() >= STANDING
                    && axes[..].iter().step_by(2).all(|&e| {
                        if e.dot(d).abs() > 0.5 {
                            return true;
                        }
                        let (a, b) = span(e);
                        let (lo, hi) = feet
                            .iter()
                            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), t| {
                                (lo.min(t.dot(e)), hi.max(t.dot(e)))
                            });
                        hi - lo >= APART * (b - a)
                    })
            };
            let standing: Vec<DVec3> = axes
                .iter()
                .copied()
                .filter(|a| a.dot(n).abs() < 0.5 && stance(*a))
                .collect();
            // (+y across the mirror plane cannot be up: a character lying on its side, or
            // modelled with x or z up, has only its limbs to say.)
            let y_along = DVec3::Y.dot(n).abs() < 0.5;
            if let [down] = standing.as_slice() {
                -*down
            } else if let (false, [down]) = (clearly, on_the_ground.as_slice()) {
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
    // (A lone part on the plane much thinner than the limbs is a tail, leaning back.)
    let limbs_end = || {
        let mut ends: Vec<f64> = off.iter().map(|l| l.end).collect();
        crate::stats::median(&mut ends).unwrap_or(0.0)
    };
    let tail = midline.len() == 1 && head.is_some_and(|h| h.end < TAIL_END * limbs_end());
    let lean = head.map_or(0.0, |h| h.direction().dot(axis)) * if tail { -1.0 } else { 1.0 };
    let feet: f64 = limbs
        .iter()
        .filter(|l| l.direction().dot(up) < -0.5)
        .map(|l| (l.tip - l.pivot).dot(axis))
        .sum();
    let toes = || toes(positions, up, axis) / size.max(f64::MIN_POSITIVE);
    // (A front given along the plane's normal, a model facing across its own mirror
    // plane, is the file's mistake: the cues decide.)
    let declared = given.front.map(|f| f.dot(axis)).filter(|d| d.abs() > 0.5);
    // How far the mesh reaches along `d`.
    let extent = |d: DVec3| {
        let (a, b) = positions
            .iter()
            .map(|p| p.dot(d))
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| {
                (a.min(x), b.max(x))
            });
        b - a
    };
    // How much finer the surface is made at the front end of `axis` than at the back.
    let finer = {
        let a = axis.abs();
        let k = if a.x >= a.y && a.x >= a.z {
            0
        } else if a.y >= a.z {
            1
        } else {
            2
        };
        if a[k] > 0.99 {
            detail[k] * axis[k].signum()
        } else {
            0.0
        }
    };
    let sign = if let Some(declared) = declared {
        declared.signum()
    } else if limbs.iter().any(|l| l.direction().dot(up) < -0.5)
        && extent(axis) >= LONG * extent(up)
        && finer.abs() >= DETAIL.ln()
    {
        // Legs hang from a long body: the end modelled finer is the face.
        finer.signum()
    } else if placed.abs() > FRONT_END * size {
        placed.signum()
    } else if lean.abs() > 0.3 {
        lean.signum()
    } else if feet.abs() > 1e-9 {
        // Legs hang: their soles say it, where they clearly lie ahead of the shins, else
        // the limbs' tips.
        let toes = toes();
        if toes.abs() >= TOES {
            toes.signum()
        } else {
            feet.signum()
        }
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

/// How far the soles (the vertices in the lowest 4 % of the height along `up`) lie ahead of
/// the shins above them (8–15 %) along `axis`: feet point forward, on a person in shoes as
/// on a paw.
fn toes(positions: &[DVec3], up: DVec3, axis: DVec3) -> f64 {
    let height = |p: &DVec3| p.dot(up);
    let (lo, hi) = positions
        .iter()
        .map(height)
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), h| {
            (a.min(h), b.max(h))
        });
    let along = |from: f64, to: f64| {
        let (lo, hi) = (lo + from * (hi - lo), lo + to * (hi - lo));
        let (sum, n) = positions
            .iter()
            .filter(|p| (lo..=hi).contains(&height(p)))
            .fold((0.0, 0usize), |(s, n), p| (s + p.dot(axis), n + 1));
        (n > 0).then(|| sum / n as f64)
    };
    match (along(0.0, 0.04), along(0.08, 0.15)) {
        (Some(soles), Some(shins)) => soles - shins,
        _ => 0.0,
    }
}

/// Which of the parts on the mirror plane `midline` is most like a head (or the neck it
/// ends): of those ending at least `thickest` thick, the one ending widest, leaning up.
pub fn head_of(midline: &[&Reach], thickest: f64, up: DVec3) -> Option<usize> {
    (0..midline.len())
        .filter(|&m| midline[m].end >= thickest)
        .max_by(|&a, &b| {
            midline[a]
                .head_score(up)
                .total_cmp(&midline[b].head_score(up))
        })
}

#[cfg(test)]
mod tests {
    use super::*;

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
        let (n, o) = mirror_plane(&bust.positions, &bust.triangles, None).unwrap();
        assert!(n.dot(DVec3::Z).abs() < 0.5, "{n}");
        // Its cues: the plane along the axis, the base below.
        let cues = Cues::of(&bust, None);
        assert_eq!(cues.base, Some(DVec3::NEG_Z));
        assert_eq!(cues.mirror, Some((n, o)));
        let f = frame(&bust.positions, cues, &[], Given::default());
        assert_eq!(f.up, DVec3::Z);
        // A given up wins, and without a base the convention stays.
        let given = frame(&bust.positions, cues, &[], Given::with_up(DVec3::X));
        assert_eq!(given.up, DVec3::X);
        assert_eq!(
            frame(
                &bust.positions,
                Cues { base: None, ..cues },
                &[],
                Given::default()
            )
            .up,
            DVec3::Y
        );
    }

    #[test]
    fn legs_hanging_along_an_axis_make_the_other_way_up() {
        let plane = crate::mesh::mirror::tests::figure(false);
        // Four legs off the plane hanging along -z: z is up, front across it and x.
        let leg = |x: f64, y: f64| Reach {
            pivot: DVec3::new(x, y, 0.0),
            tip: DVec3::new(x, y, -1.0),
            end: 0.1,
            carried: None,
        };
        let limbs = [leg(0.5, 0.2), leg(1.5, 0.2), leg(0.5, 1.8), leg(1.5, 1.8)];
        let cues = Cues {
            mirror: mirror_plane(&plane, &[], None),
            base: None,
            detail: [0.0; 3],
        };
        let f = frame(&plane, cues, &limbs, Given::default());
        assert_eq!(f.up, DVec3::Z);
        assert!(f.front.dot(DVec3::Y).abs() > 0.99);
        assert!((f.left - f.up.cross(f.front)).length() < 1e-12);
        // Given, up is kept.
        assert_eq!(
            frame(&plane, cues, &limbs, Given::with_up(DVec3::Y)).up,
            DVec3::Y
        );
        // Sprawled legs say little: +y stays.
        let sprawl = |x: f64, y: f64, s: f64| Reach {
            pivot: DVec3::new(x, y, 0.0),
            tip: DVec3::new(x + s, y, -0.3),
            end: 0.1,
            carried: None,
        };
        let limbs = [sprawl(0.5, 0.2, -1.0), sprawl(1.5, 0.2, 1.0)];
        assert_eq!(frame(&plane, cues, &limbs, Given::default()).up, DVec3::Y);
    }

    /// A leg hanging straight down from (x, 0.5, z) to the ground, its far half `end` thick.
    fn hanging(x: f64, z: f64, end: f64) -> Reach {
        Reach {
            pivot: DVec3::new(x, 0.5, z),
            tip: DVec3::new(x, 0.0, z),
            end,
            carried: None,
        }
    }

    /// Two legs standing either side of the mirror plane x = 0, their tips (the heels)
    /// a little behind (−z), and the cues that plane gives.
    fn standing_legs() -> ([Reach; 2], Cues) {
        let leg = |x: f64| Reach {
            pivot: DVec3::new(x, 0.9, 0.0),
            tip: DVec3::new(x, 0.0, -0.05),
            end: 0.05,
            carried: None,
        };
        let cues = Cues {
            mirror: Some((DVec3::X, 0.0)),
            base: None,
            detail: [0.0; 3],
        };
        ([leg(0.1), leg(-0.1)], cues)
    }

    /// A standing figure whose legs' tips (the heels, farthest from the hips) lie behind:
    /// its soles, reaching forward of its shins, tell the front (+z); without soles ahead
    /// of the shins the limbs' tips do (−z).
    #[test]
    fn soles_ahead_of_the_shins_tell_the_front_of_a_standing_figure() {
        let figure = |soles: bool| {
            let mut p = Vec::new();
            for i in 0..=170 {
                let y = i as f64 * 0.01;
                for x in [-0.1, 0.1] {
                    p.push(DVec3::new(x, y, 0.0));
                    if soles && y <= 0.05 {
                        for k in 1..=6 {
                            p.push(DVec3::new(x, y, 0.025 * k as f64));
                        }
                    }
                }
            }
            p
        };
        let (limbs, cues) = standing_legs();
        let with = figure(true);
        assert!(toes(&with, DVec3::Y, DVec3::Z) > TOES * 1.7);
        assert_eq!(
            frame(&with, cues, &limbs, Given::with_up(DVec3::Y)).front,
            DVec3::Z
        );
        let without = figure(false);
        assert_eq!(toes(&without, DVec3::Y, DVec3::Z), 0.0);
        assert_eq!(
            frame(&without, cues, &limbs, Given::with_up(DVec3::Y)).front,
            DVec3::NEG_Z
        );
    }

    /// The front a file declares wins over the cues where it lies across up and the
    /// mirror plane (the figure's limbs say −z; a glTF file says +z), and not where it lies
    /// along the plane's normal (a model facing across its own mirror plane): there the
    /// cues decide. Taken only with the file's own up.
    #[test]
    fn a_front_the_file_declares_is_taken_along_the_line_the_cues_allow() {
        let (limbs, cues) = standing_legs();
        let figure: Vec<DVec3> = (0..=170)
            .flat_map(|i| [-0.1, 0.1].map(|x| DVec3::new(x, i as f64 * 0.01, 0.0)))
            .collect();
        let found = frame(&figure, cues, &limbs, Given::with_up(DVec3::Y));
        assert_eq!(found.front, DVec3::NEG_Z);
        let gltf = Axes::given(Some(Axes::GLTF), None, None);
        assert_eq!(gltf.up, Some(DVec3::Y));
        let declared = frame(&figure, cues, &limbs, gltf);
        assert_eq!(declared.front, DVec3::Z);
        assert_eq!(declared.left, DVec3::X);
        let across = Given {
            front: Some(DVec3::X),
            ..gltf
        };
        assert_eq!(frame(&figure, cues, &limbs, across).front, DVec3::NEG_Z);
        // A rig's own up sets the file's front aside; the file's up again keeps it.
        let rig = Axes::given(Some(Axes::GLTF), Some(Up::PosZ), None);
        assert_eq!((rig.up, rig.front), (Some(DVec3::Z), None));
        assert_eq!(Axes::given(Some(Axes::GLTF), Some(Up::PosY), None), gltf);
        assert_eq!(Axes::given(None, None, None), Given::default());
        // A rig's front over the file's.
        let turned = Axes::given(Some(Axes::GLTF), None, Some(Up::NegZ));
        assert_eq!(frame(&figure, cues, &limbs, turned).front, DVec3::NEG_Z);
        assert_eq!(
            Axes::given(None, Some(Up::PosZ), Some(Up::PosX)).front,
            Some(DVec3::X)
        );
    }

    /// A four-legged figure with one part on its mirror plane, reaching back along -z: thin
    /// (a rat's tail, a tenth of the legs' ends), it is a tail and the figure faces +z;
    /// ending as thick as the legs (a head on a long neck), the figure faces where it leans.
    #[test]
    fn a_lone_thin_part_on_the_plane_is_a_tail_that_leans_back() {
        let positions: Vec<DVec3> = (0..=20)
            .flat_map(|i| {
                let z = -1.6 + 0.12 * i as f64;
                [DVec3::new(-0.4, 0.0, z), DVec3::new(0.4, 1.0, z)]
            })
            .collect();
        let leg = |x: f64, z: f64| hanging(x, z, 0.2);
        let part = |end: f64| Reach {
            pivot: DVec3::new(0.0, 0.6, -0.8),
            tip: DVec3::new(0.0, 0.7, -1.6),
            end,
            carried: None,
        };
        let cues = Cues {
            mirror: Some((DVec3::X, 0.0)),
            base: None,
            detail: [0.0; 3],
        };
        let legs = [
            leg(0.3, 0.5),
            leg(-0.3, 0.5),
            leg(0.3, -0.5),
            leg(-0.3, -0.5),
        ];
        let with = |end: f64| {
            let limbs: Vec<Reach> = legs.iter().copied().chain([part(end)]).collect();
            frame(&positions, cues, &limbs, Given::with_up(DVec3::Y)).front
        };
        assert_eq!(with(0.02), DVec3::Z);
        assert_eq!(with(TAIL_END * 0.2 * 1.1), DVec3::NEG_Z);
        assert_eq!(with(0.2), DVec3::NEG_Z);
    }

    /// Of two parts on the mirror plane about as thick and leaning up alike, the one carrying
    /// parts that point up (ears) is the head; carrying parts that hang (a dog's hind legs
    /// on its hindquarters), it is not: the other, carrying nothing, is.
    #[test]
    fn a_part_carrying_legs_is_no_head_and_one_carrying_ears_is() {
        let part = |z: f64, end: f64, carried: Option<DVec3>| Reach {
            pivot: DVec3::new(0.0, 1.0, z),
            tip: DVec3::new(0.0, 1.8, 2.0 * z),
            end,
            carried,
        };
        let with = |carried| {
            let (a, b) = (part(0.5, 0.3, None), part(-0.5, 0.29, carried));
            head_of(&[&a, &b], 0.0, DVec3::Y)
        };
        assert_eq!(with(Some(DVec3::NEG_Y)), Some(0));
        assert_eq!(with(Some(DVec3::new(0.7, 0.7, 0.0))), Some(1));
    }

    /// A face is modelled finer than a rump: [`detail`] reads how much finer one half of
    /// a mesh is made along each axis. Where legs hang from a long body, the finer end is
    /// its front, before the head's place (a tail thicker than the head, taken for one);
    /// an upright figure's finer back is not.
    #[test]
    fn a_long_bodys_finer_end_is_its_front_and_an_upright_ones_is_not() {
        let ball = crate::mesh::shapes::icosphere(1.0, 3);
        assert!(
            detail(&ball).iter().all(|d| d.abs() < 0.2),
            "{:?}",
            detail(&ball)
        );
        // Each triangle of the +z half split in four at its edges' midpoints.
        let mut fine = ball.clone();
        fine.triangles.clear();
        for t in &ball.triangles {
            let p = t.map(|v| ball.positions[v as usize]);
            if (p[0] + p[1] + p[2]).z <= 0.0 {
                fine.triangles.push(*t);
                continue;
            }
            let mut mid = |a: usize, b: usize| {
                fine.positions.push((p[a] + p[b]) * 0.5);
                (fine.positions.len() - 1) as u32
            };
            let (ab, bc, ca) = (mid(0, 1), mid(1, 2), mid(2, 0));
            let [a, b, c] = *t;
            fine.triangles
                .extend([[a, ab, ca], [ab, b, bc], [ca, bc, c], [ab, bc, ca]]);
        }
        let d = detail(&fine);
        assert!((d[2] - 4f64.ln()).abs() < 0.3 && d[0].abs() < 0.2, "{d:?}");
        // Four legs hanging from a body twice as long (z) as it is tall (y), a thick part
        // on the plane at its back (-z) that reads as a head.
        let body = |length: f64| -> Vec<DVec3> {
            (0..=20)
                .flat_map(|i| {
                    let z = length * (i as f64 / 20.0 - 0.5);
                    [DVec3::new(0.0, 0.0, z), DVec3::new(0.0, 1.0, z)]
                })
                .collect()
        };
        let leg = |x: f64, z: f64| hanging(x, z, 0.05);
        let tail = |length: f64| Reach {
            pivot: DVec3::new(0.0, 0.6, -0.4 * length),
            tip: DVec3::new(0.0, 0.7, -0.5 * length),
            end: 0.3,
            carried: None,
        };
        let cues = |finer: f64| Cues {
            mirror: Some((DVec3::X, 0.0)),
            base: None,
            detail: [0.0, 0.0, finer],
        };
        let front = |length: f64, finer: f64| {
            let limbs = [
                leg(0.2, 0.3 * length),
                leg(-0.2, 0.3 * length),
                leg(0.2, -0.3 * length),
                leg(-0.2, -0.3 * length),
                tail(length),
            ];
            let given = Given::with_up(DVec3::Y);
            frame(&body(length), cues(finer), &limbs, given).front
        };
        assert_eq!(
            front(2.0, 0.0),
            DVec3::NEG_Z,
            "the thick part reads as a head"
        );
        assert_eq!(front(2.0, DETAIL.ln() * 1.1), DVec3::Z);
        assert_eq!(front(2.0, -DETAIL.ln() * 1.1), DVec3::NEG_Z);
        assert_eq!(
            front(2.0, DETAIL.ln() * 0.9),
            DVec3::NEG_Z,
            "not finer enough"
        );
        // Standing as deep as a person (0.3 of its height): its finer end says nothing,
        // either way.
        let upright = front(0.3, 0.0);
        assert_eq!(front(0.3, DETAIL.ln() * 2.0), upright);
        assert_eq!(front(0.3, -DETAIL.ln() * 2.0), upright);
    }

    /// Three feet on the ground one way, standing apart, make it down whatever the other
    /// limbs say: a bull whose hindquarters are cut as limbs, thick, one reaching back and
    /// up, stands on its front legs and a hind hoof (the limbs' thickness-weighted reach
    /// says −z). Its hind hoof raised, it is no stance. (Feet side by side are none either:
    /// `tests/suggest.rs`, a creature with its ears up and an arm raised high.)
    #[test]
    fn three_feet_apart_on_the_ground_say_down() {
        let body: Vec<DVec3> = [-1.0, 1.0]
            .into_iter()
            .flat_map(|x| {
                [0.0, 4.5]
                    .into_iter()
                    .flat_map(move |y| [-3.0, 3.0].into_iter().map(move |z| DVec3::new(x, y, z)))
            })
            .collect();
        let limb = |pivot: DVec3, tip: DVec3, end: f64| Reach {
            pivot,
            tip,
            end,
            carried: None,
        };
        let frame_of = |front_feet: [DVec3; 2], hind_hoof: DVec3| {
            let hip = |x: f64| DVec3::new(x, 2.0, -1.9);
            let limbs = [
                limb(DVec3::new(0.8, 2.1, 1.9), front_feet[0], 0.19),
                limb(DVec3::new(-0.8, 2.1, 1.9), front_feet[1], 0.19),
                limb(hip(0.5), DVec3::new(0.5, 4.3, -2.9), 0.86),
                limb(hip(-0.6), hind_hoof, 0.84),
            ];
            let cues = Cues {
                mirror: Some((DVec3::X, 0.0)),
                base: None,
                detail: [0.0; 3],
            };
            frame(&body, cues, &limbs, Given::default()).up
        };
        let apart = [DVec3::new(0.8, 0.0, 2.3), DVec3::new(-0.8, 0.0, 2.3)];
        assert_eq!(frame_of(apart, DVec3::new(-0.6, 0.0, -2.9)), DVec3::Y);
        assert_ne!(frame_of(apart, DVec3::new(-0.6, 0.5, -2.9)), DVec3::Y);
    }
}
