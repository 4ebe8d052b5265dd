//! Docs that cannot drift from the code: every command and bench mode is named in README,
//! CONTRIBUTING and `--help`; every command README, the guide, BENCHMARKS and the engine
//! benchmarks (`docs/engine-benchmarks.md`) quote parses with the current arguments (parse
//! only: nothing runs); ARCHITECTURE lists the files that hold `unsafe`.

use super::Cli;
use clap::{CommandFactory, Parser};

const README: &str = include_str!("../../README.md");
const BENCHMARKS: &str = include_str!("../../BENCHMARKS.md");
const CONTRIBUTING: &str = include_str!("../../CONTRIBUTING.md");
const GUIDE: &str = include_str!("../../docs/guide.md");
const ENGINE: &str = include_str!("../../docs/engine-benchmarks.md");

/// The commands (`skeleton`, …) and the bench modes (`throughput`, …) as clap knows them.
fn commands_and_modes() -> (Vec<String>, Vec<String>) {
    let cli = Cli::command();
    let names = |c: &clap::Command| -> Vec<String> {
        c.get_subcommands()
            .map(|s| s.get_name().to_string())
            .filter(|n| n != "help")
            .collect()
    };
    let bench = cli
        .find_subcommand("bench")
        .expect("a bench command")
        .clone();
    (names(&cli), names(&bench))
}

#[test]
fn every_command_and_bench_mode_is_documented() {
    let (commands, modes) = commands_and_modes();
    assert!(modes.len() >= 11, "{modes:?}");
    let help = Cli::command().render_long_help().to_string();
    for c in &commands {
        assert!(
            README.contains(&format!("puppet {c}")),
            "README: `puppet {c}`"
        );
        assert!(help.contains(c.as_str()), "--help: {c}");
    }
    for m in &modes {
        assert!(
            README.contains(&format!("puppet bench {m}")),
            "README: `puppet bench {m}`"
        );
        assert!(
            CONTRIBUTING.contains(&format!("`{m}`")),
            "CONTRIBUTING: `{m}`"
        );
        // The bench command's line in `puppet --help` lists its modes.
        let listed = help
            .split(|ch: char| !(ch.is_alphanumeric() || ch == '-'))
            .any(|word| word == m);
        assert!(listed, "--help does not list the bench mode {m}");
    }
}

/// The arguments of a quoted command, its synopsis made concrete: optional parts kept, the
/// first of alternatives (`a|b`, `A | B`) taken, placeholders for numbers given one.
fn arguments(quoted: &str) -> Vec<String> {
    let line = quoted.split(" # ").next().unwrap_or_default();
    let line = line.replace(['[', ']'], " ").replace('…', " ");
    let mut out = Vec::new();
    let mut skip_next = false;
    for word in line.split_whitespace() {
        if skip_next {
            skip_next = false;
            continue;
        }
        match word {
            "|" => skip_next = true,
            "..." => {}
            w if w.chars().all(|c| c.is_ascii_uppercase()) && w.len() == 1 => {
                out.push("1".to_string())
            }
            w => out.push(w.split('|').next().unwrap_or(w).to_string()),
        }
    }
    out
}

/// Every command quoted in `text`: the lines of its `sh` blocks and its inline code spans
/// that start with `puppet` (or `target/release/puppet`).
fn quoted_commands(text: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut in_block = false;
    for line in text.lines() {
        if line.starts_with("```") {
            in_block = !in_block;
            continue;
        }
        if in_block && line.starts_with("puppet ") {
            out.push(line.to_string());
        }
    }
    for (k, span) in text.split('`').enumerate() {
        let span = span.replace('\n', " ");
        let span = span.trim_start_matches("target/release/");
        // A fragment of a command in a sentence (`puppet simulate … --out`) is not one.
        let fragment = span.split_whitespace().any(|w| w == "…");
        if k % 2 == 1 && span.starts_with("puppet ") && !fragment {
            out.push(span.to_string());
        }
    }
    out
}

#[test]
fn every_quoted_command_parses() {
    let mut checked = 0;
    let mut failed = Vec::new();
    for (doc, text) in [
        ("README.md", README),
        ("docs/guide.md", GUIDE),
        ("BENCHMARKS.md", BENCHMARKS),
        ("docs/engine-benchmarks.md", ENGINE),
    ] {
        for quoted in quoted_commands(text) {
            let args = arguments(&quoted);
            if let Err(e) = Cli::try_parse_from(&args) {
                let e = e.to_string();
                failed.push(format!(
                    "{doc}: `{quoted}`: {}",
                    e.lines().next().unwrap_or("")
                ));
            }
            checked += 1;
        }
    }
    assert!(failed.is_empty(), "{}", failed.join("\n"));
    assert!(checked >= 30, "only {checked} commands found");
}

#[test]
fn synopses_are_made_concrete() {
    assert_eq!(
        arguments("puppet simulate [MESH.obj] --out FINAL.obj | TAKE.glb | DIR/ [--frames N]"),
        [
            "puppet",
            "simulate",
            "MESH.obj",
            "--out",
            "FINAL.obj",
            "--frames",
            "1"
        ]
    );
    assert_eq!(
        arguments("puppet skeleton MESH [--method fitted-ball|pole]  # the skeleton"),
        ["puppet", "skeleton", "MESH", "--method", "fitted-ball"]
    );
}

