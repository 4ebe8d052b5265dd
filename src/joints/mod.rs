//! Joints (paper §3.4): cutting the skeleton with planes, spheres or boxes into sections, the
//! pivot of each cut, and how the rotations of a pose compose down the section tree.
//!
//! # Sections and cuts
//! Section 0, the *root*, is the whole object. A [`Cut`] is a plane (point + unit normal),
//! a sphere or a box ([`Shape`]) applied to one existing section: every vertex of that
//! section whose **skeletal point** `sp_i` lies strictly on the side the normal points to
//! (inside a sphere or a box) moves to a new section named after the cut; the rest stay. Cutting by skeletal points rather than surface positions keeps
//! thin features whole (the surface of a bent arm can cross the plane where its medial axis
//! does not). The cuts form a binary tree: each cut splits one section in two.
//!
//! # The joint hierarchy and how rotations compose
//! The new section is the *child* of the section it was cut from, hinged at the cut's
//! **pivot** (by default, for a plane, the centroid of the skeletal points of the cut
//! section nearest the plane, projected onto the plane; for a sphere or a box, the centroid
//! of the skeletal points of the new section's vertices on the seam, those with a mesh
//! neighbour left behind; editable). When a later cut splits a section that
//! already has children, a child whose pivot lies on the new side is handed to the new
//! section: cutting the shoulder after the elbow makes the forearm a child of the upper arm.
//!
//! A pose gives every section a local [`Local`] rotation about its own pivot (plus an
//! optional translation, used for the root). World transforms compose from the root down:
//!
//! `W(s) = W(parent(s)) · T(pivot_s + t_s) · R_s · T(−pivot_s)`
//!
//! so rotating the upper arm carries the forearm and the hand with it, and the forearm's own
//! rotation is about its elbow *as carried by the upper arm*. Every section can be posed at
//! once. A section at the end of a joint band also moves by the band's shift,
//! `T(shift(R_s))` on the left of its own motion: along an arc (two limbs meeting: an
//! elbow, a knee) the bent limb keeps its length ([`band`]); at a fan, and at an arc
//! too, the child slides along the cut's normal by what keeps its volume ([`slide`]).
//! What the slides leave of a section's volume is measured in the pose and given back by
//! swelling the bands' levels (`volume`).
//!
//! # Shared pivots
//! The paper's pivot is "the rotation center for the two generated joint sections". A
//! section turns about its own cut's pivot (the root about the centroid of its skeletal
//! points) unless one of its child cuts has a **shared pivot** ([`Cut::shared_pivot`]):
//! then it turns about that cut's pivot, so both jaws of a mouth open about one hinge. A
//! section turns about one point: at most one of its child cuts shares its pivot.
//! [`Section::pivot`] is the point a section turns about, whichever it is.
//!
//! # Connected cuts
//! A plane reaches across the whole section: a cut at one hip would take both legs. A
//! *connected* cut takes only the piece of the positive side that is connected (through
//! mesh edges) to the skeletal point nearest the cut's point: the leg you cut, not the
//! other. Cuts made in the window and suggested cuts are connected; a rig file's cut is a
//! plain plane unless it says `connected = true`.
//!
//! # Riders
//! Small separate closed parts (eyes, teeth) have no skeleton of their own worth the name:
//! each of their vertices rides with the section of a *host* vertex of the body (the one
//! nearest to it), whatever the cuts. A rider whose host moves with a band's level rides
//! on that level's motion made rigid about its host ([`band::Twin`]): a swell that
//! keeps a section's volume does not scale an eye or a backpack with the flesh.
//!
//! # Files
//! * this file: the types, and the joints of one puppet;
//! * `cut`: applying and removing cuts, pivots, connected pieces;
//! * `shape`: planes, spheres and boxes, as signed distances;
//! * `band`: joint bands, their levels, contacts and where they overlap;
//! * `blend`: a band's weight blended over the surface around its seam;
//! * `carry`: the siblings a band carries whole, and the order bands compose in;
//! * `slide`: a fan's skin slid along its normal so the child keeps its volume;
//! * `volume`: each section's volume measured in a pose, and given back by swelling bands;
//! * `levels`: a band's weights rounded to its levels, short edges on one;
//! * `reach`: where a band reaches: the vertices near a cut, its radius, its flesh;
//! * `pose`: composing a pose down the section tree;
//! * `suggest`: joints suggested from the skeleton;
//! * `skin`: joints from the skeleton the mesh file came with (a glTF skin);
//! * `whole`: whole sections, a stray piece of one joining the section around it, and a
//!   part of the mesh a cut splits beside its limb turning whole;
//! * `collide`: the pose limit, which stops a part where it meets another;
//! * `spread`: random poses within a spread of angles.
//!
//! # Removing cuts
//! Removing a cut merges its section back into the section it was cut from; its children
//! and the cuts applied to it move to that section. The assignment is replayed from the
//! remaining cuts (O(vertices × cuts)); the skeleton is never recomputed.

