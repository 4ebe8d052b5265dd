//! # puppet
//!
//! A character mesh as an elastic puppet: the medial-surface mass-spring method of
//! Pfaff & Wüthrich ("Medial Surface-Based Real Time Simulation of Elastic Objects").
//!
//! Data flows one way through the core:
//!
//! [`mesh`] → [`skeleton`] (on [`delaunay`] and [`geom`]) → [`rig`] → [`sim`] ← [`joints`];
//! [`anim`], [`puppet`], [`session`], [`export`] and [`controls`] (live devices mapped to
//! sections) on top; [`bench`] holds what only measurement uses (scenarios, references,
//! labels).
//!
//! The shell (`render`, `ui`, `app`, behind the default `gui` feature, and the command line
//! in the binary) only reads the core. The core never imports a GPU or windowing crate: they
//! are optional dependencies that only the `gui` feature enables, so
//! `cargo build --no-default-features` fails if the core ever uses one (CI builds and tests
//! the core that way). See `ARCHITECTURE.md`.
#![warn(missing_docs)]

pub mod anim;
pub mod bench;
pub mod controls;
pub mod delaunay;
pub mod export;
pub mod files;
pub mod geom;
pub mod joints;
pub mod mesh;
pub mod progress;
pub mod puppet;
pub mod random;
pub mod rig;
pub mod session;
pub mod sim;
pub mod skeleton;
pub mod stats;

#[cfg(feature = "gui")]
pub mod app;
#[cfg(feature = "gui")]
pub mod render;
#[cfg(feature = "gui")]
pub mod ui;

pub use puppet::{Puppet, RigFile};
