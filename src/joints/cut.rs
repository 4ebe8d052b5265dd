//! Applying and removing cuts: which vertices a cut takes (the positive side of its plane
//! in the section it splits, or only the connected piece of it), where its pivot goes, and
//! which children follow the new section.

use super::pose::parents_first;
use super::{Cut, JointError, Joints, Section, MAX_SECTIONS};
use glam::DVec3;

impl Joints {
    /// Applies a cut; returns the new section's index. On error nothing changes.
    pub fn add_cut(&mut self, cut: Cut) -> Result<usize, JointError> {
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
        let taken = self.taken(parent, cut.point, normal, cut.connected);
        let inside = taken.iter().filter(|&&t| t).count();
        let outside = (0..self.section_of.len())
            .filter(|&i| !self.body.is_rider(i) && self.section_of[i] as usize == parent)
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
            // A plane's pivot comes from the whole section near it; a connected cut's from
            // the piece it takes (the section near a hip holds the other leg too).
            None if cut.connected => self.default_pivot(&taken, cut.point, normal),
            None => {
                let section: Vec<bool> = (0..self.section_of.len())
                    .map(|i| !self.body.is_rider(i) && self.section_of[i] as usize == parent)
                    .collect();
                self.default_pivot(&section, cut.point, normal)
            }
        };
        let index = self.sections.len();
        for (s, &t) in self.section_of.iter_mut().zip(&taken) {
            if t {
                *s = index as u16;
            }
        }
        // Children of the split section follow it when their pivot is on the new side (and,
        // for a connected cut, when they touch the piece taken).
        let side = |p: DVec3| (p - cut.point).dot(normal) > 0.0;
        let follows: Vec<bool> = (0..self.sections.len())
            .map(|k| {
                let s = &self.sections[k];
                s.parent == Some(parent)
                    && side(s.pivot)
                    && (!cut.connected || self.touches(k, &taken))
            })
            .collect();
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
        self.place_riders();
        self.order = parents_first(&self.sections);
        self.refresh_bands();
        Ok(index)
    }

    /// Which vertices a cut of section `section` through `point` with `normal` (any
    /// non-zero length) would take, for a preview.
    pub fn preview(
        &self,
        section: usize,
        point: DVec3,
        normal: DVec3,
        connected: bool,
    ) -> Vec<bool> {
        let normal = normal.normalize_or_zero();
        if normal == DVec3::ZERO || !point.is_finite() || section >= self.sections.len() {
            return vec![false; self.section_of.len()];
        }
        self.taken(section, point, normal, connected)
    }

    /// Which vertices of section `parent` a cut through `point` with unit `normal` takes:
    /// those whose skeletal point lies strictly on the side the normal points to, and with
    /// `connected` only the piece of them joined by mesh edges to the one nearest `point`.
    /// Riders are never taken directly (they follow their hosts).
    fn taken(&self, parent: usize, point: DVec3, normal: DVec3, connected: bool) -> Vec<bool> {
        let body = &self.body;
        let n = self.section_of.len();
        let candidate: Vec<bool> = (0..n)
            .map(|i| {
                !body.is_rider(i)
                    && self.section_of[i] as usize == parent
                    && (body.points[i] - point).dot(normal) > 0.0
            })
            .collect();
        if !connected || body.neighbours.is_empty() {
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

    /// Does section `k` have a vertex joined by a mesh edge to one of `taken`?
    fn touches(&self, k: usize, taken: &[bool]) -> bool {
        (0..self.section_of.len()).any(|i| {
            self.section_of[i] as usize == k
                && self.body.neighbours(i).iter().any(|&w| taken[w as usize])
        })
    }

    /// Riders take their hosts' sections; every section's vertex count is brought up to
    /// date.
    fn place_riders(&mut self) {
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
            rebuilt.add_cut(c)?;
        }
        *self = rebuilt;
        Ok(())
    }

    /// Moves the pivot of section `index` (for the root too).
    pub fn set_pivot(&mut self, index: usize, pivot: DVec3) {
        if !pivot.is_finite() || index >= self.sections.len() {
            return;
        }
        self.sections[index].pivot = pivot;
        if index > 0 {
            self.cuts[index - 1].pivot = Some(pivot);
        }
    }

    /// The pivot a cut gets by default: the centroid of the skeletal points of `among`
    /// that lie nearest the plane (the `max(4, √m)` nearest of its `m` points), projected
    /// onto the plane.
    fn default_pivot(&self, among: &[bool], point: DVec3, normal: DVec3) -> DVec3 {
        let mut near: Vec<(f64, DVec3)> = among
            .iter()
            .zip(&self.body.points)
            .filter(|(t, _)| **t)
            .map(|(_, p)| ((*p - point).dot(normal).abs(), *p))
            .collect();
        let k = ((near.len() as f64).sqrt().ceil() as usize)
            .max(4)
            .min(near.len());
        if k == 0 {
            return point;
        }
        near.select_nth_unstable_by(k - 1, |a, b| a.0.total_cmp(&b.0));
        let centroid = near[..k].iter().map(|(_, p)| *p).sum::<DVec3>() / k as f64;
        centroid - normal * (centroid - point).dot(normal)
    }
}
