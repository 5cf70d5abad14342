#!/usr/bin/env bash
# copies-scene.sh STORE N OUT.toml: N (1 to 10) copies of the point set STORE side by side on one
# floor, in rows of five one behind the other, under one camera that frames the first row, one
# light, shadows and reflections (bench/RESULTS.md, "What a frame costs as the set grows").
set -euo pipefail
if [ $# -ne 3 ]; then echo "usage: $0 STORE N OUT.toml" >&2; exit 2; fi
store=$1; n=$2; out=$3
case $n in [1-9]|10) ;; *) echo "$0: N must be 1 to 10, not $n" >&2; exit 2;; esac
# Each copy's x and z: rows of five centred on x = 0, 0.26 apart, the second row 0.3 behind.
places=$(awk -v n="$n" 'BEGIN { for (i = 0; i < n; i++) { row = int(i / 5); in_row = n - 5 * row;
    if (in_row > 5) in_row = 5; printf "%.2f,%.2f ", (i % 5 - (in_row - 1) / 2) * 0.26, -0.3 * row } }')
cat > $out <<TOML
background = { top = [0.5, 0.65, 0.9], bottom = [0.95, 0.95, 0.95] }
[render]
width = 1920
height = 1080
max_depth = 2
[camera]
position = [0.0, 0.45, 1.3]
look_at = [0.0, 0.1, 0.0]
vfov_degrees = 40.0
[[lights]]
type = "point"
position = [0.3, 0.8, 0.8]
intensity = 1.0
TOML
i=0
for place in $places; do
  i=$((i+1))
  x=${place%,*}; z=${place#*,}
  cat >> $out <<TOML
[[objects]]
name = "dragon$i"
type = "points"
path = "$store"
[objects.transform]
translate = [$x, 0.0, $z]
[objects.material]
diffuse = [0.4, 0.7, 0.4]
specular = 0.4
shininess = 48.0
TOML
done
cat >> $out <<TOML
[[objects]]
type = "ground"
auto = true
[objects.material]
diffuse = [0.6, 0.6, 0.6]
specular = 0.0
reflectivity = 0.4
TOML
