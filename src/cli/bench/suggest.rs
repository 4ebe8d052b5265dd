//! `puppet bench suggest`: the suggested joints of each labelled character against its
//! labels (see `puppet::bench::labels`): recall of the required joints,
//! spurious cuts, names, up and front, RigNet's joint-to-joint distance, and the time
//! taken; totals per half of the population (`Half`), which must agree.

use super::table::{self, Column, Table};
use crate::cli::LoadArgs;
use anyhow::{anyhow, bail, Result};
use puppet::bench::labels::{Half, Labels, Score, TOLERANCE};
use puppet::mesh::orientation::Up;
use puppet::{Puppet, RigFile};
use std::path::{Path, PathBuf};
use std::time::Instant;

/// `puppet bench suggest`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Folder of a labelled set: one labels file (`NAME.toml`) per character. Repeat it
    /// for several; by default the hand-labelled set and the population from artists' rigs.
    #[arg(
        long,
        default_values = ["tests/data/characters", "tests/data/population"]
    )]
    set: Vec<PathBuf>,
    /// Only the characters of this half of the population (by default both, each with its
    /// totals).
    #[arg(long, value_enum)]
    half: Option<Half>,
    /// Only the characters whose name contains this.
    #[arg(long)]
    only: Option<String>,
    /// Write a picture of each character's suggested sections here (`NAME.png`).
    #[arg(long)]
    images: Option<PathBuf>,
    /// Fail when the recall of required joints over the set is below this (%).
    #[arg(long, value_parser = super::bound)]
    min_recall: Option<f64>,
    /// Fail when the share of spurious cuts over the set is above this (%).
    #[arg(long, value_parser = super::bound)]
    max_spurious: Option<f64>,
    /// Fail when a character's suggestion takes longer than this share (%) of the time its
    /// skeleton and rig take.
    #[arg(long, value_parser = super::bound)]
    max_time_share: Option<f64>,
    /// Roughen each mesh first: every vertex moved by up to this share of the mean edge
    /// length, in a random direction (`--seed`), as a scan's surface is rough.
    #[arg(long, value_name = "SHARE", value_parser = share)]
    jitter: Option<f64>,
    /// The seed of `--jitter`.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Find up and front from the shape alone: set aside the axes a file's format declares
    /// (a glTF file's +y up and +z front), to measure the suggestion's own cues.
    #[arg(long)]
    ignore_format_axes: bool,
    /// Turn each character so that the up it is labelled with (+y where it says none)
    /// becomes this axis, its labels with it, and find up and front from the shape alone
    /// (as `--ignore-format-axes`): how the cues do on a file modelled with another axis
    /// up, as CAD and Blender model +z.
    #[arg(long, value_name = "AXIS", allow_hyphen_values = true)]
    turn_up: Option<Up>,
    /// Print JSON instead of a Markdown table.
    #[arg(long)]
    json: bool,
}

/// `run` three times: the last result, and the median time in milliseconds.
fn median_of_three<T>(mut run: impl FnMut() -> Result<T>) -> Result<(T, f64)> {
    let mut times = Vec::with_capacity(3);
    let mut last = None;
    for _ in 0..3 {
        let t = Instant::now();
        last = Some(run()?);
        times.push(t.elapsed().as_secs_f64() * 1e3);
    }
    times.sort_by(f64::total_cmp);
    let last = last.ok_or_else(|| anyhow!("nothing ran"))?;
    Ok((last, times[1]))
}

/// A `--jitter` share: finite, from 0 to 10 edge lengths.
fn share(s: &str) -> Result<f64, String> {
    let v: f64 = s.parse().map_err(|_| format!("not a number: {s}"))?;
    if v.is_finite() && (0.0..=10.0).contains(&v) {
        Ok(v)
    } else {
        Err(format!("{s} is not a share from 0 to 10"))
    }
}

#[derive(serde::Serialize)]
struct Row {
    character: String,
    kind: String,
    vertices: usize,
    /// Its half of the population.
    half: Half,
    /// Up as found, and whether the labels say the same.
    up: String,
    up_right: bool,
    /// Front as found (the axis nearest it), and whether the labels say the same.
    front: String,
    front_right: bool,
    #[serde(flatten)]
    score: Score,
    /// The sections that reach across the body's mirror plane (`Joints::across_mirror`):
    /// a limb's cut that slipped into the body.
    across: Vec<String>,
    ms_skeleton: f64,
    ms_suggest: f64,
    /// Why the character could not be suggested on (the loader refused it).
    refused: Option<String>,
}

/// The labels files in `dir`, by name.
fn label_files(dir: &Path) -> Result<Vec<(String, PathBuf)>> {
    let mut out: Vec<(String, PathBuf)> = std::fs::read_dir(dir)
        .map_err(|e| anyhow!("{}: {}", dir.display(), puppet::files::io_message(&e)))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .filter_map(|p| Some((p.file_stem()?.to_str()?.to_string(), p.clone())))
        .collect();
    out.sort();
    Ok(out)
}

