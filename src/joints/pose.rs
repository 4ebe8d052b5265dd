//! Composing a pose down the section tree: `W(s) = W(parent) · T(pivot + t) · R · T(−pivot)`
//! (at the end of a band, moved by its [`Band::shift`] too), then the joint bands'
//! levels and contacts.

use super::band::{axis_angle, Band, BULGE, LEVELS};
use super::slide::Slide;
use super::{Joints, Local, Section};
use crate::sim::Pose;
use glam::{Affine3A, DAffine3, DMat3, DQuat, DVec3};

impl Joints {
    /// World transform of every section for the given local poses (one per section; missing
    /// entries are at rest), composed from the root down (see module docs).
    pub fn world(&self, local: &[Local]) -> Vec<DAffine3> {
        let mut world = Vec::new();
        self.world_into(local, &mut world);
        world
    }

    /// [`Joints::world`] into existing storage (the sections' turns and slides it reads
    /// in storage of its own; [`Joints::pose_into`] keeps theirs).
    pub fn world_into(&self, local: &[Local], world: &mut Vec<DAffine3>) {
        let (mut turns, mut slides) = (Vec::new(), Vec::new());
        self.world_slid_into(local, world, (&mut turns, &mut slides));
    }

    /// [`Joints::world_into`] with storage for each section's turn and the slide of the
    /// band that ends in it ([`Joints::slides_into`]), which it leaves filled.
    pub(super) fn world_slid_into(
        &self,
        local: &[Local],
        world: &mut Vec<DAffine3>,
        (turns, slides): (&mut Vec<DVec3>, &mut Vec<Slide>),
    ) {
        self.slides_into(local, turns, slides);
        world.clear();
        world.resize(self.sections.len(), DAffine3::IDENTITY);
        for &s in &self.order {
            let own = self.own_motion_slid(s, local, slides[s]);
            world[s] = match self.sections[s].parent {
                Some(p) if self.is_carried(s) => {
                    world[p] * self.carry_with(s, local, |b| slides[b.child]) * own
                }
                Some(p) => world[p] * own,
                None => own,
            };
        }
    }

    /// Whether section `s` rides on a band of one of its parent's other children (see
    /// [`super::band`]: *carried*).
    fn is_carried(&self, s: usize) -> bool {
        self.carried.get(s).is_some_and(|c| !c.is_empty())
    }

    /// The motion, relative to its parent, of the skin section `s` rides on: the bands
    /// that carry it, each at its level, carriers first (the identity for most; see
    /// [`super::band`]: *carried*).
    fn carry(&self, s: usize, local: &[Local]) -> DAffine3 {
        self.carry_with(s, local, |band| self.slide(band, rotation_in(local)))
    }

    /// [`Joints::carry`] with each band's slide from `slide_of`.
    fn carry_with(&self, s: usize, local: &[Local], slide_of: impl Fn(&Band) -> Slide) -> DAffine3 {
        let mut t = DAffine3::IDENTITY;
        for &(k, level) in self.carried.get(s).map_or(&[][..], Vec::as_slice) {
            let Some(band) = self.bands.get(k).and_then(Option::as_ref) else {
                continue;
            };
            let l = local.get(band.child).copied().unwrap_or_default();
            let slide = slide_of(band);
            let child = self.own_motion_slid(band.child, local, slide);
            t *= self.band_motion(band, &l, &child, slide, f64::from(level) / LEVELS as f64);
        }
        t
    }

    /// The frame section `s` turns in, in the pose `local` whose world transforms are
    /// `world`: its parent's world transform, carried as [`Joints::carry`] says (the
    /// identity for the root). Its local pose is relative to this frame.
    ///
    /// # Panics
    /// If `s`'s parent is not a section of `world`.
    pub fn parent_frame(&self, s: usize, world: &[DAffine3], local: &[Local]) -> DAffine3 {
        match self.sections.get(s).and_then(|x| x.parent) {
            Some(p) if self.is_carried(s) => world[p] * self.carry(s, local),
            Some(p) => world[p],
            None => DAffine3::IDENTITY,
        }
    }

    /// The simulation's pose (single precision) for the given local poses.
    pub fn pose(&self, local: &[Local]) -> Pose {
        let mut scratch = PoseScratch::default();
        self.pose_into(local, &mut scratch);
        scratch.pose
    }

    /// The surface where the bones of the pose `local` hold it: each vertex's rest
    /// position moved by its transform, into `now` (one per vertex; a vertex beyond the
    /// rest positions, or with no transform, is left as it is).
    pub fn held_surface(&self, local: &[Local], scratch: &mut PoseScratch, now: &mut [DVec3]) {
        let rest = &self.body.rest;
        let pose = self.pose_into(local, scratch);
        for ((x, r), &t) in now.iter_mut().zip(rest).zip(&self.transform_of) {
            if let Some(m) = pose.transforms.get(usize::from(t)) {
                *x = m.transform_point3(r.as_vec3()).as_dvec3();
            }
        }
    }

