//! Applying and removing cuts: which vertices a cut takes (the positive side of its shape
//! in the section it splits, or only the connected piece of it), where its pivot goes,
//! which children follow the new section, and which point each section turns about.

use super::pose::parents_first;
use super::{Cut, JointError, Joints, Section, Shape, MAX_SECTIONS};
use glam::DVec3;

impl Joints {
    /// Applies a cut; returns the new section's index. On error nothing changes.
    pub fn add_cut(&mut self, cut: Cut) -> Result<usize, JointError> {
        self.changing();
        let index = self.add_cut_unbanded(cut)?;
        self.refresh_bands();
        Ok(index)
    }

    /// [`Joints::add_cut`] but the bands, which the caller refreshes before the joints pose
    /// anything ([`Joints::refresh_bands`]): the sections are assigned (what the
    /// suggestion measures while it places cuts).
    pub(super) fn add_cut_unbanded(&mut self, cut: Cut) -> Result<usize, JointError> {
        self.changing();
        let index = self.insert_cut(cut)?;
        self.assign_sections(true);
        Ok(index)
    }

    /// Applies cuts in order, as [`Joints::add_cut`] each, with the bands worked out once
    /// at the end instead of after every cut (each refresh visits every band: dozens of
    /// suggested joints would cost dozens of refreshes). Stops at the first that fails,
    /// with the ones before it applied.
    pub fn add_cuts(&mut self, cuts: impl IntoIterator<Item = Cut>) -> Result<(), JointError> {
        self.changing();
        let added = self.add_cuts_unbanded(cuts);
        self.refresh_bands();
        added
    }

    /// [`Joints::add_cuts`] but the bands, which the caller refreshes before the joints
    /// pose anything ([`Joints::refresh_bands`]): the sections are assigned.
    pub(super) fn add_cuts_unbanded(
        &mut self,
        cuts: impl IntoIterator<Item = Cut>,
    ) -> Result<(), JointError> {
        self.changing();
        let added = cuts
            .into_iter()
            .try_for_each(|cut| self.insert_cut(cut).map(|_| ()));
        self.assign_sections(true);
        added
    }

