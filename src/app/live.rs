//! Live input in the window: a thread per kind of device the controls file uses (OSC
//! packets on a UDP port; every MIDI input port, watched for ports that come and go;
//! gamepads) turns what arrives into events and hands them to the frame loop, waking it (a
//! settled window sleeps until then); the frame loop feeds them to the controls bound to
//! the current puppet's sections. Devices that come or go are a line in the panel.

use crate::controls::{midi, osc, Controls, ControlsFile, Event, Source};
use crate::session::Session;
use crate::ui::LiveCounts;
use std::net::UdpSocket;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::mpsc::{channel, Receiver, Sender};
use std::sync::Arc;
use std::time::Instant;
use winit::event_loop::EventLoopProxy;

/// What the window asks of its event loop from other threads.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Wake {
    /// Live input arrived.
    Input,
}

/// A controls file and the port its OSC messages arrive on, as the command line gave them
/// (the socket is bound before the window opens, so a port in use is an `error:` line).
pub struct LiveOptions {
    /// The controls.
    pub file: ControlsFile,
    /// The bound socket, when the file reads OSC.
    pub socket: Option<UdpSocket>,
}

/// What a device thread hands the frame loop.
enum Arrival {
    /// Events, and when they arrived.
    Events(Vec<Event>, Instant),
    /// A device came or went (a line for the panel).
    Notice(String),
}

/// The live controls of an open window.
pub(super) struct Live {
    file: ControlsFile,
    /// The controls bound to the session with this id.
    controls: Option<(u64, Controls)>,
    rx: Receiver<Arrival>,
    start: Instant,
    /// Packets that were not OSC.
    bad_packets: Arc<AtomicUsize>,
    /// The port listened on.
    pub port: u16,
}

impl Live {
    /// Starts the receiving thread on `options.socket`; it wakes the loop through `proxy`.
    pub(super) fn start(options: LiveOptions, proxy: EventLoopProxy<Wake>) -> Live {
        let (tx, rx) = channel();
        let bad_packets = Arc::new(AtomicUsize::new(0));
        let uses =
            |kind: fn(&Source) -> bool| options.file.controls.iter().any(|c| kind(&c.source));
        let mut port = 0;
        if let Some(socket) = options.socket {
            port = socket.local_addr().map_or(0, |a| a.port());
            let (tx, proxy, bad) = (tx.clone(), proxy.clone(), bad_packets.clone());
            std::thread::spawn(move || listen_osc(socket, tx, proxy, bad));
        }
        if uses(|s| matches!(s, Source::MidiCc { .. } | Source::MidiNote { .. })) {
            let (tx, proxy) = (tx.clone(), proxy.clone());
            std::thread::spawn(move || watch_midi(tx, proxy));
        }
        if uses(|s| matches!(s, Source::Gamepad { .. })) {
            let (tx, proxy) = (tx.clone(), proxy.clone());
            std::thread::spawn(move || watch_gamepads(tx, proxy));
        }
        Live {
            file: options.file,
            controls: None,
            rx,
            start: Instant::now(),
            bad_packets,
            port,
        }
    }

    /// Feeds what arrived to the controls of `session` (binding them first when the
    /// puppet changed) and lets them drive it. Returns a message for the panel: what a
    /// stopped take said, or why the controls do not fit this puppet.
    pub(super) fn pump(&mut self, session: &mut Session) -> Option<(String, bool)> {
        let mut message = None;
        if self.controls.as_ref().map(|c| c.0) != Some(session.id) {
            match Controls::new(self.file.clone(), &session.section_names()) {
                Ok(c) => self.controls = Some((session.id, c)),
                Err(e) => {
                    self.controls = None;
                    message = Some((format!("controls: {e}"), true));
                }
            }
        }
        let arrived: Vec<Arrival> = self.rx.try_iter().collect();
        let Some((_, controls)) = &mut self.controls else {
            return message;
        };
        for a in arrived {
            match a {
                Arrival::Events(events, at) => {
                    let time = (at - self.start).as_secs_f64();
                    for e in &events {
                        controls.feed(e, time);
                    }
                }
                Arrival::Notice(line) => message = Some((line, false)),
            }
        }
        session
            .drive(controls)
            .map(|said| (said, false))
            .or(message)
    }

