//! What a renderer draws, described without any GPU type: the surface (positions,
//! triangles, a colour per vertex) and overlay lines, with revision counters that tell it
//! what changed since it last looked. The renderer (`render`, behind the `gui` feature)
//! only uploads and draws what a [`View`] gives it.

use super::Session;
use crate::joints::{Cut, Shape};
use crate::sim::Positions;
use glam::{DAffine3, DVec3, Vec3};

/// Which overlays are drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Overlays {
    /// Every mesh edge.
    pub wireframe: bool,
    /// A small cross at every skeletal point.
    pub skeleton: bool,
    /// Crosses at the inner (green) and outer (red) bone points.
    pub bone_points: bool,
    /// The bone springs from each mass point to its two bone points.
    pub bone_springs: bool,
    /// The planes of all applied cuts (without it, only those of the selected sections, or
    /// all while the cut tool is on: eleven suggested planes at once hide the puppet).
    pub cuts: bool,
    /// The cuts' pivots (a drag moves one).
    pub pivots: bool,
    /// Where loading repaired the mesh: the edges of filled holes (orange) and the split
    /// vertices (magenta crosses). On by itself when a file needed repairs.
    pub repairs: bool,
    /// The ground under the puppet with its soft shadow and a faint grid ([`Ground`]).
    pub ground: bool,
    /// Creases shaded by how much of the sky the body's own medial balls hide
    /// ([`crate::geom::occlusion`]): armpits, a mouth, a bent joint's inside.
    pub occlusion: bool,
    /// How the surface is lit.
    pub lighting: Lighting,
}

/// How the surface is lit: studio lights placed around the puppet, or a matcap, light
/// fixed to the camera and read from the normal as the eye sees it (the same shape reads
/// the same from every side, as sculptors' viewports light it).
#[derive(
    Clone,
    Copy,
    Debug,
    Default,
    PartialEq,
    Eq,
    Hash,
    clap::ValueEnum,
    serde::Serialize,
    serde::Deserialize,
)]
#[serde(rename_all = "lowercase")]
pub enum Lighting {
    /// A warm key, a cool fill, a rim from behind and a small highlight.
    #[default]
    Studio,
    /// A matte matcap: a soft light from the upper left and a pale rim.
    Clay,
    /// A glossy matcap: a sharp highlight and edges that glow in the part's own colour,
    /// as light through jelly or latex.
    Jelly,
}

impl Lighting {
    /// Its name in the panel.
    pub fn label(self) -> &'static str {
        match self {
            Lighting::Studio => "studio",
            Lighting::Clay => "clay matcap",
            Lighting::Jelly => "jelly matcap",
        }
    }
}

impl Default for Overlays {
    fn default() -> Self {
        Overlays {
            wireframe: false,
            skeleton: false,
            bone_points: false,
            bone_springs: false,
            cuts: false,
            pivots: true,
            repairs: false,
            ground: true,
            occlusion: true,
            lighting: Lighting::Studio,
        }
    }
}

impl Overlays {
    /// What a video of the take shows of these: the look (lighting, the ground, shaded
    /// creases, the wireframe), none of the marks for editing (pivots, cut planes, the
    /// skeleton, bone points and springs, repairs).
    pub fn for_video(self) -> Overlays {
        Overlays {
            wireframe: self.wireframe,
            ground: self.ground,
            occlusion: self.occlusion,
            lighting: self.lighting,
            pivots: false,
            ..Overlays::default()
        }
    }

    /// True when any overlay line is shown (the ground is drawn apart from them).
    pub fn any(&self) -> bool {
        self.wireframe
            || self.skeleton
            || self.bone_points
            || self.bone_springs
            || self.cuts
            || self.pivots
            || self.repairs
    }
}

/// A coloured line segment in world space (linear RGBA).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Line {
    /// One end.
    pub a: Vec3,
    /// The other end.
    pub b: Vec3,
    /// Linear RGB and opacity.
    pub color: [f32; 4],
}

