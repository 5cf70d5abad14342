#!/usr/bin/env bash
# Runs every check CI runs: installs the system's Vulkan pieces (lavapipe and the Khronos
# validation layer) and cargo-machete if missing, then formatting, clippy with warnings denied,
# the unused-dependency check, all tests with validation on, and the Python package's tests. Vulkan tests fail rather than
# skip when CI=true and no device is found.
set -euo pipefail
cd "$(dirname "$0")/.."

bash scripts/install-system-deps.sh
export POINTRAY_VALIDATION=1

command -v cargo-machete >/dev/null || cargo install cargo-machete --version 0.9.2 --locked

cargo fmt --all --check
cargo clippy --workspace --all-targets --locked -- -D warnings
cargo machete
cargo test --workspace --locked
bash scripts/test-python.sh
