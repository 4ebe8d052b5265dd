//! The response of one point to the balls it meets (see [`super::Colliders`],
//! *Response* and *Caught, let go*): out along the line from the ball's centre, at most
//! half its shortest edge farther off its bones than the step left it; its motion into
//! the ball dropped.

use super::{Colliders, Stage};
use glam::Vec3;

/// The most margin a point keeps from a foreign ball, as a share of its own medial
/// radius: the margin is a share of the mesh's diagonal, and on a body a finger's radius
/// is not much more (a finger held that far from the next was pulled off its bones, and
/// its skin stretched 2.94×).
const MARGIN_SHARE: f32 = 0.25;

/// How much farther from where its bones hold it than the step left it a contact may
/// move a point, as a share of its shortest rest edge (`slot_edge`). A neighbour left
/// where it was then stretches that edge at most 1.5×. A whole edge let a mech's leg,
/// pushed off its hip's balls, stretch 2.28× where the same pose without collision
/// stretched 1.20×; half an edge fixes as much at the parts' surfaces (every press of
/// `bench collide` the same, soft flesh denting as deep).
const PUSH: f32 = 0.5;

impl Colliders {
    /// Puts slot `k`, at `x` after the step and at `p` before it, out of the foreign balls
    /// among `candidates`. Returns, when that moves it, where it goes and its velocity
    /// after the response.
    pub(super) fn point(
        &self,
        stage: &Stage,
        k: usize,
        candidates: &[u32],
        sweep: bool,
        x: Vec3,
        p: Vec3,
    ) -> Option<(Vec3, Vec3)> {
        let slots = &stage.layout.slots;
        let (section, rest, own) = (
            self.slot_section[k],
            slots.rest.get(k),
            f64::from(self.slot_radius[k]),
        );
        // Where its bones hold it: a ball that merely caught it on the way lets it go
        // (see `caught`).
        let target = stage
            .transforms
            .get(usize::from(slots.section[k]))
            .map(|t| t.transform_point3(rest));
        // (A finger keeps a finger's margin, not the body's.)
        let margin = stage.margin.min(MARGIN_SHARE * own as f32);
        let (mut x, start) = (x, x);
        let mut normal = None;
        for _pass in 0..2 {
            let mut again = false;
            for &b in candidates {
                let b = b as usize;
                let Some(yields) = self.meets(section, self.section[b]) else {
                    continue;
                };
                // Soft flesh: a part pressed into it sinks into its balls by the flesh's
                // give, and its own balls, grown by as much (its surface bulges around
                // them as it squashes), push the flesh in; the flesh is never swept (it
                // does not follow the part).
                let (c, whole) = (self.posed[b], self.radius[b] + margin);
                let give = self.radius[b] * stage.flesh;
                let r = if yields { whole - give } else { whole + give };
                let sweep = sweep && yields;
                let d = x - c;
                let d2 = d.length_squared();
                if d2 >= r * r && (!sweep || entry(p + (c - self.before[b]), x, c, r).is_none()) {
                    // Outside, and (swept) its way did not cross the ball: whatever follows
                    // leaves it.
                    continue;
                }
                if yields && target.is_some_and(|t| caught(t, x, c, r, own as f32)) {
                    continue;
                }
                // Near at rest: the flesh about their joint, never pushed.
                if self.ignores(stage, k, b) {
                    continue;
                }
                // Two parts that merely rest near each other collide; where the point lay
                // inside the ball at rest, it is put back only as far out as it lay then
                // (and not swept: it may be inside).
                let joint = self.slot_joint.get(k).copied().unwrap_or(0);
                let at_rest = rest.distance(self.center[b]);
                let (r, sweep) = if self.everywhere || (joint != 0 && joint == self.joint[b]) {
                    (r, sweep)
                } else if at_rest < r.max(whole) {
                    let r = r.min(at_rest);
                    if d2 >= r * r {
                        continue;
                    }
                    (r, false)
                } else {
                    (r, sweep)
                };
                let to = if d2 < r * r {
                    // Inside: out along the line from the centre (or, at the centre, back
                    // the way it came).
                    let dir = d
                        .try_normalize()
                        .or_else(|| (p - x).try_normalize())
                        .unwrap_or(Vec3::Y);
                    Some((c + dir * r, dir))
                } else if sweep {
                    // Outside now: did it cross the ball in this step (in the ball's frame)?
                    let from = p + (c - self.before[b]);
                    entry(from, x, c, r).map(|e| (e, (e - c) / r))
                } else {
                    None
                };
                if let Some((to, n)) = to {
                    x = to;
                    normal = Some(n);
                    again = true;
                }
            }
            if !again {
                break;
            }
        }
        let mut n = normal?;
        if !x.is_finite() {
            return None;
        }
        // No farther from where its bones hold it than half its shortest edge more than
        // the step left it (see `PUSH`).
        if let Some(t) = target {
            let (most, off) = (
                (PUSH * self.slot_edge[k]).max(start.distance(t)),
                x.distance(t),
            );
            if off > most {
                x = t + (x - t) * (most / off);
            }
        }
        // The floor, a half-space contact with the same response, wins.
        if let Some(floor) = stage.floor {
            if let Some(lifted) = floor.lift(x) {
                x = lifted;
                n = floor.up.vector();
            }
        }
        // Response: the motion into the ball is dropped, the sliding motion keeps `keep`.
        let v = x - p;
        let along = v.dot(n);
        let tangent = v - n * along;
        let v = tangent * stage.keep + n * along.max(0.0);
        if x == start && v == start - p {
            return None;
        }
        Some((x, v))
    }
}