/// The ground a renderer draws under the puppet: a square across its up, at its lowest
/// point at rest (at the floor when the floor is on), that the puppet's shadow falls on and
/// a faint grid covers, fading out towards its edge. It stays put while the puppet moves,
/// so a lifted foot is seen to leave it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ground {
    /// The point under the middle of the mesh's bounding box at rest.
    pub centre: Vec3,
    /// The puppet's up (the floor's, when the floor is on).
    pub up: Vec3,
    /// Two directions across `up`, at right angles (the floor's axes when it is on).
    pub across: [Vec3; 2],
    /// Half its side.
    pub half: f32,
    /// The grid's spacing: the floor grid's, so their lines meet when both are drawn.
    pub spacing: f32,
}

/// Half the ground's side, and of the floor grid's, in bounding-box diagonals.
pub const GROUND_HALF: f32 = 0.75;

/// Grid lines either side of the ground's (and the floor's) centre line.
pub const GRID_LINES: i32 = 8;

/// Counters that change when what they describe changes: a renderer re-uploads only the
/// parts whose counter moved.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Revisions {
    /// Another puppet (another mesh, other triangles).
    pub puppet: u64,
    /// The surface moved.
    pub surface: u64,
    /// Vertex colours changed (sections, selection, the cut draft).
    pub colours: u64,
    /// The sections changed (a cut made, moved or undone).
    pub layout: u64,
    /// Overlay lines changed.
    pub overlays: u64,
}

/// What to draw of a session with a choice of overlays.
#[derive(Clone, Copy)]
pub struct View<'a> {
    session: &'a Session,
    overlays: Overlays,
}

impl Session {
    /// What to draw of this session with `overlays` shown.
    pub fn view(&self, overlays: Overlays) -> View<'_> {
        View {
            session: self,
            overlays,
        }
    }

    /// Changes when the cut draft changes (plane, section or pivot).
    fn draft_key(&self) -> u64 {
        let mut key = Fnv::default();
        if let Some(d) = &self.draft {
            key.add(d.section as u64);
            key.add(d.connected as u64);
            let extent = match d.shape {
                Shape::Plane | Shape::Skin => DVec3::ZERO,
                Shape::Sphere { radius } => DVec3::splat(radius),
                Shape::Box { size } => size,
            };
            key.add(match d.shape {
                Shape::Plane => 0,
                Shape::Sphere { .. } => 1,
                Shape::Box { .. } => 2,
                Shape::Skin => 3,
            });
            for v in [d.point, d.normal, d.pivot.unwrap_or(DVec3::NAN), extent] {
                for c in v.to_array() {
                    key.add(c.to_bits());
                }
            }
        }
        key.0
    }
}

/// FNV-1a over 64-bit words: a key that changes with its inputs (not a secure hash).
struct Fnv(u64);

impl Default for Fnv {
    fn default() -> Self {
        Fnv(0xcbf2_9ce4_8422_2325)
    }
}

impl Fnv {
    fn add(&mut self, word: u64) {
        for byte in word.to_le_bytes() {
            self.0 = (self.0 ^ byte as u64).wrapping_mul(0x0100_0000_01b3);
        }
    }
}

