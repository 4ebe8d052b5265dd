//! Joints suggested from the skeleton: cuts where the protrusions of a mesh (limbs, neck,
//! tail, ears, fingers) leave the body and where they narrow, organised as a section tree
//! (shoulder → elbow → wrist).
//!
//! 1. **The body and a distance from it.** Two sweeps of shortest paths find two far tips;
//!    of the points on the middle three fifths of the path between them at least `THICK`
//!    of the thickest there, the root is the one nearest the centroid of the enclosed
//!    volume (the body the limbs hang from, not a big head on it). The body's core is every
//!    vertex whose skeletal point lies in the root's medial ball, grown through vertices
//!    nearly as thick (`CORE`) within a few radii of it (`CORE_REACH`: a long body is all
//!    core, fingers as thick as the palm are not). `g(v)` is the shortest path from the
//!    core to `v` over the surface, each edge counted in units of the local skeletal
//!    distance: one unit is about one local radius, so a fat body is crossed in a few units
//!    and limbs stand out, and the level sets of `g` are close to cross-sections of a limb.
//!    When a limb of that root has more tips than all the root's other limbs and is as
//!    thick inside (`BODY_TIPS`, `BODY_THICK`: a body hanging by its neck from a head
//!    bigger than it, with the arms and legs), the tree is built again from that limb's
//!    thickest point, and the head turns at the neck cut the other way round. A mesh with
//!    a flat base (a bust) is rooted at its thickest point within `STANDING` of its height
//!    above the base: the head on it turns at its neck.
//! 2. **Protrusions.** The vertices are added from the largest `g` down, joined by mesh
//!    edges (a union-find sweep: the join tree of `g`). Every local maximum (a tip) starts a
//!    component; where two or more reaching `ELONGATED` radii meet (a fork) a new segment
//!    starts; shorter ones (bumps) fold into the longest.
//! 3. **Cuts.** A segment that hangs from a fork, is narrower than the trunk below it
//!    (`THINNER`, by the rings' sizes), longer than wide, and sticks out of the trunk's
//!    thickest medial ball by `PROTRUDES` of its size and `SMALL` of the mesh (an ear on a
//!    head, a face, a nose, an eye do not: they are bumps, and get no cuts at all) is a
//!    *limb*: it is cut at its base, and turns about a point half its radius in from the
//!    cut; once named (step 5), a shoulder's or a hip's cut moves toward the body while
//!    the mesh's slice around it stays within `ROUND` of the limb's width (up to where it
//!    meets the trunk: thighs that touch below the crotch tilt the rings of `g`), and it
//!    turns a whole radius in from there (`SOCKET`: the ball of a hip sits above the
//!    crotch, inside the trunk). A part growing from the core that
//!    forks within `HEAD` radii (a pelvis both legs hang from) is body. A part as wide as
//!    the body with two or more limbs of its own, each at most `SLENDER` of its width or
//!    of its base's, whichever is wider (a head with ears and horns, a hand with fingers,
//!    an ant's head with antennae thicker than its neck), is cut at its base too (`HEAD`),
//!    if that base is a clear narrowing (`NARROW`: a neck, not a waist as wide as the
//!    hips). One with no limbs of its own, as thick as `BODY_THICK` of the body (an ant's
//!    abdomen), is cut at the narrowest slice across the line from the core to it, when
//!    that is a clear narrowing (a waist).
//!    Inside a part, cuts go where the medial radius or the ring's size narrows below the
//!    widest within three radii before it and widens again soon (`DIP`: an elbow, a knee, a
//!    neck, not the wobble of a coarse mesh's rings); where the axis, over three radii either side, bends (`BEND`:
//!    a bent knee, an ankle, a hock; not within those three radii of another cut; a short
//!    limb ending at an extremity over as much as it has, down to 1.5 radii); where a
//!    limb widens into an extremity that limbs grow from (a wrist); along a digit (a tip
//!    among four or more of one extremity, or of a root whose tips are more than `SLENDER`
//!    of its thickness: a palm, not a body) at 45 % and 72 % of its length; and halfway, in
//!    metres, along a limb's first stretch, from the ball of its root (`SOCKET` of a radius
//!    in from its base) to its first joint, when that is longer than `LONG` radii (an elbow or a knee that neither narrows nor bends; a shin
//!    between a knee and an ankle already found is not cut again; nor is a flat part,
//!    `FLAT`: a big thin ear's length in radii of its thickness says nothing).
//!    The core itself is cut only at a clear narrowing along its long axis (`NARROW`): a
//!    head as thick as the body it sits on (a teddy's) is part of the core, and turns at
//!    its neck, with what hangs from it past the neck.
//! 4. **Sections.** Each cut is a connected plane through the ring's centre, across the
//!    limb's axis there, its pivot on the axis; cuts apply parent-first, and one that would
//!    leave a section of fewer than `SMALLEST` of the vertices, or whose plane takes more
//!    than twice what lies past it in the join tree (it slipped past the limb into the
//!    body), is dropped; a limb's root plane that slips so first tries the mirror image of
//!    its partner's on the other side (an arm hanging closer to the body on one side).
//! 5. **Anatomy.** A mirror plane, up (given, or found from how the limbs hang, or from a
//!    bust's flat base), front and
//!    left, and names by role: `neck`, `head`, `arm.L`, `forearm.L`, `hand.L`, `thumb.L`…
//!    (a hand not cut at its wrist: of two parts at an arm's end, the one carrying
//!    fingers, beside a bare one, its thumb; an arm's or a leg's one part with none of its
//!    own, at most `SLENDER` as thick, its `thumb` or `toe`),
//!    `leg.R`, `shin.R`, `foot.R`, `tail` (`abdomen` when it ends as thick as the head),
//!    `ear.L` (on a head, or, on a biped whose head is not cut from its body, a raised
//!    part above its side's arm and smaller, or a lone pair not hanging down, short, from
//!    above the centre: a head modelled on its own, whose face is then no neck), a bust's
//!    part holding its top is its `neck`, `horn.L` (of two parts on a head's side,
//!    the one pointing most up),
//!    `antenna.L` (a head's part long and round: `ANTENNA`), `jaw`; a cut no role fits keeps its
//!    place in the tree (`joint 2.1`). A head's one short part on the mirror plane (a
//!    snout, a muzzle, a nose: `SNOUT`) is the head's end, and its cut is taken back. See `anatomy`. A left and a right cut that nearly mirror
//!    each other (`PAIRED`) are made to mirror each other exactly: at their mean, or, where
//!    that leaves a side empty, one as the other's image; a pair that cannot keeps its
//!    places, and the others are still mirrored. A biped (arms hanging well above its
//!    legs) whose head nothing cuts, a head as wide as the chest it sits on (Homer's), is
//!    cut across up at the top of its shoulders, when what lies above is at least as tall
//!    as the slice there is wide and no taller than the character below it; the ears on
//!    it turn with it (`head`).
//!
//! 6. **Seams.** Once the cuts apply to the puppet (its sections whole over the surface),
//!    a section that meets one it neither hangs from, nor carries, nor sits beside over
//!    `FOREIGN` of its seam loses its cut (`seams`): the two would turn apart with no band
//!    between them. A section that meets its parent along two loops (`TWICE`: a statue's
//!    hind legs standing on its pedestal, met at the hips and across the pedestal) loses
//!    its cut too: turned about one, it tears the other. Then the joints are turned through
//!    `TRIALS` random poses; a section
//!    whose skin tears there (an edge past `TEAR` times its length where the bones hold
//!    it: a body standing on a pedestal by four legs, turned about one) loses its cut.
//!
//! `puppet bench suggest` scores it against the labelled characters of
//! `tests/data/characters` (`labels`).
//!
//! # Where things are
//! * `rules`: the thresholds named above (`CORE`, `THINNER`, …), in one place;
//! * `graph`: the mesh's edges in local radii, shortest paths;
//! * `union_find`: the sweep's sets, a slice's loops;
//! * `tree`: the root, the core, `g` and the join tree (steps 1–2);
//! * `trunk`: the cut across the core at a neck (step 3);
//! * `cuts`: which segments are limbs and where they are cut (step 3);
//! * `sections`: numbering and applying the cuts (step 4);
//! * `slice`: the mesh's slice by a plane, how far a shoulder's or a hip's cut moves in;
//! * `frame`: the mirror plane, up, front and left (step 5, first half);
//! * `anatomy`: the names by role within that frame (step 5, second half);
//! * `head`: a biped's head with no neck to cut at turns at the top of its shoulders;
//! * `characters`: two or more characters in one file, each suggested on its own;
//! * `labels`: a labelled character's joints, and a suggestion's score against them;
//! * `seams`: the cuts applied, a section meeting one it is not related to, or its parent
//!   in two places, or tearing in random poses, loses its cut (step 6).

mod anatomy;
pub mod characters;
mod cuts;
mod frame;
mod graph;
mod head;
pub mod labels;
mod rules;
pub mod seams;
mod sections;
mod slice;
mod tree;
mod trunk;
mod union_find;

#[cfg(test)]
mod tests;

pub use anatomy::other_side;
pub use frame::{image, mirror_plane, Frame, Up};
pub use sections::suggest;
