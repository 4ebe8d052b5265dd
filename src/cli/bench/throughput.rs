//! Step throughput on the standard scenario, and the largest subdivision of the input that
//! holds 60 steps/s.
//!
//! The limb swings during the whole measurement and sleeping is off, so every step
//! integrates every spring: this is the full cost, not the cost of a scenario at rest
//! (`--skip` measures what sleeping saves).

use super::table::{self, Column, Table};
use super::{median_p95, Base, Input};
use crate::cli::LoadArgs;
use anyhow::Result;
use puppet::bench::scenario::Scenario;
use puppet::mesh::subdivide_loop_values;
use puppet::sim::Constraint;
use puppet::sim::{Layer, Material, Options, Params, Regions, Simulation, REFERENCE_STEP};

/// Steps before timing starts.
const WARM_UP: usize = 20;
/// 60 steps per second.
const BUDGET_MS: f64 = 1000.0 / 60.0;

#[derive(serde::Serialize, Clone)]
pub struct Row {
    pub vertices: usize,
    pub springs: usize,
    pub steps: usize,
    pub method: &'static str,
    pub ms_per_step_median: f64,
    pub ms_per_step_p95: f64,
    /// Stage medians (ms): wake, fused (bones + forces + Verlet + constraint), sleep.
    pub wake_ms_median: f64,
    pub fused_ms_median: f64,
    pub fused_ms_p95: f64,
    pub sleep_ms_median: f64,
    /// Stage 4c, contacts between sections (0 with collision off).
    pub contact_ms_median: f64,
    pub springs_per_second: f64,
    pub steps_per_second: f64,
    pub threads: usize,
    pub simd: bool,
    /// Bytes the fused pass streams per step (see `docs/engine-benchmarks.md`) and the rate that makes.
    pub bytes_per_step: usize,
    pub gb_per_second: f64,
}

/// Bytes the fused pass reads and writes per step: per slot its constants (10 `f32` and a
/// `u16` section: 42), its current position (16, packed) and its previous one (16 read, 16
/// written); per entry of the spring rows (one per half-spring plus padding) the neighbour
/// offset and the rest length (8). Neighbour positions are gathered from lines already
/// loaded (Hilbert order), so they are not counted.
fn bytes_per_step(vertices: usize, lane_entries: usize) -> usize {
    vertices * (42 + 16 + 32) + lane_entries * 8
}

/// Measures `steps` timed steps of `scenario` with every tile integrated.
pub fn measure(scenario: &Scenario, params: Params, regions: Regions, steps: usize) -> Row {
    let options = Options {
        sleeping: false,
        ..Options::default()
    };
    let mut sim =
        Simulation::with_options(scenario.rig(params.material.bone_distance), params, options);
    sim.set_sections(scenario.joints.transform_of().to_vec());
    sim.set_joint_sections(scenario.joints.joint_sections());
    sim.set_regions(regions);
    let springs = sim.rig().spring_count();
    let vertices = sim.rig().len();
    let h = params.solver.time_step as f64;
    let (mut total, mut wake, mut fused, mut sleep, mut contact) =
        (Vec::new(), Vec::new(), Vec::new(), Vec::new(), Vec::new());
    let mut scratch = puppet::joints::PoseScratch::default();
    for k in 0..steps + WARM_UP {
        // The pose is part of the step's cost (a joint band's levels and contacts).
        let t = std::time::Instant::now();
        let pose = scenario
            .joints
            .pose_into(&scenario.local(k as f64 * h), &mut scratch);
        sim.step(pose);
        let dt = t.elapsed().as_secs_f64() * 1e3;
        if k >= WARM_UP {
            let st = sim.last_times();
            total.push(dt);
            wake.push(st.wake * 1e3);
            fused.push(st.fused * 1e3);
            sleep.push(st.sleep * 1e3);
            contact.push(st.contact * 1e3);
        }
    }
    let (med, p95) = median_p95(total);
    let (fused_med, fused_p95) = median_p95(fused);
    let bytes = bytes_per_step(vertices, sim.lane_entries());
    Row {
        vertices,
        springs,
        steps,
        method: params.solver.constraint.name(),
        ms_per_step_median: med,
        ms_per_step_p95: p95,
        wake_ms_median: median_p95(wake).0,
        fused_ms_median: fused_med,
        fused_ms_p95: fused_p95,
        sleep_ms_median: median_p95(sleep).0,
        contact_ms_median: median_p95(contact).0,
        springs_per_second: springs as f64 / (med * 1e-3),
        steps_per_second: 1e3 / med,
        threads: rayon::current_num_threads(),
        simd: sim.options().simd,
        bytes_per_step: bytes,
        gb_per_second: bytes as f64 / (fused_med * 1e-3) / 1e9,
    }
}

