//! Run options: how a step is run (sleeping, tile size, SIMD), which changes its cost, not
//! its physics (the solver's settings are [`super::Solver`]; beyond the error of
//! sleeping, which `puppet bench skip` measures).

/// Run options: how a step is run, not what it computes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Options {
    /// Let tiles that stopped moving sleep (see [`super::Simulation::step`], stage 5).
    pub sleeping: bool,
    /// A tile whose every mass point moved less than this fraction of the rig's bounding-box
    /// diagonal per step, for [`SLEEP_AFTER`] steps in a row, with no moving neighbour and
    /// no pose change, sleeps.
    pub sleep_threshold: f32,
    /// Slots per tile (at least 1).
    pub tile: usize,
    /// Use the AVX2 build of the kernel where the CPU has it (results are bit-identical).
    pub simd: bool,
}

/// Steps a tile must stay under the sleep threshold before it sleeps.
pub const SLEEP_AFTER: u16 = 8;

impl Default for Options {
    /// Values chosen by measurement (`puppet bench skip`, `docs/engine-benchmarks.md`).
    fn default() -> Self {
        Options {
            sleeping: true,
            sleep_threshold: 1e-6,
            tile: 256,
            simd: true,
        }
    }
}