    /// [`Joints::add_cut`] but the bands, which the caller refreshes.
    fn insert_cut(&mut self, cut: Cut) -> Result<usize, JointError> {
        self.changing();
        let name = cut.name.clone();
        if name.trim().is_empty() {
            return Err(JointError::EmptyName(name));
        }
        if self.find(&name).is_some() {
            return Err(JointError::DuplicateName(name));
        }
        if self.sections.len() >= MAX_SECTIONS {
            return Err(JointError::TooMany);
        }
        let parent = self
            .find(&cut.section)
            .ok_or_else(|| JointError::UnknownSection {
                cut: name.clone(),
                section: cut.section.clone(),
                known: self
                    .sections
                    .iter()
                    .map(|s| s.name.as_str())
                    .collect::<Vec<_>>()
                    .join(", "),
            })?;
        for (what, v) in [
            ("point", Some(cut.point)),
            ("normal", Some(cut.normal)),
            ("pivot", cut.pivot),
        ] {
            if v.is_some_and(|v| !v.is_finite()) {
                return Err(JointError::NotFinite {
                    cut: name.clone(),
                    what,
                });
            }
        }
        let normal = cut.normal.normalize_or_zero();
        if normal == DVec3::ZERO || !normal.is_finite() {
            return Err(JointError::ZeroNormal(name));
        }
        if !cut.shape.is_valid() {
            return Err(JointError::BadSize(name, cut.shape.name()));
        }
        if cut.shape == Shape::Skin && self.skin_joint(&name).is_none() {
            return Err(JointError::NoSkinJoint(name));
        }
        let taken = self.taken(parent, &cut, normal);
        let inside = taken.iter().filter(|&&t| t).count();
        let outside = (0..self.skeletal_of.len())
            .filter(|&i| !self.body.is_rider(i) && self.skeletal_of[i] as usize == parent)
            .count()
            - inside;
        for (count, side) in [
            (inside, "the side the normal points to"),
            (outside, "the other side"),
        ] {
            if count == 0 {
                return Err(JointError::EmptySide {
                    cut: name,
                    section: cut.section.clone(),
                    side,
                });
            }
        }
        let pivot = match cut.pivot {
            Some(p) => p,
            None if cut.shape != Shape::Plane => self.seam_pivot(&taken, parent, &cut, normal),
            // A plane's pivot comes from the whole section near it; a connected cut's from
            // the piece it takes (the section near a hip holds the other leg too).
            None if cut.connected => self.default_pivot(&taken, &cut, normal),
            None => {
                let section: Vec<bool> = (0..self.skeletal_of.len())
                    .map(|i| !self.body.is_rider(i) && self.skeletal_of[i] as usize == parent)
                    .collect();
                self.default_pivot(&section, &cut, normal)
            }
        };
        // Children of the split section follow it when their own pivot is on the new side;
        // for a connected cut, when most of their seam with it is on the piece taken (a
        // plane reaches across the whole body: a tail's tip can lie behind the plane of a
        // cut that takes the body the tail hangs from), by the pivot where they share no
        // edge with it.
        let follows: Vec<bool> = (0..self.sections.len())
            .map(|k| {
                self.sections[k].parent == Some(parent)
                    && if cut.connected {
                        let (on, off) = self.seam_sides(k, parent, &taken);
                        on > off || on + off == 0 && cut.signed(self.own_pivot(k), normal) > 0.0
                    } else {
                        cut.signed(self.own_pivot(k), normal) > 0.0
                    }
            })
            .collect();
        // A section turns about one point: the split section may keep one sharing child.
        if cut.shared_pivot {
            if let Some(other) = self.shared_child(parent).filter(|&k| !follows[k]) {
                return Err(JointError::SharedPivot {
                    cut: name,
                    section: cut.section.clone(),
                    other: self.sections[other].name.clone(),
                });
            }
        }
        let index = self.sections.len();
        for (s, &t) in self.skeletal_of.iter_mut().zip(&taken) {
            if t {
                *s = index as u16;
            }
        }
        for (s, follow) in self.sections.iter_mut().zip(follows) {
            if follow {
                s.parent = Some(index);
            }
        }
        self.sections.push(Section {
            name,
            parent: Some(parent),
            pivot,
            vertices: 0,
        });
        self.cuts.push(Cut {
            pivot: Some(pivot),
            ..cut
        });
        self.assign_sections(false);
        self.order = parents_first(&self.sections);
        self.refresh_pivots();
        Ok(index)
    }

    /// The pivot of the cut that made section `k` (the root's own for the root).
    fn own_pivot(&self, k: usize) -> DVec3 {
        match k.checked_sub(1).and_then(|c| self.cuts.get(c)) {
            Some(cut) => cut.pivot.unwrap_or(self.sections[k].pivot),
            None => self.root_pivot,
        }
    }

    /// The child of section `parent` whose cut shares its pivot, if one does.
    fn shared_child(&self, parent: usize) -> Option<usize> {
        (1..self.sections.len())
            .find(|&k| self.sections[k].parent == Some(parent) && self.cuts[k - 1].shared_pivot)
    }

    /// Sets every section's turning point: its own pivot, or that of its first child cut
    /// (in cut order) with a shared pivot (see the module docs).
    fn refresh_pivots(&mut self) {
        self.changing();
        let n = self.sections.len();
        let mut shared = vec![false; n];
        for k in 0..n {
            self.sections[k].pivot = self.own_pivot(k);
        }
        for c in 1..n {
            match self.sections[c].parent {
                Some(p) if self.cuts[c - 1].shared_pivot && !shared[p] => {
                    shared[p] = true;
                    self.sections[p].pivot = self.own_pivot(c);
                }
                _ => {}
            }
        }
    }

    /// Lets the section that the cut named `name` splits turn about that cut's pivot
    /// (`shared`), or about its own again; a sibling cut that shared its pivot stops (a
    /// section turns about one point). Returns false when there is no such cut.
    pub fn set_shared_pivot(&mut self, name: &str, shared: bool) -> bool {
        self.changing();
        let Some(k) = self.find(name).filter(|&k| k > 0) else {
            return false;
        };
        let parent = self.sections[k].parent;
        for j in 1..self.sections.len() {
            if self.sections[j].parent == parent {
                self.cuts[j - 1].shared_pivot = false;
            }
        }
        self.cuts[k - 1].shared_pivot = shared;
        // Bands bend about the cuts' own pivots: only the turning points change.
        self.refresh_pivots();
        true
    }