pub mod band;
mod blend;
mod carry;
pub mod collide;
mod cut;
mod levels;
mod pose;
mod reach;
mod shape;
pub mod skin;
mod slide;
pub mod spread;
pub mod suggest;
mod volume;
mod whole;

pub use band::{Band, DEFAULT_BAND, MAX_BAND};
pub use pose::{to_f32, PoseScratch};
pub use shape::Shape;
pub use slide::{Slide, MAX_SLIDE};
pub use volume::{section_size, SMALL_SECTION};

use glam::{DQuat, DVec3};
use std::sync::Arc;

/// Most sections a rig may have (the simulation stores a `u16` section per vertex).
pub const MAX_SECTIONS: usize = 4096;

/// Name of the root section unless a rig file says otherwise.
pub const ROOT: &str = "root";

/// A cut as written by a user or a file: which section it splits, the shape, the pivot.
#[derive(Clone, Debug, PartialEq)]
pub struct Cut {
    /// Name of the new section (the side the normal points to, or inside).
    pub name: String,
    /// Name of the section this cut splits.
    pub section: String,
    /// Plane, sphere or box (see [`Shape`]).
    pub shape: Shape,
    /// A point on the plane; the centre of a sphere or a box.
    pub point: DVec3,
    /// Plane normal, pointing into the new section (any non-zero length); a box's third
    /// axis; unused by a sphere.
    pub normal: DVec3,
    /// Rotation point; `None` takes the default (see module docs).
    pub pivot: Option<DVec3>,
    /// Take only the piece of the positive side connected to the point (see module docs).
    pub connected: bool,
    /// Half-width of the joint band in local medial radii (see [`band`]); `None` takes
    /// [`DEFAULT_BAND`], 0 is a hinge.
    pub band: Option<f64>,
    /// The section this cut splits turns about this cut's pivot too (see module docs).
    pub shared_pivot: bool,
}

impl Cut {
    /// A plain plane cut of `section` through `point` with `normal` into the new section
    /// `name`: the default pivot and band, not connected, no shared pivot.
    pub fn plane(name: &str, section: &str, point: DVec3, normal: DVec3) -> Cut {
        Cut {
            name: name.into(),
            section: section.into(),
            shape: Shape::Plane,
            point,
            normal,
            pivot: None,
            connected: false,
            band: None,
            shared_pivot: false,
        }
    }

    /// The cut with its numbers at the precision files write them ([`crate::files::shortest`]):
    /// a cut made by the suggestion or the cut tool is then the cut its rig file holds,
    /// written in short numbers (`0.45`, not `0.45000000298023224`) and read back the same.
    pub fn rounded(self) -> Cut {
        use crate::files::{shortest, shortest3};
        Cut {
            shape: match self.shape {
                Shape::Plane => Shape::Plane,
                Shape::Skin => Shape::Skin,
                Shape::Sphere { radius } => Shape::Sphere {
                    radius: shortest(radius),
                },
                Shape::Box { size } => Shape::Box {
                    size: shortest3(size),
                },
            },
            point: shortest3(self.point),
            normal: shortest3(self.normal),
            pivot: self.pivot.map(shortest3),
            band: self.band.map(shortest),
            ..self
        }
    }
}

