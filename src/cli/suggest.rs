//! `puppet suggest MESH [-o RIG.toml] [--json]`: the joints the skeleton suggests (or, for
//! a skinned glTF, the joints of its skin), printed as a section tree and written as a rig
//! file, with the file's clips.

use super::progress_bar::ProgressBar;
use super::{load_mesh, FileError};
use anyhow::Result;
use puppet::puppet::JointsFrom;
use puppet::{Puppet, RigFile};
use std::path::PathBuf;
use std::time::Instant;

#[derive(clap::Args, Debug)]
pub struct Args {
    /// Mesh; the embedded Spot when omitted.
    pub mesh: Option<PathBuf>,
    /// Write the suggested cuts here as a rig file (TOML, or JSON with a .json extension).
    #[arg(short = 'o', long = "output")]
    pub output: Option<PathBuf>,
    /// Also draw the suggested sections (PNG, rendered offscreen by the app's renderer).
    #[arg(long)]
    pub image: Option<PathBuf>,
    /// Print one JSON object instead of the tree.
    #[arg(long)]
    pub json: bool,
    /// How the skeletal distance is taken (default: the rig file's default method).
    #[arg(long, value_enum)]
    pub method: Option<puppet::skeleton::Method>,
    /// The axis the mesh is modelled with as up: +x, -x, +y, -y, +z or -z (default: found
    /// from its shape; written into the rig file when given).
    #[arg(long, value_name = "AXIS", allow_hyphen_values = true)]
    pub up: Option<puppet::mesh::orientation::Up>,
    /// The way the character faces, across up: +x, -x, +y, -y, +z or -z (default: a glTF
    /// file's +z, else found from its shape; written into the rig file when given). It
    /// names left and right: `.L` is the character's own left.
    #[arg(long, value_name = "AXIS", allow_hyphen_values = true)]
    pub front: Option<puppet::mesh::orientation::Up>,
    /// Suggest joints from the skeleton even when the file has a skin (a skinned glTF's
    /// joints are used by default).
    #[arg(long)]
    pub ignore_skin: bool,
}

/// What the command prints (`--json` prints exactly these fields).
#[derive(serde::Serialize)]
struct Summary {
    mesh: String,
    vertices: usize,
    /// Up, as given or found, and the way the character faces.
    up: [f64; 3],
    front: [f64; 3],
    /// Where the joints come from: `skin` (the file's) or `suggestion`.
    joints_from: JointsFrom,
    cuts: Vec<CutRow>,
    /// The file's skin: its joint count and its clips (none without a skin).
    skin: Option<SkinRow>,
    seconds_skeleton: f64,
    seconds_suggest: f64,
    output: Option<String>,
}

#[derive(serde::Serialize)]
struct SkinRow {
    joints: usize,
    clips: Vec<ClipRow>,
}

#[derive(serde::Serialize)]
struct ClipRow {
    name: String,
    seconds: f64,
    /// Channels that drive morph-target weights, which are not played.
    morph_channels: usize,
}

#[derive(serde::Serialize)]
struct CutRow {
    name: String,
    /// The role the name gives (`arm.L`, `thumb.R`, `tail`…), none for a numbered cut.
    role: Option<String>,
    /// The character it is of, where the file holds several (0 the largest; its names
    /// end in `.001` from the second on).
    character: usize,
    parent: String,
    vertices: usize,
    pivot: [f64; 3],
    normal: [f64; 3],
}

