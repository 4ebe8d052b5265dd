//! `puppet send-osc`: streams a synthetic glove performance as OSC over UDP, so the
//! controls can be tried without hardware (`assets/examples/glove.toml` reads it).

use anyhow::{Context, Result};
use puppet::controls::{glove, osc};
use std::net::UdpSocket;
use std::time::{Duration, Instant};

#[derive(clap::Args, Debug)]
pub struct Args {
    /// Where to send: host:port of a window started with `--controls … --listen PORT`.
    #[arg(long, default_value = "127.0.0.1:9000")]
    pub to: String,
    /// How long to play (seconds).
    #[arg(long, default_value_t = 10.0)]
    pub seconds: f64,
    /// Messages per second of each kind.
    #[arg(long, default_value_t = 60.0)]
    pub rate: f64,
    /// Press the glove's record button at the start and again at the end (`/glove/button`).
    #[arg(long)]
    pub record: bool,
}

pub fn run(args: &Args) -> Result<()> {
    let valid = args.seconds.is_finite() && args.seconds >= 0.0;
    if !(valid && args.rate > 0.0 && args.rate <= 10_000.0) {
        anyhow::bail!("--seconds must be at least 0 and --rate within 0..10000");
    }
    let socket = UdpSocket::bind("0.0.0.0:0").context("cannot open a UDP socket")?;
    socket
        .connect(&args.to)
        .with_context(|| format!("{}: cannot send there", args.to))?;
    let send = |address: &str, values: &[f32]| {
        // A window that is not there yet is no error: UDP is fire and forget.
        let _ = socket.send(&osc::encode(address, values));
    };
    let press = || {
        send("/glove/button", &[1.0]);
        std::thread::sleep(Duration::from_millis(50));
        send("/glove/button", &[0.0]);
    };
    if args.record {
        press();
    }
    let start = Instant::now();
    let period = Duration::from_secs_f64(1.0 / args.rate);
    let mut sent = 0u64;
    loop {
        let t = start.elapsed().as_secs_f64();
        if t >= args.seconds {
            break;
        }
        for (address, values) in glove::performance(t) {
            send(address, &values);
        }
        sent += 1;
        let next = start + period.mul_f64(sent as f64);
        if let Some(wait) = next.checked_duration_since(Instant::now()) {
            std::thread::sleep(wait);
        }
    }
    if args.record {
        press();
    }
    eprintln!("sent {sent} glove frames to {}", args.to);
    Ok(())
}
