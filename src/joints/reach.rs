//! Where a cut's band reaches: the local medial radius at the cut, the vertices near it
//! (the child's joined to the seam), how deep and how far as a limb the child goes, how
//! spread the parent's skeleton is, the cut's frame, and the flesh around each joint that
//! the pose limit keeps apart. The band itself, its levels and transforms: [`super::band`].

use super::band::{Band, BULB, CONTACT_REACH};
use super::Joints;
use glam::DVec3;

impl Joints {
    /// The local medial radius at cut `k` (see the module docs) and its child and parent
    /// sections; `None` without radii or when the cut's section is gone.
    pub(super) fn local_radius(&self, k: usize) -> Option<(f64, usize, usize)> {
        let n = self.section_of.len();
        let cut = self.cuts.get(k)?;
        if self.body.radius.len() != n {
            return None;
        }
        let child = self.find(&cut.name)?;
        let parent = self.sections[child].parent?;
        let normal = cut.normal.normalize_or_zero();
        let mut near: Vec<(f64, f64)> = (0..n)
            .filter(|&i| !self.body.is_rider(i) && self.section_before(i) == child)
            .map(|i| {
                let d = cut.signed(self.point(i), normal);
                (d.abs(), self.body.radius[i])
            })
            .collect();
        if near.is_empty() {
            return None;
        }
        let m = (near.len() / 50).max(8).min(near.len());
        near.select_nth_unstable_by(m - 1, |a, b| a.0.total_cmp(&b.0));
        let mut radii: Vec<f64> = near[..m].iter().map(|x| x.1).collect();
        let radius = crate::stats::median(&mut radii)?;
        (radius.is_finite() && radius > 0.0).then_some((radius, child, parent))
    }

    /// Is vertex `i` on a part made whole beside a cut ([`super::whole`])?
    pub(super) fn on_whole_part(&self, i: usize) -> bool {
        self.whole_part
            .get(i)
            .is_some_and(|&s| s != super::NOT_MOVED)
    }

    /// Vertex `i`'s section before parts went whole ([`super::whole`]): what a band's
    /// width is measured on. A part beside a limb is no flesh of it, but the band's width
    /// as the skeleton's sections set it is what the skin around the joint was tuned on
    /// (measured without its helmet, a spacesuit's shoulder band narrowed and its skin
    /// stretched 2.49 → 3.69× in `bench poses`).
    fn section_before(&self, i: usize) -> usize {
        match self.whole_part.get(i) {
            Some(&s) if s != super::NOT_MOVED => usize::from(s),
            _ => usize::from(self.section_of[i]),
        }
    }

    /// Where vertex `i` lies for the bands: its skeletal point, or, for a vertex of a piece
    /// moved to make its section whole, the skeletal point of the nearest vertex around
    /// the piece ([`super::whole`]).
    pub(super) fn point(&self, i: usize) -> DVec3 {
        self.body.points[self.borrowed.get(i).map_or(i, |&j| j as usize)]
    }

    /// The body's vertices (riders excluded) near cut `k`, with the signed distance `d` of
    /// their skeletal point from its plane (positive into the child): the child's with
    /// `d < width` joined to the seam through such vertices, and the parent's with
    /// `−width < d ≤ 0` within `2.5 r` of the pivot in the plane (see the module docs).
    /// What a band of half-width `width` moves.
    pub(super) fn near_cut(&self, k: usize, radius: f64, width: f64) -> Vec<(usize, f64)> {
        let cut = &self.cuts[k];
        let Some(child) = self.find(&cut.name) else {
            return Vec::new();
        };
        let parent = self.sections[child].parent;
        let (pivot, along) = self.cut_frame(k);
        let normal = cut.normal.normalize_or_zero();
        let reach = 2.5 * radius;
        let members: Vec<(usize, f64)> = (0..self.section_of.len())
            .filter(|&i| !self.body.is_rider(i) && !self.on_whole_part(i))
            .filter_map(|i| {
                let p = self.point(i);
                let d = cut.signed(p, normal);
                let s = self.section_of[i] as usize;
                let v = p - pivot;
                let in_plane = (v - along * v.dot(along)).length();
                let member = (s == child && d < width)
                    || (Some(s) == parent && d <= 0.0 && d > -width && in_plane <= reach);
                member.then_some((i, d))
            })
            .collect();
        self.joined_to_seam(child, members)
    }

