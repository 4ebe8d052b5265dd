//! Down one limb: its chain of names (`arm`, `forearm`, `hand`; `leg`, `shin`, `foot`, or
//! `leg`, `foot` where the joint below the hip points back, a hock; `neck`, `head`) and
//! what branches from it: the digits of a hand or a foot, a head's ears, horns and
//! antennae.

use super::naming::{short, Naming};
use super::tagged;
use crate::joints::suggest::rules::{ANTENNA, HOCK, SLENDER};
use glam::DVec3;

impl Naming<'_> {
    /// Names section `s` and the single chain that follows it with `family`'s names (side
    /// `tag`), then what branches from the chain: digits of a hand or foot, ears of a head.
    pub(super) fn chain(&mut self, s: usize, family: Family, tag: &str) {
        let list = family.names();
        let mut at = s;
        let mut k = 0;
        // A leg's next joint that points back is its ankle (a hock): its foot, with the
        // knee hidden in the body above it.
        let mut skip = 0;
        loop {
            if family == Family::Leg && k == 1 && self.points_back(s, at) {
                skip = 1;
            }
            let n = k + skip;
            let base = if n < list.len() {
                list[n].clone()
            } else {
                format!("{}.{}", list[list.len() - 1], n - list.len() + 2)
            };
            self.names[at] = Some(tagged(&base, tag));
            match self.children[at].as_slice() {
                [] => {
                    if family == Family::Leg && skip == 0 && k >= 3 {
                        self.foot_ahead(s, tag);
                    }
                    return;
                }
                // A lone part with none of its own, at most SLENDER as thick as the limb it
                // hangs from, is a digit on it (a thumb on an arm whose hand is not cut),
                // not the limb's next stretch.
                [only] if self.lone_digit(at, *only, family) => {
                    let digit = if family == Family::Arm {
                        "thumb"
                    } else {
                        "toe"
                    };
                    self.names[*only] = Some(tagged(digit, tag));
                    return;
                }
                // A neck's one short part with none of its own, at most SLENDER as thick as
                // the neck (a snout, a beak turned aside, not a head), is the head's end,
                // no joint: the neck is the head.
                [only]
                    if family == Family::Neck
                        && self.children[*only].is_empty()
                        && short(&self.reach(*only))
                        && self.reach(*only).end <= SLENDER * self.reach(at).end =>
                {
                    self.ends.push(*only);
                    self.names[at] = Some(tagged("head", tag));
                    return;
                }
                [only] if !(family == Family::Neck && k + 1 >= list.len()) => {
                    at = *only;
                    k += 1;
                }
                _ => break,
            }
        }
        if family != Family::Neck {
            if family == Family::Leg && skip == 0 && k >= 3 {
                self.foot_ahead(s, tag);
            }
            self.digits(at, tag);
            return;
        }
        // A neck whose head has no cut of its own is the head.
        if k == 0 && self.children[at].len() >= 2 {
            self.names[at] = Some(tagged("head", tag));
        }
        // Off the plane: ears; on it, below the head: a jaw. A head's one short part on the
        // plane (a snout, a muzzle, a nose: at most SNOUT of its own thickness long) is its
        // end, no joint; a jaw is one of two (an open mouth).
        let kids = self.children[at].clone();
        let on_plane: Vec<usize> = kids
            .iter()
            .copied()
            .filter(|&c| self.side(self.sections[c].pivot).is_none())
            .collect();
        // With two or more parts on one side (ears and horns), the one pointing most
        // up is a horn.
        let up = self.frame.up;
        let horns: Vec<usize> = ["L", "R"]
            .iter()
            .filter_map(|&lr| {
                let mine: Vec<usize> = kids
                    .iter()
                    .copied()
                    .filter(|&c| self.side(self.sections[c].pivot) == Some(lr))
                    .collect();
                if mine.len() < 2 {
                    return None;
                }
                mine.into_iter()
                    .map(|c| (c, self.reach(c).direction().dot(up)))
                    .max_by(|a, b| a.1.total_cmp(&b.1))
                    .map(|(c, _)| c)
            })
            .collect();
        for c in kids {
            match self.side(self.sections[c].pivot) {
                Some(lr) if horns.contains(&c) => self.chain(c, Family::Horn, lr),
                Some(lr) if self.feeler(c) => self.chain(c, Family::Antenna, lr),
                Some(lr) => self.chain(c, Family::Ear, lr),
                None => {
                    if on_plane.len() == 1 && short(&self.reach(c)) && self.children[c].is_empty() {
                        self.ends.push(c);
                        continue;
                    }
                    self.chain(c, Family::Jaw, "");
                }
            }
        }
    }

    /// Whether `c`, the only part of limb section `at` (of `family`), is a digit on it: an
    /// arm's or a leg's (an insect's numbered legs' digits are its feet's `toe1`…), with no
    /// parts of its own, its far half at most [`SLENDER`] as
    /// thick as the far half of the limb with it.
    pub(super) fn lone_digit(&self, at: usize, c: usize, family: Family) -> bool {
        matches!(family, Family::Arm | Family::Leg)
            && self.children[c].is_empty()
            && self.reach(c).end <= SLENDER * self.reach(at).end
    }

    /// A head's feelers ([`Naming::feeler`]) are an insect's, on a body whose legs are
    /// numbered (three pairs or more): on any other, a head's long thin parts off the plane
    /// are its ears (a donkey's, a fox's), unless an ear of that name is there already.
    pub(super) fn ears_unless_insect(&mut self) {
        let insect = self.names.iter().flatten().any(|n| {
            n.strip_prefix("leg")
                .is_some_and(|rest| rest.starts_with(|c: char| c.is_ascii_digit()))
        });
        if insect {
            return;
        }
        let taken: std::collections::HashSet<String> =
            self.names.iter().flatten().cloned().collect();
        for name in self.names.iter_mut().flatten() {
            if let Some(rest) = name.strip_prefix("antenna") {
                let ear = format!("ear{rest}");
                // (Not where an ear of that name is already: each name once.)
                if !taken.contains(&ear) {
                    *name = ear;
                }
            }
        }
    }

    /// Whether head part `c` is a feeler (an insect's antenna, not an ear or a horn): at
    /// least [`ANTENNA`] times as long as its far half is thick, and that far half round,
    /// no wider across than thick (a big flat ear is long against its thickness too).
    pub(super) fn feeler(&self, c: usize) -> bool {
        let r = self.reach(c);
        let reach = r.tip.distance(r.pivot);
        if reach < ANTENNA * r.end {
            return false;
        }
        // The far half's spread across its long axis: the root mean square of its points'
        // distances from that axis, per direction across (a round tube of radius `t`
        // spreads 0.71 t; a flat ear as much as it is wide).
        let far: Vec<DVec3> = self.within[c]
            .iter()
            .map(|&v| self.mesh.positions[v])
            .filter(|p| p.distance(r.pivot) >= 0.5 * reach)
            .collect();
        let mean = far.iter().sum::<DVec3>() / far.len().max(1) as f64;
        let axis = crate::joints::suggest::limbs::long_axis(far.iter().map(|&p| p - mean));
        let across = far
            .iter()
            .map(|&p| (p - mean).reject_from_normalized(axis).length_squared())
            .sum::<f64>()
            / (2 * far.len()).max(1) as f64;
        across.sqrt() <= r.end
    }

    /// Names the branches of section `at`: four or five digits as fingers (thumb first) or
    /// toes; each digit's chain goes on with `.2`, `.3`…. A branch of the root pointing
    /// away from the digits (a forearm below a palm) is the forearm.
    pub(super) fn digits(&mut self, at: usize, tag: &str) {
        let kids = self.children[at].clone();
        if kids.len() < 2 {
            return;
        }
        let dirs: Vec<DVec3> = kids.iter().map(|&c| self.reach(c).direction()).collect();
        let mean = dirs.iter().sum::<DVec3>().normalize_or_zero();
        let digits: Vec<usize> = (0..kids.len())
            .filter(|&i| dirs[i].dot(mean) > 0.0)
            .collect();
        let toes = self.names[at]
            .as_deref()
            .is_some_and(|n| n.starts_with("foot"));
        // A hand not cut at its wrist: of two parts, one with two or more digits of its
        // own and one with none, the first is the hand and the other its thumb.
        if !toes && at != 0 && digits.len() == 2 {
            let (a, b) = (kids[digits[0]], kids[digits[1]]);
            let palm = |c: usize| self.children[c].len() >= 2;
            let bare = |c: usize| self.children[c].is_empty();
            let pair = if palm(a) && bare(b) {
                Some((a, b))
            } else if palm(b) && bare(a) {
                Some((b, a))
            } else {
                None
            };
            if let Some((hand, thumb)) = pair {
                self.names[hand] = Some(tagged("hand", tag));
                self.digit(thumb, &tagged("thumb", tag));
                self.digits(hand, tag);
                return;
            }
        }
        if !toes && (4..=5).contains(&digits.len()) {
            // The thumb is the digit turned most from the others; the rest by distance
            // from it.
            let others = |i: usize| {
                digits
                    .iter()
                    .filter(|&&j| j != i)
                    .map(|&j| dirs[j])
                    .sum::<DVec3>()
                    .normalize_or_zero()
            };
            let thumb = digits
                .iter()
                .copied()
                .min_by(|&a, &b| dirs[a].dot(others(a)).total_cmp(&dirs[b].dot(others(b))))
                .unwrap_or(digits[0]);
            let base = self.sections[kids[thumb]].pivot;
            let mut order = digits.clone();
            order.sort_by(|&a, &b| {
                let d = |i: usize| self.sections[kids[i]].pivot.distance(base);
                d(a).total_cmp(&d(b))
            });
            let fingers = ["thumb", "index", "middle", "ring", "little"];
            let skip = 5 - digits.len();
            for (rank, &i) in order.iter().enumerate() {
                let name = if rank == 0 {
                    fingers[0]
                } else {
                    fingers[rank + skip]
                };
                self.digit(kids[i], &tagged(name, tag));
            }
        } else if digits.len() >= 2 {
            let base = if toes { "toe" } else { "finger" };
            for (rank, &i) in digits.iter().enumerate() {
                self.digit(kids[i], &tagged(&format!("{base}{}", rank + 1), tag));
            }
        }
        if at == 0 {
            for (i, &c) in kids.iter().enumerate() {
                if !digits.contains(&i) && self.names[c].is_none() {
                    self.digit(c, &tagged("forearm", tag));
                }
            }
        }
    }

    /// A leg's chain down from section `s`, longer than its three names: its `foot`
    /// is the first part below the knee that points ahead more than down (a foot off its
    /// ankle: a person's leg cut at a boot's top and at the ankle), the parts between the
    /// knee and it `shin.2`…, those below it `foot.2`…. A leg with a mirror image (the
    /// other of the pair) is renamed only where the other's foot is found at the same
    /// place down its chain, so the pair keeps one set of names.
    fn foot_ahead(&mut self, s: usize, tag: &str) {
        let path = self.down_from(s);
        let Some(foot) = self.ahead_at(&path) else {
            return;
        };
        if let Some(twin) = self.twin(s) {
            let other = self.down_from(twin);
            if other.len() != path.len() || self.ahead_at(&other) != Some(foot) {
                return;
            }
        }
        for (i, &c) in path.iter().enumerate().skip(2) {
            let name = if i < foot {
                format!("shin.{i}")
            } else if i == foot {
                "foot".to_string()
            } else {
                format!("foot.{}", i - foot + 1)
            };
            self.names[c] = Some(tagged(&name, tag));
        }
    }

    /// Section `s` and the sections down from it, each its predecessor's only part.
    fn down_from(&self, s: usize) -> Vec<usize> {
        let mut path = vec![s];
        while let [next] = self.children[path[path.len() - 1]].as_slice() {
            path.push(*next);
        }
        path
    }

    /// Down a leg's chain `path` (hip first), the first part below the knee whose own
    /// vertices lie more ahead of its pivot than below it.
    fn ahead_at(&self, path: &[usize]) -> Option<usize> {
        let (up, front) = (self.frame.up, self.frame.front);
        (2..path.len()).find(|&i| {
            let c = path[i];
            self.own_middle(c).is_some_and(|m| {
                let d = m - self.sections[c].pivot;
                d.dot(front) > -d.dot(up)
            })
        })
    }

    /// The middle of section `c`'s own vertices (not those of what hangs from it); `None`
    /// where it has none.
    fn own_middle(&self, c: usize) -> Option<DVec3> {
        let under: std::collections::HashSet<usize> = self.children[c]
            .iter()
            .flat_map(|&k| self.within[k].iter().copied())
            .collect();
        let own: Vec<DVec3> = (self.within[c].iter())
            .filter(|v| !under.contains(v))
            .map(|&v| self.mesh.positions[v])
            .collect();
        (!own.is_empty()).then(|| own.iter().sum::<DVec3>() / own.len() as f64)
    }

    /// The section beside `s` (of its parent) nearest its mirror image, within the
    /// thickness of `s`'s far half: the other limb of its pair.
    fn twin(&self, s: usize) -> Option<usize> {
        let plane = self.frame.mirror?;
        let parent = self.sections[s].parent?;
        let image = crate::mesh::mirror::image(plane, self.sections[s].pivot);
        let twin = (self.children[parent].iter().copied())
            .filter(|&c| c != s)
            .min_by(|&a, &b| {
                let d = |c: usize| self.sections[c].pivot.distance(image);
                d(a).total_cmp(&d(b))
            })?;
        (self.sections[twin].pivot.distance(image) <= self.reach(s).end).then_some(twin)
    }

    /// Whether the joint at the top of section `at`, the next down a leg from section `s`,
    /// points back by more than [`HOCK`] ([`Naming::bend`]): a hock, the ankle, with the
    /// knee hidden in the body above it (a knee points ahead, or not at all). A leg with a
    /// mirror image (the other leg of the pair) is measured with it, so both get one name.
    fn points_back(&self, s: usize, at: usize) -> bool {
        let Some(own) = self.bend(s, at) else {
            return false;
        };
        // The other leg, and its one part.
        let other = self
            .twin(s)
            .and_then(|twin| match self.children[twin].as_slice() {
                [next] => self.bend(twin, *next),
                _ => None,
            });
        let bend = other.map_or(own, |o| 0.5 * (own + o));
        bend < -HOCK
    }

    /// How far ahead the joint at the top of section `at` (the next down a limb from
    /// section `s`) points: `(upper − lower) · front`, the unit directions from `s`'s pivot
    /// to `at`'s and from `at`'s to the next joint's (or, at the limb's end, to the middle
    /// of `at`'s own vertices). `None` where it has none.
    fn bend(&self, s: usize, at: usize) -> Option<f64> {
        let (top, joint) = (self.sections[s].pivot, self.sections[at].pivot);
        let upper = (joint - top).normalize_or_zero();
        let below = match self.children[at].as_slice() {
            [next] => self.sections[*next].pivot,
            _ => self.own_middle(at)?,
        };
        let lower = (below - joint).normalize_or_zero();
        Some((upper - lower).dot(self.frame.front))
    }

    /// Names a digit's chain: `index`, `index.2`, `index.3`….
    pub(super) fn digit(&mut self, s: usize, name: &str) {
        let mut at = s;
        let mut k = 1;
        loop {
            self.names[at] = Some(if k == 1 {
                name.to_string()
            } else {
                format!("{name}.{k}")
            });
            match self.children[at].as_slice() {
                [only] => {
                    at = *only;
                    k += 1;
                }
                _ => return,
            }
        }
    }
}

