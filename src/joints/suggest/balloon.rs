//! Balloons, once the suggested cuts apply and none tears ([`super::seams::add`]): a joint
//! that, turned alone, changes its own section's volume or its parent's by more than
//! [`BALLOON`] of its size loses its cut.
//!
//! Each section's volume is kept in a pose by its bands' slides and swells
//! ([`crate::joints::slide`], [`crate::joints::volume`]), each held to what the band's
//! width allows. A cut whose pivot lies far off its seam (a frog's body cut across its
//! trunk with the pivot at its side; a hind leg cut slantwise, its pivot six seam radii
//! off; a fish's fin) swings its child out like a door: the band's side that opens gains
//! more than any slide or swell gives back, and its section or its parent swells by a
//! third to two thirds in a pose. Such a joint is not one a puppeteer can turn without
//! the body ballooning, and the suggestion takes it back, as it takes back one whose skin
//! tears.
//!
//! Each cut is turned alone by the spread `puppet bench poses` draws from (±90° at the
//! root, ±60° below it) about four axes across its cut, posed as the puppet poses it
//! (volumes kept), and each of its two sections' capped volumes is measured where the
//! bones hold the surface, against its size at rest (its volume, or a hundredth of the
//! whole's for one that holds little, as `bench poses` measures it). The cut with the
//! largest change past [`BALLOON`] loses it, and the rest are turned again: a section
//! that ballooned only through a child's band keeps its own cut once that one is gone.
//!
//! Turning each cut alone four ways costs four poses a cut, which took the labelled
//! set's suggestion 1.4× as long. So every joint is first turned at once, four times
//! (each its own way), and only the cuts of a section that changes by half of
//! [`BALLOON`] there, or of its children, are turned alone: on the three corpora of
//! `bench poses` the same cuts are taken back as when every cut is turned alone (every
//! pose's figures the same), for about 3 ms a suggestion. Random poses (the tear
//! check's 16) missed one: a whale's head balloons in 2 of `bench poses`' 20.

use super::rules::BALLOON;
use crate::joints::spread::{across, Spread};
use crate::joints::{Joints, Local, PoseScratch};
use crate::mesh::measure::Capped;
use glam::DVec3;
use rayon::prelude::*;

/// The name of the section whose cut balloons the most past [`BALLOON`], if any (see the
/// module docs). Without rest positions it names none.
pub fn ballooned(joints: &Joints) -> Option<String> {
    let volumes = Volumes::of(joints)?;
    let worst = volumes
        .changes(joints, &volumes.suspects(joints))
        .into_iter()
        .max_by(|a, b| a.1.total_cmp(&b.1).then(a.0.cmp(&b.0)))?;
    (worst.1 > BALLOON).then(|| joints.sections()[worst.0].name.clone())
}

/// Each section's surface, capped, and its size at rest: what a pose's volumes are
/// measured against.
struct Volumes {
    /// Per section (empty for one no band ends on or starts from: no turn bends it).
    surfaces: Vec<Capped>,
    /// Per section, its volume at rest.
    rest: Vec<f64>,
    /// Per section, its size: its volume, or a share of the whole's for one that holds
    /// little (as `bench poses` measures it).
    size: Vec<f64>,
}

impl Volumes {
    /// `None` without rest positions or cuts.
    fn of(joints: &Joints) -> Option<Volumes> {
        let body = &joints.body;
        if body.rest.len() != joints.section_of().len() || joints.sections().len() < 2 {
            return None;
        }
        let surfaces = joints.capped_sections();
        let rest: Vec<f64> = surfaces.iter().map(|s| s.volume(&body.rest)).collect();
        let size = rest
            .iter()
            .map(|&v| crate::joints::section_size(v, body.whole))
            .collect();
        Some(Volumes {
            surfaces,
            rest,
            size,
        })
    }

    /// Section `s`'s volume change, by its size, with the surface at `now` (0 for one
    /// with no surface here).
    fn change(&self, s: usize, now: &[DVec3]) -> f64 {
        match (self.surfaces.get(s), self.size.get(s)) {
            (Some(surface), Some(&size)) if size > 0.0 => {
                ((surface.volume(now) - self.rest[s]) / size).abs()
            }
            _ => 0.0,
        }
    }

