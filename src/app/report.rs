//! What the window shows, as data: the screenshot's report (printed by `--screenshot`) and
//! the state file of `--report FILE`, which tests and scripts read while driving the real
//! window (written whenever the puppet settles, and when the window closes).

use super::WindowState;
use crate::session::Session;
use glam::Vec2;
use std::collections::BTreeMap;
use std::path::Path;

/// What the window shows.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize)]
pub struct Report {
    /// Where the screenshot was saved, if one was taken.
    pub screenshot: Option<String>,
    /// The window's size in pixels.
    pub width: u32,
    /// The window's size in pixels.
    pub height: u32,
    /// Frames drawn with the puppet.
    pub frames: u32,
    /// Key presses received.
    pub keys: u64,
    /// The mesh's name.
    pub mesh: String,
    /// Every section, root first.
    pub sections: Vec<String>,
    /// The selected sections.
    pub selection: Vec<String>,
    /// Turned sections as `name:degrees`.
    pub turned: Vec<String>,
    /// The cut tool is on.
    pub cut_tool: bool,
    /// A cut draft is placed.
    pub draft: bool,
    /// The brush is on.
    pub brush: bool,
    /// An animation plays.
    pub playing: bool,
    /// Where the animation is, in seconds (when one is loaded).
    pub animation_time: Option<f64>,
    /// A take is being recorded.
    pub recording: bool,
    /// Sections the loaded animation has tracks for.
    pub tracks: Vec<String>,
    /// The clips of the mesh file's skin, as the panel lists them.
    pub clips: Vec<String>,
    /// Vertices the brush's target (a region, or the pinning) has painted.
    pub painted: usize,
    /// Vertices the simulation pins (weight above 0).
    pub pinned: usize,
    /// `running`, `settled` or `paused`.
    pub state: String,
    /// The largest edge stretch of the surface now (its length over its rest length).
    pub stretch: f64,
    /// The first-run hint is shown.
    pub hint: bool,
    /// The panel's message line, if any.
    pub message: Option<String>,
    /// Per section, a pixel where it is visible (a click there picks it), if any.
    pub targets: BTreeMap<String, [f32; 2]>,
    /// *Move pivots* is on.
    pub move_pivots: bool,
    /// With *move pivots* on, per cut, the pixel its pivot is drawn at (a drag from there
    /// moves it), if in view right of the panel.
    pub pivots: BTreeMap<String, [f32; 2]>,
    /// The graphics adapter.
    pub adapter: String,
    /// Samples a pixel the view is drawn with (1: no anti-aliasing).
    pub samples: u32,
    /// Samples a pixel the last frame's scene was drawn with: [`crate::render::scene::MSAA`]
    /// for the still frame where the view is otherwise drawn with one (`app::still`).
    pub drawn_samples: u32,
    /// The last frame's scene was drawn with one sample and its edges smoothed after
    /// (FXAA).
    pub drawn_fxaa: bool,
    /// How the moving view's edges are smoothed, as chosen (`msaa`, `fxaa`, `off`).
    pub anti_aliasing: crate::render::AntiAliasing,
    /// The ground and its shadow are drawn.
    pub ground: bool,
    /// How the surface is lit (`studio`, `clay matcap`, `jelly matcap`).
    pub lighting: String,
    /// The process, and the X display and authority it draws on (for scripts that drive
    /// the window with `xdotool`).
    pub pid: u32,
    /// `$DISPLAY`.
    pub display: Option<String>,
    /// `$XAUTHORITY`.
    pub xauthority: Option<String>,
    /// The live controls' counts and values, once the command line or the panel started
    /// them.
    pub controls: Option<crate::ui::LiveCounts>,
}

