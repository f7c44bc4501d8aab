#!/bin/sh
# frame-times.sh — every technique's frame on this device, as a Markdown
# table: cold frame (every light product drawn), steady frame (the lights
# still: shadow maps, RSMs and what derives from them kept) and the steady
# frame's GPU time (its passes' timer queries), in ms, then for the gathers
# their evaluations/s and their fraction of `rtgi probe`'s bound
# (`render --timings --probe run`). On a GPU this is the table of
# docs/gpu.md; on llvmpipe keep to small sizes.
#   scripts/frame-times.sh [SCENE] [SIZE] [SHADOW] [FRAMES]
#       (default: cornell 1920x1080 pcss 20)
#   GI="rsm vct" scripts/frame-times.sh      (the techniques; default all)
#   PROBE=out/probe.json scripts/frame-times.sh   (the gathers' bound from
#       a saved `rtgi probe --json` result instead of a probe run each)
# Run from the checkout's root after building.
set -eu
scene=${1:-cornell}
size=${2:-1920x1080}
shadow=${3:-pcss}
frames=${4:-20}
rtgi=${RTGI:-build/rtgi}
gi=${GI:-"none rsm rsm-interp rsm-interleaved vpl-clamped vpl-slc vpl-interleaved vpl-metalights vpl-all lpv vct"}
log=$(mktemp)
img=$(mktemp --suffix=.png)
trap 'rm -f "$log" "$img"' EXIT
# The value of `render --timings` line KEY in the log ('—' when absent).
get() { v=$(sed -n "s/^$1: \([^ ]*\).*/\1/p" "$log" | head -n 1); echo "${v:-—}"; }
first=1
for g in $gi; do
    probe=""
    case $g in rsm*|vpl*) probe="--probe ${PROBE:-run}" ;; esac
    # shellcheck disable=SC2086
    "$rtgi" render --scene "$scene" --size "$size" --shadow "$shadow" --gi "$g" --timings \
        --frames "$frames" $probe --quiet --out "$img" >"$log"
    if [ $first = 1 ]; then
        echo "$scene, $size, --shadow $shadow, $frames frames, $(sed -n 's/^renderer: //p' "$log" | head -n 1)" \
             "($("$rtgi" --version))"
        echo
        echo "| --gi | cold ms | steady ms | steady GPU ms | gather evals/s | of the probe's bound |"
        echo "|---|---|---|---|---|---|"
        first=0
    fi
    echo "| $g | $(get frame_cold_ms) | $(get frame_steady_ms) | $(get frame_steady_gpu_ms) |" \
         "$(get gather_evals_per_s) | $(get gather_fraction_of_bound) |"
done