    /// [`Joints::pose`] reusing `scratch` (nothing allocated once it has grown): every
    /// section's transform, then every joint band's levels (see [`super::band`]).
    /// The same pose asked for again of the same joints is the one made last.
    pub fn pose_into<'a>(&self, local: &[Local], scratch: &'a mut PoseScratch) -> &'a Pose {
        if scratch.made == Some(self.stamp.0) && scratch.made_of == local {
            return &scratch.pose;
        }
        if scratch.made != Some(self.stamp.0) {
            // Positions another rig's pose left (see `keep_volumes`).
            scratch.positions.clear();
        }
        scratch.made = Some(self.stamp.0);
        scratch.made_of.clear();
        scratch.made_of.extend_from_slice(local);
        let slid = (&mut scratch.turns, &mut scratch.slides);
        self.world_slid_into(local, &mut scratch.world, slid);
        scratch.keep.clear();
        scratch
            .keep
            .resize(self.bands.iter().flatten().count(), [0.0; 4]);
        self.levels_into(local, scratch);
        // Each section's volume measured, and the bands swollen to keep it (`volume`).
        if scratch.keep_volumes {
            scratch.newton.first = true;
            if self.keep_volumes(
                &scratch.world,
                &scratch.pose.transforms,
                &mut scratch.positions,
                &mut scratch.keep,
                &mut scratch.newton,
            ) {
                // The levels as the slides left them, for each step to swell afresh.
                scratch.unswollen.clone_from(&scratch.motions);
                scratch.newton.first = false;
                let steps = scratch.newton_steps;
                for step in 1..=steps {
                    self.keep_into(local, scratch);
                    if step == steps
                        || !self.keep_volumes(
                            &scratch.world,
                            &scratch.pose.transforms,
                            &mut scratch.positions,
                            &mut scratch.keep,
                            &mut scratch.newton,
                        )
                    {
                        break;
                    }
                }
            }
        }
        &scratch.pose
    }

    /// The pose's transforms after the sections' (`scratch.world`, made): each band's
    /// levels with its sides swollen by `scratch.keep`, where bands overlap, contacts,
    /// the skin's mixes.
    fn levels_into(&self, local: &[Local], scratch: &mut PoseScratch) {
        let transforms = &mut scratch.pose.transforms;
        transforms.clear();
        transforms.extend(scratch.world.iter().map(to_f32));
        // Each band's motion at every weight step, relative to its parent (kept for its
        // contacts), and its levels' transforms.
        let motions = &mut scratch.motions;
        motions.clear();
        for (band, &keep) in self.bands.iter().flatten().zip(&scratch.keep) {
            let l = local.get(band.child).copied().unwrap_or_default();
            let parent = scratch.world[band.parent];
            let slide = scratch.slides[band.child];
            let child = self.own_motion_slid(band.child, local, slide);
            let bending = self.bending(band, &l, &child, slide);
            for level in 0..=LEVELS {
                let w = level as f64 / LEVELS as f64;
                let own = band.kept(bending.at(w), keep, w);
                if (1..LEVELS).contains(&level) {
                    transforms.push(to_f32(&(parent * own)));
                }
                motions.push(own);
            }
        }
        self.overlaps_into(local, scratch);
    }

    /// Swells the levels of each band whose swells the last Newton step changed
    /// (`scratch.newton.changed`) by `scratch.keep`, on the motions [`Joints::levels_into`]
    /// made unswollen (`scratch.unswollen`: no band turned again), then makes again what
    /// composes such a band: the blends it is part of and its contacts (the rest read no
    /// swollen motion).
    fn keep_into(&self, local: &[Local], scratch: &mut PoseScratch) {
        let changed = &scratch.newton.changed;
        let mut end = self.sections.len();
        for (b, (band, &keep)) in self.bands.iter().flatten().zip(&scratch.keep).enumerate() {
            end = band.first_level + LEVELS - 1;
            if !changed[b] {
                continue;
            }
            let parent = scratch.world[band.parent];
            for level in 0..=LEVELS {
                let w = level as f64 / LEVELS as f64;
                let k = b * (LEVELS + 1) + level;
                let m = &mut scratch.motions[k];
                *m = band.kept(scratch.unswollen[k], keep, w);
                if (1..LEVELS).contains(&level) {
                    scratch.pose.transforms[band.first_level + level - 1] = to_f32(&(parent * *m));
                }
            }
        }
        let transforms = &mut scratch.pose.transforms;
        for (k, blend) in self.blends.iter().enumerate() {
            let parts = &blend.parts[..usize::from(blend.count)];
            if parts.iter().any(|&(slot, _)| changed[usize::from(slot)]) {
                transforms[end + k] = self.blended(blend, &scratch.world, &scratch.motions);
            }
        }
        for (b, band) in self.bands.iter().flatten().enumerate() {
            if changed[b] && !band.contacts.is_empty() {
                let at = Some(band.first_contact);
                let (world, motions) = (&scratch.world, &scratch.motions);
                self.contacts_into(b, band, local, (world, motions), transforms, at);
            }
        }
        // The riders' twins, numbered last.
        let first = transforms.len() - self.twins.len();
        for (k, twin) in self.twins.iter().enumerate() {
            let t = transforms[usize::from(twin.source)];
            transforms[first + k] = twin.rigid(&t);
        }
    }

    /// Blend `blend`'s transform: its bands' motions composed on its base's world
    /// transform.
    fn blended(
        &self,
        blend: &super::band::Blend,
        world: &[DAffine3],
        motions: &[DAffine3],
    ) -> Affine3A {
        let mut t = world[usize::from(blend.base)];
        for &(slot, level) in &blend.parts[..usize::from(blend.count)] {
            t *= motions[usize::from(slot) * (LEVELS + 1) + usize::from(level)];
        }
        to_f32(&t)
    }

    /// The transforms after the bands' levels: where bands overlap, contacts, the skin's
    /// mixes.
    fn overlaps_into(&self, local: &[Local], scratch: &mut PoseScratch) {
        let transforms = &mut scratch.pose.transforms;
        let (world, motions) = (&scratch.world, &scratch.motions);
        // Where bands overlap, the bands composed (see `band::Blend`).
        for blend in &self.blends {
            transforms.push(self.blended(blend, world, motions));
        }
        for (b, band) in self.bands.iter().flatten().enumerate() {
            self.contacts_into(b, band, local, (world, motions), transforms, None);
        }
        // The skin's mixes: the sections' motions blended by weight, as dual quaternions so
        // the blend stays rigid (see `skin`).
        for mix in &self.mixes {
            let parts = mix.parts[..usize::from(mix.count)]
                .iter()
                .map(|&(s, w)| (&scratch.world[usize::from(s)], w as f64));
            transforms.push(to_f32(&super::skin::blend_rigid(parts)));
        }
        // The riders' twins (see `band::Twin`).
        for twin in &self.twins {
            let t = transforms[usize::from(twin.source)];
            transforms.push(twin.rigid(&t));
        }
    }

    /// Band `b`'s contacts' transforms (see `band`), pushed onto `transforms`, or written
    /// from index `at` on; `world` and `motions` as [`PoseScratch`] holds them.
    fn contacts_into(
        &self,
        b: usize,
        band: &Band,
        local: &[Local],
        (world, motions): (&[DAffine3], &[DAffine3]),
        transforms: &mut Vec<Affine3A>,
        at: Option<usize>,
    ) {
        let l = local.get(band.child).copied().unwrap_or_default();
        let parent = world[band.parent];
        let plane = if band.arc {
            let child = motions[b * (LEVELS + 1) + LEVELS];
            let at_cut = band.motion(l.rotation, &child, band.cut_share());
            contact_plane(
                band,
                &l,
                at_cut.transform_point3(band.pivot),
                at_cut.matrix3 * band.normal,
            )
        } else {
            let turned = motions[b * (LEVELS + 1) + LEVELS];
            let point = (band.pivot + turned.transform_point3(band.pivot)) * 0.5;
            contact_plane(band, &l, point, band.normal + l.rotation * band.normal)
        };
        let swell = BULGE * bend_angle(band.normal, l.rotation);
        let pivot = band.pivot;
        // The child's side rides on what carries the child.
        let carried = parent * self.carry(band.child, local);
        for (j, c) in band.contacts.iter().enumerate() {
            let base = match c.level {
                0 => band.parent,
                l if l >= LEVELS => band.child,
                l => band.first_level + l - 1,
            };
            let w = c.level as f64 / LEVELS as f64;
            let rest = self.body.rest[c.vertex as usize];
            let mut own = motions[b * (LEVELS + 1) + c.level];
            // The swelling (see `band`): a translation away from the pivot's line, so
            // the vertex's bone points keep their spacing.
            let swelling = swell * 4.0 * w * (1.0 - w);
            if swelling > 0.0 {
                let v = rest - pivot;
                let away = (v - band.normal * v.dot(band.normal)) * swelling;
                own.translation += own.matrix3 * away;
            }
            // Only an arc's two limbs meet on its plane; a fan's trunk is not pushed.
            let push = plane
                .filter(|_| band.arc)
                .and_then(|plane| plane.push(&own, rest, c));
            let frame = if c.level >= LEVELS { carried } else { parent };
            let t = match push {
                // `frame * T(v) * own` as one product.
                Some(v) => to_f32(&DAffine3 {
                    matrix3: frame.matrix3 * own.matrix3,
                    translation: frame.matrix3 * own.translation
                        + (frame.matrix3 * v + frame.translation),
                }),
                None if swelling <= 0.0 => transforms[base],
                None => to_f32(&(frame * own)),
            };
            match at {
                Some(first) => transforms[first + j] = t,
                None => transforms.push(t),
            }
        }
    }
}

