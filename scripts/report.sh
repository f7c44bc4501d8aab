#!/usr/bin/env bash
# The HTML report of every technique against the path-traced reference:
# a thin wrapper over `rtgi bench` (see docs/measuring.md, "Benchmarks").
# Usage: scripts/report.sh [SCENE] [WxH] [SPP] → out/report/<scene>_<size>/report.html
set -euo pipefail
cd "$(dirname "$0")/.."
SCENE=${1:-cornell}
SIZE=${2:-256x256}
SPP=${3:-256}
tag=$(basename "$SCENE" | tr -c 'A-Za-z0-9\n' '_')_$SIZE
exec build/rtgi bench --scene "$SCENE" --size "$SIZE" --spp "$SPP" --shadow pcss --out "out/report/$tag" \
  --gi "none,rsm,rsm:weighting=paper,rsm:weighting=unbiased:r_max=2,rsm-interp,rsm-interleaved,vpl-all,vpl-clamped,vpl-slc,vpl-interleaved,vpl-metalights,lpv,lpv:lpv_size=16:lpv_iterations=8,lpv:lpv_cascades=3,vct,vct:vct_bounces=2,vct:vct_aniso=off"
