//! `puppet bench joints`: how a bent joint's surface holds up, a hinge against joint bands
//! (see `puppet::puppet::bend`): faces crossing, volume change, the largest dihedral angle
//! in the joint region, for each joint of `puppet::puppet::bend::JOINTS` at each angle.

use super::table::{self, Column, Table};
use anyhow::{anyhow, bail, Result};
use puppet::puppet::bend::{Bent, JOINTS};
use std::path::PathBuf;

/// `puppet bench joints`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Folder holding `human.obj` and `hand.obj`.
    #[arg(long, default_value = "tests/data/meshes")]
    meshes: PathBuf,
    /// Bend angles in degrees.
    #[arg(long, value_delimiter = ',', default_values_t = [45.0, 90.0, 135.0])]
    angles: Vec<f64>,
    /// Band factors to compare (0: a hinge).
    #[arg(long, value_delimiter = ',', default_values_t = [0.0, puppet::joints::DEFAULT_BAND])]
    bands: Vec<f64>,
    /// Only the joints whose name contains this.
    #[arg(long)]
    only: Option<String>,
    /// Print JSON instead of a Markdown table.
    #[arg(long)]
    json: bool,
}

#[derive(serde::Serialize)]
struct Row {
    joint: &'static str,
    band: f64,
    #[serde(flatten)]
    bent: Bent,
}

pub fn run(args: &Args) -> Result<()> {
    for &a in &args.angles {
        if !(a.is_finite() && a.abs() <= 180.0) {
            bail!("--angles: {a} is outside -180..180");
        }
    }
    let mut bands = args.bands.clone();
    bands.dedup();
    for &b in &bands {
        if !(b.is_finite() && (0.0..=puppet::joints::MAX_BAND).contains(&b)) {
            bail!("--bands: {b} is outside 0..{}", puppet::joints::MAX_BAND);
        }
    }
    let mut rows = Vec::new();
    let mut table = Table::new(&[
        Column::Text("joint"),
        Column::Figure("band"),
        Column::Figure("bend"),
        Column::Figure("faces crossing"),
        Column::Figure("volume"),
        Column::Figure("region volume"),
        Column::Figure("largest dihedral (rest)"),
        Column::Figure("crease (bones alone)"),
    ]);
    for joint in JOINTS.iter().filter(|j| {
        args.only
            .as_ref()
            .is_none_or(|o| j.name.contains(o.as_str()))
    }) {
        let path = args.meshes.join(joint.mesh);
        let mesh = puppet::mesh::load(&path)
            .map_err(|e| anyhow!("{}: {e}", path.display()))?
            .0;
        for &band in &bands {
            for &degrees in &args.angles {
                let bent = joint
                    .bend(&mesh, Some(band), degrees, puppet::sim::Params::default())
                    .map_err(|e| anyhow!("{}: {e}", path.display()))?;
                let row = Row {
                    joint: joint.name,
                    band,
                    bent,
                };
                if !args.json {
                    table.row(&cells(&row));
                }
                rows.push(row);
            }
        }
    }
    if args.json {
        table::json(&rows)?;
    }
    Ok(())
}

/// A row's cells, as its table prints them.
fn cells(r: &Row) -> Vec<String> {
    vec![
        r.joint.to_string(),
        if r.band == 0.0 {
            "hinge".to_string()
        } else {
            format!("{}", r.band)
        },
        format!("{}°", r.bent.degrees),
        format!("{} of {}", r.bent.crossing, r.bent.region_faces),
        format!("{:+.2} %", 100.0 * r.bent.volume),
        format!("{:+.2} %", 100.0 * r.bent.region_volume),
        format!("{:.0}° ({:.0}°)", r.bent.dihedral, r.bent.rest_dihedral),
        format!("{:+.0}° ({:+.0}°)", r.bent.crease, r.bent.target_crease),
    ]
}
