//! `puppet bench draw`: what a frame of the viewport costs, and what each part of the look
//! adds to it.
//!
//! The input (the embedded Spot when omitted) is Loop-subdivided `--subdivisions` times
//! (twice: 46,754 vertices), rigged with a head cut, and drawn offscreen at `--width` ×
//! `--height` (the window's default 1280 × 800) while the head nods, so every frame
//! uploads the moved surface and redraws the shadow map, as the window does while the
//! puppet moves. A frame is timed from `prepare` to the GPU being done with it (the
//! simulation's step is not counted). The configurations alternate frame by frame
//! (anti-aliasing and the ground; FXAA and the ground; each alone; neither; the creases
//! unshaded; the clay matcap instead of the studio's lights), so load on the shared
//! machine hits them alike. Exit status 2 when the window's default on this adapter (the
//! ground, with 4 samples on a GPU, FXAA on a software renderer) draws fewer than
//! `--min-fps` frames a second.

use super::table::{self, Column, Table};
use super::Input;
use crate::cli::LoadArgs;
use anyhow::{bail, Result};
use puppet::joints::Cut;
use puppet::render::scene::{msaa_supported, window_msaa, MSAA};
use puppet::render::{AntiAliasing, Gpu, SceneRenderer, OFFSCREEN_FORMAT};
use puppet::session::{Camera, Lighting, Overlays, Session};
use puppet::stats::median_p95;
use puppet::{Puppet, RigFile};
use std::time::Instant;

/// A configuration's samples that stand for one sample and the smoothing pass.
const FXAA: u32 = 0;

/// `puppet bench draw`.
#[derive(clap::Args, Debug)]
pub struct Args {
    #[command(flatten)]
    input: Input,
    /// Loop subdivision steps (each quadruples the faces; at most 4).
    #[arg(long, default_value_t = 2, value_parser = clap::value_parser!(u8).range(0..=4))]
    subdivisions: u8,
    /// Image width in pixels.
    #[arg(long, default_value_t = 1280, value_parser = clap::value_parser!(u32).range(16..=8192))]
    width: u32,
    /// Image height in pixels.
    #[arg(long, default_value_t = 800, value_parser = clap::value_parser!(u32).range(16..=8192))]
    height: u32,
    /// Frames drawn in each configuration.
    #[arg(long, default_value_t = 60, value_parser = clap::value_parser!(u32).range(1..))]
    frames: u32,
    /// Keep the puppet still and orbit the camera instead: nothing is uploaded and the
    /// shadow is not redrawn (a settled puppet looked at from around).
    #[arg(long)]
    still: bool,
    /// Fail when the window's default on this adapter draws fewer frames a second.
    #[arg(long, value_parser = super::bound)]
    min_fps: Option<f64>,
    /// Fail when the clay matcap's frame costs more than this share (%) over the studio's
    /// lights with the same ground, creases and anti-aliasing.
    #[arg(long, value_parser = super::bound)]
    max_matcap_cost: Option<f64>,
    /// Print JSON instead of a Markdown table.
    #[arg(long)]
    json: bool,
}

#[derive(serde::Serialize)]
struct Row {
    config: &'static str,
    samples: u32,
    /// Edges smoothed after drawing (FXAA).
    fxaa: bool,
    ground: bool,
    /// Creases shaded ([`Overlays::occlusion`]).
    creases: bool,
    /// How the surface is lit ([`Overlays::lighting`]).
    lighting: &'static str,
    /// What the window draws on this adapter by default.
    window_default: bool,
    ms_per_frame: f64,
    ms_p95: f64,
    fps: f64,
}

#[derive(serde::Serialize)]
struct Report {
    mesh: String,
    vertices: usize,
    triangles: usize,
    width: u32,
    height: u32,
    adapter: String,
    frames: u32,
    rows: Vec<Row>,
}

