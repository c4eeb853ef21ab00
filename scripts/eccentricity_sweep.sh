#!/usr/bin/env bash
# The eye model against FovVideoVDP across the gaze's offset from the view
# axis: the eccentricity component's savings where objects lie 0-60 deg from
# where the viewer looks.
#
# Two scenes, each with an eye tracker (1 deg margin) holding the gaze at a
# fixed screen point `offset` deg right of centre (the metric is foveated
# at the same point):
# - `scenes/vr_sweep.toml` with the head still (0.75 s, 68 frames at
#   360x400 over 90x100 deg; offsets 0, 15, 30, 45: objects reach 90 deg
#   from the gaze);
# - `scenes/default.toml` (its first 2 s, 60 frames at 640x480 over
#   43.6x33.4 deg; offsets 0, 10, 20).
# Each variant runs `acuity experiment error` at s = 1 for acuity_size,
# acuity_size_ecc and acuity_all, with screen size at two biases; the rows
# go to OUT/sweep.csv (scene, offset, policy, knob, triangles, share of full
# detail, JOD), with plots of share and JOD against the offset per scene.
#
# Usage: scripts/eccentricity_sweep.sh [OUT]   (default out/eccentricity-sweep)
# Needs a release build and ACUITY_PYTHON pointing at a Python with pyfvvdp.
set -euo pipefail
cd "$(dirname "$0")/.."
acuity=${ACUITY:-target/release/acuity}
out=${1:-out/eccentricity-sweep}
mkdir -p "$out/scenes"
echo "scene,offset_deg,policy,knob,triangles,share,jod" > "$out/sweep.csv"
gaze="mode = \"fixed\"\npoint_deg = [OFFSET, 0.0]\ntracker = \"eye\"\neye_error_deg = 1.0"
variant() {
  local base=$1 offset=$2 resolution=$3 frames=$4 biases=$5 extra=$6
  local name="${base}_${offset}" scene="$out/scenes/${base}_${offset}.toml"
  # The [gaze] table is replaced whole; the camera keeps its path.
  awk -v gaze="${gaze//OFFSET/$offset.0}" '
    /^\[gaze\]/ { print; print gaze; skip = 1; next }
    /^\[/ { skip = 0 }
    !skip { print }' "scenes/$base.toml" \
    | sed -e "s|mesh = \"../models/|mesh = \"$PWD/models/|" -e "$extra" > "$scene"
  "$acuity" experiment error --scene "$scene" --resolution "$resolution" --frames "$frames" \
    --biases "$biases" --scales 1 --acuity-policies acuity_size,acuity_size_ecc,acuity_all \
    --metric fvvdp --cache-dir scenes/.acuity-cache --out "$out/$name" --quiet
  awk -F, -v scene="$base" -v offset="$offset" '
    NR == 1 { next }
    $1 == "full" { full = $5 }
    { rows[NR] = $0 }
    END {
      for (i = 2; i <= NR; i++) {
        split(rows[i], f, ",")
        printf "%s,%s,%s,%s,%.0f,%.3f,%.3f\n", scene, offset, f[1], f[2], f[5], f[5] / full, f[11]
      }
    }' "$out/$name/error.csv" >> "$out/sweep.csv"
}
still="s|^duration_s = 8.0|duration_s = 0.75|;s|^yaw_sweep = .*||"
for offset in 0 15 30 45; do variant vr_sweep "$offset" 360x400 68 8,32 "$still"; done
for offset in 0 10 20; do variant default "$offset" 640x480 60 4,16 ""; done
column -s, -t "$out/sweep.csv"
for base in vr_sweep default; do
  for y in share jod; do
    "$acuity" plot "$out/sweep.csv" --x offset_deg --y "$y" --group policy,knob \
      --filter "scene=$base" --title "$y against the gaze offset, $base" \
      --out "$out/sweep_${y}_$base.png"
  done
done