#[derive(serde::Serialize)]
struct Report {
    #[serde(flatten)]
    first: Row,
    /// The largest measured size whose median step fits in 1/60 s.
    largest_at_60_steps_per_second: Option<Row>,
    sizes: Vec<Row>,
}

/// `puppet bench throughput`.
#[derive(clap::Args, Debug)]
pub struct Args {
    #[command(flatten)]
    input: Input,
    /// Loop-subdivide the mesh until it has at least this many springs.
    #[arg(long)]
    springs: Option<usize>,
    /// Instead of a mesh file, a generated torus (tube radius half the ring radius) with
    /// about --springs springs (five per vertex), its skeletal distance the exact one (the
    /// tube radius): sizes between the fourfold steps of subdivision.
    #[arg(long, requires = "springs", conflicts_with = "mesh")]
    torus: bool,
    /// The constraint.
    #[arg(long, value_enum, default_value_t = Constraint::Circumsphere)]
    constraint: Constraint,
    /// Timed steps per size.
    #[arg(long, default_value_t = 120)]
    frames: usize,
    /// Throughput at every subdivision level 0..=--subdivisions, not only up to the first
    /// size that misses 60 steps/s.
    #[arg(long)]
    scaling: bool,
    /// Loop subdivision steps for --scaling (each quadruples the faces; at most 6).
    #[arg(long, default_value_t = 3, value_parser = clap::value_parser!(u8).range(0..=6))]
    subdivisions: u8,
    /// Gravity in g, pulling down (`-y`).
    #[arg(long, default_value_t = 0.0)]
    gravity: f32,
    /// A floor a tenth of the mesh's height above its lowest point (the limb and the body
    /// squash against it).
    #[arg(long)]
    floor: bool,
    /// Sections collide (the limb with the body; see `puppet bench collide`).
    #[arg(long)]
    collision: bool,
    /// With collision, the body's flesh gives this share of its balls' radii (0: hard).
    #[arg(long, allow_negative_numbers = true, default_value_t = 0.0)]
    flesh: f32,
    /// Measure the first size with collision on and off, alternating, ROUNDS times each,
    /// and fail when the step with collision costs more than PERCENT % above the one
    /// without.
    #[arg(long, value_name = "PERCENT", conflicts_with = "max_band_cost", value_parser = super::bound)]
    max_collision_cost: Option<f64>,
    /// Painted materials: the half of the surface with `x` above the middle is "thick skin",
    /// with stiffening exponent 2, and every tenth vertex is pinned with weight 0.5.
    #[arg(long)]
    mixed: bool,
    /// Give the limb's cut a joint band of this many local medial radii (0: a hinge), with
    /// its contacts; the pose is then computed inside the timed step.
    #[arg(long)]
    band: Option<f64>,
    /// With --band: measure the first size with that band and as a hinge (band 0),
    /// alternating, ROUNDS times each, and fail when the band's median step costs more than
    /// PERCENT % above the hinge's.
    #[arg(long, requires = "band", value_name = "PERCENT", value_parser = super::bound)]
    max_band_cost: Option<f64>,
    /// Rounds of --max-band-cost.
    #[arg(long, default_value_t = 3, value_name = "ROUNDS")]
    rounds: usize,
    /// Print JSON instead of a Markdown table.
    #[arg(long)]
    json: bool,
}

/// The painted materials of `--mixed` (see there).
fn mixed_regions(scenario: &Scenario) -> Regions {
    let (lo, hi) = scenario.mesh.bounds();
    let middle = 0.5 * (lo.x + hi.x);
    let thick = Material::preset("thick skin").unwrap_or_default();
    Regions {
        layers: vec![Layer {
            material: Material {
                stiffening: 2,
                ..thick
            },
            weight: scenario
                .mesh
                .positions
                .iter()
                .map(|p| if p.x > middle { 1.0 } else { 0.0 })
                .collect(),
        }],
        pin: (0..scenario.mesh.positions.len())
            .map(|i| if i % 10 == 0 { 0.5 } else { 0.0 })
            .collect(),
    }
}

