//! Contacts between sections (paper §5: the medial balls as colliders).
//!
//! The skeleton gives every surface vertex `i` a medial ball, centre `p_i − d_i n_i` and
//! radius `d_i`, and their union is the inside. A ball moves rigidly with its vertex's
//! section. After the step's constraint (stage 4), every mass point of one section is put
//! back out of the balls of the other sections (stage 4c):
//!
//! * **Which balls.** Those [`balls::thin`] keeps: most balls are nearly inside a bigger
//!   one of the same section.
//! * **Which pairs.** A point yields to the balls of sections nearer the root (an arm to
//!   the body, a finger to the palm; of two at one depth, the later), never to its own
//!   section's, and never to a ball of its own joint's flesh that it was a neighbour of at
//!   rest ([`balls::neighbours`], `Joints::joint_flesh`; `ignore`): at a joint the two
//!   sides touch at rest, and the band holds the fold. Parts that merely rest near each other (an arm
//!   hanging by the body) collide; a point that lay inside a ball at rest (the balls
//!   reach a little past a crevice's surface) is kept no deeper than it lay.
//! * **Soft flesh** (`flesh` > 0, a share of a ball's radius): the point sinks into the
//!   balls it yields to by that share of their radii, and, the other way round, a point
//!   of a section nearer the root is pushed in by the balls of the parts pressed into it,
//!   grown by the same share (the pressing part bulges around its balls as it squashes):
//!   an arm dents a belly instead of squashing against it. Every ball is then posed and
//!   gridded, and every tile may be tested.
//! * **Broad phase.** The posed balls go into uniform grids (one for the balls points
//!   yield to, one for those that dent soft flesh; each rebuilt only in steps where one of
//!   its sections moved). A tile of one section keeps the box of its points from its last
//!   test, grown by how far they moved since: while that box meets no cell holding a ball
//!   the tile's section meets, its points are not read. Otherwise a tile whose box meets
//!   no such ball is skipped whole.
//! * **Kept lists** (`near`). A tile keeps the balls near its points' box, gathered for
//!   a box a quarter cell larger (or, while balls move, ten of their last step's
//!   motions), and each group of its points the balls of that list that reach the group
//!   anywhere along their step's sweep (less those of the flesh about every point's
//!   joint, `ignore`); each is gathered again when its points' box, grown by how far any
//!   ball moved since (an odometer of the steps' largest motions), leaves the box it was
//!   gathered for. A swinging arm's tiles keep their lists a step or more instead of
//!   gathering every step. A point keeps
//!   its room: how far it may move, in a step where no ball moves, before it can meet one
//!   of its group's balls; a point that stayed within it is not tested, and a tile whose
//!   points have all moved less, since it was last read, than the least room (or way
//!   out of its lists' boxes) any of them had then is not read. In a step where a ball
//!   moves, no room is kept. A settling pose reads few points; what the stage finds is
//!   the same (`tests/collide.rs`).
//! * **Response** (`response`). A point inside a ball goes to its surface (plus the margin, at most a
//!   quarter of the point's own medial radius: `response::MARGIN_SHARE`) along the line from the
//!   centre, but never more than half its shortest edge farther from where its bones hold
//!   it than the step left it (`response::PUSH`): the pose limit keeps the parts apart, and a
//!   contact only fixes what is left at their surfaces. Its motion into the ball is
//!   dropped and its sliding motion keeps `1 − friction` (the floor's friction). It is a
//!   projection, so a limb posed deep into the body squashes against it and nothing gains
//!   energy: no explosion.
//! * **Caught, let go.** A ball does not hold a point whose bones hold it beyond the ball
//!   (its target lies outside it) and more than the point's own medial radius away: the
//!   pose does not press it in, only its way there crossed the ball (a paw's vertex hooked
//!   on the other paw while its neighbours passed), and held there its skin tears. A point
//!   pressed in, or resting on the ball, is held.
//! * **The floor** ([`Floor`], `floor`) is a half-space contact with the same response.
//!   Every point may touch it, so the kernel runs it in its fused pass (stages 3b and 4b);
//!   a point a ball pushed goes through the same code here, and ends above it.
//! * **No tunnelling.** A point tests the segment it moved along in the step, taken in the
//!   frame of each ball (the ball's own motion subtracted): a point that crossed a ball in
//!   one step is put back at the surface where it entered, however fast the drag.
//! * **Sleeping.** A sleeping tile is tested only in a step where a ball that may touch
//!   it moved near its box, and wakes when a contact moves one of its points or lets go
//!   of one it held (that point may lie outside its constraint: it must come back); a settled pose with contacts
//!   settles (the contact puts a point back where it was, so the tile's motion is zero).
//! * **Broad phase** (`grid`): balls by grid cell, one grid per set of balls that move
//!   together.
//! * **Which sections** (`pairs`): a puppet lets the contacts act only between the
//!   sections its pose limit stopped against each other ([`Pairs`]).