/// The files ARCHITECTURE.md's *Where `unsafe` is* names, and those that hold `unsafe`.
#[test]
fn unsafe_is_where_architecture_says() {
    let architecture = include_str!("../../ARCHITECTURE.md");
    let section = architecture
        .split("## Where `unsafe` is")
        .nth(1)
        .and_then(|s| s.split("\n## ").next())
        .expect("ARCHITECTURE.md has a section on unsafe");
    let mut listed: Vec<String> = section
        .split('`')
        .skip(1)
        .step_by(2)
        .filter(|s| s.ends_with(".rs") && !s.contains("docs.rs"))
        .map(|s| format!("src/{s}"))
        .collect();
    listed.sort();
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut found = Vec::new();
    let mut stack = vec![root.join("src")];
    while let Some(dir) = stack.pop() {
        for entry in std::fs::read_dir(&dir).expect("src is readable").flatten() {
            let path = entry.path();
            if path.is_dir() {
                stack.push(path);
            } else if path.extension().is_some_and(|e| e == "rs") {
                let text = std::fs::read_to_string(&path).unwrap_or_default();
                let has_unsafe = text.lines().any(|l| {
                    let code = l.split("//").next().unwrap_or("");
                    code.split(|c: char| !c.is_alphanumeric() && c != '_')
                        .any(|w| w == "unsafe")
                });
                let rel = path
                    .strip_prefix(root)
                    .unwrap_or(&path)
                    .display()
                    .to_string();
                // This file names the word in its strings, not in code.
                if has_unsafe && rel != "src/cli/docs.rs" {
                    found.push(rel);
                }
            }
        }
    }
    found.sort();
    assert_eq!(found, listed, "files with `unsafe` against ARCHITECTURE.md");
}

/// Each folder's `mod.rs` is its map: its module docs name every file the folder has
/// (in backticks or as a link), tests aside.
#[test]
fn every_mod_rs_names_its_files() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut stack = vec![root.clone()];
    let mut missing = Vec::new();
    while let Some(dir) = stack.pop() {
        let Ok(entries) = std::fs::read_dir(&dir) else {
            continue;
        };
        for entry in entries.flatten() {
            let path = entry.path();
            if path.is_dir() {
                stack.push(path.clone());
                let map = std::fs::read_to_string(path.join("mod.rs")).unwrap_or_default();
                let docs: String = map
                    .lines()
                    .filter(|l| l.starts_with("//!"))
                    .collect::<Vec<_>>()
                    .join(" ");
                for file in std::fs::read_dir(&path).into_iter().flatten().flatten() {
                    let name = file.file_name().to_string_lossy().into_owned();
                    let stem = name.trim_end_matches(".rs");
                    let is_module = name.ends_with(".rs") || file.path().is_dir();
                    if !is_module || stem == "mod" || stem == "tests" {
                        continue;
                    }
                    if !docs.contains(&format!("`{stem}`"))
                        && !docs.contains(&format!("[`{stem}`]"))
                    {
                        let rel = path
                            .strip_prefix(&root)
                            .unwrap_or(&path)
                            .display()
                            .to_string();
                        missing.push(format!("src/{rel}/mod.rs does not name `{stem}`"));
                    }
                }
            }
        }
    }
    missing.sort();
    assert!(missing.is_empty(), "{}", missing.join("\n"));
}

/// CONTRIBUTING names every top-level module, core or shell, and ARCHITECTURE counts the
/// labelled characters there are.
#[test]
fn contributing_names_every_module_and_architecture_counts_the_characters() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut missing = Vec::new();
    for entry in std::fs::read_dir(root.join("src")).expect("src").flatten() {
        let name = entry.file_name().to_string_lossy().into_owned();
        let stem = name.trim_end_matches(".rs");
        if stem == "lib" || stem == "main" {
            continue;
        }
        if !CONTRIBUTING.contains(&format!("`{stem}`")) {
            missing.push(stem.to_string());
        }
    }
    assert!(missing.is_empty(), "CONTRIBUTING does not name {missing:?}");
    let characters = std::fs::read_dir(root.join("tests/data/characters"))
        .expect("the labelled characters")
        .flatten()
        .filter(|e| e.path().extension().is_some_and(|x| x == "toml"))
        .count();
    let words = [
        "",
        "One",
        "Two",
        "Three",
        "Four",
        "Five",
        "Six",
        "Seven",
        "Eight",
        "Nine",
        "Ten",
        "Eleven",
        "Twelve",
        "Thirteen",
        "Fourteen",
        "Fifteen",
        "Sixteen",
        "Seventeen",
        "Eighteen",
        "Nineteen",
        "Twenty",
    ];
    let said = format!(
        "{} characters in",
        words.get(characters).copied().unwrap_or("Many")
    );
    let architecture = include_str!("../../ARCHITECTURE.md");
    assert!(
        architecture.contains(&said),
        "ARCHITECTURE should say \"{said}\""
    );
}
