#!/usr/bin/env bash
# Runs the Table 1 benchmark on a machine with an NVIDIA GPU and the Vulkan loader
# (bench/RESULTS.md has the exact calls). Expects, carried from the workspace: .gl (the .deb
# packages of the Vulkan loader and of libglvnd, which NVIDIA's Vulkan driver loads through:
# libvulkan1 libglvnd0 libegl1 libgl1 libglx0 libopengl0 libgles2),
# .devbin/bench/pointray (a release build of pointray-cli) and .devbin/data (the shared
# meshes and points). Writes table1.json and table1.md to $OUT (or out/bench here).
# FRAMES and WARMUP set the timed and warm-up frames (default 100 and 10); extra arguments
# go to `pointray bench` (e.g. --model Bunny).
set -euo pipefail
for f in .gl/*.deb; do dpkg -x "$f" /; done
ldconfig
if ! ls /usr/share/vulkan/icd.d/ 2>/dev/null | grep -qi nvidia; then
    export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
fi
out=${OUT:-out/bench}
mkdir -p "$out"
nvidia-smi --query-gpu=name,driver_version,clocks.sm,clocks.max.sm --format=csv || true
bin=.devbin/bench/pointray
"$bin" devices
"$bin" bench table1 --data .devbin/data --cache /tmp/pointray-bench-cache \
    --frames "${FRAMES:-100}" --warmup "${WARMUP:-10}" \
    --ablations --json "$out/table1.json" --markdown "$out/table1.md" "$@"