/// A section: a node of the joint hierarchy.
#[derive(Clone, Debug, PartialEq)]
pub struct Section {
    /// Its name (the cut's, or the root's).
    pub name: String,
    /// Parent section (`None` for the root).
    pub parent: Option<usize>,
    /// The point it turns about: its cut's pivot (for the root, the centroid of all
    /// skeletal points), or a child cut's shared pivot (see module docs).
    pub pivot: DVec3,
    /// Number of vertices in this section.
    pub vertices: usize,
}

/// A section's pose relative to its parent: a rotation about its pivot, then a translation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Local {
    /// Rotation about the section's pivot.
    pub rotation: DQuat,
    /// Translation after the rotation.
    pub translation: DVec3,
}

impl Default for Local {
    fn default() -> Self {
        Local {
            rotation: DQuat::IDENTITY,
            translation: DVec3::ZERO,
        }
    }
}

impl Local {
    /// A rotation of `degrees` about `axis` (no translation). A zero or non-finite axis
    /// gives the identity.
    pub fn axis_angle(axis: DVec3, degrees: f64) -> Local {
        let axis = axis.normalize_or_zero();
        if axis == DVec3::ZERO || !degrees.is_finite() {
            return Local::default();
        }
        Local {
            rotation: DQuat::from_axis_angle(axis, degrees.to_radians()),
            translation: DVec3::ZERO,
        }
    }
}

