//! Live input in the window: a thread per kind of device the controls file uses (OSC
//! packets on a UDP port; every MIDI input port, watched for ports that come and go;
//! gamepads) turns what arrives into events and hands them to the frame loop, waking it (a
//! settled window sleeps until then); the frame loop feeds them to the controls bound to
//! the current puppet's sections. Devices that come or go are a line in the panel.
//!
//! *Learn* watches every kind of device and maps the control that moved to the section
//! the puppeteer clicks; *Calibrate* sets each control's range from a move end to end
//! (see [`crate::controls::learn`]).

use crate::controls::{midi, osc, Calibrate, Controls, ControlsFile, Event, Learn, Source};
use crate::session::Session;
use crate::ui::LiveCounts;
use glam::DVec3;
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

/// The UDP port OSC arrives on when the command line names none.
pub const DEFAULT_PORT: u16 = 9000;

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
    /// A device came or went (a line for the panel), and whether it went.
    Notice(String, bool),
}

/// The live controls of an open window.
pub(super) struct Live {
    file: ControlsFile,
    /// The controls bound to the session with this id.
    controls: Option<(u64, Controls)>,
    rx: Receiver<Arrival>,
    tx: Sender<Arrival>,
    proxy: EventLoopProxy<Wake>,
    start: Instant,
    /// Packets that were not OSC.
    bad_packets: Arc<AtomicUsize>,
    /// The port listened on (0: none).
    pub port: u16,
    /// Which device threads run: MIDI, gamepads.
    watching: (bool, bool),
    /// The learn step, while it runs.
    learn: Option<Learn>,
    /// The calibrate step, while it runs.
    calibrate: Option<Calibrate>,
}

impl Live {
    /// Starts the receiving threads the file needs (OSC on `options.socket`); they wake
    /// the loop through `proxy`.
    pub(super) fn start(options: LiveOptions, proxy: EventLoopProxy<Wake>) -> Live {
        let (tx, rx) = channel();
        let mut live = Live {
            file: ControlsFile::default(),
            controls: None,
            rx,
            tx,
            proxy,
            start: Instant::now(),
            bad_packets: Arc::new(AtomicUsize::new(0)),
            port: 0,
            watching: (false, false),
            learn: None,
            calibrate: None,
        };
        if let Some(socket) = options.socket {
            live.listen(socket);
        }
        live.set_file(options.file);
        live
    }

    /// Listens for OSC on `socket`.
    fn listen(&mut self, socket: UdpSocket) {
        self.port = socket.local_addr().map_or(0, |a| a.port());
        let (tx, proxy, bad) = (
            self.tx.clone(),
            self.proxy.clone(),
            self.bad_packets.clone(),
        );
        std::thread::spawn(move || listen_osc(socket, tx, proxy, bad));
    }

    /// Listens on the default port if nothing listens yet; says why not where it cannot.
    pub(super) fn ensure_osc(&mut self) -> Option<String> {
        if self.port != 0 {
            return None;
        }
        match UdpSocket::bind(("0.0.0.0", DEFAULT_PORT)) {
            Ok(socket) => {
                self.listen(socket);
                None
            }
            Err(e) => Some(format!(
                "OSC: cannot listen on UDP port {DEFAULT_PORT}: {} (start with --listen PORT)",
                crate::files::io_message(&e)
            )),
        }
    }

    /// Starts the MIDI and gamepad threads that are not running yet: those the file uses,
    /// or all of them (`all`, for learning).
    fn watch(&mut self, all: bool) {
        let uses = |kind: fn(&Source) -> bool| self.file.controls.iter().any(|c| kind(&c.source));
        let midi = all || uses(|s| matches!(s, Source::MidiCc { .. } | Source::MidiNote { .. }));
        let pads = all || uses(|s| matches!(s, Source::Gamepad { .. }));
        if midi && !self.watching.0 {
            self.watching.0 = true;
            let (tx, proxy) = (self.tx.clone(), self.proxy.clone());
            std::thread::spawn(move || watch_midi(tx, proxy));
        }
        if pads && !self.watching.1 {
            self.watching.1 = true;
            let (tx, proxy) = (self.tx.clone(), self.proxy.clone());
            std::thread::spawn(move || watch_gamepads(tx, proxy));
        }
    }

    /// Uses `file` from now on (loaded from the panel): bound again to the puppet at the
    /// next frame, with the devices it reads watched. Learning and calibrating stop.
    pub(super) fn set_file(&mut self, file: ControlsFile) {
        self.file = file;
        self.controls = None;
        self.learn = None;
        self.calibrate = None;
        self.watch(false);
    }

    /// The controls file as it stands (with what was learned and calibrated).
    pub(super) fn file(&self) -> &ControlsFile {
        &self.file
    }

    /// Starts or stops learning. Starting clears the selection: the next section clicked
    /// takes the control that moved. Returns a line for the panel.
    pub(super) fn toggle_learn(&mut self, session: &mut Session) -> (String, bool) {
        if self.learn.take().is_some() {
            return ("learning stopped".into(), false);
        }
        self.calibrate = None;
        self.watch(true);
        let osc = self.ensure_osc();
        self.learn = Some(Learn::new());
        session.select(None, false);
        match osc {
            Some(why) => (why, true),
            None => (
                "learn: move a control, then click the section it drives".into(),
                false,
            ),
        }
    }

    /// Starts calibrating: move every control end to end, then finish.
    pub(super) fn start_calibrating(&mut self) {
        self.learn = None;
        self.calibrate = Some(Calibrate::new(&self.file));
    }