impl Joints {
    /// The local pose of section `s` whose motion relative to its parent is `motion` (its
    /// rotation part; a scale in it is dropped), the other sections turned as in `local`:
    /// the inverse of the composition above, the band's shift included.
    pub fn local_for(&self, s: usize, motion: &DAffine3, local: &[Local]) -> Local {
        let (_, rotation, translation) = motion.to_scale_rotation_translation();
        let rotation = rotation.normalize();
        let pivot = self.sections[s].pivot;
        let shift = self.band_ending_in(s).map_or(DVec3::ZERO, |band| {
            let slide = self.slide(band, |k| {
                if k == s {
                    rotation
                } else {
                    rotation_in(local)(k)
                }
            });
            band.shift(rotation, slide)
        });
        Local {
            rotation,
            translation: translation - shift - pivot + rotation * pivot,
        }
    }

    /// Section `s`'s motion relative to its parent in the pose `local`: the turn about
    /// its pivot and its translation, and, at the end of a band, the band's
    /// [`Band::shift`].
    fn own_motion(&self, s: usize, local: &[Local]) -> DAffine3 {
        let slide = self
            .band_ending_in(s)
            .map_or_else(Slide::default, |band| self.slide(band, rotation_in(local)));
        self.own_motion_slid(s, local, slide)
    }

