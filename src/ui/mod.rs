//! The puppeteer's interface: the session logic (selection, undo/redo, cut tool, sleeping)
//! that needs no window, and the egui panels that edit it.

pub mod panels;
pub mod session;

pub use panels::{Action, CutAxis, PanelState};
pub use session::{CutDraft, Hit, Session};
