#!/usr/bin/env bash
# Measures the LiDAR section of bench/FIDELITY.md: the built-in street scanned by each spinning
# preset, prepped three ways (the paper's radius, the cell radius, scan-aware patches), against
# the street mesh from the sensor (4 yaws) and from 20 m above, with sensor-ray consistency;
# then prep throughput on a simulated terrestrial scan of about 2M returns, scan-aware against
# unstructured. Needs a release build (`cargo build --release -p pointray-cli`) and python3.
# Writes JSON, images and tables.md into OUT (default out/lidar).
set -euo pipefail
cd "$(dirname "$0")/.."
bin=${BIN:-target/release/pointray}
out=${OUT:-out/lidar}
mkdir -p "$out"
"$bin" scan --street --sensor hdl64 --seed 1 -o "$out/street-hdl64.ply" --mesh-out "$out/street.ply"
for sensor in hdl64 hdl32 vlp16 os128; do
    [ "$sensor" = hdl64 ] || "$bin" scan --street --sensor "$sensor" --seed 1 -o "$out/street-$sensor.ply"
    for mode in paper cell scan; do
        case $mode in
            paper) flags=(--radius paper --scan off) ;;
            cell) flags=(--radius cell --scan off) ;;
            scan) flags=(--scan auto) ;;
        esac
        images=()
        [ "$sensor" = hdl64 ] && images=(--images "$out/images/$sensor-$mode")
        "$bin" fidelity "$out/street-$sensor.ply" "$out/street.ply" --views sensor:4,above:20 --size 256 \
            "${flags[@]}" "${images[@]}" --json "$out/fidelity-$sensor-$mode.json"
        "$bin" consistency "$out/street-$sensor.ply" "${flags[@]}" --json "$out/consistency-$sensor-$mode.json"
    done
done
"$bin" scan --street --sensor terrestrial --stations "-20,0,1.5;20,0,1.5" --azimuth-step 0.184 --seed 1 \
    -o "$out/street-tls.ply"
for mode in auto off; do
    /usr/bin/time -v "$bin" prep "$out/street-tls.ply" -o "$out/street-tls-$mode.patches" --scan "$mode" \
        > "$out/prep-tls-$mode.txt" 2>&1
done
python3 - "$out" <<'PY'
import json, sys, pathlib
out = pathlib.Path(sys.argv[1])
rows = ["| sensor | patches | view | hole % | seen hole % | false surface % | depth mean | normal mean ° | normal p95 ° (worst view) | consistent % | floaters % | holes % |",
        "|---|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
pct = lambda v: "-" if v is None else f"{100 * v:.2f}"
for sensor in ["hdl64", "hdl32", "vlp16", "os128"]:
    for mode in ["paper", "cell", "scan"]:
        report = json.loads((out / f"fidelity-{sensor}-{mode}.json").read_text())
        consistency = json.loads((out / f"consistency-{sensor}-{mode}.json").read_text())
        sensor_views = [v for v in report["views"] if v["label"].startswith("sensor")]
        groups = [("sensor (4 yaws)", sensor_views), ("above 20 m", [v for v in report["views"] if v["label"].startswith("above")])]
        for label, views in groups:
            mesh = sum(v["metrics"]["mesh_pixels"] for v in views)
            weigh = lambda key, base="mesh_pixels": sum((v["metrics"][key] or 0) * v["metrics"][base] for v in views) / max(1, sum(v["metrics"][base] for v in views))
            seen = sum(v["metrics"]["seen_mesh_pixels"] or 0 for v in views)
            seen_holes = sum((v["metrics"]["seen_hole_rate"] or 0) * (v["metrics"]["seen_mesh_pixels"] or 0) for v in views) / max(1, seen)
            both = lambda key: weigh(key, "both_hit_pixels")
            c = consistency
            rows.append(f"| {sensor} | {mode} | {label} | {pct(weigh('hole_rate'))} | {pct(seen_holes)} | {pct(weigh('false_surface_rate'))} | "
                        f"{both('depth_error_mean'):.2e} | {both('normal_error_mean_degrees'):.2f} | "
                        f"{max(v['metrics']['normal_error_p95_degrees'] or 0 for v in views):.1f} | "
                        f"{pct(c['consistent_fraction'])} | {pct(c['occluded_in_front_fraction'])} | {pct(c['passed_through_fraction'])} |")
(out / "tables.md").write_text("\n".join(rows) + "\n")
print("\n".join(rows))
PY
