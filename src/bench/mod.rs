//! What only measurement uses: `puppet bench`, the criterion benches in `benches/` and the
//! tests read these, the product (the window, `skeleton`, `suggest`, `simulate`) never
//! does. Kept in one folder so the product's modules hold only what a puppet needs.
//!
//! * [`scenario`]: the standard scenarios (a limb swinging on a cut mesh) and their `f64`
//!   reference step, the accuracy reference;
//! * [`truth`]: analytic shapes with known medial radii, the skeleton's ground truth;
//! * [`labels`]: a labelled character's joints, and a suggestion's score against them;
//! * [`decimate`]: quadric-error decimation, for the uneven shapes of `truth` and the rough
//!   copies the suggestion is measured on.

pub mod decimate;
pub mod labels;
pub mod scenario;
pub mod truth;

pub use decimate::decimate;