    /// `members` (vertex, signed distance) less the child's vertices that are not joined
    /// to the seam through the child's members: a limb that curls back to its cut's plane
    /// (a spider's leg, a fingertip beside the palm's cut) has skeletal points near the
    /// plane far from the seam, and a band level there turns them about a pivot many
    /// edges away, so a step of one level tears (4.3× on a downloaded spider). Kept as
    /// they are where the child has no seam (a piece that only passes into its parent).
    fn joined_to_seam(&self, child: usize, members: Vec<(usize, f64)>) -> Vec<(usize, f64)> {
        let n = self.section_of.len();
        let moves = self.moves_with(child);
        let in_child = |i: usize| usize::from(self.section_of[i]) == child;
        let mut member = vec![false; n];
        for &(i, _) in &members {
            member[i] = in_child(i);
        }
        let mut joined = vec![false; n];
        let mut stack: Vec<usize> = members
            .iter()
            .map(|&(i, _)| i)
            .filter(|&i| {
                member[i]
                    && self.body.neighbours(i).iter().any(|&j| {
                        let j = j as usize;
                        !self.body.is_rider(j) && !moves[usize::from(self.section_of[j])]
                    })
            })
            .collect();
        if stack.is_empty() {
            return members;
        }
        for &i in &stack {
            joined[i] = true;
        }
        while let Some(i) = stack.pop() {
            for &j in self.body.neighbours(i) {
                let j = j as usize;
                if member[j] && !joined[j] {
                    joined[j] = true;
                    stack.push(j);
                }
            }
        }
        members
            .into_iter()
            .filter(|&(i, _)| !member[i] || joined[i])
            .collect()
    }

    /// The body's vertices whose rest position lies within `reach` of band `band`'s cut
    /// along its normal and within [`super::pose::PUSH_FADE`]'s outer radius of its
    /// pivot's line: where a contact may push (its push fades to nothing at the edge, so
    /// the surface stays whole).
    pub(super) fn near_surface(&self, band: &Band, reach: f64) -> Vec<usize> {
        let side = super::pose::PUSH_FADE[1] * band.radius;
        (0..self.section_of.len())
            .filter(|&i| !self.body.is_rider(i))
            .filter(|&i| {
                let v = self.body.rest[i] - band.pivot;
                let along = v.dot(band.normal);
                along.abs() < reach && (v - band.normal * along).length() < side
            })
            .collect()
    }

    /// How far beyond cut `k` the skeletal points of its child section reach (the largest
    /// signed distance).
    pub(super) fn depth(&self, k: usize, child: usize) -> f64 {
        let cut = &self.cuts[k];
        let normal = cut.normal.normalize_or_zero();
        (0..self.section_of.len())
            .filter(|&i| !self.body.is_rider(i) && self.section_of[i] as usize == child)
            .map(|i| cut.signed(self.point(i), normal))
            .fold(0.0, f64::max)
    }

    /// How far beyond cut `k` its child stays a limb of about the local medial `radius`:
    /// the start of the first slab (a radius thick) where a tenth of the skeletal
    /// distances exceed [`BULB`] radii (a head beyond its neck; the 90th percentile, as
    /// a face's bumps give many small balls), or infinity.
    pub(super) fn tube(&self, k: usize, child: usize, radius: f64) -> f64 {
        let cut = &self.cuts[k];
        let normal = cut.normal.normalize_or_zero();
        let mut slabs: Vec<Vec<f64>> = Vec::new();
        for i in 0..self.section_of.len() {
            if self.body.is_rider(i) || self.section_of[i] as usize != child {
                continue;
            }
            let d = cut.signed(self.point(i), normal);
            if !(d >= 0.0 && d.is_finite()) {
                continue;
            }
            let slab = (d / radius) as usize;
            if slab >= 16 {
                continue;
            }
            if slabs.len() <= slab {
                slabs.resize(slab + 1, Vec::new());
            }
            slabs[slab].push(self.body.radius[i]);
        }
        for (s, radii) in slabs.iter_mut().enumerate() {
            if radii.len() < 3 {
                continue;
            }
            radii.sort_by(f64::total_cmp);
            if radii[radii.len() * 9 / 10] > BULB * radius {
                return s as f64 * radius;
            }
        }
        f64::INFINITY
    }