    /// What the panel and the report show.
    pub(super) fn counts(&self) -> LiveCounts {
        let mut out = LiveCounts {
            port: self.port,
            bad_packets: self.bad_packets.load(Ordering::Relaxed),
            ..LiveCounts::default()
        };
        if let Some((_, c)) = &self.controls {
            out.used = c.used;
            out.unknown = c.unknown;
            out.ignored = c.ignored;
            out.values = c
                .values()
                .into_iter()
                .map(|(name, v)| (name.to_string(), v))
                .collect();
        }
        out
    }
}

/// Receives OSC packets until the window goes.
fn listen_osc(
    socket: UdpSocket,
    tx: Sender<Arrival>,
    proxy: EventLoopProxy<Wake>,
    bad: Arc<AtomicUsize>,
) {
    let mut buf = vec![0u8; 65536];
    while let Ok((n, _)) = socket.recv_from(&mut buf) {
        match osc::decode(&buf[..n]) {
            Some(events) => {
                if tx.send(Arrival::Events(events, Instant::now())).is_err() {
                    return;
                }
            }
            None => {
                bad.fetch_add(1, Ordering::Relaxed);
            }
        }
        if proxy.send_event(Wake::Input).is_err() {
            return;
        }
    }
}

/// Connects to every MIDI input port, and every second to ports that appeared; says when
/// one comes or goes.
fn watch_midi(tx: Sender<Arrival>, proxy: EventLoopProxy<Wake>) {
    let notice = |line: String| {
        let sent = tx.send(Arrival::Notice(line)).is_ok();
        sent && proxy.send_event(Wake::Input).is_ok()
    };
    let mut open: Vec<(String, midir::MidiInputConnection<()>)> = Vec::new();
    loop {
        let Ok(probe) = midir::MidiInput::new("puppet") else {
            let _ = notice("MIDI: no MIDI system here (ALSA sequencer)".to_string());
            return;
        };
        let names: Vec<(String, midir::MidiInputPort)> = probe
            .ports()
            .into_iter()
            .filter_map(|p| Some((probe.port_name(&p).ok()?, p)))
            .collect();
        // Ports that went.
        let before = open.len();
        open.retain(|(name, _)| names.iter().any(|(n, _)| n == name));
        if open.len() < before && !notice("MIDI: a device was unplugged".to_string()) {
            return;
        }
        for (name, port) in names {
            if open.iter().any(|(n, _)| *n == name) {
                continue;
            }
            let Ok(input) = midir::MidiInput::new("puppet") else {
                continue;
            };
            let (tx, proxy) = (tx.clone(), proxy.clone());
            let connected = input.connect(
                &port,
                "puppet",
                move |_, bytes, _| {
                    if let Some(e) = midi::event(bytes) {
                        let _ = tx.send(Arrival::Events(vec![e], Instant::now()));
                        let _ = proxy.send_event(Wake::Input);
                    }
                },
                (),
            );
            if let Ok(c) = connected {
                if !notice(format!("MIDI: {name} connected")) {
                    return;
                }
                open.push((name, c));
            }
        }
        std::thread::sleep(std::time::Duration::from_secs(1));
    }
}

/// Gamepads' axes and buttons as events, and their coming and going.
fn watch_gamepads(tx: Sender<Arrival>, proxy: EventLoopProxy<Wake>) {
    let mut gilrs = match gilrs::Gilrs::new() {
        Ok(g) => g,
        Err(e) => {
            let _ = tx.send(Arrival::Notice(format!("gamepads: not available ({e})")));
            let _ = proxy.send_event(Wake::Input);
            return;
        }
    };
    while let Some(ev) = gilrs.next_event_blocking(None) {
        let arrival = match ev.event {
            gilrs::EventType::AxisChanged(axis, value, _) => Arrival::Events(
                vec![midi::gamepad(&format!("{axis:?}"), value)],
                Instant::now(),
            ),
            gilrs::EventType::ButtonChanged(button, value, _) => Arrival::Events(
                vec![midi::gamepad(&format!("{button:?}"), value)],
                Instant::now(),
            ),
            gilrs::EventType::Connected => Arrival::Notice(format!(
                "gamepad: {} connected",
                gilrs.gamepad(ev.id).name()
            )),
            gilrs::EventType::Disconnected => Arrival::Notice(format!(
                "gamepad: {} unplugged",
                gilrs.gamepad(ev.id).name()
            )),
            _ => continue,
        };
        if tx.send(arrival).is_err() || proxy.send_event(Wake::Input).is_err() {
            return;
        }
    }
}
