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
//!   pass for a plane across up where its left and right, bent as it swims, do not. Where
//!   that finds none, soles at one end only ([`SOLES`]) stand for up, and the surface test
//!   is tried on the two planes that hold it (a low-poly alpaca with its head turned).
//! * **Up.** Given (`--up`, the rig file's `up`, a glTF file's +y: `Puppet` passes it), or
//!   found: of the axis directions along the mirror plane, the one three feet or more
//!   stand on the ground along, apart, when only one has them ([`STANDING`], [`APART`]);
//!   else the one opposite to where the tips of the root's limbs off the plane lie from
//!   the mesh's centre, the legs hanging down, each limb counted as much as it is thick (legs carry the body; an armadillo's ears and raised arm say less).
//!   With no mirror plane or no limb off it, a flat base at the mesh's far end along an
//!   axis ([`BASE_AREA`] of its area: a bust's, a statue's) faces down, if that axis lies along
//!   the plane; with no plane and no base, soles at one end only ([`soles`]) do. Else, when the limbs do not clearly hang, and two pairs or more all end
//!   within [`FEET`] of the mesh's far end along one axis only, that way is down (a
//!   lizard's, an insect's sprawled feet on the ground). Else, without a plane, when +y
//!   does nearly as well, or when the limbs do not clearly hang along it, +y (the OBJ and
//!   glTF convention), unless +y is across the plane.
//!   Clearly: the root's limbs off the plane on the whole, or those that point that way at
//!   all when one of them reaches the mesh's far end that way (a biped's legs stand on the
//!   ground while its arms are held out and its ears raised; a lizard's sprawled hind legs
//!   reach no farther back than its tail). Soles come before all but a stance: where one
//!   end along the plane is flat as soles are and its opposite is not ([`SOLES`]), that
//!   end is down; and where the end taken as the top is, it is down instead (a cartoon
//!   hero whose huge head is the root, its ears the limbs that hang).
//! * **Front.** Across up and the mirror plane: given (a rig's `front`, a glTF file's +z
//!   as the format declares, [`Axes::GLTF`]) where it lies along that line; else, where
//!   legs hang from a long body ([`LONG`]), the end of it modelled clearly finer
//!   ([`DETAIL`], [`detail`]: a face is made of smaller triangles than a rump); else, for
//!   a long body with nothing to stand on (a fish), the end its bulk lies toward ([`BULK`],
//!   [`bulk`]); else the end
//!   of the body that the part on the plane most like a head grows from (with ears on the body, the one nearest them), away
//!   from another part on the plane, a tail ([`FRONT_END`]: a cat stretching looks up and
//!   back); else the way that part leans, else, with limbs hanging down, the way the soles
//!   lie ahead of the shins ([`TOES`]) or else the limbs' tips point, else the convention
//!   (+z for y up, −y for z up).
//!   **Left** = up × front: a character's own left, as `.L` in Blender's names.
//!
//! Files: `cues` (the mirror plane, the flat base, how finely each half is modelled:
//! what the first stage reads), `frame` (up, front and left: the fifth stage), `tests`.
pub use crate::mesh::mirror::{image, mirror_plane, reflect, MIRRORED};
use cues::soled;
pub use cues::{bulk, detail, flat_base, flat_ends, soles, Cues};
pub use frame::frame;
use glam::DVec3;

mod cues;
mod frame;
#[cfg(test)]
mod tests;

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
/// share of the mesh's size ahead of the shins do (`frame::toes`), before the limbs' tips. On the development half
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
/// Flat faces at the far end along an axis covering at least this share of the area
/// ([`flat_ends`]), with at most a third as much at the opposite end, are soles: where one
/// axis direction along the mirror plane has them, it is down, before what the limbs say
/// (a stance of three feet apart aside), and where the end the limbs or the convention
/// put on top has them, it is down instead. Chosen on the development half of the labelled
/// characters: soles cover 0.57–2.26 % of the area at the feet of those that stand (the
/// rat's 0.18 % the exception), flat tops at most 0.44 % (a mech's cap); 0.5 is the round
/// share above every top there. Turned with each axis up (`bench suggest --turn-up`),
/// the development half finds as many ups or more (±z: 20 → 24 of 38), the held-out half
/// more on every turn (+z 6 → 11 of 21).
pub const SOLES: f64 = 0.005;
/// A long body ([`LONG`]) with nothing to stand on (no limb off the mirror plane, none
/// reaching the ground: a fish, a whale) faces the end its bulk lies toward, when the
/// solid's centre of mass lies this share of its length ahead of the middle ([`bulk`]):
/// thickest near the head, tapering to a tail. On the development half of the labelled
/// characters (read from shape alone) the four fish that reach this cue lie 0.09–0.23
/// ahead: any share up to 0.088 turns the one that faced wrong right, and no other
/// labelled front changes; 0.05 lies below. Held-out: two fish turn right (0.06 and
/// 0.09 ahead), the whale stays right.
pub const BULK: f64 = 0.05;
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