    /// [`Joints::own_motion`] where the band that ends in `s` (if one does) slides by
    /// `slide`.
    fn own_motion_slid(&self, s: usize, local: &[Local], slide: Slide) -> DAffine3 {
        let l = local.get(s).copied().unwrap_or_default();
        let pivot = self.sections[s].pivot;
        let own = DAffine3::from_translation(pivot + l.translation)
            * DAffine3::from_quat(l.rotation)
            * DAffine3::from_translation(-pivot);
        match self.band_ending_in(s) {
            Some(band) => DAffine3::from_translation(band.shift(l.rotation, slide)) * own,
            None => own,
        }
    }

    /// The motion, relative to the parent, of the bone points a band moves with weight
    /// `w` of the child's `local` pose, `child` its own motion ([`Bending::at`]).
    fn band_motion(
        &self,
        band: &Band,
        local: &Local,
        child: &DAffine3,
        slide: Slide,
        w: f64,
    ) -> DAffine3 {
        self.bending(band, local, child, slide).at(w)
    }

    /// `band` bent by the child's `local` pose, `child` its own motion and `slide` the
    /// band's ([`Joints::slide`]), with what its levels share worked out once.
    fn bending<'a>(
        &self,
        band: &'a Band,
        local: &Local,
        child: &DAffine3,
        slide: Slide,
    ) -> Bending<'a> {
        if !band.arc {
            return Bending::Fan {
                band,
                pivot: self.sections[band.child].pivot,
                local: *local,
                slide,
                turn: fan_turn(local.rotation),
            };
        }
        // What the arc does not give (the child's translation, less the slide, which rises
        // on the child's side only), spread evenly along it.
        let bent = band.bent(local.rotation);
        let spread = bent.spread(child, band.slid(local.rotation, slide, 1.0));
        Bending::Arc {
            band,
            bent,
            spread,
            slide,
        }
    }

    /// Where a bent arc band carries the cut that made section `s`, in the pose `local`
    /// whose world transforms are `world`: the parent's world transform times the band's
    /// motion at the cut ([`Band::motion`]); `None` for a section at the end of a fan, a
    /// hinge, or no cut (its own world transform carries its pivot). Where its pivot is
    /// drawn and dragged: the child's own frame puts it off the bent centre line.
    pub fn cut_carrier(&self, s: usize, world: &[DAffine3], local: &[Local]) -> Option<DAffine3> {
        let band = self.band_ending_in(s).filter(|b| b.arc)?;
        let l = local.get(s).copied().unwrap_or_default();
        let at_cut = band.motion(l.rotation, &self.own_motion(s, local), band.cut_share());
        world.get(band.parent)?;
        Some(self.parent_frame(s, world, local) * at_cut)
    }

    /// The transform that carries section `s`'s pivot in the pose `local` whose world
    /// transforms are `world`: [`Joints::cut_carrier`] at the end of an arc band, else the
    /// section's own world transform.
    ///
    /// # Panics
    /// If `s` is not a section of `world`.
    pub fn pivot_carrier(&self, s: usize, world: &[DAffine3], local: &[Local]) -> DAffine3 {
        self.cut_carrier(s, world, local).unwrap_or(world[s])
    }

    /// The band that ends in section `s` (the band of the cut that made it), if any.
    pub(super) fn band_ending_in(&self, s: usize) -> Option<&Band> {
        let k = (*self.band_of.get(s)?)?;
        self.bands.get(k)?.as_ref().filter(|b| b.child == s)
    }
}