pub fn run(args: &Args, load: &LoadArgs) -> Result<()> {
    let mut rows = Vec::new();
    let mut table = Table::new(&COLUMNS);
    super::image_folder(args.images.as_ref())?;
    let mut files = Vec::new();
    for set in &args.set {
        files.extend(label_files(set)?);
    }
    for (name, file) in files {
        if args
            .only
            .as_ref()
            .is_some_and(|o| !name.contains(o.as_str()))
        {
            continue;
        }
        let labels = Labels::read(&file).map_err(|e| anyhow!("{}: {e}", file.display()))?;
        if args.half.is_some_and(|h| h != labels.half) {
            continue;
        }
        let row = match measure(&name, &labels, &file, args, load) {
            Ok(row) => row,
            // A character the loader refuses scores nothing: its required joints are
            // all missed, and it says why.
            Err(e) => Row {
                character: name,
                kind: labels.kind.clone(),
                vertices: 0,
                half: labels.half,
                up: "none".into(),
                up_right: false,
                front: "none".into(),
                front_right: false,
                score: labels.score(&[], 1.0),
                across: Vec::new(),
                ms_skeleton: 0.0,
                ms_suggest: 0.0,
                refused: Some(e.to_string()),
            },
        };
        if !args.json {
            table.row(&cells(&row));
        }
        rows.push(row);
    }
    let halves: Vec<Half> = [Half::Development, Half::HeldOut]
        .into_iter()
        .filter(|h| rows.iter().any(|r| r.half == *h))
        .collect();
    let totals: Vec<(String, Totals)> = halves
        .iter()
        .map(|h| {
            let of: Vec<&Row> = rows.iter().filter(|r| r.half == *h).collect();
            (format!("{} half", h.name()), Totals::of(&of))
        })
        .chain(std::iter::once((
            "all".to_string(),
            Totals::of(&rows.iter().collect::<Vec<_>>()),
        )))
        .collect();
    if args.json {
        table::json(&rows)?;
    } else {
        for (name, t) in &totals {
            table.row(&total_cells(name, t));
        }
        println!(
            "\nA cut matches a joint within {:.0} % of the height (the longest side of the bounding box).",
            TOLERANCE * 100.0
        );
    }
    // Each half meets the targets (one half alone when `--half` picks it).
    for (name, t) in totals
        .iter()
        .filter(|(n, _)| halves.len() < 2 || n != "all")
    {
        let (recall, spurious_share) = (t.recall(), t.spurious_share());
        if let Some(min) = args.min_recall {
            if recall < min {
                bail!("{name}: recall {recall:.1} % is below --min-recall {min}");
            }
        }
        if let Some(max) = args.max_spurious {
            if spurious_share > max {
                bail!("{name}: {spurious_share:.1} % spurious cuts is above --max-spurious {max}");
            }
        }
    }
    if let Some(max) = args.max_time_share {
        if let Some(r) = rows
            .iter()
            .find(|r| r.ms_suggest > 0.01 * max * r.ms_skeleton)
        {
            bail!(
                "{}: the suggestion takes {:.1} ms, above --max-time-share {max} % of the skeleton and rig's {:.1} ms",
                r.character,
                r.ms_suggest,
                r.ms_skeleton
            );
        }
    }
    Ok(())
}

/// Suggests joints on one labelled character and scores them.
fn measure(name: &str, labels: &Labels, file: &Path, args: &Args, load: &LoadArgs) -> Result<Row> {
    let path = labels.mesh_path(file);
    let (mut mesh, report, shown) = crate::cli::load_mesh(Some(&path), load)?;
    if let Some(share) = args.jitter {
        mesh = puppet::mesh::shapes::roughen(&mesh, share, args.seed);
    }
    let turned;
    let labels = match args.turn_up {
        Some(to) => {
            let from = labels.up.unwrap_or(Up::PosY).vector();
            let turn = glam::DQuat::from_rotation_arc(from, to.vector());
            for p in &mut mesh.positions {
                *p = turn * *p;
            }
            turned = labels.turned(turn);
            &turned
        }
        None => labels,
    };
    let height = mesh.longest_side();
    // The skeleton and rig's time, once (a second build would find the skeleton in
    // `skeleton::cache`), then the suggestion's, the median of three.
    let t = Instant::now();
    let mut built = Puppet::build_loaded(
        mesh,
        Some(&report),
        RigFile::default(),
        puppet::progress::silent(),
    )
    .map_err(|e| anyhow!("{shown}: {e}"))?;
    let ms_skeleton = t.elapsed().as_secs_f64() * 1e3;
    if args.ignore_format_axes || args.turn_up.is_some() {
        built.ignore_format_axes();
    }
    let (puppet, ms_suggest) = median_of_three(|| {
        let mut puppet = built.clone();
        puppet
            .suggest_joints()
            .map_err(|e| anyhow!("{shown}: {e}"))?;
        Ok(puppet)
    })?;
    let score = labels.score(&puppet.joints.cut_pivots(), height);
    let found = Up::nearest(puppet.up());
    let up_right = labels.up.is_none_or(|u| u == found);
    let up = found.to_string();
    let front = puppet
        .frame()
        .map(|f| Up::nearest(f.front).to_string())
        .unwrap_or_else(|| "none".into());
    let front_right = labels.front.is_none_or(|f| f.to_string() == front);
    let across = puppet
        .frame()
        .and_then(|f| f.mirror)
        .map(|m| puppet.joints.across_mirror(m))
        .unwrap_or_default()
        .into_iter()
        .map(|k| puppet.joints.sections()[k].name.clone())
        .collect();
    let vertices = puppet.mesh.positions.len();
    if let Some(dir) = &args.images {
        crate::cli::suggest::picture(puppet, &dir.join(format!("{name}.png")))?;
    }
    let row = Row {
        character: name.to_string(),
        kind: labels.kind.clone(),
        vertices,
        half: labels.half,
        up,
        up_right,
        front,
        front_right,
        score,
        across,
        ms_skeleton,
        ms_suggest,
        refused: None,
    };
    Ok(row)
}

