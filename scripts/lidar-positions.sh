#!/usr/bin/env bash
# Measures the table "The street from other sensor positions" in bench/FIDELITY.md: each
# spinning preset scans the built-in street from the middle of the road and from three
# positions beside it, and its scan-aware patches are compared with the street mesh from the
# sensor (4 yaws) and from 20 m above, with sensor-ray consistency. Needs a release build
# (`cargo build --release -p pointray-cli`) and python3. Writes JSON and positions.md into OUT
# (default out/lidar-positions).
set -euo pipefail
cd "$(dirname "$0")/.."
bin=${BIN:-target/release/pointray}
out=${OUT:-out/lidar-positions}
mkdir -p "$out"
# name, seed, position (empty: the default, the middle of the road at the mount height)
positions=("default 1 -" "p20 1 20,1.5,1.73" "m35 2 -35,-1.5,1.73" "p6 3 6,-1.8,1.73")
for sensor in hdl64 hdl32 vlp16 os128; do
    for entry in "${positions[@]}"; do
        read -r name seed position <<<"$entry"
        where=()
        [ "$position" = - ] || where=(--position="$position")
        scan="$out/$sensor-$name.ply"
        "$bin" scan --street --sensor "$sensor" --seed "$seed" "${where[@]}" -o "$scan" \
            --mesh-out "$out/street-$sensor-$name.ply"
        "$bin" fidelity "$scan" "$out/street-$sensor-$name.ply" --views sensor:4,above:20 --size 256 \
            --scan auto --json "$out/fidelity-$sensor-$name.json"
        "$bin" consistency "$scan" --scan auto --json "$out/consistency-$sensor-$name.json"
    done
done
python3 - "$out" "${positions[@]}" <<'PY'
import json, sys, pathlib
out = pathlib.Path(sys.argv[1])
positions = [entry.split() for entry in sys.argv[2:]]
rows = ["| sensor | position | seed | normal sensor ° | holes from sensor % | false % | normal above ° | seen holes above % | consistent % |",
        "|---|---|---:|---:|---:|---:|---:|---:|---:|"]
def pooled(views, key, base):
    total = sum(v["metrics"][base] or 0 for v in views)
    return sum((v["metrics"][key] or 0) * (v["metrics"][base] or 0) for v in views) / max(1, total)
for sensor in ["hdl64", "hdl32", "vlp16", "os128"]:
    for name, seed, _ in positions:
        report = json.loads((out / f"fidelity-{sensor}-{name}.json").read_text())
        consistency = json.loads((out / f"consistency-{sensor}-{name}.json").read_text())
        sensor_views = [v for v in report["views"] if v["label"].startswith("sensor")]
        above = [v for v in report["views"] if v["label"].startswith("above")]
        rows.append(f"| {sensor} | {name} | {seed} "
                    f"| {pooled(sensor_views, 'normal_error_mean_degrees', 'both_hit_pixels'):.2f} "
                    f"| {100 * pooled(sensor_views, 'hole_rate', 'mesh_pixels'):.2f} "
                    f"| {100 * pooled(sensor_views, 'false_surface_rate', 'mesh_pixels'):.2f} "
                    f"| {pooled(above, 'normal_error_mean_degrees', 'both_hit_pixels'):.2f} "
                    f"| {100 * pooled(above, 'seen_hole_rate', 'seen_mesh_pixels'):.2f} "
                    f"| {100 * consistency['consistent_fraction']:.2f} |")
(out / "positions.md").write_text("\n".join(rows) + "\n")
print("\n".join(rows))
PY
