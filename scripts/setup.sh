#!/usr/bin/env bash
# Installs what puppet needs on a fresh Debian machine. Idempotent; safe to run again.
# The Rust toolchain is expected (rustup); system packages come from apt.
set -euo pipefail

need=()
# Software Vulkan (lavapipe), a virtual X server, and xdotool to drive the real window in
# the window tests the way a user would; ALSA and udev headers for MIDI and gamepad input.
# Node and npm for the Khronos glTF validator the export tests read takes back with.
for pkg in mesa-vulkan-drivers libvulkan1 xvfb xauth xdotool libasound2-dev libudev-dev pkg-config; do
  dpkg -s "$pkg" >/dev/null 2>&1 || need+=("$pkg")
done
# ffmpeg to encode a take rendered to video (`simulate --out TAKE.mp4`; without it the
# frames are PNG files) and ffprobe to read the video back in the tests.
command -v ffmpeg >/dev/null || need+=(ffmpeg)
command -v node >/dev/null || need+=(nodejs)
command -v npm >/dev/null || need+=(npm)
if [ ${#need[@]} -gt 0 ]; then
  SUDO=""
  [ "$(id -u)" -ne 0 ] && SUDO="sudo"
  echo "setup: installing ${need[*]}" >&2
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${need[@]}" >/dev/null
fi
command -v cargo >/dev/null || { echo "setup: cargo not found; install Rust from https://rustup.rs" >&2; exit 1; }
rustup component list --installed 2>/dev/null | grep -q clippy || rustup component add clippy rustfmt >/dev/null 2>&1 || true
# The Khronos glTF validator for the export tests (tests/export.rs runs it; under CI, set
# `CI`, a missing validator fails them). Without the npm registry it says so.
if command -v npm >/dev/null && [ ! -d target/npm/node_modules/gltf-validator ]; then
  mkdir -p target/npm
  npm install --prefix target/npm --silent --no-audit --no-fund gltf-validator@2.0.0-dev.3.10 >/dev/null 2>&1 \
    || echo "setup: could not install gltf-validator from npm (the export tests fail under CI without it)" >&2
fi