/// Why a cut or a removal was refused. Nothing changes when one is returned.
#[derive(Debug, PartialEq, thiserror::Error)]
pub enum JointError {
    /// The cut names a section that does not exist.
    #[error("cut '{cut}': unknown section '{section}' (known: {known})")]
    UnknownSection {
        /// The cut.
        cut: String,
        /// The section it names.
        section: String,
        /// The sections there are, comma-separated.
        known: String,
    },
    /// The cut's name is empty.
    #[error("cut '{0}': the name is empty")]
    EmptyName(String),
    /// A section of that name exists.
    #[error("cut '{0}': a section with this name already exists")]
    DuplicateName(String),
    /// A point, normal or pivot with a NaN or infinite coordinate.
    #[error("cut '{cut}': {what} is not a finite vector")]
    NotFinite {
        /// The cut.
        cut: String,
        /// Which vector.
        what: &'static str,
    },
    /// The plane normal has zero length.
    #[error("cut '{0}': the normal is zero")]
    ZeroNormal(String),
    /// A sphere's radius or a box's size that is not a positive finite number.
    #[error("cut '{0}': a {1}'s size must be positive and finite")]
    BadSize(String, &'static str),
    /// Two cuts of one section with a shared pivot.
    #[error("cut '{cut}': section '{section}' already turns about the pivot of cut '{other}' (a section turns about one point)")]
    SharedPivot {
        /// The cut.
        cut: String,
        /// The section both split.
        section: String,
        /// The cut whose pivot it already shares.
        other: String,
    },
    /// The plane leaves one side of the section without a skeletal point.
    #[error("cut '{cut}': leaves {side} of section '{section}' empty (no skeletal point on that side of the plane)")]
    EmptySide {
        /// The cut.
        cut: String,
        /// The section it cuts.
        section: String,
        /// Which side is empty.
        side: &'static str,
    },
    /// More than [`MAX_SECTIONS`] sections.
    #[error("too many sections (at most {MAX_SECTIONS})")]
    TooMany,
    /// No cut of that name to remove.
    #[error("no cut named '{0}'")]
    NoSuchCut(String),
    /// A skin cut whose name is no joint of the mesh's skin (or the mesh has none).
    #[error("cut '{0}': a skin cut takes the mesh's skin joint of its name, and the mesh has no such joint")]
    NoSkinJoint(String),
}

/// What the joints know of the body, shared by every copy of them (undo keeps copies).
#[derive(Clone, Debug, Default, PartialEq)]
struct Body {
    /// Skeletal point of each vertex.
    points: Vec<DVec3>,
    /// Mesh neighbours of each vertex (CSR): `neighbours[start[i]..start[i + 1]]`; empty
    /// without a mesh, where connected cuts take the whole positive side.
    start: Vec<u32>,
    neighbours: Vec<u32>,
    /// The mesh's triangles (empty without a mesh): where a fan's slide is measured
    /// ([`slide`]).
    triangles: Vec<[u32; 3]>,
    /// Each vertex's part of the mesh, connected through its own triangles alone,
    /// whatever attaches it (empty without a mesh): what [`whole`] turns whole.
    part_of: Vec<u32>,
    /// For each vertex of a rider, its host vertex; `u32::MAX` for the body's own.
    host: Vec<u32>,
    /// Skeletal distance (medial radius) of each vertex; empty when unknown (then every
    /// cut is a hinge).
    radius: Vec<f64>,
    /// Rest position of each surface vertex (with `radius`; empty when unknown).
    rest: Vec<DVec3>,
    /// The whole surface's capped volume at rest (0 until `rest` is known): what a
    /// section too small to keep is measured against ([`volume`]).
    whole: f64,
    /// The skeleton the mesh file came with, its `vertex_joint` one per vertex (skin cuts
    /// take their vertices from it).
    skin: Option<Arc<crate::mesh::Skin>>,
}

/// No host: a vertex of the body.
const NO_HOST: u32 = u32::MAX;

/// A vertex on no part made whole ([`Joints`]' `whole_part`).
const NOT_MOVED: u16 = u16::MAX;

/// The joints of one puppet: cuts, the sections they make and each vertex's section.
#[derive(Clone, Debug, PartialEq)]
pub struct Joints {
    body: Arc<Body>,
    /// Cuts in the order applied, with resolved pivots.
    cuts: Vec<Cut>,
    sections: Vec<Section>,
    /// The root's own pivot (its section's turns about a shared one when a cut says so).
    root_pivot: DVec3,
    section_of: Vec<u16>,
    /// Each vertex's section by its skeletal point alone, which cuts split
    /// (`section_of` is this made whole over the surface, see [`whole`]).
    skeletal_of: Vec<u16>,
    /// Per vertex, the vertex whose skeletal point places it across the bands: itself,
    /// or one around the piece it was moved with (empty when none moved, see [`whole`]).
    borrowed: Vec<u32>,
    /// Per vertex of a part made whole beside a cut ([`whole`]), the section it
    /// had before ([`NOT_MOVED`] for every other vertex; empty when no part moved): no
    /// band takes it by its skeletal point, and a band's width is measured as before.
    whole_part: Vec<u16>,
    /// Whether parts split beside a cut go whole to one section ([`whole`]).
    parts_whole: bool,
    /// Sections parents-first (for composing transforms).
    order: Vec<usize>,
    /// Per cut, its joint band (see [`band`]).
    bands: Vec<Option<Band>>,
    /// Per section, the cut whose band ends in it (the section it made), if any.
    band_of: Vec<Option<usize>>,
    /// Per section, the bands of its parent's other children that carry it on the skin
    /// they move (cut, level), carriers first; empty for most (see [`band`]: *carried*).
    carried: Vec<Vec<(usize, u16)>>,
    /// Per vertex, the transform the simulation moves it with (its section's or a band
    /// level's).
    transform_of: Vec<u16>,
    /// Per vertex, the joint whose flesh it is ([`Joints::joint_flesh`]), kept with the
    /// bands.
    flesh: Vec<u16>,
    /// The vertices where bands overlap, each with a transform of its own after the
    /// levels' ([`band::Blend`]).
    blends: Vec<band::Blend>,
    /// Blends of sections by the skin's weights, their transforms after the contacts'
    /// ([`skin::Mix`]).
    mixes: Vec<skin::Mix>,
    /// The riders' own transforms, after the mixes' ([`band::Twin`]).
    twins: Vec<band::Twin>,
    /// The sections whose volume a pose keeps, with the bands that swell them
    /// ([`volume`]), kept with the bands.
    kept: Vec<volume::Kept>,
    /// Which content this is ([`Stamp`]): a pose asked for again of the same content is
    /// read from [`PoseScratch`] instead of made again.
    stamp: Stamp,
}

/// Tells one content of a [`Joints`] from another: a fresh number each time one may
/// change (every `&mut self` method takes one first), drawn from a counter shared by all,
/// so that two clones changed apart never read alike. In comparisons every stamp is equal:
/// two joints alike are alike whatever their history.
#[derive(Clone, Copy, Debug)]
struct Stamp(u64);

impl Stamp {
    fn fresh() -> Stamp {
        static NEXT: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(1);
        Stamp(NEXT.fetch_add(1, std::sync::atomic::Ordering::Relaxed))
    }
}

impl PartialEq for Stamp {
    fn eq(&self, _: &Stamp) -> bool {
        true
    }
}

impl Joints {
    /// One root section named `root` holding every vertex; `skeleton_points` are the
    /// skeletal points `sp_i`. Without a mesh, connected cuts take the whole positive side.
    pub fn new(skeleton_points: &[DVec3], root: &str) -> Joints {
        Joints::with_body(
            Body {
                points: skeleton_points.to_vec(),
                ..Body::default()
            },
            root,
        )
    }