/// A band bent in one pose ([`Joints::bending`]): its motion at each share `w` of the
/// band, relative to the parent.
enum Bending<'a> {
    /// `T(pivot + w t + s(w)) · Q(w) · T(−pivot)`, `Q(w) = slerp(I, R, w)`, `pivot` the
    /// point the child turns about and `s(w)` the band's slide at `w` along the normal
    /// turned by `Q(w)` ([`Band::slide_for`], [`Band::slid`]).
    Fan {
        band: &'a Band,
        pivot: DVec3,
        local: Local,
        slide: Slide,
        /// `R`'s axis and angle (the short way), to make `Q(w)` at each level from one
        /// sine and cosine instead of a slerp's arc cosine and three sines; `None` for a
        /// turn too small to have an axis.
        turn: Option<(DVec3, f64)>,
    },
    /// Turned by share `w` of the rotation about the point of the bent centre line at
    /// `w` ([`Band::motion`]), and slid along the normal turned with it by the band's
    /// slide at `w`, which rises on the child's side only.
    Arc {
        band: &'a Band,
        bent: Bent,
        /// What the arc does not give of the child's translation ([`Bent::spread`]).
        spread: DVec3,
        slide: Slide,
    },
}

impl Bending<'_> {
    /// The motion at share `w` of the band.
    fn at(&self, w: f64) -> DAffine3 {
        match self {
            Bending::Fan {
                band,
                pivot,
                local,
                slide,
                turn,
            } => {
                let turned = match turn {
                    Some((axis, angle)) => DQuat::from_axis_angle(*axis, angle * w),
                    None => DQuat::IDENTITY.slerp(local.rotation, w),
                };
                // Turned (and swollen) about the pivot, then moved: the products of a
                // translation, the turn, the swell and the pivot's translation back, as
                // one transform (glam's products give the same bits).
                let moved = *pivot + local.translation * w + band.slid(turned, *slide, w);
                let mut matrix3 = DMat3::from_quat(turned);
                if slide.swell != 0.0 {
                    let swell = 1.0
                        + slide.swell
                            * super::slide::bump(band.cut_share(), super::slide::along(w));
                    matrix3 *= DMat3::from_diagonal(DVec3::splat(swell));
                }
                DAffine3 {
                    matrix3,
                    translation: matrix3 * -*pivot + moved,
                }
            }
            Bending::Arc {
                band,
                bent,
                spread,
                slide,
            } => {
                let mut motion = bent.motion(w, *spread);
                motion.translation += band.slid(bent.turned(w), *slide, w);
                motion
            }
        }
    }
}

impl Band {
    /// The band's centre line bent by the child's `rotation` (see [`super::band`]).
    pub(super) fn bent(&self, rotation: DQuat) -> Bent {
        let (axis, angle) = axis_angle(rotation);
        let along = axis * axis.dot(self.normal);
        let across = self.normal - along;
        let (start, _, length) = self.ends();
        Bent {
            axis,
            angle,
            start,
            normal: self.normal,
            length,
            along,
            across,
            side: axis.cross(across),
        }
    }
}

/// A band's centre line bent by a rotation ([`Band::bent`]): the band's length times
/// `∫₀ʷ Q(u) n du` from its parent end (`start`), `Q(u)` the rotation by share `u` of the
/// angle.
pub(super) struct Bent {
    axis: DVec3,
    angle: f64,
    start: DVec3,
    normal: DVec3,
    length: f64,
    along: DVec3,
    across: DVec3,
    side: DVec3,
}

impl Bent {
    /// The bent centre line's point at share `w`, relative to the parent end.
    pub(super) fn point(&self, w: f64) -> DVec3 {
        let (sin, versin) = if self.angle < 1e-9 {
            (w, 0.5 * w * w * self.angle)
        } else {
            let half = 0.5 * w * self.angle;
            (
                (w * self.angle).sin() / self.angle,
                2.0 * half.sin() * half.sin() / self.angle,
            )
        };
        (self.along * w + self.across * sin + self.side * versin) * self.length
    }