mod floor;
mod grid;
mod ignore;
mod near;
mod pairs;
mod response;

pub use floor::{Floor, Up};
pub use pairs::Pairs;

use super::layout::{Layout, Packed};
use crate::geom::balls;
use glam::{Affine3A, DVec3, Vec3, Vec4};
use grid::{key, Set};
use ignore::Rest;
use near::Near;
use rayon::prelude::*;

/// A worker's lists, kept from tile to tile so the stage allocates nothing per tile: the
/// balls near a group of a tile's points.
#[derive(Default)]
struct Buffers {
    group: Vec<u32>,
    /// Where each ball of the tile's list swept ([`Colliders::swept`]), side by side
    /// (read once for every group whose list is taken from it).
    spheres: Vec<(Vec4, Vec4)>,
    /// The tile's held flags before the stage.
    was: Vec<bool>,
    /// Per group of the tile's points: its slots, its index and what they share
    /// ([`Colliders::shared`]), read when the tile's list is gathered.
    shares: Vec<Share>,
}

/// A group of a tile's points as [`Colliders::ignored_by_all`] reads it: its slots, its
/// index among every tile's groups, and the joint section and joint they share.
type Share = (std::ops::Range<usize>, usize, (Option<u16>, Option<u16>));

/// A tile the contact stage moved a point of, or let go of one.
#[derive(Clone, Copy, Debug)]
pub struct Touched {
    /// The tile.
    pub tile: usize,
    /// The largest squared distance a point of it moved in the whole step, when a
    /// contact moved one.
    pub motion: Option<f32>,
    /// A point it held is held no more.
    pub released: bool,
}

/// Points tested together against the balls that meet their box.
const GROUP: usize = 8;

/// The balls of a puppet and the broad phase over them.
#[derive(Clone, Debug, Default)]
pub struct Colliders {
    /// The pairs of sections the contacts act between (`None`: every pair).
    pairs: Option<Pairs>,
    /// Per joint section, its rank: a point yields to the balls of sections of lower rank
    /// only (the body's parts nearer the root stay where they are).
    rank: Vec<u32>,
    /// Rest centre, radius, joint section and transform of each ball kept.
    center: Vec<Vec3>,
    radius: Vec<f32>,
    section: Vec<u16>,
    transform: Vec<u16>,
    /// The joint whose flesh each ball's vertex is (0: none), and each slot's; with
    /// `everywhere`, every pair near at rest counts as a joint's flesh (no joints given).
    joint: Vec<u16>,
    slot_joint: Vec<u16>,
    everywhere: bool,
    /// The joint section and skeletal distance of each slot, and the section of each tile
    /// when it has only one.
    slot_section: Vec<u16>,
    slot_radius: Vec<f32>,
    /// Per slot, its shortest rest edge: a contact moves a point at most a share of it
    /// (`response::PUSH`) farther from where its bones hold it than the step left it. The pose limit keeps
    /// the parts apart, and a contact fixes what is left at their surfaces; one that
    /// pulled a point farther (a cow's tail pressed 5° into its rump pulled a vertex of
    /// its band two edges off) tore the skin between it and its neighbours (3.24×).
    slot_edge: Vec<f32>,
    /// Per group of points (each tile's groups in turn, [`GROUP`] slots each), where its
    /// slots lie at rest ([`Rest`]).
    group_rest: Vec<Rest>,
    /// Per tile: a point of it yields to some ball (a tile of the root has none to yield
    /// to, and is skipped, unless the flesh gives).
    tile_yields: Vec<bool>,
    /// The lowest and highest rank of a section with balls, and with points.
    ranks: (u32, u32),
    /// The flesh's give the sets and grids were built for: a ball reaches `1 + flesh` of
    /// its radius, and with any give every ball may dent a point.
    flesh: f32,
    /// Per joint section, the box of its posed needed balls' reach (empty: none), and
    /// whether they moved in this step.
    boxes: Vec<(Vec3, Vec3)>,
    moving: Vec<bool>,
    /// Per tile, the box of its points when it was last tested (a sleeping tile's points
    /// stay there): a sleeping tile far from every ball that moved is not read.
    tile_box: Vec<Option<(Vec3, Vec3)>>,
    tile_section: Vec<Option<u16>>,
    /// Per tile, its kept list of the balls near it ([`Near`]).
    near: Vec<Near>,
    /// Counts the times the balls were posed from scratch or their reach or the margin
    /// changed: a list kept in another generation is gathered again.
    generation: u32,
    /// The margin the kept lists were gathered with.
    margin: f32,
    /// The balls some point may meet, each set posed and gridded on its own (see
    /// [`Colliders::choose`]): a set whose sections did not move keeps its grid.
    sets: Vec<Set>,
    /// The centres as posed at the last and at this step.
    posed: Vec<Vec3>,
    before: Vec<Vec3>,
    /// Grid cell size.
    cell: f32,
    /// How far the balls that moved most moved in the last step, and those motions
    /// summed over every step (an odometer: a kept list reads how far a ball may have
    /// come since it was gathered, [`near::List::drift`]).
    motion: f32,
    travelled: f64,
    /// Per slot: a ball holds it (set when a step moves it out of one, kept while its
    /// tile sleeps).
    held: Vec<bool>,
    /// The grid is out of date (the first step, or a section moved).
    stale: bool,
    /// Smallest radius kept (the sweep's threshold).
    smallest: f32,
}