    /// The share of `parent`'s skeletal points on the parent's side of cut `k`'s band
    /// (`−width < d ≤ 0`, within `2.5 r` of the pivot across the normal) that lie more
    /// than `r` from the pivot's line: near 0 where the parent is a limb (its skeleton a
    /// line along its axis), high where it is a trunk (a sheet across it).
    pub(super) fn spread(&self, k: usize, parent: usize, radius: f64, width: f64) -> f64 {
        let cut = &self.cuts[k];
        let normal = cut.normal.normalize_or_zero();
        let (pivot, along) = self.cut_frame(k);
        let (mut all, mut off) = (0usize, 0usize);
        for i in 0..self.section_of.len() {
            if self.body.is_rider(i) || self.section_of[i] as usize != parent {
                continue;
            }
            let d = cut.signed(self.point(i), normal);
            let v = self.point(i) - pivot;
            let across = (v - along * v.dot(along)).length();
            if d > 0.0 || d <= -width || across > 2.5 * radius {
                continue;
            }
            all += 1;
            off += usize::from(across > radius);
        }
        if all == 0 {
            1.0
        } else {
            off as f64 / all as f64
        }
    }

    /// Cut `k`'s pivot and the unit normal of its surface there (into the child): where a
    /// band bends and along what.
    pub(super) fn cut_frame(&self, k: usize) -> (DVec3, DVec3) {
        let cut = &self.cuts[k];
        let pivot = cut.pivot.unwrap_or(cut.point);
        (pivot, cut.normal_near(pivot))
    }

    /// The vertices (riders included, with their host) whose skeletal point lies within
    /// `radii` local medial radii of the plane of the cut named `name`, on the limb's two
    /// sides as a band takes them (see the module docs), and that radius; `None` for an
    /// unknown cut or without radii. Where a bend is measured.
    pub fn joint_region(&self, name: &str, radii: f64) -> Option<(Vec<bool>, f64)> {
        let k = self.cuts.iter().position(|c| c.name == name)?;
        let (radius, _, _) = self.local_radius(k)?;
        let mut region = vec![false; self.section_of.len()];
        for (i, _) in self.near_cut(k, radius, radii * radius) {
            region[i] = true;
        }
        for (i, &h) in self.body.host.iter().enumerate() {
            if h != super::NO_HOST {
                region[i] = region[h as usize];
            }
        }
        Some((region, radius))
    }

    /// Per vertex, the joint whose flesh it is: 1 + the index of the cut within whose
    /// [`CONTACT_REACH`] local radii of its plane it lies, in the section it made or, as
    /// far from the pivot across the plane's normal, its parent (the nearest plane wins),
    /// 0 for none (each by its skeletal point). The simulation's contacts never push a
    /// point out of a ball of its own joint's flesh that it lay near at rest
    /// (`sim::contact`); two parts that merely rest against each other (an arm hanging by
    /// the body) do collide.
    ///
    /// Empty without the skeletal distances (joints of skeletal points alone): then there
    /// are no local radii to measure by, and every pair near at rest is a joint's flesh.
    ///
    /// Kept with the bands: worked out once each time the cuts change.
    pub fn joint_flesh(&self) -> &[u16] {
        &self.flesh
    }

    /// [`Joints::joint_flesh`] worked out, with each cut's [`Joints::local_radius`].
    pub(super) fn flesh_of(&self, radii: &[Option<(f64, usize, usize)>]) -> Vec<u16> {
        let n = self.section_of.len();
        if self.body.radius.len() != n {
            return Vec::new();
        }
        let mut out = vec![0u16; n];
        let mut nearest = vec![f64::INFINITY; n];
        for k in 0..self.cuts.len().min(usize::from(u16::MAX) - 1) {
            let Some(&Some((radius, child, parent))) = radii.get(k) else {
                continue;
            };
            let parent = Some(parent);
            // Both sides of the plane: the child's anywhere along it (a cut through a ring
            // meets its section at two places), the parent's about the limb's root only.
            let cut = &self.cuts[k];
            let normal = cut.normal.normalize_or_zero();
            let (pivot, along) = self.cut_frame(k);
            for i in 0..n.min(self.body.points.len()) {
                let s = usize::from(self.section_of[i]);
                if s != child && Some(s) != parent {
                    continue;
                }
                // (The body's side below an armpit, its skeletal points deep in the chest,
                // collides with the arm.)
                if s != child {
                    let v = self.point(i) - pivot;
                    if (v - along * v.dot(along)).length() > CONTACT_REACH * radius {
                        continue;
                    }
                }
                let d = cut.signed(self.point(i), normal);
                let depth = d.abs() / radius;
                if depth < CONTACT_REACH && depth < nearest[i] {
                    nearest[i] = depth;
                    out[i] = k as u16 + 1;
                }
            }
        }
        for (i, &h) in self.body.host.iter().enumerate() {
            if h != super::NO_HOST {
                out[i] = out.get(h as usize).copied().unwrap_or(0);
            }
        }
        out
    }
}