    /// As [`Joints::new`], with the mesh's `triangles` (for connected cuts) and a host
    /// vertex for every vertex of a rider (`None` for the body's own; see module docs).
    ///
    /// # Panics
    /// If `hosts` is not empty and not one per skeletal point, or a triangle or host names a
    /// vertex that does not exist.
    pub fn with_mesh(
        skeleton_points: &[DVec3],
        triangles: &[[u32; 3]],
        hosts: &[Option<u32>],
        root: &str,
    ) -> Joints {
        let n = skeleton_points.len();
        assert!(
            hosts.is_empty() || hosts.len() == n,
            "one host entry per vertex"
        );
        let (start, neighbours) = crate::mesh::neighbours(n, &crate::mesh::unique_edges(triangles));
        let host = if hosts.iter().any(Option::is_some) {
            hosts.iter().map(|h| h.unwrap_or(NO_HOST)).collect()
        } else {
            Vec::new()
        };
        Joints::with_body(
            Body {
                points: skeleton_points.to_vec(),
                start,
                neighbours,
                triangles: triangles.to_vec(),
                part_of: crate::mesh::components(n, triangles),
                host,
                radius: Vec::new(),
                rest: Vec::new(),
                whole: 0.0,
                skin: None,
            },
            root,
        )
    }

    fn with_body(body: Body, root: &str) -> Joints {
        let n = body.points.len();
        let own: Vec<DVec3> = (0..n)
            .filter(|&i| !body.is_rider(i))
            .map(|i| body.points[i])
            .collect();
        let centroid = own.iter().copied().sum::<DVec3>() / own.len().max(1) as f64;
        Joints {
            body: Arc::new(body),
            cuts: Vec::new(),
            sections: vec![Section {
                name: root.to_string(),
                parent: None,
                pivot: centroid,
                vertices: n,
            }],
            root_pivot: centroid,
            section_of: vec![0; n],
            skeletal_of: vec![0; n],
            borrowed: Vec::new(),
            whole_part: Vec::new(),
            parts_whole: true,
            order: vec![0],
            bands: Vec::new(),
            band_of: vec![None],
            carried: vec![Vec::new()],
            transform_of: vec![0; n],
            flesh: Vec::new(),
            blends: Vec::new(),
            mixes: Vec::new(),
            twins: Vec::new(),
            kept: Vec::new(),
            stamp: Stamp::fresh(),
        }
    }

    /// Marks the joints changed (see [`Stamp`]).
    fn changing(&mut self) {
        self.stamp = Stamp::fresh();
    }

    /// Joins the body's separate parts where they meet ([`crate::mesh::attachments`]): a
    /// connected cut, and a whole section, take a piece with the pieces attached to it, as
    /// with its mesh neighbours. Cuts made before keep the sections they made.
    ///
    /// # Panics
    /// If an attachment names a vertex that does not exist.
    pub fn attach_parts(&mut self, attachments: &[(u32, u32)]) {
        self.changing();
        if attachments.is_empty() {
            return;
        }
        let n = self.body.points.len();
        let body = Arc::make_mut(&mut self.body);
        let mut edges: Vec<(u32, u32)> = attachments.to_vec();
        for a in 0..n.min(body.start.len().saturating_sub(1)) {
            for &b in body.neighbours(a) {
                if (a as u32) < b {
                    edges.push((a as u32, b));
                }
            }
        }
        edges.sort_unstable();
        edges.dedup();
        (body.start, body.neighbours) = crate::mesh::neighbours(n, &edges);
    }