/// A set's totals over its characters.
struct Totals {
    characters: usize,
    ups: usize,
    fronts: usize,
    required: usize,
    found: usize,
    cuts: usize,
    spurious: usize,
    matched: usize,
    named: usize,
    across: usize,
    j2j: f64,
}

impl Totals {
    fn of(rows: &[&Row]) -> Totals {
        let sum = |f: fn(&Score) -> usize| rows.iter().map(|r| f(&r.score)).sum();
        Totals {
            characters: rows.len(),
            ups: rows.iter().filter(|r| r.up_right).count(),
            fronts: rows.iter().filter(|r| r.front_right).count(),
            required: sum(|s| s.required),
            found: sum(|s| s.found),
            cuts: sum(|s| s.cuts),
            spurious: sum(|s| s.spurious),
            matched: sum(|s| s.matched),
            named: sum(|s| s.named),
            across: rows.iter().map(|r| r.across.len()).sum(),
            j2j: rows.iter().map(|r| r.score.j2j).sum::<f64>() / rows.len().max(1) as f64,
        }
    }

    /// Required joints found, in %.
    fn recall(&self) -> f64 {
        100.0 * self.found as f64 / self.required.max(1) as f64
    }

    /// Spurious cuts, in % of the cuts.
    fn spurious_share(&self) -> f64 {
        100.0 * self.spurious as f64 / self.cuts.max(1) as f64
    }
}

/// The columns of `bench suggest`'s table.
const COLUMNS: [Column; 14] = [
    Column::Text("character"),
    Column::Text("kind"),
    Column::Figure("vertices"),
    Column::Text("up found"),
    Column::Figure("required found"),
    Column::Figure("spurious cuts"),
    Column::Figure("named as the role"),
    Column::Figure("CD-J2J (% height)"),
    Column::Figure("across the body"),
    Column::Figure("skeleton (ms)"),
    Column::Figure("suggestion (ms)"),
    Column::Text("front found"),
    Column::Text("half"),
    Column::Text("missed; spurious"),
];

/// A character's cells, as its table prints them.
fn cells(r: &Row) -> Vec<String> {
    let s = &r.score;
    let wrong = |right: bool| if right { "" } else { " (wrong)" };
    vec![
        r.character.to_string(),
        r.kind.to_string(),
        r.vertices.to_string(),
        format!("{}{}", r.up, wrong(r.up_right)),
        format!("{}/{}", s.found, s.required),
        format!("{}/{}", s.spurious, s.cuts),
        format!("{}/{}", s.named, s.matched),
        format!("{:.1}", s.j2j),
        r.across.len().to_string(),
        format!("{:.0}", r.ms_skeleton),
        format!("{:.1}", r.ms_suggest),
        format!("{}{}", r.front, wrong(r.front_right)),
        r.half.name().to_string(),
        format!(
            "{}; {}",
            s.missed.join(", "),
            match &r.refused {
                Some(why) => format!("refused: {why}"),
                None if r.across.is_empty() => s.extra.join(", "),
                None => format!(
                    "{}; across the body: {}",
                    s.extra.join(", "),
                    r.across.join(", ")
                ),
            }
        ),
    ]
}

/// A half's (or all's) totals, in the table's columns.
fn total_cells(name: &str, t: &Totals) -> Vec<String> {
    let empty = String::new;
    vec![
        format!("**{name}**"),
        empty(),
        empty(),
        format!("{}/{} right", t.ups, t.characters),
        format!("{}/{} ({:.0} %)", t.found, t.required, t.recall()),
        format!("{}/{} ({:.0} %)", t.spurious, t.cuts, t.spurious_share()),
        format!("{}/{}", t.named, t.matched),
        format!("{:.1}", t.j2j),
        t.across.to_string(),
        empty(),
        empty(),
        format!("{}/{} fronts right", t.fronts, t.characters),
        empty(),
        empty(),
    ]
}