    /// The cuts worth turning alone: each cut of a section, or of a child of a section,
    /// whose volume changes by more than half of [`BALLOON`] with every joint turned at
    /// once, as far as the spread goes, one of the four ways (see [`Volumes::changes`]).
    /// A section's own cut and its children's all bend it then; one that balloons alone
    /// is seen there unless another's bend takes back half of it.
    fn suspects(&self, joints: &Joints) -> Vec<usize> {
        let sections = joints.sections();
        let changed: Vec<bool> = (0..4)
            .into_par_iter()
            .map(|way| {
                let local: Vec<Local> = (0..sections.len()).map(|k| turn(joints, k, way)).collect();
                let now = surface(joints, &local, &mut PoseScratch::default());
                (0..sections.len())
                    .map(|s| self.change(s, &now) > BALLOON / 2.0)
                    .collect::<Vec<bool>>()
            })
            .reduce(
                || vec![false; sections.len()],
                |a, b| a.iter().zip(&b).map(|(x, y)| *x || *y).collect(),
            );
        (1..sections.len())
            .filter(|&k| changed[k] || sections[k].parent.is_some_and(|p| changed[p]))
            .collect()
    }

    /// For each of `cuts` (by its section), the largest share by which turning it alone
    /// (see the module docs) changes its section's volume or its parent's.
    fn changes(&self, joints: &Joints, cuts: &[usize]) -> Vec<(usize, f64)> {
        let sections = joints.sections();
        cuts.par_iter()
            .filter_map(|&k| Some((k, sections[k].parent?)))
            .map_init(
                || {
                    (
                        PoseScratch::default(),
                        vec![Local::default(); sections.len()],
                    )
                },
                |(scratch, local), (k, parent)| {
                    let largest = (0..4)
                        .map(|way| {
                            local[k] = turn(joints, k, way);
                            let now = surface(joints, local, scratch);
                            local[k] = Local::default();
                            self.change(k, &now).max(self.change(parent, &now))
                        })
                        .fold(0.0, f64::max);
                    (k, largest)
                },
            )
            .collect()
    }
}

/// Section `k`'s turn one of four `way`s: as far as the spread goes (see the module
/// docs) about either axis across its cut, either way (a fin's or a trunk's two sides
/// are not alike, and the turn that closes one can balloon where the other does not).
/// The root does not turn.
fn turn(joints: &Joints, k: usize, way: usize) -> Local {
    match across(joints, k, Spread::default()) {
        Some((a, b, degrees)) => Local::axis_angle([a, b, -a, -b][way % 4], degrees),
        None => Local::default(),
    }
}

/// The surface where the bones of the pose `local` hold it ([`Joints::held_surface`]).
fn surface(joints: &Joints, local: &[Local], scratch: &mut PoseScratch) -> Vec<DVec3> {
    let mut now = joints.body.rest.clone();
    joints.held_surface(local, scratch, &mut now);
    now
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::joints::Cut;

    /// A capsule along y, 2.6 long and 0.6 thick, cut across its middle into `upper` with
    /// its pivot at `pivot`.
    fn halved(pivot: DVec3) -> Joints {
        let mesh = crate::mesh::shapes::capsule(0.3, 1.0, 8, 40, 32);
        let mut p = crate::puppet::Puppet::build(
            mesh,
            crate::puppet::RigFile::default(),
            crate::progress::silent(),
        )
        .expect("a capsule builds");
        let root = p.joints.sections()[0].name.clone();
        let cut = Cut {
            pivot: Some(pivot),
            ..Cut::plane("upper", &root, DVec3::ZERO, DVec3::Y)
        };
        p.joints.add_cut(cut).expect("the cut fits");
        p.joints
    }

    /// The capsule's one cut turned alone: its largest change.
    fn turned_alone(joints: &Joints) -> f64 {
        let volumes = Volumes::of(joints).expect("rest positions and a cut");
        volumes.changes(joints, &[1])[0].1
    }

    #[test]
    fn a_joint_turned_about_a_pivot_far_off_its_seam_balloons_and_one_on_its_axis_does_not() {
        // Pivot on the capsule's axis: a turn bends the band, and the slides and swells
        // keep both halves' volumes (1.0 %).
        let centred = halved(DVec3::ZERO);
        let change = turned_alone(&centred);
        assert!(change < BALLOON / 2.0, "on the axis: {change}");
        assert_eq!(ballooned(&centred), None);
        // Pivot three radii off the axis (on the rim, the swells still give back what
        // the side that opens gains: 2.8 %): turned 90° about it, the upper half swings
        // out like a door, and its band's side stretches by more than they can give.
        let hinged = halved(DVec3::new(0.9, 0.0, 0.0));
        let change = turned_alone(&hinged);
        assert!(change > BALLOON, "three radii off: {change}");
        assert_eq!(ballooned(&hinged), Some("upper".into()));
    }
}