pub fn run(args: &Args, load: &LoadArgs) -> Result<()> {
    let (mut mesh, _, name) = super::super::load_mesh(args.input.mesh.as_deref(), load)?;
    for _ in 0..args.subdivisions {
        mesh = puppet::mesh::subdivide_loop(&mesh);
    }
    let (lo, hi) = mesh.bounds();
    let (vertices, triangles) = (mesh.positions.len(), mesh.triangles.len());
    // A cut across the top fifth along the longest axis: a head (or whatever is there) to
    // nod, so the surface moves every frame.
    let extent = hi - lo;
    let axis = extent.max_position();
    let mut point = (lo + hi) * 0.5;
    point[axis] = hi[axis] - 0.2 * extent[axis];
    let normal = glam::DVec3::AXES[axis];
    let rig = RigFile {
        cuts: vec![Cut::plane("head", puppet::joints::ROOT, point, normal)],
        ..RigFile::default()
    };
    let puppet = Puppet::build(mesh, rig, puppet::progress::silent())
        .map_err(|e| anyhow::anyhow!("{name}: {e}"))?;
    let mut session = Session::new(puppet, "draw");
    session.select(session.puppet.joints.find("head"), false);
    let mut camera = Camera {
        up: session.puppet.up().as_vec3(),
        ..Camera::default()
    };
    camera.frame(lo.as_vec3(), hi.as_vec3());

    let gpu = Gpu::headless()?;
    let adapter = gpu.adapter.get_info().name;
    let msaa = if msaa_supported(&gpu, OFFSCREEN_FORMAT) {
        MSAA
    } else {
        1
    };
    // The window's choice on this adapter (see `render::scene::window_msaa`).
    let window = if window_msaa(&gpu, OFFSCREEN_FORMAT) {
        AntiAliasing::Msaa
    } else {
        AntiAliasing::Fxaa
    };
    let studio = Lighting::Studio;
    // (name, renderer, ground, creases, lighting)
    let mut configs: Vec<(&'static str, SceneRenderer, bool, bool, Lighting)> = [
        ("anti-aliasing and ground", msaa, true, true, studio),
        ("ground, fxaa", FXAA, true, true, studio),
        ("ground, no anti-aliasing", 1, true, true, studio),
        (
            "ground, no anti-aliasing, creases unshaded",
            1,
            true,
            false,
            studio,
        ),
        (
            "ground, no anti-aliasing, clay matcap",
            1,
            true,
            true,
            Lighting::Clay,
        ),
        ("anti-aliasing, no ground", msaa, false, true, studio),
        ("neither", 1, false, true, studio),
    ]
    .into_iter()
    .map(|(name, samples, ground, creases, lighting)| {
        let renderer = if samples == FXAA {
            SceneRenderer::with_fxaa(&gpu, OFFSCREEN_FORMAT)
        } else {
            SceneRenderer::with_samples(&gpu, OFFSCREEN_FORMAT, samples)
        };
        (name, renderer, ground, creases, lighting)
    })
    .collect();
    let texture = gpu.device.create_texture(&wgpu::TextureDescriptor {
        label: Some("bench draw"),
        size: wgpu::Extent3d {
            width: args.width,
            height: args.height,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: OFFSCREEN_FORMAT,
        // (Copied from and viewed plain by the smoothing pass.)
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
        view_formats: &[OFFSCREEN_FORMAT.remove_srgb_suffix()],
    });
    let aspect = args.width as f32 / args.height as f32;
    let mut times = vec![Vec::new(); configs.len()];
    // One frame each first: pipelines and buffers warm.
    for frame in 0..=args.frames {
        // Nod: a twentieth of a radian a frame, back and forth.
        let sign = if (frame / 20) % 2 == 0 { 1.0 } else { -1.0 };
        if args.still {
            camera.yaw += 0.02;
        } else {
            session.rotate_selected(glam::DQuat::from_rotation_x(0.05 * sign));
            session.advance(1.0 / 60.0, 1);
        }
        for (k, (_, renderer, ground, creases, lighting)) in configs.iter_mut().enumerate() {
            let overlays = Overlays {
                ground: *ground,
                occlusion: *creases,
                lighting: *lighting,
                ..Overlays::default()
            };
            let started = Instant::now();
            renderer.prepare(&gpu, &session.view(overlays), &camera, aspect);
            let mut encoder = gpu.device.create_command_encoder(&Default::default());
            renderer.render_to(&gpu, &mut encoder, &texture);
            gpu.queue.submit([encoder.finish()]);
            gpu.device
                .poll(wgpu::PollType::wait_indefinitely())
                .map_err(|e| anyhow::anyhow!("the GPU did not finish a frame: {e}"))?;
            if frame > 0 {
                times[k].push(started.elapsed().as_secs_f64() * 1e3);
            }
        }
    }
    let rows: Vec<Row> = configs
        .iter()
        .zip(times)
        .map(|((config, renderer, ground, creases, lighting), t)| {
            let (ms, p95) = median_p95(t);
            Row {
                config,
                samples: renderer.samples(),
                fxaa: renderer.fxaa(),
                ground: *ground,
                creases: *creases,
                lighting: lighting.label(),
                window_default: *ground
                    && *creases
                    && *lighting == Lighting::Studio
                    && AntiAliasing::of(renderer) == window,
                ms_per_frame: ms,
                ms_p95: p95,
                fps: 1e3 / ms.max(1e-9),
            }
        })
        .collect();
    let report = Report {
        mesh: name,
        vertices,
        triangles,
        width: args.width,
        height: args.height,
        adapter,
        frames: args.frames,
        rows,
    };
    if args.json {
        table::json(&report)?;
    } else {
        println!(
            "{} subdivided {}×: {} vertices, {} triangles; {} × {} pixels on {}; {} frames each, the head nodding",
            report.mesh,
            args.subdivisions,
            report.vertices,
            report.triangles,
            report.width,
            report.height,
            report.adapter,
            report.frames
        );
        println!();
        let mut table = Table::new(&[
            Column::Text("configuration"),
            Column::Figure("samples"),
            Column::Text("fxaa"),
            Column::Text("ground and shadow"),
            Column::Text("creases shaded"),
            Column::Text("lighting"),
            Column::Figure("ms per frame (median)"),
            Column::Figure("p95"),
            Column::Figure("frames/s"),
        ]);
        table.start();
        for r in &report.rows {
            let name = if r.window_default {
                format!("**{} (the window's default here)**", r.config)
            } else {
                r.config.to_string()
            };
            table.row(&[
                name,
                r.samples.to_string(),
                if r.fxaa { "yes" } else { "no" }.to_string(),
                if r.ground { "yes" } else { "no" }.to_string(),
                if r.creases { "yes" } else { "no" }.to_string(),
                r.lighting.to_string(),
                format!("{:.2}", r.ms_per_frame),
                format!("{:.2}", r.ms_p95),
                format!("{:.0}", r.fps),
            ]);
        }
    }
    let default = report.rows.iter().find(|r| r.window_default);
    if let (Some(min), Some(default)) = (args.min_fps, default) {
        if default.fps < min {
            bail!(
                "the viewport draws {:.1} frames/s as the window does here ({}), below --min-fps {min}",
                default.fps,
                default.config
            );
        }
    }
    if let Some(max) = args.max_matcap_cost {
        let studio = |r: &Row| {
            report.rows.iter().find(|s| {
                s.lighting == Lighting::Studio.label()
                    && (s.samples, s.fxaa, s.ground, s.creases)
                        == (r.samples, r.fxaa, r.ground, r.creases)
            })
        };
        for r in report
            .rows
            .iter()
            .filter(|r| r.lighting != Lighting::Studio.label())
        {
            if let Some(s) = studio(r) {
                let cost = 100.0 * (r.ms_per_frame / s.ms_per_frame - 1.0);
                if cost > max || cost.is_nan() {
                    bail!(
                        "the {} costs {cost:+.1} % over the studio's lights ({:.2} against {:.2} ms a frame), above --max-matcap-cost {max}",
                        r.lighting,
                        r.ms_per_frame,
                        s.ms_per_frame
                    );
                }
            }
        }
    }
    Ok(())
}