    /// Ends calibrating: `keep` sets the ranges seen (else they are dropped). Returns a
    /// line for the panel.
    pub(super) fn finish_calibrating(&mut self, keep: bool) -> Option<String> {
        let calibrate = self.calibrate.take()?;
        if !keep {
            return Some("calibration cancelled".into());
        }
        let n = calibrate.finish(&mut self.file);
        self.controls = None;
        Some(format!(
            "calibrated {n} of {} controls (those moved end to end)",
            self.file.controls.len()
        ))
    }

    /// Binds the controls to `session` when the puppet changed (or the file did). Returns
    /// why they do not fit, if they do not.
    fn bind(&mut self, session: &Session) -> Option<String> {
        if self.controls.as_ref().map(|c| c.0) == Some(session.id) {
            return None;
        }
        match Controls::new(self.file.clone(), &session.section_names()) {
            Ok(c) => {
                self.controls = Some((session.id, c));
                None
            }
            Err(e) => Some(format!("controls: {e}")),
        }
    }

    /// Feeds what arrived to the controls of `session` (binding them first when the
    /// puppet changed) and lets them drive it; while learning, maps the control that
    /// moved to the section clicked. Returns a message for the panel: what a stopped take
    /// said, what was learned, or why the controls do not fit this puppet.
    /// `view` is the camera's direction (a learned control bends its section towards the
    /// viewer).
    pub(super) fn pump(&mut self, session: &mut Session, view: DVec3) -> Option<(String, bool)> {
        let mut message = self.bind(session).map(|e| (e, true));
        for a in self.rx.try_iter().collect::<Vec<_>>() {
            match a {
                Arrival::Events(events, at) => {
                    let time = (at - self.start).as_secs_f64();
                    for e in &events {
                        if let Some(learn) = &mut self.learn {
                            learn.observe(e);
                        }
                        if let Some(calibrate) = &mut self.calibrate {
                            calibrate.observe(&self.file, e);
                        }
                        if let Some((_, controls)) = &mut self.controls {
                            controls.feed(e, time);
                        }
                    }
                }
                // A device gone while a take records: the take keeps what it did and
                // goes on (the mouse or another device may carry on).
                Arrival::Notice(line, true) if session.is_recording() => {
                    message = Some((
                        format!("{line}; the take goes on recording (Ctrl+R stops it)"),
                        true,
                    ));
                }
                Arrival::Notice(line, gone) => message = Some((line, gone)),
            }
        }
        if let Some(learned) = self.learned(session, view) {
            message = Some(learned);
        }
        let Some((_, controls)) = self.controls.as_mut() else {
            return message;
        };
        session
            .drive(controls)
            .map(|said| (said, false))
            .or(message)
    }

    /// While learning, once a control moved and a section is selected: the control now
    /// drives that section.
    fn learned(&mut self, session: &mut Session, view: DVec3) -> Option<(String, bool)> {
        let learn = self.learn.as_mut()?;
        let &k = session.selection.first()?;
        let source = learn.moved()?.0.to_string();
        let name = session.section_names().get(k)?.to_string();
        learn.bind(&mut self.file, &name, session.bend_axis(k, view))?;
        session.select(None, false);
        self.controls = None;
        let error = self.bind(session);
        Some(error.map_or_else(
            || {
                (
                    format!("learned: {source} turns {name} (move the next control, or stop)"),
                    false,
                )
            },
            |e| (e, true),
        ))
    }

    /// What the panel and the report show.
    pub(super) fn counts(&self) -> LiveCounts {
        let mut out = LiveCounts {
            port: self.port,
            bad_packets: self.bad_packets.load(Ordering::Relaxed),
            learning: self.learn.as_ref().map(|l| match l.moved() {
                Some((source, r)) => format!(
                    "moved: {source} ({:.3}–{:.3}); click the section it drives",
                    r.min, r.max
                ),
                None => "move a control, then click the section it drives".into(),
            }),
            calibrating: self.calibrate.as_ref().map(|c| {
                c.ranges()
                    .iter()
                    .map(|r| r.map(|r| [r.min, r.max]))
                    .collect()
            }),
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
    let notice = |line: String, gone: bool| {
        let sent = tx.send(Arrival::Notice(line, gone)).is_ok();
        sent && proxy.send_event(Wake::Input).is_ok()
    };
    let mut open: Vec<(String, midir::MidiInputConnection<()>)> = Vec::new();
    loop {
        let Ok(probe) = midir::MidiInput::new("puppet") else {
            let _ = notice(
                "MIDI: no MIDI system here (ALSA sequencer)".to_string(),
                false,
            );
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
        if open.len() < before && !notice("MIDI: a device was unplugged".to_string(), true) {
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
                if !notice(format!("MIDI: {name} connected"), false) {
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
            let _ = tx.send(Arrival::Notice(
                format!("gamepads: not available ({e})"),
                false,
            ));
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
            gilrs::EventType::Connected => Arrival::Notice(
                format!("gamepad: {} connected", gilrs.gamepad(ev.id).name()),
                false,
            ),
            gilrs::EventType::Disconnected => Arrival::Notice(
                format!("gamepad: {} unplugged", gilrs.gamepad(ev.id).name()),
                true,
            ),
            _ => continue,
        };
        if tx.send(arrival).is_err() || proxy.send_event(Wake::Input).is_err() {
            return;
        }
    }
}