    /// Which vertices `cut` would take of section `section` (its `section` name is not
    /// read), for a preview; none for a cut [`Joints::add_cut`] would refuse for its shape.
    pub fn preview(&self, section: usize, cut: &Cut) -> Vec<bool> {
        let normal = cut.normal.normalize_or_zero();
        if normal == DVec3::ZERO
            || !cut.point.is_finite()
            || !cut.shape.is_valid()
            || section >= self.sections.len()
        {
            return vec![false; self.section_of.len()];
        }
        self.taken(section, cut, normal)
    }

    /// Which vertices of section `parent` a cut with unit `normal` takes: those whose
    /// skeletal point lies strictly on its positive side, and when it is connected only the
    /// piece of them joined by mesh edges to the one nearest its point. Riders are never
    /// taken directly (they follow their hosts).
    fn taken(&self, parent: usize, cut: &Cut, normal: DVec3) -> Vec<bool> {
        let body = &self.body;
        let n = self.skeletal_of.len();
        let point = cut.point;
        if cut.shape == Shape::Skin {
            // The vertices of the section whose joint is this one or one below it.
            let (Some(skin), Some(joint)) = (&body.skin, self.skin_joint(&cut.name)) else {
                return vec![false; n];
            };
            return (0..n)
                .map(|i| {
                    !body.is_rider(i)
                        && self.skeletal_of[i] as usize == parent
                        && skin
                            .vertex_joint
                            .get(i)
                            .is_some_and(|&j| j != u32::MAX && skin.is_within(j as usize, joint))
                })
                .collect();
        }
        let candidate: Vec<bool> = (0..n)
            .map(|i| {
                !body.is_rider(i)
                    && self.skeletal_of[i] as usize == parent
                    && cut.signed(body.points[i], normal) > 0.0
            })
            .collect();
        if !cut.connected || body.neighbours.is_empty() {
            return candidate;
        }
        let seed = (0..n).filter(|&i| candidate[i]).min_by(|&a, &b| {
            let (da, db) = (
                body.points[a].distance_squared(point),
                body.points[b].distance_squared(point),
            );
            da.total_cmp(&db)
        });
        let mut taken = vec![false; n];
        let Some(seed) = seed else {
            return taken;
        };
        taken[seed] = true;
        let mut stack = vec![seed as u32];
        while let Some(v) = stack.pop() {
            for &w in body.neighbours(v as usize) {
                if candidate[w as usize] && !taken[w as usize] {
                    taken[w as usize] = true;
                    stack.push(w);
                }
            }
        }
        taken
    }

    /// The mesh edges from section `k` to its parent section `parent`: how many end in the
    /// piece `taken`, and how many in the rest of it.
    fn seam_sides(&self, k: usize, parent: usize, taken: &[bool]) -> (usize, usize) {
        let (mut on, mut off) = (0, 0);
        for i in (0..self.skeletal_of.len()).filter(|&i| self.skeletal_of[i] as usize == k) {
            for &w in self.body.neighbours(i) {
                if taken[w as usize] {
                    on += 1;
                } else if self.skeletal_of[w as usize] as usize == parent {
                    off += 1;
                }
            }
        }
        (on, off)
    }

    /// Each vertex's section from the cuts' (by skeletal points), made `whole` over the
    /// surface when the joints have one ([`super::whole`]; once a batch of cuts is in,
    /// not after each); riders take their hosts' sections; every section's vertex count
    /// is brought up to date.
    pub(super) fn assign_sections(&mut self, whole: bool) {
        self.changing();
        self.section_of.clone_from(&self.skeletal_of);
        self.borrowed.clear();
        self.whole_part.clear();
        if whole && !self.body.rest.is_empty() && self.make_whole() > 0 {
            self.borrow_points();
        }
        let host = &self.body.host;
        if !host.is_empty() {
            for i in 0..self.section_of.len() {
                if let Some(&h) = host.get(i).filter(|&&h| h != super::NO_HOST) {
                    self.section_of[i] = self.section_of[h as usize];
                }
            }
        }
        for s in &mut self.sections {
            s.vertices = 0;
        }
        for &s in &self.section_of {
            self.sections[s as usize].vertices += 1;
        }
    }

