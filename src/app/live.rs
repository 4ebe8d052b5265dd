//! Live input in the window: a thread receives OSC packets on a UDP port, decodes them and
//! hands their messages to the frame loop, waking it (a settled window sleeps until then);
//! the frame loop feeds them to the controls bound to the current puppet's sections.

use crate::controls::{osc, Controls, ControlsFile, Event};
use crate::session::Session;
use crate::ui::LiveCounts;
use std::net::UdpSocket;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::mpsc::{channel, Receiver};
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
    /// The bound socket.
    pub socket: UdpSocket,
}

/// The live controls of an open window.
pub(super) struct Live {
    file: ControlsFile,
    /// The controls bound to the session with this id.
    controls: Option<(u64, Controls)>,
    rx: Receiver<(Vec<Event>, Instant)>,
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
        let bad = bad_packets.clone();
        let socket = options.socket;
        let port = socket.local_addr().map_or(0, |a| a.port());
        std::thread::spawn(move || {
            let mut buf = vec![0u8; 65536];
            while let Ok((n, _)) = socket.recv_from(&mut buf) {
                match osc::decode(&buf[..n]) {
                    Some(events) => {
                        if tx.send((events, Instant::now())).is_err() {
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
        });
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
        let arrived: Vec<(Vec<Event>, Instant)> = self.rx.try_iter().collect();
        let Some((_, controls)) = &mut self.controls else {
            return message;
        };
        for (events, at) in arrived {
            let time = (at - self.start).as_secs_f64();
            for e in &events {
                controls.feed(e, time);
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
                .map(|(name, _, v)| (name.to_string(), v))
                .collect();
        }
        out
    }
}
