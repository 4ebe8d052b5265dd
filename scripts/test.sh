#!/usr/bin/env bash
# Every check a change must pass: formatting, lints (warnings are errors), the core built and
# tested alone (no GPU or window crate: the compiler refuses the core if it imports one),
# then every test with the window.
# Tests run in the release profile: the skeleton and stress tests need optimised code, and
# `cargo run --release` then reuses the same build.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
# Mesa wants a private runtime directory; CI machines have none.
if [ -z "${XDG_RUNTIME_DIR:-}" ] || [ ! -d "$XDG_RUNTIME_DIR" ]; then
  XDG_RUNTIME_DIR="$(mktemp -d)"
  chmod 700 "$XDG_RUNTIME_DIR"
  export XDG_RUNTIME_DIR
fi
cargo fmt --check
cargo clippy --release --all-targets -- -D warnings
# The core alone: lints, then its unit tests, without the gui feature.
cargo clippy --release --no-default-features --all-targets -- -D warnings
cargo test --release --no-default-features --lib
# The shell's own unit tests (its modules exist only with the gui feature).
cargo test --release --lib -- app:: render:: ui::
# Everything else with the window (the core's unit tests ran above).
cargo test --release --bins --test '*' --benches
