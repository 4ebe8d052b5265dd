#!/usr/bin/env bash
# Every check a change must pass: formatting, lints (warnings are errors), all tests.
# Tests run in the release profile: the skeleton and stress tests need optimised code, and
# `cargo run --release` then reuses the same build.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
cargo fmt --check
cargo clippy --release --all-targets -- -D warnings
cargo test --release --all-targets
