//! `puppet bench suggest`: the suggested joints of each labelled character against its
//! labels (see `puppet::joints::suggest::labels`): recall of the required joints,
//! spurious cuts, names, RigNet's joint-to-joint distance, and the time taken.

use crate::cli::LoadArgs;
use anyhow::{anyhow, bail, Result};
use puppet::joints::suggest::labels::{Labels, Score, TOLERANCE};
use puppet::joints::suggest::Up;
use puppet::{Puppet, RigFile};
use std::path::{Path, PathBuf};
use std::time::Instant;

/// `puppet bench suggest`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Folder of the labelled set: one labels file (`NAME.toml`) per character.
    #[arg(long, default_value = "tests/data/characters")]
    set: PathBuf,
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
    /// Up as found, and whether the labels say the same.
    up: String,
    up_right: bool,
    #[serde(flatten)]
    score: Score,
    ms_skeleton: f64,
    ms_suggest: f64,
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
    super::image_folder(args.images.as_ref())?;
    for (name, file) in label_files(&args.set)? {
        if args
            .only
            .as_ref()
            .is_some_and(|o| !name.contains(o.as_str()))
        {
            continue;
        }
        let labels = Labels::read(&file).map_err(|e| anyhow!("{}: {e}", file.display()))?;
        let path = labels.mesh_path(&file);
        let (mut mesh, report, shown) = crate::cli::load_mesh(Some(&path), load)?;
        if let Some(share) = args.jitter {
            mesh = puppet::mesh::shapes::roughen(&mesh, share, args.seed);
        }
        let height = mesh.longest_side();
        // The skeleton and rig's time, once (a second build would find the skeleton in
        // `skeleton::cache`), then the suggestion's, the median of three.
        let t = Instant::now();
        let built = Puppet::build_loaded(
            mesh,
            Some(&report),
            RigFile::default(),
            puppet::progress::silent(),
        )
        .map_err(|e| anyhow!("{shown}: {e}"))?;
        let ms_skeleton = t.elapsed().as_secs_f64() * 1e3;
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
        let vertices = puppet.mesh.positions.len();
        if let Some(dir) = &args.images {
            crate::cli::suggest::picture(puppet, &dir.join(format!("{name}.png")))?;
        }
        let row = Row {
            character: name,
            kind: labels.kind.clone(),
            vertices,
            up,
            up_right,
            score,
            ms_skeleton,
            ms_suggest,
        };
        if !args.json {
            print_row(&row, rows.is_empty());
        }
        rows.push(row);
    }
    let required: usize = rows.iter().map(|r| r.score.required).sum();
    let found: usize = rows.iter().map(|r| r.score.found).sum();
    let cuts: usize = rows.iter().map(|r| r.score.cuts).sum();
    let spurious: usize = rows.iter().map(|r| r.score.spurious).sum();
    let recall = 100.0 * found as f64 / required.max(1) as f64;
    let spurious_share = 100.0 * spurious as f64 / cuts.max(1) as f64;
    if args.json {
        println!("{}", serde_json::to_string_pretty(&rows)?);
    } else {
        let matched: usize = rows.iter().map(|r| r.score.matched).sum();
        let named: usize = rows.iter().map(|r| r.score.named).sum();
        let j2j = rows.iter().map(|r| r.score.j2j).sum::<f64>() / rows.len().max(1) as f64;
        let ups = rows.iter().filter(|r| r.up_right).count();
        let characters = rows.len();
        println!(
            "| **all** | | | {ups}/{characters} | {found}/{required} ({recall:.0} %) | {spurious}/{cuts} ({spurious_share:.0} %) | {named}/{matched} | {j2j:.1} | | | |"
        );
        println!(
            "\nA cut matches a joint within {:.0} % of the height (the longest side of the bounding box).",
            TOLERANCE * 100.0
        );
    }
    if let Some(min) = args.min_recall {
        if recall < min {
            bail!("recall {recall:.1} % is below --min-recall {min}");
        }
    }
    if let Some(max) = args.max_spurious {
        if spurious_share > max {
            bail!("{spurious_share:.1} % spurious cuts is above --max-spurious {max}");
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

fn print_row(r: &Row, header: bool) {
    if header {
        println!("| character | kind | vertices | up found | required found | spurious cuts | named as the role | CD-J2J (% height) | skeleton (ms) | suggestion (ms) | missed; spurious |");
        println!("|---|---|---:|---|---:|---:|---:|---:|---:|---:|---|");
    }
    let s = &r.score;
    println!(
        "| {} | {} | {} | {}{} | {}/{} | {}/{} | {}/{} | {:.1} | {:.0} | {:.1} | {}; {} |",
        r.character,
        r.kind,
        r.vertices,
        r.up,
        if r.up_right { "" } else { " (wrong)" },
        s.found,
        s.required,
        s.spurious,
        s.cuts,
        s.named,
        s.matched,
        s.j2j,
        r.ms_skeleton,
        r.ms_suggest,
        s.missed.join(", "),
        s.extra.join(", ")
    );
}