pub fn run(args: &Args, load: &LoadArgs) -> Result<()> {
    if let Some(band) = args.band {
        if !(band.is_finite() && (0.0..=puppet::joints::MAX_BAND).contains(&band)) {
            anyhow::bail!("--band: {band} is outside 0..{}", puppet::joints::MAX_BAND);
        }
    }
    if let Some(max) = args.max_band_cost.filter(|m| !m.is_finite()) {
        anyhow::bail!("--max-band-cost: {max} is not a number of percent");
    }
    if let Some(max) = args.max_collision_cost.filter(|m| !m.is_finite()) {
        anyhow::bail!("--max-collision-cost: {max} is not a number of percent");
    }
    let base = Base::load(&args.input, load, args.springs.filter(|_| args.torus))?;
    let mut params = Params::default();
    params.solver.constraint = args.constraint;
    params.solver.time_step = REFERENCE_STEP;
    params.world.gravity = [0.0, -args.gravity, 0.0];
    params.world.floor = args.floor;
    params.world.collision = args.collision;
    params.world.flesh = args.flesh;
    params
        .world
        .check()
        .map_err(|e| anyhow::anyhow!("--flesh: {e}"))?;
    let params = params.sanitized();
    let max_level = if args.scaling {
        args.subdivisions as usize
    } else {
        6
    };
    // The first size: the input, or its first subdivision with enough springs.
    let mut level = 0;
    if let Some(want) = args.springs {
        let (v, e) = (base.mesh.positions.len(), base.mesh.edge_count());
        let (mut v, mut e, mut f) = (v, e, base.mesh.triangles.len());
        while e + 2 * v < want && level < 6 {
            (v, e, f) = (v + e, 2 * e + 3 * f, 4 * f);
            level += 1;
        }
    }
    let mut rows: Vec<Row> = Vec::new();
    // Each level subdivides the previous one (not the input again).
    let (mut mesh, mut distance) = base.subdivided(level);
    loop {
        if !rows.is_empty() {
            (mesh, distance) = subdivide_loop_values(&mesh, &distance);
        }
        let scenario = banded(
            base.scenario_of(mesh.clone(), distance.clone(), f64::INFINITY)?,
            args.band,
        );
        let (lo, hi) = scenario.mesh.bounds();
        let mut params = params;
        params.world.floor_height = (0.1 * (hi.y - lo.y)) as f32;
        let regions = if args.mixed {
            mixed_regions(&scenario)
        } else {
            Regions::default()
        };
        if let (Some(max), Some(band)) = (args.max_band_cost, args.band) {
            let hinge = banded(scenario.clone(), Some(0.0));
            return band_cost(&scenario, &hinge, params, &regions, args, band, max);
        }
        if let Some(max) = args.max_collision_cost {
            return collision_cost(&scenario, params, &regions, args, max);
        }
        let row = measure(&scenario, params, regions, args.frames.max(1));
        let held = row.ms_per_step_median <= BUDGET_MS;
        log::info!(
            "{} springs: {:.3} ms per step",
            row.springs,
            row.ms_per_step_median
        );
        rows.push(row);
        level += 1;
        let stop = if args.scaling {
            level > max_level
        } else {
            !held || level > max_level
        };
        if stop {
            break;
        }
    }
    let largest = rows
        .iter()
        .filter(|r| r.ms_per_step_median <= BUDGET_MS)
        .max_by_key(|r| r.springs)
        .cloned();
    if args.json {
        let report = Report {
            first: rows[0].clone(),
            largest_at_60_steps_per_second: largest,
            sizes: rows,
        };
        return table::json(&report);
    }
    println!(
        "standard scenario on {} (Loop-subdivided), {} constraint, {} threads, SIMD {}, median/p95 of {} steps, sleeping off",
        base.name,
        args.constraint,
        rayon::current_num_threads(),
        if rows[0].simd { "AVX2" } else { "off" },
        args.frames
    );
    println!();
    let mut table = Table::new(&[
        Column::Figure("vertices"),
        Column::Figure("springs"),
        Column::Figure("ms/step median"),
        Column::Figure("p95"),
        Column::Figure("fused pass ms (median / p95)"),
        Column::Figure("wake + sleep ms"),
        Column::Figure("springs/s"),
        Column::Figure("steps/s"),
        Column::Figure("fused GB/s"),
    ]);
    table.start();
    for r in &rows {
        table.row(&[
            r.vertices.to_string(),
            r.springs.to_string(),
            format!("{:.3}", r.ms_per_step_median),
            format!("{:.3}", r.ms_per_step_p95),
            format!("{:.3} / {:.3}", r.fused_ms_median, r.fused_ms_p95),
            format!("{:.3}", r.wake_ms_median + r.sleep_ms_median),
            format!("{:.2e}", r.springs_per_second),
            format!("{:.0}", r.steps_per_second),
            format!("{:.2}", r.gb_per_second),
        ]);
    }
    println!();
    match largest {
        Some(r) => println!(
            "largest size at 60 steps/s: {} vertices, {} springs ({:.2} ms per step)",
            r.vertices, r.springs, r.ms_per_step_median
        ),
        None => println!("no measured size holds 60 steps/s"),
    }
    Ok(())
}

