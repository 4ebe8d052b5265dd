//! Third-party readers held to the project's rule for bad input: one error line, never a
//! panic. A panic inside a reader crate (a bug of its own on some malformed file) is caught
//! and becomes a [`MeshError::Parse`] naming the format; while a reader runs under
//! [`contained`], the panic's own message is not printed (every other panic still is).
//! Where a crate's bug is known, the reader checks its input before handing it over
//! (`gltf/mod.rs`), and this is the net below.

use super::MeshError;
use std::cell::Cell;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::sync::Once;

thread_local! {
    /// True while this thread runs a reader under [`contained`].
    static QUIET: Cell<bool> = const { Cell::new(false) };
}

/// Installs, once, a panic hook that stays quiet on a thread inside [`contained`] and hands
/// every other panic to the hook that was there before.
fn install_hook() {
    static HOOK: Once = Once::new();
    HOOK.call_once(|| {
        let previous = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            if !QUIET.with(Cell::get) {
                previous(info);
            }
        }));
    });
}

/// Runs the `format` reader `read`; a panic inside it is the error "`format`: the file is
/// malformed (the reader failed on it)".
pub(super) fn contained<T>(
    format: &str,
    read: impl FnOnce() -> Result<T, MeshError>,
) -> Result<T, MeshError> {
    install_hook();
    let was = QUIET.with(|q| q.replace(true));
    let result = catch_unwind(AssertUnwindSafe(read));
    QUIET.with(|q| q.set(was));
    result.unwrap_or_else(|_| {
        Err(MeshError::Parse(format!(
            "{format}: the file is malformed (the reader failed on it)"
        )))
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_panic_inside_becomes_an_error_and_results_pass_through() {
        let e = contained::<()>("PLY", || panic!("index out of bounds")).unwrap_err();
        assert_eq!(
            e.to_string(),
            "PLY: the file is malformed (the reader failed on it)"
        );
        assert_eq!(contained("PLY", || Ok(3)).unwrap(), 3);
        assert!(!QUIET.with(Cell::get), "quiet only inside");
    }
}