    /// Removes the cut that made section `name`: the section merges back into the one it was
    /// cut from, and cuts that split it now split that one. The skeleton is not touched. On
    /// error (the replay of the remaining cuts fails) nothing changes.
    pub fn remove_cut(&mut self, name: &str) -> Result<(), JointError> {
        self.changing();
        self.remove_cut_unbanded(name)?;
        self.refresh_bands();
        Ok(())
    }

    /// [`Joints::remove_cut`] but the bands, which the caller refreshes before the joints
    /// pose anything ([`Joints::refresh_bands`]): the sections are assigned.
    pub(super) fn remove_cut_unbanded(&mut self, name: &str) -> Result<(), JointError> {
        self.changing();
        let k = self
            .cuts
            .iter()
            .position(|c| c.name == name)
            .ok_or_else(|| JointError::NoSuchCut(name.to_string()))?;
        let mut cuts = self.cuts.clone();
        let removed = cuts.remove(k);
        for c in &mut cuts {
            if c.section == removed.name {
                c.section = removed.section.clone();
            }
        }
        let mut rebuilt = self.uncut();
        for c in cuts {
            match rebuilt.insert_cut(c.clone()) {
                // Two shared pivots on the section they now both split: the first keeps it.
                Err(JointError::SharedPivot { .. }) => rebuilt.insert_cut(Cut {
                    shared_pivot: false,
                    ..c
                })?,
                r => r?,
            };
        }
        rebuilt.assign_sections(true);
        *self = rebuilt;
        Ok(())
    }

    /// Moves the pivot of the cut that made section `index` (the root's own pivot for 0);
    /// a section sharing it turns about the new point too. A non-finite pivot changes
    /// nothing.
    pub fn set_pivot(&mut self, index: usize, pivot: DVec3) {
        self.changing();
        if !pivot.is_finite() || index >= self.sections.len() {
            return;
        }
        match index {
            0 => self.root_pivot = pivot,
            k => self.cuts[k - 1].pivot = Some(pivot),
        }
        self.refresh_pivots();
        self.refresh_bands();
    }

    /// The default pivot of a sphere or a box cut: the centroid of the skeletal points of
    /// the vertices it takes that have a mesh neighbour of section `parent` it leaves (the
    /// seam); without a mesh, of the `max(4, √m)` taken nearest its surface.
    fn seam_pivot(&self, taken: &[bool], parent: usize, cut: &Cut, normal: DVec3) -> DVec3 {
        let body = &self.body;
        let seam: Vec<DVec3> = (0..taken.len())
            .filter(|&i| {
                taken[i]
                    && body.neighbours(i).iter().any(|&w| {
                        let w = w as usize;
                        !taken[w] && !body.is_rider(w) && self.skeletal_of[w] as usize == parent
                    })
            })
            .map(|i| body.points[i])
            .collect();
        if seam.is_empty() {
            return self.default_pivot(taken, cut, normal);
        }
        seam.iter().copied().sum::<DVec3>() / seam.len() as f64
    }

    /// The pivot a cut gets by default: the centroid of the skeletal points of `among`
    /// that lie nearest its surface (the `max(4, √m)` nearest of its `m` points), for a
    /// plane projected onto it. `normal` is the cut's unit normal.
    fn default_pivot(&self, among: &[bool], cut: &Cut, normal: DVec3) -> DVec3 {
        let mut near: Vec<(f64, DVec3)> = among
            .iter()
            .zip(&self.body.points)
            .filter(|(t, _)| **t)
            .map(|(_, p)| (cut.signed(*p, normal).abs(), *p))
            .collect();
        let k = ((near.len() as f64).sqrt().ceil() as usize)
            .max(4)
            .min(near.len());
        if k == 0 {
            return cut.point;
        }
        near.select_nth_unstable_by(k - 1, |a, b| a.0.total_cmp(&b.0));
        let centroid = near[..k].iter().map(|(_, p)| *p).sum::<DVec3>() / k as f64;
        match cut.shape {
            Shape::Plane => centroid - normal * cut.signed(centroid, normal),
            _ => centroid,
        }
    }
}