    /// Gives the joints the surface's rest positions and each vertex's skeletal distance
    /// (the medial radius), which set the joint bands and their contacts (see [`band`]);
    /// without them every cut is a hinge.
    ///
    /// # Panics
    /// If `positions` or `radii` is not one per skeletal point.
    pub fn set_surface(&mut self, positions: &[DVec3], radii: &[f64]) {
        self.changing();
        let n = self.body.points.len();
        assert_eq!(positions.len(), n, "one position per vertex");
        assert_eq!(radii.len(), n, "one radius per vertex");
        let body = Arc::make_mut(&mut self.body);
        body.rest = positions.to_vec();
        body.radius = radii.to_vec();
        body.whole = if body.triangles.is_empty() {
            0.0
        } else {
            crate::mesh::measure::Capped::from_faces(body.triangles.clone())
                .volume(&body.rest)
                .abs()
        };
        self.assign_sections(true);
        self.refresh_bands();
    }

    /// Gives the joints the skeleton the mesh file came with, for skin cuts
    /// ([`Shape::Skin`]). A skin whose `vertex_joint` is not one per vertex is ignored.
    pub fn set_skin(&mut self, skin: Option<Arc<crate::mesh::Skin>>) {
        self.changing();
        let n = self.body.points.len();
        Arc::make_mut(&mut self.body).skin = skin.filter(|s| s.vertex_joint.len() == n);
    }

    /// The skin the joints were given, if any.
    pub fn skin(&self) -> Option<&Arc<crate::mesh::Skin>> {
        self.body.skin.as_ref()
    }

    /// The skin's joint named `name`.
    fn skin_joint(&self, name: &str) -> Option<usize> {
        self.body.skin.as_ref()?.find(name)
    }

    /// The same body with no cuts and the root named `root` (its pivot kept).
    pub fn without_cuts(&self, root: &str) -> Joints {
        let mut j = self.uncut();
        j.changing();
        j.sections[0].name = root.to_string();
        j
    }

    /// The same body with no cuts (the root keeps its name and own pivot).
    fn uncut(&self) -> Joints {
        let mut j = Joints {
            body: self.body.clone(),
            cuts: Vec::new(),
            sections: vec![Section {
                name: self.sections[0].name.clone(),
                parent: None,
                pivot: self.root_pivot,
                vertices: self.section_of.len(),
            }],
            root_pivot: self.root_pivot,
            section_of: vec![0; self.section_of.len()],
            skeletal_of: vec![0; self.section_of.len()],
            borrowed: Vec::new(),
            whole_part: Vec::new(),
            parts_whole: self.parts_whole,
            order: vec![0],
            bands: Vec::new(),
            band_of: vec![None],
            carried: vec![Vec::new()],
            transform_of: vec![0; self.section_of.len()],
            flesh: Vec::new(),
            blends: Vec::new(),
            mixes: Vec::new(),
            twins: Vec::new(),
            kept: Vec::new(),
            stamp: Stamp::fresh(),
        };
        // (No cuts: no bands, and no joint has flesh.)
        j.refresh_bands();
        j
    }

    /// The root's own pivot (the point it turns about unless a cut shares its pivot).
    pub fn root_pivot(&self) -> DVec3 {
        self.root_pivot
    }

    /// The sections; index 0 is the root.
    pub fn sections(&self) -> &[Section] {
        &self.sections
    }

    /// Section indices, parents before children.
    pub fn parents_first(&self) -> &[usize] {
        &self.order
    }

    /// The cuts in the order applied, with their pivots resolved.
    pub fn cuts(&self) -> &[Cut] {
        &self.cuts
    }

    /// Each cut's name and the pivot of the section it makes (cut `k` makes section
    /// `k + 1`), as `puppet bench suggest` scores them.
    pub fn cut_pivots(&self) -> Vec<(String, DVec3)> {
        self.cuts
            .iter()
            .zip(&self.sections[1..])
            .map(|(c, s)| (c.name.clone(), s.pivot))
            .collect()
    }

    /// Section index of each vertex.
    pub fn section_of(&self) -> &[u16] {
        &self.section_of
    }

    /// The skeletal points the cuts classify.
    pub fn points(&self) -> &[DVec3] {
        &self.body.points
    }

