//! `puppet bench collide`: parts pressed into the body (see `puppet::puppet::press`), with
//! collision off and on, turned by a hand and by an animation: faces crossing, the deepest
//! penetration, section volumes, and the step's cost.

use super::table::{self, Column, Table};
use crate::cli::LoadArgs;
use anyhow::{anyhow, Result};
use puppet::puppet::press::{Drive, Pressed, PRESSES};
use std::path::PathBuf;

/// `puppet bench collide`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Folder holding `human.obj` and `hand.obj`.
    #[arg(long, default_value = "tests/data/meshes")]
    meshes: PathBuf,
    /// Only the presses whose name contains this.
    #[arg(long)]
    only: Option<String>,
    /// Margin (share of the diagonal) with collision on.
    #[arg(long, allow_negative_numbers = true, default_value_t = puppet::sim::World::default().collision_margin)]
    margin: f32,
    /// How far the body's flesh gives in the third run of each press (0: two runs only).
    #[arg(long, allow_negative_numbers = true, default_value_t = 0.25)]
    flesh: f32,
    /// Write a picture of each settled press here (`NAME-off.png`, `NAME-on.png`).
    #[arg(long)]
    images: Option<PathBuf>,
    /// Print JSON instead of a Markdown table.
    #[arg(long)]
    json: bool,
}

#[derive(serde::Serialize)]
struct Row {
    press: &'static str,
    collision: bool,
    flesh: f32,
    drive: Drive,
    #[serde(flatten)]
    pressed: Pressed,
}

pub fn run(args: &Args, load: &LoadArgs) -> Result<()> {
    let mut rows = Vec::new();
    let mut table = Table::new(&COLUMNS);
    // Both settings checked before any press runs.
    puppet::sim::World {
        collision: true,
        collision_margin: args.margin,
        flesh: args.flesh,
        ..puppet::sim::World::default()
    }
    .check()
    .map_err(|e| anyhow!("--margin/--flesh: {e}"))?;
    super::image_folder(args.images.as_ref())?;
    for press in PRESSES.iter().filter(|p| {
        args.only
            .as_ref()
            .is_none_or(|o| p.name.contains(o.as_str()))
    }) {
        // The cow is the embedded one.
        let path = (press.mesh != "spot.obj").then(|| args.meshes.join(press.mesh));
        let (mesh, _, name) = crate::cli::load_mesh(path.as_deref(), load)?;
        // Off, a hand and an animation play alike; on, both are measured.
        let mut runs = vec![
            (false, 0.0, Drive::Hand),
            (true, 0.0, Drive::Hand),
            (true, 0.0, Drive::Animation),
        ];
        if args.flesh > 0.0 {
            runs.push((true, args.flesh, Drive::Hand));
        }
        for (collision, flesh, drive) in runs {
            let mut params = puppet::sim::Params::default();
            params.world.collision = collision;
            params.world.collision_margin = args.margin;
            params.world.flesh = flesh;
            let pressed = press
                .press_by(&mesh, params, drive)
                .map_err(|e| anyhow!("{name}: {e}"))?;
            if let Some(dir) = args.images.as_ref().filter(|_| drive == Drive::Hand) {
                let p = press
                    .posed(&mesh, params)
                    .map_err(|e| anyhow!("{name}: {e}"))?
                    .puppet;
                let file: String = press
                    .name
                    .chars()
                    .map(|c| if c.is_ascii_alphanumeric() { c } else { '-' })
                    .collect();
                let on = match (collision, flesh > 0.0) {
                    (false, _) => "off",
                    (true, false) => "on",
                    (true, true) => "soft",
                };
                crate::cli::suggest::picture(p, &dir.join(format!("{file}-{on}.png")))?;
            }
            let row = Row {
                press: press.name,
                collision,
                flesh,
                drive,
                pressed,
            };
            if !args.json {
                table.row(&cells(&row));
            }
            rows.push(row);
        }
    }
    if args.json {
        table::json(&rows)?;
    }
    Ok(())
}

/// The columns of `bench collide`'s table.
const COLUMNS: [Column; 11] = [
    Column::Text("pose"),
    Column::Text("collision"),
    Column::Text("turned by"),
    Column::Figure("reached"),
    Column::Figure("new crossing faces"),
    Column::Figure("deepest (% diagonal)"),
    Column::Figure("vertices inside"),
    Column::Figure("body dent / part squashed (% diagonal)"),
    Column::Figure("section volumes"),
    Column::Figure("step (ms)"),
    Column::Figure("awake tiles at the end"),
];

/// A row's cells, as its table prints them.
fn cells(r: &Row) -> Vec<String> {
    let p = &r.pressed;
    vec![
        r.press.to_string(),
        match (r.collision, r.flesh > 0.0) {
            (false, _) => "off".to_string(),
            (true, false) => "on".to_string(),
            (true, true) => format!("on, flesh {}", r.flesh),
        },
        match r.drive {
            Drive::Hand => "hand",
            Drive::Animation => "animation",
        }
        .to_string(),
        format!("{:.0}°", p.reached),
        format!("{} of {}", p.crossing, p.faces),
        format!("{:.2}", p.deepest),
        p.inside.to_string(),
        format!("{:.2} / {:.2}", p.dent[0], p.dent[1]),
        format!(
            "{:+.1} % … {:+.1} %",
            100.0 * p.volume[0],
            100.0 * p.volume[1]
        ),
        format!("{:.2}", p.step_ms),
        format!("{} of {}", p.awake[0], p.awake[1]),
    ]
}
