//! The puppeteer's panels (egui): file, material, pose, cuts, overlays and stats. They edit
//! the core's [`crate::session::Session`] directly and hand what needs the window back as
//! [`Action`]s.

pub mod panels;

pub use panels::{Action, PanelState, Stats};