/// A point at `x` whose bones hold it at `target`, farther than its own radius `own`
/// away, is caught on the ball `(c, r)` when the target lies outside it: the part's pose
/// does not press it into the ball (the pose limit stopped the parts apart), only its way
/// there crossed it. Held, it stays on the near side while its neighbours reach their
/// places, and the skin between tears; let go, it goes where its bones hold it.
fn caught(target: Vec3, x: Vec3, c: Vec3, r: f32, own: f32) -> bool {
    target.distance_squared(c) >= r * r && target.distance_squared(x) > own * own
}

/// The first point where the segment `a → b` enters the ball `(c, r)`, when `a` is
/// outside it and the segment passes through it.
fn entry(a: Vec3, b: Vec3, c: Vec3, r: f32) -> Option<Vec3> {
    let d = b - a;
    let len2 = d.length_squared();
    if len2 <= 0.0 {
        return None;
    }
    let f = a - c;
    let (bq, cq) = (f.dot(d), f.length_squared() - r * r);
    if cq <= 0.0 || bq >= 0.0 {
        return None;
    }
    let disc = bq * bq - len2 * cq;
    if disc < 0.0 {
        return None;
    }
    let t = (-bq - disc.sqrt()) / len2;
    (0.0..=1.0).contains(&t).then(|| a + d * t)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_point_is_caught_only_when_its_bones_hold_it_beyond_the_ball_and_far_off() {
        let (c, r, own) = (Vec3::ZERO, 1.0, 0.2);
        let x = Vec3::new(-1.0, 0.0, 0.0);
        // Held beyond the ball, far off: caught, let go.
        assert!(caught(Vec3::new(1.5, 0.0, 0.0), x, c, r, own));
        // Pressed into the ball (the flesh squashes): held.
        assert!(!caught(Vec3::new(-0.5, 0.0, 0.0), x, c, r, own));
        // Just outside, within its own radius: held (a point resting on the ball).
        assert!(!caught(Vec3::new(-1.1, 0.0, 0.0), x, c, r, own));
    }

    #[test]
    fn a_segment_entering_a_ball_is_found() {
        let (c, r) = (Vec3::ZERO, 1.0);
        let e = entry(Vec3::new(-3.0, 0.0, 0.0), Vec3::new(3.0, 0.0, 0.0), c, r).unwrap();
        assert!(e.distance(Vec3::new(-1.0, 0.0, 0.0)) < 1e-6);
        assert!(entry(Vec3::new(-3.0, 2.0, 0.0), Vec3::new(3.0, 2.0, 0.0), c, r).is_none());
        assert!(entry(Vec3::new(-3.0, 0.0, 0.0), Vec3::new(-2.0, 0.0, 0.0), c, r).is_none());
        assert!(entry(Vec3::new(0.5, 0.0, 0.0), Vec3::new(3.0, 0.0, 0.0), c, r).is_none());
    }
}