impl WindowState {
    /// What the window shows now; `screenshot` is where the screenshot went, if one was
    /// taken.
    pub fn report(&self, screenshot: Option<&Path>) -> Report {
        let mut report = Report {
            screenshot: screenshot.map(|p| p.display().to_string()),
            width: self.config.width,
            height: self.config.height,
            frames: self.frames,
            keys: self.hooks.keys,
            hint: self.panel.hint,
            message: self.panel.message.as_ref().map(|(m, _)| m.clone()),
            adapter: self.gpu.adapter.get_info().name,
            samples: self.scene.samples(),
            drawn_samples: self.drawn_samples,
            drawn_fxaa: self.drawn_fxaa,
            anti_aliasing: crate::render::AntiAliasing::of(&self.scene),
            ground: self.panel.overlays.ground,
            lighting: self.panel.overlays.lighting.label().to_string(),
            pid: std::process::id(),
            display: std::env::var("DISPLAY").ok(),
            xauthority: std::env::var("XAUTHORITY").ok(),
            controls: self.live.as_ref().map(|l| l.counts()),
            ..Report::default()
        };
        let Some(s) = &self.session else {
            return report;
        };
        let sections = s.puppet.joints.sections();
        report.mesh = s.name.clone();
        report.sections = sections.iter().map(|x| x.name.clone()).collect();
        report.selection = s
            .selection
            .iter()
            .map(|&i| sections[i].name.clone())
            .collect();
        report.turned = s
            .local
            .iter()
            .enumerate()
            .map(|(i, l)| (i, l.rotation.angle_between(glam::DQuat::IDENTITY)))
            .filter(|&(_, angle)| angle > 1e-6)
            .map(|(i, angle)| format!("{}:{:.1}", sections[i].name, angle.to_degrees()))
            .collect();
        report.cut_tool = s.cut_tool.active;
        report.draft = s.draft.is_some();
        report.brush = s.paint_tool.active;
        report.playing = s.is_playing();
        report.animation_time = s.playback_time().map(|(t, _)| t);
        report.recording = s.is_recording();
        report.tracks = s.playback.as_ref().map_or_else(Vec::new, |p| {
            p.animation
                .track
                .iter()
                .map(|t| t.section.clone())
                .collect()
        });
        report.clips = s.clips().into_iter().map(|(name, _)| name).collect();
        report.painted = s.painted();
        let regions = s.puppet.sim.regions();
        report.pinned = (0..s.puppet.mesh.positions.len())
            .filter(|&i| regions.pin_of(i) > 0.0)
            .count();
        report.stretch = crate::puppet::poses::worst_stretch(&s.puppet);
        report.state = if s.is_paused() {
            "paused"
        } else if s.is_settled() {
            "settled"
        } else {
            "running"
        }
        .into();
        for (k, section) in sections.iter().enumerate() {
            if let Some(at) = self.target(s, k) {
                report.targets.insert(section.name.clone(), at.to_array());
            }
        }
        report.move_pivots = s.cut_tool.move_pivots;
        if s.cut_tool.move_pivots {
            let size = self.viewport();
            let left = self.panel.width_px;
            for (k, at) in s.pivots_on_screen(&self.camera, size) {
                if at.x > left + 4.0 && at.x < size.x - 4.0 && at.y > 4.0 && at.y < size.y - 4.0 {
                    report
                        .pivots
                        .insert(sections[k].name.clone(), at.to_array());
                }
            }
        }
        report
    }

    /// A pixel right of the panel where section `k` is the first surface hit, near the
    /// middle of its vertices.
    fn target(&self, s: &Session, k: usize) -> Option<Vec2> {
        let x = s.puppet.sim.positions();
        let of = s.puppet.joints.section_of();
        let members: Vec<usize> = (0..x.len()).filter(|&i| of[i] as usize == k).collect();
        let centroid =
            members.iter().map(|&i| x.get(i)).sum::<glam::Vec3>() / members.len().max(1) as f32;
        let mut near = members;
        near.sort_by(|&a, &b| {
            let (da, db) = (
                (x.get(a) - centroid).length(),
                (x.get(b) - centroid).length(),
            );
            da.total_cmp(&db)
        });
        let size = self.viewport();
        let left = self.panel.width_px;
        near.into_iter().take(200).find_map(|i| {
            let at = self.camera.project(x.get(i), size)?;
            if at.x <= left + 4.0 || at.x >= size.x - 4.0 || at.y <= 4.0 || at.y >= size.y - 4.0 {
                return None;
            }
            let (origin, dir) = self.camera.ray(at, size);
            let hit = s.pick(origin, dir)?;
            (s.section_at(&hit) == k).then_some(at)
        })
    }

    /// Writes the `--report` file (atomically: a temporary file renamed over it).
    pub fn write_report(&self) {
        let Some(path) = &self.hooks.report else {
            return;
        };
        let tmp = path.with_extension("tmp");
        let text = match serde_json::to_string_pretty(&self.report(None)) {
            Ok(t) => t,
            Err(e) => {
                log::error!("{}: {e}", path.display());
                return;
            }
        };
        if let Err(e) = std::fs::write(&tmp, text).and_then(|()| std::fs::rename(&tmp, path)) {
            log::error!("{}: cannot write: {e}", path.display());
        }
    }
}
