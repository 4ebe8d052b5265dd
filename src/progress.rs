//! Progress reporting for long library calls: a callback receives the stage name and the
//! fraction done of that stage. The library never prints; the command line draws a bar.

/// A progress sink. `Sync` so parallel stages may report.
pub type Progress<'a> = &'a (dyn Fn(&str, f64) + Sync);

/// A sink that ignores everything.
pub fn silent() -> Progress<'static> {
    &|_, _| {}
}