/// `scenario` with the limb's cut given a joint band of `band` local radii (`None`: as it is).
fn banded(mut scenario: Scenario, band: Option<f64>) -> Scenario {
    if let Some(band) = band {
        scenario
            .joints
            .set_surface(&scenario.mesh.positions, &scenario.distance);
        scenario.joints.set_band("limb", Some(band));
    }
    scenario
}

/// `--max-band-cost`: the same scene with the band and as a hinge, alternating.
fn band_cost(
    scenario: &Scenario,
    hinge: &Scenario,
    params: Params,
    regions: &Regions,
    args: &Args,
    band: f64,
    max_percent: f64,
) -> Result<()> {
    let frames = args.frames.max(1);
    compare(
        args.rounds,
        ("hinge", &|| measure(hinge, params, regions.clone(), frames)),
        (&format!("band {band}"), &|| {
            measure(scenario, params, regions.clone(), frames)
        }),
        max_percent,
        "the band's step",
        "a hinge's",
    )
}

/// `--max-collision-cost`: the same scene with collision off and on, alternating.
fn collision_cost(
    scenario: &Scenario,
    params: Params,
    regions: &Regions,
    args: &Args,
    max_percent: f64,
) -> Result<()> {
    let frames = args.frames.max(1);
    let with = |collision: bool| {
        let mut p = params;
        p.world.collision = collision;
        measure(scenario, p, regions.clone(), frames)
    };
    compare(
        args.rounds,
        ("collision off", &|| with(false)),
        ("on", &|| with(true)),
        max_percent,
        "the step with collision",
        "one without",
    )
}

/// Measures `base` and `other` alternating, `rounds` times each; prints their median
/// steps and fails when `other`'s is more than `max_percent` % above `base`'s.
fn compare(
    rounds: usize,
    base: (&str, &dyn Fn() -> Row),
    other: (&str, &dyn Fn() -> Row),
    max_percent: f64,
    what: &str,
    against: &str,
) -> Result<()> {
    let (mut a, mut b) = (Vec::new(), Vec::new());
    let mut springs = 0;
    for _ in 0..rounds.max(1) {
        a.push((base.1)().ms_per_step_median);
        let row = (other.1)();
        b.push(row.ms_per_step_median);
        springs = row.springs;
    }
    let (a_ms, b_ms) = (median_p95(a.clone()).0, median_p95(b.clone()).0);
    let percent = 100.0 * (b_ms / a_ms - 1.0);
    let list = |v: &[f64]| {
        v.iter()
            .map(|m| format!("{m:.2}"))
            .collect::<Vec<_>>()
            .join(", ")
    };
    println!(
        "{springs} springs, median ms per step over {} alternating rounds: {} {a_ms:.2} ({}), {} {b_ms:.2} ({}): {percent:+.1} %",
        rounds.max(1),
        base.0,
        list(&a),
        other.0,
        list(&b)
    );
    if percent.is_nan() || percent > max_percent {
        anyhow::bail!("{what} costs {percent:+.1} % against {against}, more than {max_percent} %");
    }
    Ok(())
}