/// Whether a ball that swept `(centre, half)` ([`Colliders::swept`]) reaches into the box
/// `lo..hi` (whose `w` spans everything) anywhere along its sweep: the box of its centre's
/// sweep, rounded by its reach, meets the box (a ball that did not move: its sphere).
fn touches((centre, half): (Vec4, Vec4), lo: Vec4, hi: Vec4) -> bool {
    let gap = (lo - (centre + half))
        .max((centre - half) - hi)
        .max(Vec4::ZERO);
    gap.length_squared() <= centre.w * centre.w
}

/// What the contact stage needs of the step.
pub struct Stage<'a> {
    /// The layout (slot order, rest positions, sections).
    pub layout: &'a Layout,
    /// Each section's transform this step.
    pub transforms: &'a [Affine3A],
    /// Which sections' transforms changed this step.
    pub changed: &'a [bool],
    /// Margin kept between a point and a foreign ball (mesh units).
    pub margin: f32,
    /// Share of sliding motion a touching point keeps.
    pub keep: f32,
    /// How far the flesh of a part nearer the root gives under a part pressed into it,
    /// as a share of its balls' radii (0: hard, as the medial balls are).
    pub flesh: f32,
    /// Per tile, the largest squared distance a point of it moved in this step's
    /// integration (awake tiles).
    pub tile_motion: &'a [f32],
    /// The floor, when there is one: a point a ball pushed is then held above it (the
    /// floor wins, as in the kernel).
    pub floor: Option<Floor>,
}

impl Colliders {
    /// The balls of `centers`/`radii` (one per vertex, in vertex order), each in its
    /// vertex's joint section (`section_of`) and moved by its transform (`transform_of`),
    /// thinned ([`balls::thin`]). [`Colliders::bind`] gives it the slots.
    pub fn new(
        centers: &[Vec3],
        radii: &[f32],
        section_of: &[u16],
        transform_of: &[u16],
        flesh: &[u16],
    ) -> Colliders {
        let group = |i: usize| section_of.get(i).copied().unwrap_or(0);
        let mut out = Colliders {
            stale: true,
            ..Colliders::default()
        };
        let wide: Vec<DVec3> = centers.iter().map(|c| c.as_dvec3()).collect();
        let radii64: Vec<f64> = radii.iter().map(|&r| f64::from(r)).collect();
        for i in balls::thin(&wide, &radii64, section_of) {
            out.center.push(centers[i]);
            out.radius.push(radii[i]);
            out.section.push(group(i));
            out.transform
                .push(transform_of.get(i).copied().unwrap_or(0));
            out.joint.push(flesh.get(i).copied().unwrap_or(0));
        }
        if out.is_empty() {
            return out;
        }
        out.smallest = out.radius.iter().copied().fold(f32::INFINITY, f32::min);
        let kept: Vec<f64> = out.radius.iter().map(|&r| f64::from(r)).collect();
        out.cell = balls::cell(&kept) as f32;
        out.posed = out.center.clone();
        out.before = out.center.clone();
        out
    }

