#!/usr/bin/env bash
# What --gi-visibility on costs (issue 47): each technique rendered with
# `render --timings`, visibility off and on alternating, REPS times each;
# prints one Markdown row per technique with the medians of
#   steady: frame_steady_ms, the light products kept (the lights stand still:
#           the maps were built once, as in the window);
#   cold:   frame_cold_ms, every frame draws the light products again, so it
#           rebuilds the maps too (a moving light);
# their ratios on/off (the same run, alternating: this machine's load
# cancels), the passes of visibility's cold frame (ism_reps, ism_splat,
# ism_pull_push: the mean of the timed frames) and its steady gather pass
# against off's, and visibility_memory_mib.
#
# Usage: scripts/visibility-cost.sh [SCENE] [SIZE] [REPS]
#        (defaults: cornell 256x256 3)
# Environment: RTGI=build/rtgi; TECHS="rsm vpl-slc ..." (default: the seven);
#              ARGS="..." more render options for both (e.g. "--vpls 16384")
set -euo pipefail
cd "$(dirname "$0")/.."
SCENE=${1:-cornell}
SIZE=${2:-256x256}
REPS=${3:-3}
RTGI=${RTGI:-build/rtgi}
TECHS=${TECHS:-"rsm rsm-interp rsm-interleaved vpl-all vpl-slc vpl-interleaved vpl-metalights"}
[ -x "$RTGI" ] || { echo "visibility-cost: $RTGI missing (make build)" >&2; exit 1; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

median() { sort -g | awk '{v[NR] = $1} END {print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2}'; }
value() { awk -v k="$1:" '$1 == k {print $2}' "$2"; }
# The mean GPU ms of pass $1 in the --timings table of file $2 (empty if none).
pass() { awk -v p="$1" '$1 == p && NF == 3 {print $2}' "$2"; }
# The steady frame's gather passes: every steady_*_ms but the frame's own.
gather() { grep -E '^steady_' "$1" | grep -vE '^steady_(gbuffer|shade|total|tonemap|resolve|fxaa)_ms' |
           sed -E 's/^steady_(.*)_ms: (.*)/\1 \2/' | awk '{printf "%s%s %.1f", (NR > 1 ? ", " : ""), $1, $2}'; }

echo "$SCENE $SIZE, $REPS runs each, alternating; $("$RTGI" --version 2>/dev/null | head -1)"
echo
echo "| technique | steady ms off | on | on/off | cold ms off | on | on/off | ism_reps | ism_splat | ism_pull_push | steady gather off | steady gather on | visibility MiB |"
echo "|---|---|---|---|---|---|---|---|---|---|---|---|---|"
for t in $TECHS; do
  for r in $(seq "$REPS"); do
    for v in off on; do
      # shellcheck disable=SC2086 # ARGS are words
      "$RTGI" render --scene "$SCENE" --size "$SIZE" --gi "$t" --gi-visibility "$v" ${ARGS:-} \
        --out "$tmp/img.pfm" --timings --quiet > "$tmp/${v}_$r.txt"
      value frame_steady_ms "$tmp/${v}_$r.txt" >> "$tmp/${v}_steady"
      value frame_cold_ms "$tmp/${v}_$r.txt" >> "$tmp/${v}_cold"
    done
  done
  so=$(median < "$tmp/off_steady") sn=$(median < "$tmp/on_steady")
  co=$(median < "$tmp/off_cold") cn=$(median < "$tmp/on_cold")
  last="$tmp/on_$REPS.txt"
  printf '| %s | %.1f | %.1f | %.2f | %.1f | %.1f | %.2f | %s | %s | %s | %s | %s | %s |\n' "$t" "$so" "$sn" \
    "$(echo "$sn / $so" | bc -l)" "$co" "$cn" "$(echo "$cn / $co" | bc -l)" "$(pass ism_reps "$last")" \
    "$(pass ism_splat "$last")" "$(pass ism_pull_push "$last")" "$(gather "$tmp/off_$REPS.txt")" "$(gather "$last")" \
    "$(value visibility_memory_mib "$last")"
  rm -f "$tmp"/*_steady "$tmp"/*_cold
done