    /// What the arc does not give of the child's motion `child` (its translation, less
    /// `slid`), to be spread evenly along the band.
    pub(super) fn spread(&self, child: &DAffine3, slid: DVec3) -> DVec3 {
        let end = self.start + self.normal * self.length;
        child.transform_point3(end) - slid - self.start - self.point(1.0)
    }

    /// The motion, relative to the parent, of the bone points at share `w`: turned by
    /// share `w` of the rotation about the bent centre line's point there, moved by `w`
    /// of `spread`.
    pub(super) fn motion(&self, w: f64, spread: DVec3) -> DAffine3 {
        DAffine3::from_translation(self.start + self.point(w) + spread * w)
            * DAffine3::from_axis_angle(self.axis, self.angle * w)
            * DAffine3::from_translation(-(self.start + self.normal * (w * self.length)))
    }

    /// The rotation by share `w` of the turn.
    pub(super) fn turned(&self, w: f64) -> DQuat {
        DQuat::from_axis_angle(self.axis, self.angle * w)
    }
}

/// The axis and angle of `rotation` the short way (as `slerp` from the identity turns),
/// `None` where it is too small to have an axis (the slerp's own threshold, or an axis
/// shorter than that).
fn fan_turn(rotation: DQuat) -> Option<(DVec3, f64)> {
    let q = if rotation.w < 0.0 {
        -rotation
    } else {
        rotation
    };
    let v = q.xyz();
    let sin = v.length();
    if q.w > 1.0 - f64::EPSILON || sin < 1e-12 || !sin.is_finite() {
        return None;
    }
    Some((v / sin, 2.0 * sin.atan2(q.w)))
}

/// Each section's rotation in the pose `local` (at rest where it has none).
fn rotation_in(local: &[Local]) -> impl Fn(usize) -> DQuat + '_ {
    move |s| local.get(s).map_or(DQuat::IDENTITY, |l| l.rotation)
}

/// The plane the two sides of a bent band meet on, in the parent's frame, through
/// `point` with `normal` (see [`super::band`]); `None` when the joint does not bend (a
/// twist about the normal, or nothing).
fn contact_plane(band: &Band, local: &Local, point: DVec3, normal: DVec3) -> Option<ContactPlane> {
    let n = band.normal;
    let bent = local.rotation * n;
    let inner = bent - n * n.dot(bent);
    let normal = normal.normalize_or_zero();
    if inner.length() < 1e-9 || normal == DVec3::ZERO {
        return None;
    }
    Some(ContactPlane {
        point,
        normal,
        pivot: band.pivot,
        inner: inner.normalize(),
        axis: n,
        radius: band.radius,
        reach: band.width.max(super::band::CONTACT_REACH * band.radius),
        at_cut: band.weight_at_cut(),
    })
}

/// See [`contact_plane`].
#[derive(Clone, Copy, Debug)]
struct ContactPlane {
    point: DVec3,
    normal: DVec3,
    /// The cut's pivot at rest, and the side of the limb the child turns towards.
    pivot: DVec3,
    inner: DVec3,
    /// The cut's normal at rest, and the band's local medial radius: how far from the
    /// pivot's line the limb's sides are.
    axis: DVec3,
    radius: f64,
    /// How far from the cut the band's contacts reach, and the weight at the cut (where a
    /// vertex's side changes).
    reach: f64,
    at_cut: f64,
}

impl ContactPlane {
    /// The push that brings contact `c` (rest position `rest`, moved by `own`) back onto
    /// its side of the plane, if it is on the inner side of the bend and farther across
    /// than it lay at rest (so the push grows from nothing as the joint bends).
    ///
    /// The push fades to nothing towards the limb's middle on the inner side and beyond
    /// the limb's sides ([`PUSH_FADE`]): the plane is where a limb's two inner sides meet,
    /// and a vertex beside it (a trunk's, a face's) is not pushed, so the push is
    /// continuous over the surface.
    fn push(&self, own: &DAffine3, rest: DVec3, c: &super::band::Contact) -> Option<DVec3> {
        let v = rest - self.pivot;
        let inner = v.dot(self.inner);
        if inner <= 0.0 {
            return None;
        }
        let s = (own.transform_point3(rest) - self.point).dot(self.normal);
        // How far across the vertex lies, less how far across the cut's plane it lay at
        // rest (a parent's skin beyond a rounded cut's plane, a hip's beside the thigh):
        // at rest the plane is the cut's, so the push starts from nothing as the joint
        // starts to bend instead of jumping there at the first degree.
        let at_rest = v.dot(self.axis);
        let excess = if c.child_side {
            -s - (-at_rest).max(0.0)
        } else {
            s - at_rest.max(0.0)
        };
        if excess <= 0.0 {
            return None;
        }
        let r = self.radius.max(1e-12);
        let along = v.dot(self.axis);
        let side = (v - self.axis * along).length() / r;
        let along = along.abs();
        let w = c.level as f64 / super::band::LEVELS as f64;
        let fade = (inner / (0.5 * r)).min(1.0)
            * (1.0 - ((side - PUSH_FADE[0]) / (PUSH_FADE[1] - PUSH_FADE[0])).clamp(0.0, 1.0))
            * (2.0 * (1.0 - along / self.reach)).clamp(0.0, 1.0)
            * ((w - self.at_cut).abs() / FLIP_FADE).min(1.0);
        (fade > 0.0).then_some(-s.signum() * excess * fade * self.normal)
    }
}

