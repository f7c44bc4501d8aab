#!/usr/bin/env bash
# The many-VPL techniques at several VPL counts against the one-bounce-novis
# reference: a thin wrapper over `rtgi bench` that prints its Markdown table
# (evaluations per pixel from the techniques' counters).
# Usage: scripts/bench-vpl.sh [SCENE] [WxH] [SPP] [COUNTS...] → out/bench/vpl_<scene>_<size>/
set -euo pipefail
cd "$(dirname "$0")/.."
SCENE=${1:-cornell}
SIZE=${2:-256x256}
SPP=${3:-128}
shift $(( $# > 3 ? 3 : $# )) || true
COUNTS=("$@")
[ ${#COUNTS[@]} -gt 0 ] || COUNTS=(4096 16384 65536)
list=""
for n in "${COUNTS[@]}"; do
  for gi in vpl-all vpl-clamped vpl-slc vpl-interleaved vpl-metalights; do
    list="$list${list:+,}$gi:vpls=$n"
  done
done
tag=$(basename "$SCENE" | tr -c 'A-Za-z0-9\n' '_')_$SIZE
exec build/rtgi bench --scene "$SCENE" --size "$SIZE" --spp "$SPP" --ref-mode one-bounce-novis --shadow hard \
  --frames 1 --gi "$list" --out "out/bench/vpl_$tag" --markdown