    /// Takes the slots of `layout`, whose vertices are in the joint sections `section_of`
    /// (vertex order), and each section's rank (a point yields to the balls of lower rank;
    /// missing ranks: the section's index).
    pub fn bind(
        &mut self,
        layout: &Layout,
        section_of: &[u16],
        rank: &[u32],
        radii: &[f32],
        flesh: &[u16],
    ) {
        self.everywhere = flesh.is_empty();
        self.slot_joint = layout
            .order
            .iter()
            .map(|&v| flesh.get(v as usize).copied().unwrap_or(0))
            .collect();
        self.slot_edge = (0..layout.len())
            .map(|k| {
                let r = layout.slots.rest.get(k);
                let (a, b) = (layout.start[k] as usize, layout.start[k + 1] as usize);
                layout.edges[a..b]
                    .iter()
                    .map(|e| layout.slots.rest.get(e.neighbour as usize).distance(r))
                    .filter(|&d| d > 0.0)
                    .fold(f32::INFINITY, f32::min)
            })
            .collect();
        self.slot_radius = layout
            .order
            .iter()
            .map(|&v| radii.get(v as usize).copied().unwrap_or(0.0))
            .collect();
        self.group_rest = ignore::rest_of_groups(layout, &self.slot_radius);
        let sections = section_of
            .iter()
            .map(|&s| usize::from(s) + 1)
            .max()
            .unwrap_or(1);
        self.rank = (0..sections)
            .map(|s| rank.get(s).copied().unwrap_or(s as u32))
            .collect();
        let group = |v: u32| section_of.get(v as usize).copied().unwrap_or(0);
        self.slot_section = layout.order.iter().map(|&v| group(v)).collect();
        let lowest = self
            .section
            .iter()
            .map(|&s| self.rank_of(s))
            .min()
            .unwrap_or(u32::MAX);
        let highest = self
            .slot_section
            .iter()
            .map(|&s| self.rank_of(s))
            .max()
            .unwrap_or(0);
        self.ranks = (lowest, highest);
        self.tile_section = (0..layout.tiles())
            .map(|t| {
                let mut r = layout.tile_range(t);
                let first = self.slot_section[r.start];
                r.all(|k| self.slot_section[k] == first).then_some(first)
            })
            .collect();
        self.choose(layout);
    }

    /// The balls some point may meet and the tiles that test any: the balls of sections
    /// below the highest-ranked section with points (they are yielded to) and the tiles
    /// with a point above the lowest-ranked section with balls; with soft flesh also, as a
    /// second set, the highest-ranked section's balls (they dent what lies below), and
    /// every tile. The sets do not share a ball: the body's balls stay still
    /// while a limb swings, and their grid is kept while the limb's is built again.
    fn choose(&mut self, layout: &Layout) {
        let (lowest, highest) = self.ranks;
        let soft = self.flesh > 0.0;
        let transforms = self
            .transform
            .iter()
            .map(|&t| usize::from(t) + 1)
            .max()
            .unwrap_or(0);
        let set = |keep: &dyn Fn(u32) -> bool| {
            let balls: Vec<u32> = (0..self.len() as u32)
                .filter(|&b| keep(self.rank_of(self.section[b as usize])))
                .collect();
            let mut moves = vec![false; transforms];
            for &b in &balls {
                moves[usize::from(self.transform[b as usize])] = true;
            }
            let big = balls
                .iter()
                .copied()
                .filter(|&b| self.radius[b as usize] > 2.0 * self.cell)
                .collect();
            Set::new(balls, moves, big)
        };
        let mut sets = vec![set(&|r| r < highest)];
        if soft {
            sets.push(set(&|r| r >= highest && r > lowest));
        }
        self.sets = sets;
        self.tile_yields = (0..layout.tiles())
            .map(|t| {
                soft || layout
                    .tile_range(t)
                    .any(|k| self.rank_of(self.slot_section[k]) > lowest)
            })
            .collect();
        self.stale = true;
    }

    /// Per slot: a ball holds it (the last step that tested it moved it out of one).
    pub fn held(&self) -> &[bool] {
        &self.held
    }

    /// Lets the contacts act between `pairs` of sections only (`None`: every pair). What
    /// the tiles kept is gathered again.
    pub fn set_pairs(&mut self, pairs: Option<Pairs>) {
        if self.pairs != pairs {
            self.pairs = pairs;
            self.forget_lists();
        }
    }

    /// Forgets the kept lists of the balls near each tile (each is gathered again).
    pub fn forget_lists(&mut self) {
        self.generation = self.generation.wrapping_add(1);
    }

    /// Forgets the contacts (a step without collision).
    pub fn clear(&mut self) {
        self.held.fill(false);
        // (The points move unwatched: what each tile kept of them is forgotten. So do the
        // balls: each is posed again, and listed again, at the next resolve.)
        self.forget_lists();
        self.stale = true;
    }

    /// Number of balls kept.
    pub fn len(&self) -> usize {
        self.center.len()
    }

    /// True when there is none.
    pub fn is_empty(&self) -> bool {
        self.center.is_empty()
    }