impl View<'_> {
    /// The revision counters of what this view draws.
    pub fn revisions(&self) -> Revisions {
        let s = self.session;
        let draft = s.draft_key();
        let mut colours = Fnv::default();
        colours.add(s.layout_revision);
        colours.add(draft);
        // Overlays follow the pose and the surface when any is shown (or the draft is).
        let mut overlays = Fnv::default();
        overlays.add(s.layout_revision);
        overlays.add(draft);
        for shown in [
            self.overlays.wireframe,
            self.overlays.skeleton,
            self.overlays.bone_points,
            self.overlays.bone_springs,
            self.overlays.cuts,
            self.overlays.pivots,
            self.overlays.ground,
        ] {
            overlays.add(shown as u64);
        }
        overlays.add(s.cut_tool.active as u64);
        overlays.add(s.cut_tool.move_pivots as u64);
        overlays.add(s.puppet.sim.floor_height().map_or(u64::MAX, |y| {
            let up = s.puppet.sim.up();
            (y.to_bits() as u64) ^ ((up.axis as u64) << 33) ^ ((up.sign < 0.0) as u64) << 35
        }));
        if self.overlays.any()
            || s.draft.is_some()
            || !s.selection.is_empty()
            || s.cut_tool.move_pivots
        {
            overlays.add(s.revision);
        }
        Revisions {
            puppet: s.id,
            surface: s.revision,
            colours: colours.0,
            layout: s.layout_revision,
            overlays: overlays.0,
        }
    }

    /// The triangles (vertex indices, counter-clockwise seen from outside).
    pub fn triangles(&self) -> &[[u32; 3]] {
        &self.session.puppet.mesh.triangles
    }

    /// Is the puppet's surface closed and turned outward ([`crate::mesh::Mesh::is_closed_outward`]):
    /// its back faces never show from outside.
    pub fn closed(&self) -> bool {
        self.session.puppet.mesh.is_closed_outward()
    }

    /// The current surface positions.
    pub fn positions(&self) -> Positions<'_> {
        self.session.puppet.sim.positions()
    }

    /// Whether creases are shaded ([`Overlays::occlusion`]).
    pub fn shades_creases(&self) -> bool {
        self.overlays.occlusion
    }

    /// How the surface is lit ([`Overlays::lighting`]).
    pub fn lighting(&self) -> Lighting {
        self.overlays.lighting
    }

    /// The medial balls creases are shaded from ([`crate::geom::occlusion`]), made from
    /// the rest surface, its skeleton and the sections now (made again when they change:
    /// [`Revisions::layout`]).
    pub fn occluders(&self) -> crate::geom::occlusion::Occluders {
        let p = &self.session.puppet;
        crate::geom::occlusion::Occluders::new(
            &p.mesh.positions,
            &p.mesh.triangles,
            &p.skeleton.points,
            &p.skeleton.distance,
            p.joints.section_of(),
        )
    }

    /// The ground under the puppet, when it is shown (see [`Ground`]).
    pub fn ground(&self) -> Option<Ground> {
        if !self.overlays.ground {
            return None;
        }
        let p = &self.session.puppet;
        let (lo, hi) = p.mesh.bounds();
        let middle = ((lo + hi) * 0.5).as_vec3();
        let half = GROUND_HALF * self.size() as f32;
        let (up, across, level) = match p.sim.floor_height() {
            Some(height) => {
                let floor = p.sim.up();
                let axis = |k: usize| Vec3::AXES[k % 3];
                let up = axis(floor.axis) * floor.sign;
                (up, [axis(floor.axis + 1), axis(floor.axis + 2)], height)
            }
            None => {
                let up = p.up().as_vec3().normalize_or(Vec3::Y);
                let lowest = p
                    .mesh
                    .positions
                    .iter()
                    .map(|x| x.as_vec3().dot(up))
                    .fold(f32::INFINITY, f32::min);
                let (a, b) = up.any_orthonormal_pair();
                (up, [a, b], if lowest.is_finite() { lowest } else { 0.0 })
            }
        };
        Some(Ground {
            centre: middle + up * (level - middle.dot(up)),
            up,
            across,
            half,
            spacing: half / GRID_LINES as f32,
        })
    }

    /// Bounding-box diagonal of the mesh (for sizes of overlay marks).
    pub fn size(&self) -> f64 {
        self.session.puppet.mesh.diagonal()
    }

    /// A linear RGBA colour per vertex: its section's, tinted by the weight of each material
    /// region and of the pinning, tinted when selected, and tinted blue on the side of the
    /// cut draft that would become the new section.
    pub fn colours(&self, out: &mut Vec<[f32; 4]>) {
        let s = self.session;
        let sections = s.puppet.joints.section_of();
        let taken = s
            .draft
            .as_ref()
            .map(|d| s.puppet.joints.preview(d.section, &d.cut(String::new())));
        let regions = s.puppet.sim.regions();
        out.clear();
        out.extend(sections.iter().enumerate().map(|(i, &k)| {
            let k = k as usize;
            let mut c = section_color(k);
            // Other materials tint towards their colour, pinning towards slate, by weight.
            for (r, layer) in regions.layers.iter().enumerate() {
                let w = layer.weight.get(i).copied().unwrap_or(0.0);
                if w > 0.0 {
                    c = mix(c, REGION_COLORS[r % REGION_COLORS.len()], 0.6 * w);
                }
            }
            let pinned = regions.pin_of(i);
            if pinned > 0.0 {
                c = mix(c, [0.22, 0.24, 0.3], 0.75 * pinned);
            }
            if s.selection.contains(&k) {
                c = mix(c, [1.0, 0.42, 0.08], 0.55);
            }
            if taken.as_ref().is_some_and(|t| t[i]) {
                c = mix(c, [0.1, 0.75, 1.0], 0.6);
            }
            [c[0], c[1], c[2], 1.0]
        }));
    }

    /// The overlay lines: `lines` are depth-tested against the surface, `top` are drawn
    /// over it (skeletal points, pivots, the cut draft).
    pub fn lines(&self, lines: &mut Vec<Line>, top: &mut Vec<Line>) {
        lines.clear();
        top.clear();
        let (s, o) = (self.session, self.overlays);
        let p = &s.puppet;
        let x = p.sim.positions();
        let size = p.mesh.diagonal() as f32;
        let world = p.joints.world(&s.local);
        if o.wireframe {
            // The surface springs are the mesh's edges.
            for e in &p.sim.rig().springs {
                let color = [0.02, 0.02, 0.02, 0.55];
                push_line(lines, x.get(e.a as usize), x.get(e.b as usize), color);
            }
        }
        if o.skeleton {
            let sections = p.joints.section_of();
            for (i, sp) in p.skeleton.points.iter().enumerate() {
                let w = world[sections[i] as usize].transform_point3(*sp).as_vec3();
                push_cross(top, w, size * 0.002, [0.95, 0.9, 0.2, 0.9]);
            }
        }
        if o.repairs {
            let marks = &s.repairs;
            let tris = &p.mesh.triangles;
            let n = x.len();
            let mut edges: Vec<(usize, usize)> = marks
                .hole_faces
                .iter()
                .filter_map(|&f| tris.get(f as usize))
                .flat_map(|t| (0..3).map(move |k| (t[k] as usize, t[(k + 1) % 3] as usize)))
                .map(|(a, b)| (a.min(b), a.max(b)))
                .filter(|&(_, b)| b < n)
                .collect();
            // Each edge once: the patch's inner edges have two of its faces.
            edges.sort_unstable();
            edges.dedup();
            for (a, b) in edges {
                push_line(lines, x.get(a), x.get(b), [1.0, 0.55, 0.1, 0.9]);
            }
            for &v in marks.split_vertices.iter().filter(|&&v| (v as usize) < n) {
                push_cross(top, x.get(v as usize), size * 0.008, [0.95, 0.2, 0.85, 1.0]);
            }
        }
        if o.bone_springs {
            for i in 0..x.len() {
                let (bi, bo) = p.sim.bone_points(i);
                let xi = x.get(i);
                push_line(lines, bi, xi, [0.3, 0.9, 0.4, 0.7]);
                push_line(lines, xi, bo, [0.9, 0.35, 0.3, 0.7]);
            }
        }
        if o.bone_points {
            for i in 0..x.len() {
                let (bi, bo) = p.sim.bone_points(i);
                push_cross(lines, bi, size * 0.0015, [0.3, 0.9, 0.4, 1.0]);
                push_cross(lines, bo, size * 0.0015, [0.9, 0.35, 0.3, 1.0]);
            }
        }
        let half = p.mesh.diagonal() * 0.18;
        {
            let sections = p.joints.sections();
            let all = o.cuts || s.cut_tool.active;
            for (k, cut) in p.joints.cuts().iter().enumerate() {
                if !all && !s.selection.contains(&(k + 1)) {
                    continue;
                }
                // In the frame the section turns in (its parent's, as it carries it).
                let frame = match sections[k + 1].parent {
                    Some(_) => p.joints.parent_frame(k + 1, &world, &s.local),
                    None => world[0],
                };
                push_cut(lines, &frame, cut, half, [0.85, 0.85, 0.95, 0.8]);
            }
        }
        if let Some(d) = &s.draft {
            let w = &world[d.section.min(world.len() - 1)];
            push_cut(
                top,
                w,
                &d.cut(String::new()),
                half * 1.3,
                [0.1, 0.8, 1.0, 1.0],
            );
            if let Some(pivot) = d.pivot {
                let c = w.transform_point3(pivot).as_vec3();
                push_cross(top, c, size * 0.025, [0.1, 0.8, 1.0, 1.0]);
            }
        }
        if let Some(height) = p.sim.floor_height() {
            // The floor: a grid under the model across its up, centred below it.
            let (lo, hi) = p.mesh.bounds();
            let up = p.sim.up();
            let mut c = ((lo + hi) * 0.5).as_vec3();
            c[up.axis] = height * up.sign;
            let (a, b) = ((up.axis + 1) % 3, (up.axis + 2) % 3);
            let half = size * GROUND_HALF;
            let color = [0.55, 0.55, 0.5, 0.6];
            for k in -GRID_LINES..=GRID_LINES {
                let t = half * k as f32 / GRID_LINES as f32;
                let at = |u: f32, v: f32| {
                    let mut p = c;
                    p[a] += u;
                    p[b] += v;
                    p
                };
                push_line(lines, at(t, -half), at(t, half), color);
                push_line(lines, at(-half, t), at(half, t), color);
            }
        }
        if o.pivots || s.cut_tool.move_pivots {
            // Each cut's pivot (what a drag moves), as its section carries it.
            for (k, cut) in p.joints.cuts().iter().enumerate() {
                let k = k + 1;
                let Some(pivot) = cut.pivot else {
                    continue;
                };
                let c = p
                    .joints
                    .pivot_carrier(k, &world, &s.local)
                    .transform_point3(pivot)
                    .as_vec3();
                let color = if s.selection.contains(&k) {
                    [1.0, 0.5, 0.1, 1.0]
                } else {
                    [1.0, 1.0, 1.0, 1.0]
                };
                push_cross(top, c, size * 0.02, color);
            }
        }
    }
}

