#!/usr/bin/env bash
# Benchmarks the RSM family on a scene: per-pass GPU time (mean of --frames
# after a warm-up) and error against the path-traced one-bounce references.
# Prints a Markdown table. Usage: scripts/bench-rsm.sh [SCENE] [WxH] [SPP]
# References are cached in out/bench/ (delete them to re-render).
set -euo pipefail
cd "$(dirname "$0")/.."
SCENE=${1:-cornell}
SIZE=${2:-512x512}
SPP=${3:-256}
RTGI=build/rtgi
OUT=out/bench
mkdir -p "$OUT"
tag=$(basename "$SCENE" | tr -c 'A-Za-z0-9\n' '_')_$SIZE
for mode in one-bounce one-bounce-novis; do
  ref="$OUT/ref_${tag}_${mode}.pfm"
  if [ ! -f "$ref" ]; then
    echo "rendering reference $mode ($SPP spp)..." >&2
    $RTGI reference --scene "$SCENE" --size "$SIZE" --mode "$mode" --spp "$SPP" --out "$ref" --quiet >&2
  fi
done

# name | options
techniques=(
  "none|--gi none"
  "rsm (paper)|--gi rsm"
  "rsm (unbiased, r_max 2)|--gi rsm --rsm-weighting unbiased --rsm-rmax 2"
  "rsm-interp|--gi rsm-interp"
  "rsm-interleaved 4x4|--gi rsm-interleaved"
  "rsm-interleaved 4x4 (unbiased, r_max 2)|--gi rsm-interleaved --rsm-weighting unbiased --rsm-rmax 2"
  "rsm exhaustive (32² RSM faces)|--gi rsm --rsm-exhaustive --rsm-size 32"
)
echo "| technique | GPU ms per pass | total ms | relMSE one-bounce | FLIP one-bounce | relMSE novis | FLIP novis |"
echo "|---|---|---|---|---|---|---|"
for t in "${techniques[@]}"; do
  name=${t%%|*}
  opts=${t#*|}
  img="$OUT/${tag}_$(echo "$name" | tr -c 'A-Za-z0-9\n' '_').pfm"
  # shellcheck disable=SC2086
  timing=$($RTGI render --scene "$SCENE" --size "$SIZE" --shadow pcss $opts --timings --frames 2 --out "$img" --quiet)
  passes=$(echo "$timing" | awk '/^  [a-z_]+ +[0-9.]+ +[0-9.]+$/ && $1 != "total" && $1 != "pass" {printf "%s%s %.1f", sep, $1, $2; sep=", "}')
  total=$(echo "$timing" | awk '$1 == "total" {printf "%.1f", $2}')
  frac=$(echo "$timing" | awk '/rsm_full_gather_fraction/ {printf " (full gathers: %.1f%% of pixels)", 100*$2}')
  row="| $name$frac | $passes | $total"
  for mode in one-bounce one-bounce-novis; do
    m=$($RTGI compare "$img" "$OUT/ref_${tag}_${mode}.pfm" --metric all --exposure 3)
    rel=$(echo "$m" | awk '/^relmse/ {printf "%.4f", $2}')
    flip=$(echo "$m" | awk '/^flip/ {printf "%.4f", $2}')
    row="$row | $rel | $flip"
  done
  echo "$row |"
done