    /// Stage 4c over the tiles: awake ones, and sleeping ones in a step where a section
    /// moved. Moves points of `cur` out of foreign balls, sets their `prev` (velocity) by
    /// the response, and returns the tiles it moved a point of, each with the largest
    /// squared distance a point of it moved in the whole step (to be woken when that is
    /// motion), and those where it let go of a point it held (to be woken: the point
    /// may lie outside its constraint, and must come back).
    pub fn resolve(
        &mut self,
        stage: &Stage,
        cur: &mut Packed,
        prev: &mut Packed,
        awake: &[bool],
    ) -> Vec<Touched> {
        let layout = stage.layout;
        if stage.flesh != self.flesh {
            let was_soft = self.flesh > 0.0;
            self.flesh = stage.flesh;
            self.stale = true;
            if was_soft != (self.flesh > 0.0) {
                self.choose(layout);
            }
        }
        self.held.resize(layout.len(), false);
        if stage.margin != self.margin {
            self.margin = stage.margin;
            self.generation = self.generation.wrapping_add(1);
        }
        // A ball some point meets moved: sleeping tiles are tested too.
        let moved = self.pose(stage);
        if self.is_empty() {
            return Vec::new();
        }
        let tile = layout.tile;
        self.tile_box.resize(layout.tiles(), None);
        self.near.resize_with(layout.tiles(), Near::default);
        let mut held = std::mem::take(&mut self.held);
        let mut boxes = std::mem::take(&mut self.tile_box);
        let mut near = std::mem::take(&mut self.near);
        let this = &*self;
        let touched: Vec<Touched> = cur
            .0
            .par_chunks_mut(tile)
            .zip(prev.0.par_chunks_mut(tile))
            .zip(held.par_chunks_mut(tile))
            .zip(boxes.par_iter_mut().zip(near.par_iter_mut()))
            .enumerate()
            .map_init(
                Buffers::default,
                |buffers, (t, (((cur, prev), held), (bx, near)))| {
                    let awake = awake.get(t).copied().unwrap_or(true);
                    if !this.tile_yields.get(t).copied().unwrap_or(true) || (!awake && !moved) {
                        return None;
                    }
                    if awake {
                        let m = stage.tile_motion.get(t).map_or(f32::INFINITY, |m| m.sqrt());
                        *bx = bx.map(|(lo, hi)| (lo - m, hi + m));
                        // Every point within its room, among balls that did not move: none
                        // meets one, and none was held (a held point has no room).
                        if !moved && near.within(this.generation, m) {
                            return None;
                        }
                    }
                    // (Only a tile that holds a point can let one go.)
                    let had = held.contains(&true);
                    if had {
                        buffers.was.clear();
                        buffers.was.extend_from_slice(held);
                    }
                    let motion = if this.may_meet(stage, t, *bx, !awake) {
                        this.tile(stage, t, cur, prev, held, (bx, near), buffers)
                    } else {
                        held.fill(false);
                        // Not tested: a ball that moved may come near its kept box unseen.
                        if moved {
                            near.forget();
                        }
                        None
                    };
                    let released =
                        had && buffers.was.iter().zip(held.iter()).any(|(&w, &h)| w && !h);
                    (motion.is_some() || released).then_some(Touched {
                        tile: t,
                        motion,
                        released,
                    })
                },
            )
            .flatten()
            .collect();
        self.held = held;
        self.tile_box = boxes;
        self.near = near;
        touched
    }

    /// Whether a ball (one that moved in this step, when `moved`) may meet tile `t`, whose
    /// points lie in `bx` (unknown: it may), without reading its points: most of the body
    /// lies far from the parts that touch it.
    fn may_meet(&self, stage: &Stage, t: usize, bx: Option<(Vec3, Vec3)>, moved: bool) -> bool {
        let (Some(own), Some((lo, hi))) = (self.tile_section[t], bx) else {
            return true;
        };
        let grow = stage.margin + self.motion;
        let (lo, hi) = (lo - grow, hi + grow);
        let boxed = self
            .boxes
            .iter()
            .zip(&self.moving)
            .enumerate()
            .any(|(s, (&(a, b), &m))| {
                (m || !moved)
                    && self.meets(own, s as u16).is_some()
                    && a.cmple(hi).all()
                    && lo.cmple(b).all()
            });
        if !boxed {
            return false;
        }
        // Then by the grids' cells (a big box: it may).
        let (a, b) = (key(lo, self.cell), key(hi, self.cell));
        if grid::cells(a, b) > 64 {
            return true;
        }
        let hit = |ball: u32| {
            let k = ball as usize;
            (!moved || self.moving.get(usize::from(self.section[k])) == Some(&true))
                && self.meets(own, self.section[k]).is_some()
        };
        self.sets.iter().any(|set| set.any(a, b, hit))
    }

