#!/usr/bin/env bash
# Benchmarks the many-VPL techniques at several VPL counts: per-pass GPU
# time (one frame, no warm-up: brute force takes minutes on llvmpipe),
# VPL–pixel evaluations and candidates (tile-list entries visited) per
# pixel, RMSE against brute force at the same
# VPLs, relMSE against the path-traced one-bounce-novis reference.
# Prints a Markdown table. Usage: scripts/bench-vpl.sh [SCENE] [WxH] [SPP] [COUNTS...]
set -euo pipefail
cd "$(dirname "$0")/.."
SCENE=${1:-cornell}
SIZE=${2:-512x512}
SPP=${3:-128}
shift $(( $# > 3 ? 3 : $# )) || true
COUNTS=("$@")
[ ${#COUNTS[@]} -gt 0 ] || COUNTS=(4096 16384 65536)
RTGI=build/rtgi
OUT=out/bench
mkdir -p "$OUT"
tag=$(basename "$SCENE" | tr -c 'A-Za-z0-9\n' '_')_$SIZE
ref="$OUT/ref_${tag}_one-bounce-novis.pfm"
if [ ! -f "$ref" ]; then
  echo "rendering reference one-bounce-novis ($SPP spp)..." >&2
  $RTGI reference --scene "$SCENE" --size "$SIZE" --mode one-bounce-novis --spp "$SPP" --out "$ref" --quiet >&2
fi
echo "| VPLs (asked → made) | technique | GPU ms per pass | total ms | evaluations/pixel | candidates/pixel | RMSE vs brute force | relMSE vs one-bounce-novis |"
echo "|---|---|---|---|---|---|---|---|"
for n in "${COUNTS[@]}"; do
  brute="$OUT/${tag}_vpl-all_$n.pfm"
  for gi in vpl-all vpl-clamped vpl-slc vpl-interleaved vpl-metalights; do
    img="$OUT/${tag}_${gi}_$n.pfm"
    echo "  $gi $n..." >&2
    timing=$($RTGI render --scene "$SCENE" --size "$SIZE" --shadow pcf --gi $gi --vpls "$n" --timings --frames 1 --warmup 0 --out "$img" --quiet)
    passes=$(echo "$timing" | awk '/^  [a-z_]+ +[0-9.]+ +[0-9.]+$/ && $1 != "total" && $1 != "pass" {printf "%s%s %.1f", sep, $1, $2; sep=", "}')
    total=$(echo "$timing" | awk '$1 == "total" {printf "%.1f", $2}')
    made=$(echo "$timing" | awk '$1 == "vpl_count:" {print $2}')
    epp=$(echo "$timing" | awk '$1 == "vpl_evaluations_per_pixel:" {print $2}')
    pixels=$(echo "$SIZE" | awk -Fx '{print $1 * $2}')
    cpp=$(echo "$timing" | awk -v n="$pixels" '$1 == "vpl_candidates:" {printf "%.1f", $2 / n}')
    rmse=$($RTGI compare "$img" "$brute" --metric rmse | awk '{printf "%.5f", $2}')
    rel=$($RTGI compare "$img" "$ref" --metric relmse | awk '{printf "%.4f", $2}')
    echo "| $n → $made | $gi | $passes | $total | $epp | $cpp | $rmse | $rel |"
  done
done