/// Tints of material regions, in order (pinning is slate).
const REGION_COLORS: [[f32; 3]; 4] = [
    [0.55, 0.2, 0.85],
    [0.1, 0.7, 0.65],
    [0.95, 0.75, 0.1],
    [0.9, 0.2, 0.45],
];

fn push_line(out: &mut Vec<Line>, a: Vec3, b: Vec3, color: [f32; 4]) {
    out.push(Line { a, b, color });
}

/// Three axis-aligned segments of half-length `r` through `c`.
fn push_cross(out: &mut Vec<Line>, c: Vec3, r: f32, color: [f32; 4]) {
    for axis in [Vec3::X, Vec3::Y, Vec3::Z] {
        push_line(out, c - axis * r, c + axis * r, color);
    }
}

/// A cut as `w` carries it: a plane as a square of half-size `half` about its pivot, a
/// sphere as three great circles, a box as its edges.
fn push_cut(out: &mut Vec<Line>, w: &DAffine3, cut: &Cut, half: f64, color: [f32; 4]) {
    let at = |p: DVec3| w.transform_point3(p).as_vec3();
    let axes = cut.axes();
    match cut.shape {
        Shape::Plane | Shape::Skin => {
            let centre = w.transform_point3(cut.pivot.unwrap_or(cut.point));
            push_plane(out, centre, w.transform_vector3(cut.normal), half, color);
        }
        Shape::Sphere { radius } => {
            const SEGMENTS: usize = 48;
            for (a, b) in [(0, 1), (1, 2), (2, 0)] {
                let (u, v) = (axes.col(a) * radius, axes.col(b) * radius);
                let ring = |k: usize| {
                    let t = k as f64 / SEGMENTS as f64 * std::f64::consts::TAU;
                    at(cut.point + u * t.cos() + v * t.sin())
                };
                for k in 0..SEGMENTS {
                    push_line(out, ring(k), ring(k + 1), color);
                }
            }
        }
        Shape::Box { size } => {
            let corner = |k: usize| {
                let sign = |bit: usize| if k >> bit & 1 == 1 { 0.5 } else { -0.5 };
                at(cut.point + axes * (size * DVec3::new(sign(0), sign(1), sign(2))))
            };
            for k in 0..8 {
                for bit in 0..3 {
                    if k >> bit & 1 == 0 {
                        push_line(out, corner(k), corner(k | 1 << bit), color);
                    }
                }
            }
        }
    }
}