    /// What the simulation's contacts need of the joints: each vertex's section, each
    /// section's rank ([`Joints::contact_ranks`]) and each vertex's joint flesh
    /// ([`Joints::joint_flesh`]).
    pub fn joint_sections(&self) -> crate::sim::JointSections {
        crate::sim::JointSections {
            section: self.section_of.clone(),
            rank: self.contact_ranks(),
            flesh: self.joint_flesh().to_vec(),
        }
    }

    /// Each section's rank for contacts: its depth in the hierarchy, then its index, so a
    /// point of a section yields to the balls of its ancestors and of shallower sections
    /// (an arm to the body, a finger to the palm), and of two at one depth the later one
    /// yields ([`crate::sim::contact`]).
    pub fn contact_ranks(&self) -> Vec<u32> {
        let sections = self.sections();
        (0..sections.len())
            .map(|s| {
                let (mut depth, mut at) = (0u32, s);
                while let Some(p) = sections[at].parent {
                    depth += 1;
                    at = p;
                    if depth as usize > sections.len() {
                        break;
                    }
                }
                depth * 65_536 + s as u32
            })
            .collect()
    }

    /// Whether section `s` hangs from section `a`, however deep (not from itself).
    ///
    /// # Panics
    /// If `s` or a section above it is not a section.
    pub fn hangs_from(&self, mut s: usize, a: usize) -> bool {
        for _ in 0..self.sections.len() {
            match self.sections[s].parent {
                Some(p) if p == a => return true,
                Some(p) => s = p,
                None => return false,
            }
        }
        false
    }

    /// Per section, whether it moves with section `s`: `s` itself and every section
    /// [hanging from it](Joints::hangs_from), however deep, all at once.
    pub(super) fn moves_with(&self, s: usize) -> Vec<bool> {
        let mut moves = vec![false; self.sections.len()];
        for &k in &self.order {
            moves[k] = k == s || self.sections[k].parent.is_some_and(|p| moves[p]);
        }
        moves
    }

    /// Index of the section named `name`.
    pub fn find(&self, name: &str) -> Option<usize> {
        self.sections.iter().position(|s| s.name == name)
    }

    /// The sections from `a` and from `b` up to the section both hang from, that one left
    /// out: the sections whose own cuts lie between the two in the section tree.
    fn between(&self, a: usize, b: usize) -> Vec<usize> {
        let up = |mut s: usize| {
            let mut chain = vec![s];
            while let Some(p) = self.sections.get(s).and_then(|x| x.parent) {
                if chain.len() > self.sections.len() {
                    break;
                }
                chain.push(p);
                s = p;
            }
            chain
        };
        let (from_a, from_b) = (up(a), up(b));
        let mut out: Vec<usize> = from_a
            .iter()
            .copied()
            .take_while(|s| !from_b.contains(s))
            .collect();
        out.extend(from_b.iter().copied().take_while(|s| !from_a.contains(s)));
        out
    }

    /// The sections whose joints lie between sections `a` and `b`: from each up to the
    /// section both hang from, that one left out (turning it moves both alike), and the
    /// sections whose bands carry one of those (turning them moves it too; see
    /// [`band`]: *carried*).
    pub fn path(&self, a: usize, b: usize) -> Vec<usize> {
        let mut out = self.between(a, b);
        let mut at = 0;
        while at < out.len() {
            for &(k, _) in self.carried.get(out[at]).map_or(&[][..], Vec::as_slice) {
                if let Some(c) = self.bands.get(k).and_then(Option::as_ref).map(|b| b.child) {
                    if !out.contains(&c) {
                        out.push(c);
                    }
                }
            }
            at += 1;
        }
        out
    }
}

impl Body {
    /// Is vertex `i` part of a rider (it goes with its host's section)?
    fn is_rider(&self, i: usize) -> bool {
        self.host.get(i).is_some_and(|&h| h != NO_HOST)
    }

    /// The mesh neighbours of vertex `i` (none without a mesh).
    fn neighbours(&self, i: usize) -> &[u32] {
        match (self.start.get(i), self.start.get(i + 1)) {
            (Some(&a), Some(&b)) => &self.neighbours[a as usize..b as usize],
            _ => &[],
        }
    }
}

#[cfg(test)]
mod tests;
