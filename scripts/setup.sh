#!/usr/bin/env bash
# Installs what puppet needs on a fresh Debian machine. Idempotent; safe to run again.
# The Rust toolchain is expected (rustup); system packages come from apt.
set -euo pipefail

need=()
# Software Vulkan (lavapipe), a virtual X server, and xdotool to drive the real window in
# the window tests the way a user would.
for pkg in mesa-vulkan-drivers libvulkan1 xvfb xauth xdotool; do
  dpkg -s "$pkg" >/dev/null 2>&1 || need+=("$pkg")
done
if [ ${#need[@]} -gt 0 ]; then
  SUDO=""
  [ "$(id -u)" -ne 0 ] && SUDO="sudo"
  echo "setup: installing ${need[*]}" >&2
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${need[@]}" >/dev/null
fi
command -v cargo >/dev/null || { echo "setup: cargo not found; install Rust from https://rustup.rs" >&2; exit 1; }
rustup component list --installed 2>/dev/null | grep -q clippy || rustup component add clippy rustfmt >/dev/null 2>&1 || true