/// Across the cut's normal, in local medial radii, where a contact's push starts to fade
/// and where it is gone (see [`ContactPlane::push`]).
pub(super) const PUSH_FADE: [f64; 2] = [1.5, 2.5];

/// Within this much weight of the cut's, where a contact's side changes, its push fades
/// to nothing (see [`ContactPlane::push`]).
const FLIP_FADE: f64 = 0.125;

/// The angle (radians) between `n` and `rotation · n`: how far a rotation bends a limb
/// along `n` (a twist about it does not count).
pub fn bend_angle(n: DVec3, rotation: DQuat) -> f64 {
    n.dot(rotation * n).clamp(-1.0, 1.0).acos()
}

/// Storage for [`Joints::pose_into`].
#[derive(Clone, Debug)]
pub struct PoseScratch {
    world: Vec<DAffine3>,
    /// Per section, its turn (a rotation vector) and the slide of the band that ends in
    /// it ([`Joints::slides_into`]).
    turns: Vec<DVec3>,
    slides: Vec<Slide>,
    /// Per band, its motion at each of the `LEVELS + 1` weight steps.
    motions: Vec<DAffine3>,
    pose: Pose,
    /// The pose asked for in a step, before the pose limit (`Puppet::step_animated`).
    pub(crate) wanted: Vec<Local>,
    /// The joints' stamp and the local poses `pose` was made for (none yet).
    made: Option<u64>,
    made_of: Vec<Local>,
    /// Per band, its sides' swells that keep their sections' volumes (see `volume`).
    keep: Vec<[f64; 4]>,
    /// The kept sections' vertices in their own frames, the rest positions elsewhere
    /// (empty until a pose needs them).
    positions: Vec<DVec3>,
    /// Whether its poses keep each section's volume (see `volume`): all but the
    /// suggestion's trials ([`PoseScratch::first_order`]).
    keep_volumes: bool,
    /// Each band's motions before any swell (`keep_into`'s).
    unswollen: Vec<DAffine3>,
    /// What a Newton step towards the volumes leaves for the next (`volume`).
    newton: super::volume::Newton,
    /// How many it takes at most ([`super::volume::NEWTON_STEPS`]).
    newton_steps: usize,
}

impl PoseScratch {
    /// Storage whose poses leave each section's volume to the slides alone (first
    /// order), without measuring it and swelling the bands (see `volume`): what the
    /// suggestion's tear check poses, so that a cut is judged by its band's own bend.
    pub fn first_order() -> PoseScratch {
        PoseScratch {
            keep_volumes: false,
            ..PoseScratch::default()
        }
    }
}

impl Default for PoseScratch {
    fn default() -> Self {
        PoseScratch {
            world: Vec::new(),
            turns: Vec::new(),
            slides: Vec::new(),
            motions: Vec::new(),
            pose: Pose::rest(1),
            wanted: Vec::new(),
            made: None,
            made_of: Vec::new(),
            keep: Vec::new(),
            positions: Vec::new(),
            keep_volumes: true,
            unswollen: Vec::new(),
            newton: Default::default(),
            newton_steps: super::volume::NEWTON_STEPS,
        }
    }
}

/// An f64 affine transform in f32.
pub fn to_f32(t: &DAffine3) -> Affine3A {
    Affine3A::from_cols_array(&t.to_cols_array().map(|v| v as f32))
}