/// A square of half-size `half` in the plane, hatched, with its normal as a stroke.
fn push_plane(out: &mut Vec<Line>, centre: DVec3, normal: DVec3, half: f64, color: [f32; 4]) {
    let n = normal.normalize_or(DVec3::Y);
    let u = n.any_orthonormal_vector();
    let v = n.cross(u);
    let at = |a: f64, b: f64| (centre + (u * a + v * b) * half).as_vec3();
    let corners = [at(-1.0, -1.0), at(1.0, -1.0), at(1.0, 1.0), at(-1.0, 1.0)];
    for k in 0..4 {
        push_line(out, corners[k], corners[(k + 1) % 4], color);
    }
    let faint = [color[0], color[1], color[2], color[3] * 0.4];
    for t in [-0.5, 0.0, 0.5] {
        push_line(out, at(t, -1.0), at(t, 1.0), faint);
    }
    let tip = (centre + n * half * 0.6).as_vec3();
    push_line(out, centre.as_vec3(), tip, color);
}

/// sRGB hex colour to linear.
fn srgb(hex: u32) -> [f32; 3] {
    let ch = |s: u32| {
        let c = ((hex >> s) & 0xff) as f32 / 255.0;
        if c <= 0.04045 {
            c / 12.92
        } else {
            ((c + 0.055) / 1.055).powf(2.4)
        }
    };
    [ch(16), ch(8), ch(0)]
}

