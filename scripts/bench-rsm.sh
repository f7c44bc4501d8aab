#!/usr/bin/env bash
# The RSM techniques against the one-bounce-novis reference (what they
# estimate): a thin wrapper over `rtgi bench` that prints its Markdown table.
# Usage: scripts/bench-rsm.sh [SCENE] [WxH] [SPP] → out/bench/rsm_<scene>_<size>/
set -euo pipefail
cd "$(dirname "$0")/.."
SCENE=${1:-cornell}
SIZE=${2:-256x256}
SPP=${3:-256}
tag=$(basename "$SCENE" | tr -c 'A-Za-z0-9\n' '_')_$SIZE
exec build/rtgi bench --scene "$SCENE" --size "$SIZE" --spp "$SPP" --ref-mode one-bounce-novis --shadow hard \
  --gi "rsm:weighting=paper,rsm:weighting=unbiased,rsm,rsm-interp,rsm-interleaved" --out "out/bench/rsm_$tag" --markdown