/// What a chain of cuts down one limb is called.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Family {
    Arm,
    Leg,
    /// Legs numbered from the front (an insect's).
    Numbered(usize),
    Neck,
    Tail,
    /// A head's part on the mirror plane below it, one of two (an open mouth).
    Jaw,
    /// A part pointing back that ends as thick as the head (an insect's).
    Abdomen,
    Ear,
    Horn,
    /// A head's long thin part off the plane (an insect's feeler).
    Antenna,
}

impl Family {
    /// The names down the chain, base first.
    pub(super) fn names(self) -> Vec<String> {
        match self {
            Family::Arm => vec!["arm".into(), "forearm".into(), "hand".into()],
            Family::Leg => vec!["leg".into(), "shin".into(), "foot".into()],
            Family::Numbered(k) => vec![format!("leg{k}"), format!("shin{k}"), format!("foot{k}")],
            Family::Neck => vec!["neck".into(), "head".into()],
            Family::Tail => vec!["tail".into()],
            Family::Jaw => vec!["jaw".into()],
            Family::Abdomen => vec!["abdomen".into()],
            Family::Ear => vec!["ear".into()],
            Family::Horn => vec!["horn".into()],
            Family::Antenna => vec!["antenna".into()],
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::orientation::Frame;
    use crate::mesh::Mesh;

    /// A section tree for naming: section `s` a row of `count` vertices from its pivot
    /// along its direction (`along[s]`), under `parent[s]`, each vertex of skeletal distance
    /// `radius(s)`; a section's `within` holds what hangs from it too. Named by `name`.
    pub(super) fn named<T>(
        along: &[(DVec3, DVec3)],
        parent: &[Option<usize>],
        count: usize,
        radius: impl Fn(usize) -> f64,
        name: impl FnOnce(&mut Naming) -> T,
    ) -> T {
        let mut positions = Vec::new();
        let mut radii = Vec::new();
        let mut within = vec![Vec::new(); along.len()];
        for (s, &(pivot, dir)) in along.iter().enumerate() {
            for k in 0..count {
                // Into this section and every one it hangs from.
                let mut at = Some(s);
                while let Some(a) = at {
                    within[a].push(positions.len());
                    at = parent[a];
                }
                positions.push(pivot + dir * (0.02 * k as f64));
                radii.push(radius(s));
            }
        }
        let sections: Vec<crate::joints::Section> = (0..along.len())
            .map(|s| crate::joints::Section {
                name: format!("s{s}"),
                parent: parent[s],
                pivot: along[s].0,
                vertices: count,
            })
            .collect();
        let mut children = vec![Vec::new(); along.len()];
        for (s, p) in parent.iter().enumerate() {
            if let Some(p) = p {
                children[*p].push(s);
            }
        }
        let mesh = Mesh {
            positions,
            triangles: Vec::new(),
        };
        let mut naming = Naming {
            mesh: &mesh,
            radius: &radii,
            sections: &sections,
            children,
            within,
            frame: Frame::default(),
            names: vec![None; along.len()],
            ends: Vec::new(),
            size: 1.0,
            base: None,
        };
        name(&mut naming)
    }

    /// A forearm ending in two parts, one carrying fingers (a hand not cut at its wrist)
    /// and one carrying none (Homer's): the first is the hand, the other its thumb, and
    /// the hand's parts are fingers.
    #[test]
    pub(super) fn a_part_carrying_fingers_beside_a_bare_one_is_a_hand_and_its_thumb() {
        // Sections: 0 the body, 1 the forearm, 2 the palm, 3 the thumb, 4–6 fingers.
        let along = [
            (DVec3::ZERO, DVec3::Y),
            (DVec3::new(0.3, 0.0, 0.0), DVec3::X),
            (DVec3::new(0.6, 0.0, 0.0), DVec3::X),
            (DVec3::new(0.55, 0.0, 0.05), DVec3::new(0.6, 0.0, 0.8)),
            (DVec3::new(0.7, 0.0, -0.03), DVec3::X),
            (DVec3::new(0.7, 0.0, 0.0), DVec3::X),
            (DVec3::new(0.7, 0.0, 0.03), DVec3::X),
        ];
        let parent = [None, Some(0), Some(1), Some(1), Some(2), Some(2), Some(2)];
        let names = named(
            &along,
            &parent,
            5,
            |_| 0.01,
            |naming| {
                naming.digits(1, "L");
                naming.names.clone()
            },
        );
        let names: Vec<Option<&str>> = names.iter().map(|n| n.as_deref()).collect();
        assert_eq!(names[2], Some("hand.L"), "{names:?}");
        assert_eq!(names[3], Some("thumb.L"), "{names:?}");
        for s in 4..7 {
            assert!(
                names[s].is_some_and(|n| n.starts_with("finger")),
                "{names:?}"
            );
        }
    }

    /// An arm whose hand is not cut, with one thin part of its own (Cheburashka's thumb
    /// sticking out, 13 and 17 vertices): that part is its thumb, not its forearm; a part
    /// as thick as the arm's far end is the forearm.
    #[test]
    pub(super) fn an_arm_s_lone_thin_part_is_its_thumb() {
        let name = |thumb_radius: f64| {
            // Sections: 0 the body, 1 the arm, 2 its one part.
            let along = [
                (DVec3::ZERO, DVec3::Y),
                (DVec3::new(0.3, 0.0, 0.0), DVec3::X),
                (DVec3::new(0.45, 0.0, 0.02), DVec3::Z),
            ];
            let radius = |s: usize| if s == 2 { thumb_radius } else { 0.03 };
            named(&along, &[None, Some(0), Some(1)], 8, radius, |naming| {
                naming.chain(1, Family::Arm, "L");
                naming.names[2].clone()
            })
        };
        assert_eq!(name(0.007).as_deref(), Some("thumb.L"));
        assert_eq!(name(0.025).as_deref(), Some("forearm.L"));
    }

    /// A person in clothes cut at the shirt's hem, then at the trousers' crotch: the chain
    /// on the mirror plane is the waist and the hips, and the two parts off it at its end
    /// are the legs (as the arms are arms).
    #[test]
    fn a_chain_hanging_down_the_midline_to_two_legs_is_the_waist_and_the_hips() {
        // Sections: 0 the chest, 1 below the hem, 2 the crotch, 3–4 legs, 5–6 arms.
        let along = [
            (DVec3::new(0.0, 1.3, 0.0), DVec3::Y),
            (DVec3::new(0.0, 1.2, 0.0), DVec3::NEG_Y),
            (DVec3::new(0.0, 1.0, 0.0), DVec3::NEG_Y),
            (DVec3::new(0.1, 0.9, 0.0), DVec3::NEG_Y),
            (DVec3::new(-0.1, 0.9, 0.0), DVec3::NEG_Y),
            (DVec3::new(0.2, 1.45, 0.0), DVec3::X),
            (DVec3::new(-0.2, 1.45, 0.0), DVec3::NEG_X),
        ];
        let parent = [None, Some(0), Some(1), Some(2), Some(2), Some(0), Some(0)];
        let names = named(
            &along,
            &parent,
            8,
            |_| 0.02,
            |naming| {
                naming.frame.mirror = Some((DVec3::X, 0.0));
                let limbs: Vec<_> = naming.children[0]
                    .clone()
                    .into_iter()
                    .map(|s| (s, naming.reach(s)))
                    .collect();
                naming.root(&limbs);
                naming.names.clone()
            },
        );
        let names: Vec<Option<&str>> = names.iter().map(|n| n.as_deref()).collect();
        assert_eq!(names[1], Some("waist"), "{names:?}");
        assert_eq!(names[2], Some("hips"), "{names:?}");
        assert_eq!(names[3], Some("leg.L"), "{names:?}");
        assert_eq!(names[4], Some("leg.R"), "{names:?}");
        assert_eq!(names[5], Some("arm.L"), "{names:?}");
    }
}