/// Colour of a section (linear RGB): a warm latex tone for the root, then a palette, then
/// hues a golden angle apart (no two sections of a puppet look alike).
pub fn section_color(section: usize) -> [f32; 3] {
    const PALETTE: [u32; 8] = [
        0xe8c39e, 0x8fb8de, 0xa8d5a2, 0xe5a3b8, 0xd8c878, 0xb4a6e0, 0x86d0c8, 0xe0a878,
    ];
    if let Some(&hex) = PALETTE.get(section) {
        return srgb(hex);
    }
    let hue = (section as f32 * 0.618_034).fract() * 6.0;
    let (s, v) = (0.42, 0.88);
    let c = v * s;
    let x = c * (1.0 - ((hue % 2.0) - 1.0).abs());
    let [r, g, b] = match hue as u32 {
        0 => [c, x, 0.0],
        1 => [x, c, 0.0],
        2 => [0.0, c, x],
        3 => [0.0, x, c],
        4 => [x, 0.0, c],
        _ => [c, 0.0, x],
    };
    let m = v - c;
    let to_linear = |u: f32| {
        let u = u + m;
        if u <= 0.04045 {
            u / 12.92
        } else {
            ((u + 0.055) / 1.055).powf(2.4)
        }
    };
    [to_linear(r), to_linear(g), to_linear(b)]
}

fn mix(a: [f32; 3], b: [f32; 3], t: f32) -> [f32; 3] {
    [0, 1, 2].map(|k| a[k] + (b[k] - a[k]) * t)
}
