#!/usr/bin/env bash
# Every check a change must pass: formatting, lints (warnings are errors), all tests.
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
cargo test --release --all-targets
