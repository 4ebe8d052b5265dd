//! `puppet bench controls`: the latency of live input, from a packet leaving the sender
//! to the end of the simulation step that shows it, on the shipped hand with
//! `assets/examples/glove.toml` (what a window does per packet, less the drawing).
//!
//! A sender thread sends the synthetic glove (`controls::glove`) over UDP on localhost,
//! each packet stamped with the time it left; a receiver thread decodes it and hands it
//! on, as the window's does; the loop wakes on it, feeds the controls, lets them drive
//! the session and advances one step. The claim: at most one frame (1/60 s) plus one
//! step, at the 95th percentile of the packets sent (a lost packet is never shown, so it
//! is late); the bench fails (exit status 2) when it does not hold.

use super::median_p95;
use super::table::{self, Column, Table};
use anyhow::{Context, Result};
use puppet::controls::{glove, osc, Controls, ControlsFile, Event};
use puppet::session::Session;
use puppet::{Puppet, RigFile};
use std::net::UdpSocket;
use std::path::Path;
use std::sync::mpsc::channel;
use std::time::{Duration, Instant};

#[derive(clap::Args, Debug)]
pub struct Args {
    /// Packets to send (60 per second).
    #[arg(long, default_value_t = 600)]
    pub packets: usize,
    /// Drop this share (%) of the packets at the sender, as a lossy network would: a
    /// lost packet is never shown, so it counts as late, and the bench fails when more
    /// than 5 % are.
    #[arg(long, default_value_t = 0.0, value_parser = lost_share)]
    pub lose: f64,
    /// Print JSON instead of a Markdown table.
    #[arg(long)]
    pub json: bool,
}

/// A `--lose` share: a finite percentage from 0 to 100.
fn lost_share(s: &str) -> Result<f64, String> {
    match s.trim().parse::<f64>() {
        Ok(v) if v.is_finite() && (0.0..=100.0).contains(&v) => Ok(v),
        _ => Err(format!("{s} is not a share from 0 to 100")),
    }
}

#[derive(serde::Serialize)]
struct Report {
    packets: usize,
    received: usize,
    latency_ms_median: f64,
    latency_ms_p95: f64,
    latency_ms_max: f64,
    step_ms_median: f64,
    budget_ms: f64,
}

pub fn run(args: &Args) -> Result<()> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/examples");
    let rig = RigFile::load(&root.join("hand.rig.toml")).map_err(|e| anyhow::anyhow!("{e}"))?;
    let mesh = puppet::mesh::load(&root.join("hand.obj"))?.0;
    let puppet = Puppet::build(mesh, rig, puppet::progress::silent())?;
    let mut session = Session::new(puppet, "hand");
    let file = ControlsFile::load(&root.join("glove.toml")).map_err(|e| anyhow::anyhow!("{e}"))?;
    let mut controls = Controls::new(file, &session.section_names())?;
    let receiver = UdpSocket::bind("127.0.0.1:0").context("cannot open a UDP socket")?;
    let to = receiver.local_addr()?;
    let start = Instant::now();
    let (tx, rx) = channel::<(Vec<Event>, f64)>();
    // The receiver: decode and hand on, with the time the packet left (its first
    // argument is the send time in µs since `start`, then the glove's values).
    std::thread::spawn(move || {
        let mut buf = vec![0u8; 65536];
        while let Ok(n) = receiver.recv(&mut buf) {
            if let Some(events) = osc::decode(&buf[..n]) {
                let sent = match events.first() {
                    Some(Event::Osc { args, .. }) => args.first().copied().flatten(),
                    _ => None,
                };
                let events = events
                    .into_iter()
                    .map(|e| match e {
                        Event::Osc { address, mut args } => {
                            args.remove(0);
                            Event::Osc { address, args }
                        }
                        e => e,
                    })
                    .collect();
                if tx.send((events, sent.unwrap_or(0.0) * 1e-6)).is_err() {
                    return;
                }
            }
        }
    });
    let packets = args.packets.max(1);
    let lose = args.lose / 100.0;
    std::thread::spawn(move || {
        let Ok(socket) = UdpSocket::bind("127.0.0.1:0") else {
            return;
        };
        for k in 0..packets {
            let t = k as f64 / 60.0;
            if let Some(wait) =
                (start + Duration::from_secs_f64(t)).checked_duration_since(Instant::now())
            {
                std::thread::sleep(wait);
            }
            // Every packet that brings the share lost past a whole one is dropped.
            if ((k + 1) as f64 * lose).floor() > (k as f64 * lose).floor() {
                continue;
            }
            let (address, values) = glove::performance(t).remove(0);
            let sent = start.elapsed().as_secs_f64() * 1e6;
            let mut args = vec![sent as f32];
            args.extend(values);
            let _ = socket.send_to(&osc::encode(address, &args), to);
        }
    });
    let step = session.puppet.sim.params().solver.time_step;
    let (mut latency, mut steps) = (Vec::new(), Vec::new());
    while let Ok((events, sent)) = rx.recv_timeout(Duration::from_secs(2)) {
        let now = start.elapsed().as_secs_f64();
        for e in &events {
            controls.feed(e, now);
        }
        session.drive(&mut controls);
        let t = Instant::now();
        session.advance(step, 1);
        steps.push(t.elapsed().as_secs_f64() * 1e3);
        latency.push((start.elapsed().as_secs_f64() - sent) * 1e3);
    }
    let received = latency.len();
    let max = latency.iter().copied().fold(0.0, f64::max);
    // A packet that never arrived is never shown: it counts as late, not as absent.
    latency.resize(packets.max(received), f64::INFINITY);
    let (median, p95) = median_p95(latency);
    let (step_median, _) = median_p95(steps);
    let report = Report {
        packets,
        received,
        latency_ms_median: median,
        latency_ms_p95: p95,
        latency_ms_max: max,
        step_ms_median: step_median,
        budget_ms: 1000.0 / 60.0 + step_median,
    };
    if args.json {
        table::json(&report)?;
    } else {
        let mut table = Table::new(&[
            Column::Figure("packets"),
            Column::Figure("received"),
            Column::Figure("latency median"),
            Column::Figure("p95"),
            Column::Figure("max"),
            Column::Figure("step"),
            Column::Figure("one frame + one step"),
        ]);
        let ms = |v: f64| format!("{v:.2} ms");
        table.row(&[
            report.packets.to_string(),
            report.received.to_string(),
            ms(report.latency_ms_median),
            ms(report.latency_ms_p95),
            ms(report.latency_ms_max),
            ms(report.step_ms_median),
            ms(report.budget_ms),
        ]);
    }
    // The claim this bench holds: a packet shows within one frame plus one step (at the
    // 95th percentile of all sent, a lost one never).
    if received == 0 || report.latency_ms_p95 > report.budget_ms {
        anyhow::bail!(
            "live input is late: {received} of {packets} packets arrived, p95 {:.2} ms against one frame plus one step, {:.2} ms",
            report.latency_ms_p95,
            report.budget_ms
        );
    }
    Ok(())
}
