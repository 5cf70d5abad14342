#!/usr/bin/env bash
# copies-scene.sh STORE N OUT.toml: N (1 to 5) copies of the point set STORE side by side on one
# floor, under one camera that frames five, one light, shadows and reflections (bench/RESULTS.md,
# "What a frame costs as the set grows").
set -euo pipefail
if [ $# -ne 3 ]; then echo "usage: $0 STORE N OUT.toml" >&2; exit 2; fi
store=$1; n=$2; out=$3
case $n in 1) xs="0.0";; 2) xs="-0.13 0.13";; 3) xs="-0.26 0.0 0.26";; 4) xs="-0.39 -0.13 0.13 0.39";;
    5) xs="-0.52 -0.26 0.0 0.26 0.52";; *) echo "$0: N must be 1 to 5, not $n" >&2; exit 2;; esac
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
for x in $xs; do
  i=$((i+1))
  cat >> $out <<TOML
[[objects]]
name = "dragon$i"
type = "points"
path = "$store"
[objects.transform]
translate = [$x, 0.0, 0.0]
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