pub fn run(args: &Args, load: &super::LoadArgs) -> Result<()> {
    let (mesh, report, name) = load_mesh(args.mesh.as_deref(), load)?;
    let bar = ProgressBar::new();
    let t = Instant::now();
    let mut rig = RigFile::default();
    if let Some(method) = args.method {
        rig.method = method;
    }
    rig.up = args.up;
    rig.front = args.front;
    if let (Some(up), Some(front)) = (args.up, args.front) {
        if !up.is_across(front) {
            return Err(FileError::new(
                &name,
                format!("--front {front} lies along --up {up}: a front lies across up"),
            )
            .into());
        }
    }
    let mut puppet = Puppet::build_loaded(mesh, Some(&report), rig, &|s, f| bar.update(s, f))
        .map_err(|e| FileError::new(&name, e))?;
    puppet.ignore_skin = args.ignore_skin;
    bar.finish();
    let seconds_skeleton = t.elapsed().as_secs_f64();
    let t = Instant::now();
    puppet
        .suggest_joints()
        .map_err(|e| FileError::new(&name, e))?;
    let seconds_suggest = t.elapsed().as_secs_f64();
    let joints_from = puppet.joints_from(true);
    let from_skin = joints_from == JointsFrom::Skin;
    // A front given along the mirror plane's normal, or along the up found, is overruled.
    if let (Some(given), Some(frame)) = (args.front, puppet.frame()) {
        if given.vector() != frame.front {
            let found = puppet::mesh::orientation::Up::nearest(frame.front);
            log::warn!(
                "{name}: --front {given} does not lie across up and the mirror plane: {found} is taken"
            );
        }
    }
    let joints = &puppet.joints;
    let sections = joints.sections().to_vec();
    let cuts: Vec<CutRow> = joints
        .cuts()
        .iter()
        .enumerate()
        .map(|(k, c)| {
            let s = &sections[k + 1];
            let (role, character) = puppet::joints::suggest::characters::role(&c.name);
            let (role, character) = match c.shape {
                puppet::joints::Shape::Skin => (puppet::mesh::skin::role(&c.name), 0),
                _ => (
                    (!c.name.starts_with("joint ")).then(|| role.to_string()),
                    character,
                ),
            };
            CutRow {
                name: c.name.clone(),
                role,
                character,
                parent: s.parent.map_or(String::new(), |p| sections[p].name.clone()),
                vertices: s.vertices,
                pivot: s.pivot.to_array(),
                normal: c.normal.normalize_or_zero().to_array(),
            }
        })
        .collect();
    if let Some(out) = &args.output {
        // The mesh relative to the rig file, so the two can move together.
        let mut rig = puppet.current_rig_file();
        rig.mesh = args.mesh.clone();
        std::fs::write(out, rig.text_for(out)).map_err(|e| {
            FileError::new(
                out.display().to_string(),
                format!("cannot write: {}", puppet::files::io_message(&e)),
            )
        })?;
    }
    let vertices = puppet.mesh.positions.len();
    let frame = puppet.frame().unwrap_or_default();
    if let Some(path) = &args.image {
        picture(puppet, path)?;
    }
    let skin = report.skin.as_ref().map(|s| SkinRow {
        joints: s.joints.len(),
        clips: s
            .clips
            .iter()
            .map(|c| ClipRow {
                name: c.name.clone(),
                seconds: c.duration,
                morph_channels: c.morph_channels,
            })
            .collect(),
    });
    let summary = Summary {
        mesh: name,
        vertices,
        up: frame.up.to_array(),
        front: frame.front.to_array(),
        joints_from,
        cuts,
        skin,
        seconds_skeleton,
        seconds_suggest,
        output: args.output.as_ref().map(|p| p.display().to_string()),
    };
    if args.json {
        println!("{}", serde_json::to_string_pretty(&summary)?);
        return Ok(());
    }
    println!(
        "{}: {} vertices, {} {} (skeleton {:.0} ms, suggestion {:.1} ms)",
        summary.mesh,
        summary.vertices,
        summary.cuts.len(),
        if from_skin {
            "joints from the file's skin"
        } else {
            "suggested joints"
        },
        summary.seconds_skeleton * 1e3,
        summary.seconds_suggest * 1e3
    );
    if let Some(skin) = &summary.skin {
        println!("skin: {} joints", skin.joints);
        for c in &skin.clips {
            let morph = match c.morph_channels {
                0 => String::new(),
                k => format!(" ({k} morph-weight channels not played)"),
            };
            println!("clip '{}': {:.2} s{morph}", c.name, c.seconds);
        }
    }
    print_tree(&summary.cuts, &sections[0].name, 1);
    if let Some(o) = &summary.output {
        println!("wrote {o}");
    }
    Ok(())
}

/// The cuts under `parent`, indented by depth.
fn print_tree(cuts: &[CutRow], parent: &str, depth: usize) {
    if depth == 1 {
        println!("{parent}");
    }
    for c in cuts.iter().filter(|c| c.parent == parent) {
        println!(
            "{}{} ({} vertices, pivot {:.3} {:.3} {:.3})",
            "  ".repeat(depth),
            c.name,
            c.vertices,
            c.pivot[0],
            c.pivot[1],
            c.pivot[2]
        );
        print_tree(cuts, &c.name, depth + 1);
    }
}

/// The puppet (as its simulation stands) drawn from the front and from the side, side by
/// side, its sections coloured.
#[cfg(feature = "gui")]
pub(crate) fn picture(puppet: Puppet, path: &std::path::Path) -> Result<()> {
    use puppet::render::{render_image, Gpu, Image, SceneRenderer, OFFSCREEN_FORMAT};
    use puppet::session::{Camera, Overlays, Session};
    let gpu = Gpu::headless()?;
    let mut renderer = SceneRenderer::new(&gpu, OFFSCREEN_FORMAT);
    let session = Session::new(puppet, "suggest");
    let (lo, hi) = session.puppet.mesh.bounds();
    let (w, h) = (480, 480);
    let overlays = Overlays {
        cuts: false,
        ..Overlays::default()
    };
    let mut shots = Vec::new();
    for yaw in [0.0f32, std::f32::consts::FRAC_PI_2] {
        let mut camera = Camera {
            yaw,
            pitch: 0.1,
            up: session.puppet.up().as_vec3(),
            ..Camera::default()
        };
        camera.frame(lo.as_vec3(), hi.as_vec3());
        shots.push(render_image(
            &gpu,
            &mut renderer,
            &session.view(overlays),
            &camera,
            w,
            h,
        )?);
    }
    let mut rgba = Vec::with_capacity((2 * w * h * 4) as usize);
    for y in 0..h as usize {
        for shot in &shots {
            let row = y * w as usize * 4;
            rgba.extend_from_slice(&shot.rgba[row..row + w as usize * 4]);
        }
    }
    let image = Image {
        width: 2 * w,
        height: h,
        rgba,
    };
    image
        .save_png(path)
        .map_err(|e| FileError::new(path.display().to_string(), format!("cannot write: {e}")))?;
    Ok(())
}

/// Without the `gui` feature there is no renderer.
#[cfg(not(feature = "gui"))]
pub(crate) fn picture(_puppet: Puppet, path: &std::path::Path) -> Result<()> {
    Err(FileError::new(
        path.display().to_string(),
        "drawing needs the renderer (a build with the `gui` feature)",
    )
    .into())
}
