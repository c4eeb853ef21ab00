#!/usr/bin/env bash
# The eye model against FovVideoVDP across head-turn speed and fixation.
#
# `scenes/vr_sweep.toml` cut to a 0.75 s yaw sweep of amplitude 30 deg at a
# constant 0, 30, 60, 120 or 200 deg/s (360x400 pixels over 90x100 deg,
# 90 Hz, head tracking, 68 frames), once with the eyes counter-rotating
# (the default rule) and once with them fixed in the head, the metric
# foveated at the modelled gaze (the screen centre) in both. EYES=hold_bunny
# adds a third: the eyes counter-rotate and hold the bunny, the selector
# still models the screen centre, and the metric foveates on the bunny
# (`[gaze] viewer_object`). Each variant
# runs `acuity experiment error` at s = 1 for every acuity component set,
# with screen size at the given biases, scored by FovVideoVDP; the rows are
# gathered into OUT/sweep.csv (rate, eyes, policy, knob, triangles, share of
# full detail, JOD, LOD switches per second), and plots of share and JOD
# against the rate (OUT/sweep_*.png).
#
# Usage: scripts/eye_model_sweep.sh [OUT]   (default out/eye-model-sweep)
# Needs a release build (`cargo build --release`) and ACUITY_PYTHON
# pointing at a Python with pyfvvdp. About 1 min per variant on 2 cores.
#
# Environment overrides (defaults in brackets): RESOLUTION [360x400],
# RATES [0 30 60 120 200], EYES [counter_rotate fixed_in_head; or hold_bunny],
# BIASES [8,32], POLICIES [acuity_size,acuity_size_ecc,acuity_size_vel,acuity_all].
# At a headset's pixel density, e.g. RESOLUTION=2700x3000 (30 px/deg),
# FovVideoVDP on the CPU takes about 8 min per policy and variant.
set -euo pipefail
cd "$(dirname "$0")/.."
acuity=${ACUITY:-target/release/acuity}
out=${1:-out/eye-model-sweep}
resolution=${RESOLUTION:-360x400}
rates=${RATES:-0 30 60 120 200}
eyes_modes=${EYES:-counter_rotate fixed_in_head}
biases=${BIASES:-8,32}
policies=${POLICIES:-acuity_size,acuity_size_ecc,acuity_size_vel,acuity_all}
mkdir -p "$out/scenes"
echo "rate_deg_per_s,eyes,policy,knob,triangles,share,jod,lod_switches_per_s,lod_reversals_per_s" > "$out/sweep.csv"
for rate in $rates; do
  for eyes in $eyes_modes; do
    name="vr_${rate}_${eyes}"
    scene="$out/scenes/$name.toml"
    case "$eyes" in
      counter_rotate | fixed_in_head | hold_bunny) ;;
      *) echo "EYES: unknown mode $eyes (counter_rotate, fixed_in_head, hold_bunny)" >&2; exit 2 ;;
    esac
    counter=$([ "$eyes" = fixed_in_head ] && echo false || echo true)
    viewer=$([ "$eyes" = hold_bunny ] && echo '\nviewer_object = "bunny"' || true)
    sweep="yaw_sweep = { amplitude_deg = 30.0, rate_deg_per_s = $rate.0 }"
    sed -e "s|^yaw_sweep = .*|$sweep|" \
        -e "s|^duration_s = 8.0|duration_s = 0.75|" \
        -e "s|mesh = \"../models/|mesh = \"$PWD/models/|" \
        -e "s|^tracker = \"head\".*|tracker = \"head\"\neyes_counter_rotate = $counter$viewer|" \
        scenes/vr_sweep.toml > "$scene"
    "$acuity" experiment error --scene "$scene" --resolution "$resolution" --frames 68 \
      --biases "$biases" --scales 1 --acuity-policies "$policies" \
      --metric fvvdp --cache-dir scenes/.acuity-cache --out "$out/$name" --quiet
    awk -F, -v rate="$rate" -v eyes="$eyes" '
      NR == 1 { next }
      $1 == "full" { full = $5 }
      { rows[NR] = $0 }
      END {
        for (i = 2; i <= NR; i++) {
          split(rows[i], f, ",")
          printf "%s,%s,%s,%s,%.0f,%.3f,%.3f,%.1f,%.1f\n", rate, eyes, f[1], f[2], f[5], f[5] / full, f[11], f[7], f[13]
        }
      }' "$out/$name/error.csv" >> "$out/sweep.csv"
  done
done
column -s, -t "$out/sweep.csv"
for eyes in $eyes_modes; do
  for y in share jod; do
    "$acuity" plot "$out/sweep.csv" --x rate_deg_per_s --y "$y" --group policy,knob \
      --filter "eyes=$eyes" --title "$y, eyes $eyes" --out "$out/sweep_${y}_$eyes.png"
  done
done