/// Section indices ordered so every parent precedes its children.
pub(super) fn parents_first(sections: &[Section]) -> Vec<usize> {
    let mut children = vec![Vec::new(); sections.len()];
    let mut roots = Vec::new();
    for (i, s) in sections.iter().enumerate() {
        match s.parent {
            Some(p) => children[p].push(i),
            None => roots.push(i),
        }
    }
    let mut order = Vec::with_capacity(sections.len());
    let mut stack = roots;
    while let Some(s) = stack.pop() {
        order.push(s);
        stack.extend(children[s].iter().rev());
    }
    order
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A pose that swells some bands makes again only what composes them (`keep_into`),
    /// and gets every transform a whole remake of the blends, contacts and mixes gets:
    /// the human with its suggested cuts, posed at random.
    #[test]
    fn a_swollen_pose_remakes_what_its_swells_change_and_matches_a_whole_remake() {
        let puppet = crate::joints::suggest::fixture::suggested_human();
        let joints = &puppet.joints;
        assert!(!joints.blends.is_empty(), "bands overlap somewhere");
        let contacts = joints.bands.iter().flatten().map(|b| b.contacts.len());
        assert!(contacts.sum::<usize>() > 0, "contacts");
        let mut swelled = 0;
        for seed in 0..6 {
            let local = crate::joints::spread::random_pose(
                joints,
                crate::joints::spread::Spread::default(),
                &mut crate::random::SplitMix(seed),
            );
            let mut scratch = PoseScratch::default();
            let made = joints.pose_into(&local, &mut scratch).transforms.clone();
            let some = scratch.keep.iter().filter(|&&k| k != [0.0; 4]).count();
            swelled += some;
            // The whole remake, on the same swollen motions.
            let levels =
                joints.sections.len() + joints.bands.iter().flatten().count() * (LEVELS - 1);
            scratch.pose.transforms.truncate(levels);
            joints.overlaps_into(&local, &mut scratch);
            assert_eq!(
                made, scratch.pose.transforms,
                "seed {seed} ({some} bands swollen)"
            );
        }
        assert!(swelled > 0, "some pose swells a band");
    }

    /// The worst section's volume change (`bench poses`' measure) where the bones of
    /// `puppet` hold its surface in `pose`.
    fn worst_volume(puppet: &crate::puppet::Puppet, pose: &Pose) -> f64 {
        let transform_of = puppet.joints.transform_of();
        let at: Vec<DVec3> = puppet
            .mesh
            .positions
            .iter()
            .zip(transform_of)
            .map(|(&x, &t)| {
                let m = pose.transforms[usize::from(t)];
                m.transform_point3(x.as_vec3()).as_dvec3()
            })
            .collect();
        let [lo, hi] = crate::puppet::press::section_volumes(puppet, &at);
        (-lo).max(hi)
    }

    #[test]
    fn a_second_newton_step_gives_back_what_the_first_leaves() {
        // A low-poly fish whose head and tail, turned up to 90° at the root, take a
        // large share of its body's volume with them.
        let puppet = crate::joints::suggest::fixture::suggested("tests/data/population/fish1.glb");
        let (mut one_sum, mut two_sum) = (0.0, 0.0);
        for seed in 0..20 {
            let local = crate::joints::spread::random_pose(
                &puppet.joints,
                crate::joints::spread::Spread::default(),
                &mut crate::random::SplitMix(seed),
            );
            let mut one = PoseScratch {
                newton_steps: 1,
                ..PoseScratch::default()
            };
            let mut two = PoseScratch::default();
            let a = worst_volume(&puppet, puppet.joints.pose_into(&local, &mut one));
            let b = worst_volume(&puppet, puppet.joints.pose_into(&local, &mut two));
            assert!(b <= a + 1e-3, "seed {seed}: {b} against {a}");
            one_sum += a;
            two_sum += b;
        }
        // Over 20 poses the worst sections keep 3 % of their volume more in all (0.242
        // against 0.272): the largest changes are held by their sides' bounds.
        assert!(two_sum < one_sum - 0.02, "{two_sum} against {one_sum}");
    }

    #[test]
    fn a_section_at_the_other_end_of_a_swollen_band_is_measured_again() {
        // Spot: where its trunk's sides swell, its arms lose what their seams give the
        // trunk, though the first step left them within `AGAIN`. Measured again in the
        // second step, every section of `bench poses`' 20 poses stays within ±6 % where
        // the bones hold it (−10.9 … +7.8 % when only the sections past `AGAIN` were).
        let puppet = crate::joints::suggest::fixture::suggested("assets/spot.obj");
        let mut worst: f64 = 0.0;
        for seed in 1..=20 {
            let local = crate::joints::spread::random_pose(
                &puppet.joints,
                crate::joints::spread::Spread::default(),
                &mut crate::random::SplitMix(seed),
            );
            let mut scratch = PoseScratch::default();
            let change = worst_volume(&puppet, puppet.joints.pose_into(&local, &mut scratch));
            worst = worst.max(change);
        }
        assert!(worst < 0.06, "{worst}");
    }
}