    /// Stage 4c on tile `t`, whose points, previous points and held flags are `cur`,
    /// `prev` and `held`: the largest squared distance a point of it moved in the step,
    /// when a contact moved one. Keeps the box of its points in `bx`, and the balls near
    /// them in `near`.
    #[allow(clippy::too_many_arguments)]
    fn tile(
        &self,
        stage: &Stage,
        t: usize,
        cur: &mut [[f32; 4]],
        prev: &mut [[f32; 4]],
        held: &mut [bool],
        (bx, near): (&mut Option<(Vec3, Vec3)>, &mut Near),
        buffers: &mut Buffers,
    ) -> Option<f32> {
        let get = |a: &[[f32; 4]], i: usize| Vec3::new(a[i][0], a[i][1], a[i][2]);
        let start = stage.layout.tile_range(t).start;
        let n = cur.len();
        let reach = self.smallest * 0.5;
        // The tile's box, with where its points were, grown by the margin and by how far
        // the balls moved (a ball that swept through it counts).
        let (mut lo, mut hi) = (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN));
        let mut fastest = 0.0f32;
        for i in 0..n {
            let (x, p) = (get(cur, i), get(prev, i));
            lo = lo.min(x.min(p));
            hi = hi.max(x.max(p));
            fastest = fastest.max((x - p).length_squared());
        }
        *bx = Some((lo, hi));
        let sweep = fastest.sqrt() > reach || self.motion > reach;
        let grow = stage.margin + if sweep { self.motion } else { 0.0 };
        let (lo, hi) = (lo - grow, hi + grow);
        let (group, spheres) = (&mut buffers.group, &mut buffers.spheres);
        // (Filled for this call's list when a group first needs it.)
        spheres.clear();
        // A list is kept while the points' box, grown by how far a ball may have moved
        // since it was gathered, lies within the box it was gathered for; gathered, with
        // a skin that lasts a few steps of the balls' present motion.
        let skin = (near::SKIN * self.cell).max(near::STEPS * self.motion);
        let since = self.travelled - f64::from(self.motion);
        let drift = near.tile.drift(self.travelled);
        let kept = near.tile.covers(self.generation, lo - drift, hi + drift);
        if !kept {
            let (lo, hi) = (lo - skin, hi + skin);
            self.near(t, lo, hi, &mut near.tile.balls);
            // A ball every group of the tile ignores (the flesh about their joint) is
            // left out here: each group would leave it out of its own list, gathered
            // again at every step the tile moves (a head turning beside its neck's flesh).
            let shares = &mut buffers.shares;
            shares.clear();
            shares.extend((0..n).step_by(GROUP).map(|i0| self.share(stage, t, n, i0)));
            near.ignored
                .retain(self.generation, &mut near.tile.balls, |b| {
                    shares.iter().all(|(slots, index, shared)| {
                        self.ignored_by_all(stage, (slots, *index), *shared, b as usize)
                    })
                });
            near.tile.keep(self.generation, lo, hi, since);
            near.gathered = near.gathered.wrapping_add(1);
        }
        if near.tile.balls.is_empty() {
            held.fill(false);
            let (a, b) = near.tile.bounds();
            let drift = near.tile.drift(self.travelled);
            near.read((lo - drift - a).min(b - hi - drift).min_element());
            return None;
        }
        let (tile_lo, tile_hi) = near.tile.bounds();
        let still = self.motion == 0.0;
        near.groups.resize_with(n.div_ceil(GROUP), Default::default);
        near.room.resize(n, (Vec3::ZERO, -1.0));
        let mut any = false;
        let mut motion = 0.0f32;
        let mut slack = f32::INFINITY;
        for (i0, kept) in (0..n).step_by(GROUP).zip(near.groups.iter_mut()) {
            let i1 = (i0 + GROUP).min(n);
            // The balls that meet this group of points' box.
            let (mut lo, mut hi) = (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN));
            for i in i0..i1 {
                let (x, p) = (get(cur, i), get(prev, i));
                lo = lo.min(x.min(p));
                hi = hi.max(x.max(p));
            }
            // (Grown by the margin only: each ball's own sweep counts, not the fastest.)
            let (lo, hi) = (lo - stage.margin, hi + stage.margin);
            let meets = |b: u32, lo: Vec3, hi: Vec3| {
                touches(
                    self.swept(b as usize),
                    lo.extend(f32::MIN),
                    hi.extend(f32::MAX),
                )
            };
            let drift = kept.drift(self.travelled);
            if !kept.covers(near.gathered, lo - drift, hi + drift) {
                // Within the tile's box, so that the tile's list holds all it meets; a
                // ball every point of the group ignores (the flesh about their joint) is
                // left out.
                let grown = skin + self.motion;
                let (lo, hi) = ((lo - grown).max(tile_lo), (hi + grown).min(tile_hi));
                let (slots, index, shared) = self.share(stage, t, n, i0);
                if spheres.len() != near.tile.balls.len() {
                    spheres.clear();
                    spheres.extend(near.tile.balls.iter().map(|&b| self.swept(b as usize)));
                }
                let (lo4, hi4) = (lo.extend(f32::MIN), hi.extend(f32::MAX));
                kept.balls.clear();
                kept.balls.extend(
                    near.tile
                        .balls
                        .iter()
                        .zip(spheres.iter())
                        .filter(|(_, &s)| touches(s, lo4, hi4))
                        .map(|(&b, _)| b)
                        .filter(|&b| {
                            !self.ignored_by_all(stage, (&slots, index), shared, b as usize)
                        }),
                );
                kept.keep(near.gathered, lo, hi, since);
                for room in &mut near.room[i0..i1] {
                    room.1 = -1.0;
                }
            }
            // (How far the group's points may go before they leave its list's box.)
            let (a, b) = kept.bounds();
            let drift = kept.drift(self.travelled);
            slack = slack.min((lo - drift - a).min(b - hi - drift).min_element());
            // Gathered when a point needs it.
            let mut filtered = false;
            for i in i0..i1 {
                let (x, p) = (get(cur, i), get(prev, i));
                let (anchor, room) = near.room[i];
                // A point that stayed (from where it was, when it is swept) within its room
                // among balls that did not move meets none.
                let within = |y: Vec3| y.distance_squared(anchor) < room * room;
                let moved = if kept.balls.is_empty() {
                    None
                } else if still && room > 0.0 && within(x) && (!sweep || within(p)) {
                    slack = slack.min(room - x.distance(anchor));
                    None
                } else {
                    if !filtered {
                        group.clear();
                        group.extend(kept.balls.iter().copied().filter(|&b| meets(b, lo, hi)));
                        filtered = true;
                    }
                    let moved = if group.is_empty() {
                        None
                    } else {
                        self.point(stage, start + i, group, sweep, x, p)
                    };
                    // (Kept for a step where no ball moves.)
                    near.room[i] = match moved {
                        None if still => (x, self.room(stage, start + i, &kept.balls, x)),
                        _ => (x, -1.0),
                    };
                    slack = slack.min(near.room[i].1);
                    moved
                };
                held[i] = moved.is_some();
                match moved {
                    Some((x, v)) => {
                        any = true;
                        motion = motion.max(x.distance_squared(p));
                        cur[i] = [x.x, x.y, x.z, 0.0];
                        let q = x - v;
                        prev[i] = [q.x, q.y, q.z, 0.0];
                    }
                    // The step's own motion (the kernel left where it was in `prev`).
                    None => motion = motion.max(x.distance_squared(p)),
                }
            }
        }
        near.read(slack);
        if any {
            let (lo, hi) = (0..n).fold(
                (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)),
                |(lo, hi), i| (lo.min(get(cur, i)), hi.max(get(cur, i))),
            );
            *bx = Some((lo, hi));
        }
        any.then_some(motion)
    }

    /// The group of tile `t`'s points (`n` of them) that starts at its `i0`-th ([`Share`]).
    fn share(&self, stage: &Stage, t: usize, n: usize, i0: usize) -> Share {
        let start = stage.layout.tile_range(t).start;
        let slots = start + i0..start + (i0 + GROUP).min(n);
        let index = t * stage.layout.tile.div_ceil(GROUP) + i0 / GROUP;
        let shared = self.shared(slots.clone());
        (slots, index, shared)
    }

    /// Where ball `b` went in this step: the box its centre swept, as its centre and half
    /// extents, with its reach as the centre's `w` (see [`touches`]).
    fn swept(&self, b: usize) -> (Vec4, Vec4) {
        let (a, c) = (self.before[b], self.posed[b]);
        (
            ((a + c) * 0.5).extend(self.reach(b)),
            ((c - a).abs() * 0.5).extend(0.0),
        )
    }

    /// Poses each set of balls one of whose transforms changed (all of them when stale)
    /// and builds its grid again; then the sections' boxes and which moved. Returns
    /// whether a ball moved.
    fn pose(&mut self, stage: &Stage) -> bool {
        let stale = std::mem::take(&mut self.stale);
        if stale {
            self.generation = self.generation.wrapping_add(1);
        }
        let mut sets = std::mem::take(&mut self.sets);
        let (mut moved, mut motion) = (false, 0.0f32);
        self.moving.clear();
        self.moving.resize(self.rank.len().max(1), false);
        for set in &mut sets {
            let changed = stale
                || stage
                    .changed
                    .iter()
                    .zip(&set.transforms)
                    .any(|(&c, &n)| c && n);
            if !changed {
                // Still: where it was is where it is.
                if std::mem::take(&mut set.moved) {
                    for &b in &set.balls {
                        self.before[b as usize] = self.posed[b as usize];
                    }
                }
                continue;
            }
            moved = true;
            set.moved = true;
            if stale {
                set.clear();
            }
            for i in 0..set.balls.len() {
                let b = set.balls[i] as usize;
                let turned = stage.changed.get(usize::from(self.transform[b])) == Some(&true);
                if !stale && !turned {
                    // Its transform still: where it was is where it is, and its cells stay.
                    self.before[b] = self.posed[b];
                    continue;
                }
                let t = stage
                    .transforms
                    .get(self.transform[b] as usize)
                    .copied()
                    .unwrap_or(Affine3A::IDENTITY);
                let now = t.transform_point3(self.center[b]);
                self.before[b] = if stale { now } else { self.posed[b] };
                self.posed[b] = now;
                motion = motion.max(now.distance(self.before[b]));
                if turned {
                    if let Some(m) = self.moving.get_mut(usize::from(self.section[b])) {
                        *m = true;
                    }
                }
                if self.radius[b] <= 2.0 * self.cell {
                    set.place(i, b as u32, now, self.reach(b), self.cell);
                }
            }
        }
        if moved {
            self.motion = motion;
            self.travelled += f64::from(motion);
            self.boxes.clear();
            self.boxes.resize(
                self.rank.len().max(1),
                (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)),
            );
            for set in &sets {
                for &b in &set.balls {
                    let b = b as usize;
                    let (c, r) = (self.posed[b], self.reach(b));
                    if let Some(bx) = self.boxes.get_mut(usize::from(self.section[b])) {
                        *bx = (bx.0.min(c - r), bx.1.max(c + r));
                    }
                }
            }
        } else {
            self.motion = 0.0;
        }
        self.sets = sets;
        moved
    }

    /// The needed balls that meet the box of tile `t`, each once, into `out` (a tile of
    /// one section: only those it yields to).
    fn near(&self, t: usize, lo: Vec3, hi: Vec3, out: &mut Vec<u32>) {
        let (a, b) = (key(lo, self.cell), key(hi, self.cell));
        let own = self.tile_section[t];
        out.clear();
        // A box spanning a huge part of the grid (a point flung far): every ball.
        let huge = grid::cells(a, b) > 4096;
        for set in &self.sets {
            if huge {
                out.extend_from_slice(&set.balls);
            } else {
                set.gather(a, b, out);
            }
        }
        out.sort_unstable();
        out.dedup();
        out.retain(|&ball| {
            let k = ball as usize;
            let (c, r) = (self.posed[k], self.reach(k));
            own.is_none_or(|s| self.meets(s, self.section[k]).is_some())
                && c.clamp(lo, hi).distance_squared(c) <= r * r
        });
    }

    /// How far the point of slot `k` at `x` may move before it can meet one of `balls`
    /// that do not move (negative: it may meet one now).
    fn room(&self, stage: &Stage, k: usize, balls: &[u32], x: Vec3) -> f32 {
        balls.iter().fold(f32::INFINITY, |room, &b| {
            let b = b as usize;
            let r = self.radius[b] * (1.0 + stage.flesh) + stage.margin;
            // (Short of the surface by a rounding: the point test compares squares.)
            let (r, d2) = (r * 1.0001, x.distance_squared(self.posed[b]));
            // (Farther than the room left: no square root.)
            if d2 >= (room + r) * (room + r) {
                return room;
            }
            let to = d2.sqrt() - r;
            if to < room && !self.ignores(stage, k, b) {
                to
            } else {
                room
            }
        })
    }

    /// How far ball `b` reaches: its radius, grown by the flesh's give (it dents that far).
    fn reach(&self, b: usize) -> f32 {
        self.radius[b] * (1.0 + self.flesh)
    }

    /// A section's rank (its index where none was given).
    fn rank_of(&self, s: u16) -> u32 {
        self.rank
            .get(usize::from(s))
            .copied()
            .unwrap_or(u32::from(s))
    }

    /// Whether a point of section `a` meets the balls of section `b`, and how: `Some(true)`
    /// when it yields to them (`b` is nearer the root), `Some(false)` when they dent its
    /// flesh (soft flesh only, `b` farther from the root).
    fn meets(&self, a: u16, b: u16) -> Option<bool> {
        if let Some(pairs) = &self.pairs {
            if !pairs.has(usize::from(a), usize::from(b)) {
                return None;
            }
        }
        let yields = self.rank_of(a) > self.rank_of(b);
        (a != b && (yields || self.flesh > 0.0)).then_some(yields)
    }
}
