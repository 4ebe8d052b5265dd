//! The brush: painting a material region or the pinning onto the surface (radius, falloff,
//! erase), and setting the regions from the panel. Each stroke is one undo step.

use super::Session;
use crate::puppet::{paint, Paint, Region};
use glam::Vec3;
use std::sync::Arc;

/// The brush's settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PaintTool {
    /// A left drag on the model paints instead of turning sections.
    pub active: bool,
    /// What it paints: region `k`, or the pinning (`None`).
    pub target: Option<usize>,
    /// Brush radius (mesh units; 0 until the panel first shows, then a tenth of the
    /// model).
    pub radius: f32,
    /// Share of the radius over which the brush fades out, 0..1 (0: a hard edge).
    pub falloff: f32,
    /// Take weight away instead of adding it.
    pub erase: bool,
}

impl Default for PaintTool {
    fn default() -> Self {
        PaintTool {
            active: false,
            target: None,
            radius: 0.0,
            falloff: 0.5,
            erase: false,
        }
    }
}

impl PaintTool {
    /// The brush's weight at distance `d` from its centre: 1 inside, fading smoothly to 0
    /// over the outer `falloff` share of the radius.
    pub fn weight_at(&self, d: f32) -> f32 {
        let inside = self.radius > 0.0 && d < self.radius;
        if !inside {
            return 0.0;
        }
        let inner = self.radius * (1.0 - self.falloff.clamp(0.0, 1.0));
        if d <= inner {
            return 1.0;
        }
        let t = (self.radius - d) / (self.radius - inner);
        t * t * (3.0 - 2.0 * t)
    }
}

/// The regions and pinning as undo keeps them: shared, and told apart by a number that
/// every change takes afresh (comparing numbers, not weights, keeps undo cheap on large
/// meshes).
#[derive(Clone, Debug)]
pub(super) struct RegionsState {
    pub id: u64,
    pub data: Arc<(Vec<Region>, Paint)>,
}

impl PartialEq for RegionsState {
    fn eq(&self, other: &Self) -> bool {
        self.id == other.id
    }
}

impl RegionsState {
    pub fn of(regions: Vec<Region>, pin: Paint) -> RegionsState {
        RegionsState {
            id: super::NEXT_ID.fetch_add(1, std::sync::atomic::Ordering::Relaxed),
            data: Arc::new((regions, pin)),
        }
    }
}

impl Session {
    /// Points the brush at `target` (a region, or `None` for pinning) and turns it on or
    /// off (as [`Session::toggle_brush`]).
    pub fn set_brush(&mut self, target: Option<usize>, on: bool) {
        self.paint_tool.target = target;
        if on != self.paint_tool.active {
            self.toggle_brush();
        } else {
            self.revision += 1;
        }
    }

    /// Turns the brush on or off (on: the cut tool goes off, and a brush that never had a
    /// size gets a tenth of the model). It paints what it painted last (the pinning at
    /// first).
    pub fn toggle_brush(&mut self) {
        let tool = &mut self.paint_tool;
        tool.active ^= true;
        if tool.active {
            self.cut_tool.active = false;
            self.draft = None;
            if tool.radius.is_nan() || tool.radius <= 0.0 {
                tool.radius = 0.1 * self.puppet.mesh.diagonal() as f32;
            }
        }
        self.revision += 1;
    }

    /// How many vertices the brush's target covers (weight above 0).
    pub fn painted(&self) -> usize {
        let paint = match self.paint_tool.target {
            Some(k) => self.puppet.rig_file.regions.get(k).map(|r| &r.paint),
            None => Some(&self.puppet.rig_file.pin),
        };
        paint.map_or(0, |p| p.weights.iter().filter(|&&w| w > 0.0).count())
    }

    /// Replaces the material regions and the pinning (as the panel edits them); the
    /// simulation takes them at once.
    pub fn set_regions(&mut self, regions: Vec<Region>, pin: Paint) {
        self.regions_state = RegionsState::of(regions.clone(), pin.clone());
        self.apply_regions(regions, pin);
    }

    pub(super) fn apply_regions(&mut self, regions: Vec<Region>, pin: Paint) {
        let target_gone = self.paint_tool.target.is_some_and(|k| k >= regions.len());
        if target_gone {
            self.paint_tool.target = None;
            self.paint_tool.active = false;
        }
        self.puppet.rig_file.regions = regions;
        self.puppet.rig_file.pin = pin;
        self.puppet.sync_regions();
        self.layout_revision += 1;
        self.wake();
    }

    /// One dab of the brush centred at `at` (on the current surface): the target's weight
    /// of every vertex within the radius rises to the brush's (or, erasing, falls).
    pub fn paint_at(&mut self, at: Vec3) {
        let tool = self.paint_tool;
        let n = self.puppet.mesh.positions.len();
        let x = self.puppet.sim.positions();
        let mut regions = self.puppet.rig_file.regions.clone();
        let mut pin = self.puppet.rig_file.pin.clone();
        let paint = match tool.target {
            Some(k) => match regions.get_mut(k) {
                Some(r) => &mut r.paint,
                None => return,
            },
            None => &mut pin,
        };
        paint.weights.resize(n, 0.0);
        let mut changed = false;
        for (i, w) in paint.weights.iter_mut().enumerate() {
            let b = tool.weight_at((x.get(i) - at).length());
            if b <= 0.0 {
                continue;
            }
            let new = paint::quantise(if tool.erase { w.min(1.0 - b) } else { w.max(b) });
            if new != *w {
                *w = new;
                changed = true;
            }
        }
        if changed {
            self.set_regions(regions, pin);
        }
    }
}
