#!/usr/bin/env bash
# Runs the Table 1 benchmark (bench/RESULTS.md has the calls and results). Needs a machine with
# an NVIDIA GPU and its driver, the Vulkan loader (libvulkan1) and libglvnd (libglvnd0 libegl1
# libgl1 libglx0 libopengl0 libgles2), through which NVIDIA's Vulkan driver loads, and a
# release build of pointray-cli. POINTRAY names the binary (default target/release/pointray),
# DATA the data folder (default data), OUT where table1.json and table1.md go (default
# out/bench). FRAMES and WARMUP set the timed and warm-up frames (default 100 and 10); extra
# arguments go to `pointray bench` (e.g. --model Bunny).
set -euo pipefail
cd "$(dirname "$0")/.."
# A driver mounted into a container lists its manifest here rather than in the system's folder.
if ! ls /usr/share/vulkan/icd.d/ 2>/dev/null | grep -qi nvidia; then
    export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
fi
out=${OUT:-out/bench}
mkdir -p "$out"
nvidia-smi --query-gpu=name,driver_version,clocks.sm,clocks.max.sm --format=csv || true
bin=${POINTRAY:-target/release/pointray}
"$bin" devices
"$bin" bench table1 --data "${DATA:-data}" --cache /tmp/pointray-bench-cache \
    --frames "${FRAMES:-100}" --warmup "${WARMUP:-10}" \
    --ablations --json "$out/table1.json" --markdown "$out/table1.md" "$@"
