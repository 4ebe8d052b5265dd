//! # puppet
//!
//! Any closed triangle mesh as an elastic puppet: the medial-surface mass-spring method of
//! Pfaff & Wüthrich ("Medial Surface-Based Real Time Simulation of Elastic Objects").
//!
//! Data flows one way: [`mesh`] → [`skeleton`] → rig → simulation ← joints; the shell (app,
//! rendering, UI, command line) only reads from the core. Core modules never depend on a
//! GPU or windowing crate. See `ARCHITECTURE.md`.

pub mod anim;
pub mod app;
pub mod delaunay;
pub mod files;
pub mod geom;
pub mod joints;
pub mod mesh;
pub mod progress;
pub mod render;
pub mod rig;
pub mod scenario;
pub mod scene;
pub mod sim;
pub mod skeleton;
pub mod ui;
