#!/usr/bin/env bash
# Renders every --shadow and --gi value on the Cornell box and Sponza, and
# the glossy Cornell box with and without VCT, into DIR as linear PFM, for
# before/after comparisons of a change that must not alter images (compare
# two directories with --compare DIR_A DIR_B).
# Usage: scripts/render-matrix.sh DIR [RTGI]
#        scripts/render-matrix.sh --compare DIR_A DIR_B [RTGI]
#        RENDER_ARGS="--gbuffer visibility" scripts/render-matrix.sh DIR   (options added to every render)
set -euo pipefail
cd "$(dirname "$0")/.."
if [ "${1:-}" = "--compare" ]; then
  A=$2; B=$3; RTGI=${4:-build/rtgi}
  printf '%-40s %12s %12s\n' image relmse rmse
  for f in "$A"/*.pfm; do
    n=$(basename "$f")
    if [ ! -f "$B/$n" ]; then printf '%-40s missing in %s\n' "$n" "$B"; continue; fi
    m=$($RTGI compare "$B/$n" "$f" --metric all 2>&1 || true)
    rel=$(echo "$m" | awk '/^relmse:/ {print $2}')
    rmse=$(echo "$m" | awk '/^rmse:/ {print $2}')
    printf '%-40s %12s %12s\n' "${n%.pfm}" "${rel:-error}" "${rmse:-error}"
  done
  exit 0
fi
DIR=${1:?usage: scripts/render-matrix.sh DIR [RTGI]}
RTGI=${2:-build/rtgi}
# shellcheck disable=SC2086 # (EXTRA: words, split on purpose)
EXTRA=${RENDER_ARGS:-}
mkdir -p "$DIR"
SPONZA=scenes/sponza_nave.json
scenes=("cornell|cornell|96x96")
if [ -f ../shared/assets/sponza/Sponza.gltf ]; then scenes+=("sponza|$SPONZA|160x90"); fi
for s in "${scenes[@]}"; do
  IFS='|' read -r tag scene size <<<"$s"
  for sh in none hard pcf pcss; do
    $RTGI render --scene "$scene" --size "$size" --shadow "$sh" --out "$DIR/${tag}_shadow_$sh.pfm" --quiet $EXTRA
  done
  for gi in rsm rsm-interp rsm-interleaved; do
    $RTGI render --scene "$scene" --size "$size" --gi "$gi" --rsm-size 128 --out "$DIR/${tag}_gi_$gi.pfm" --quiet $EXTRA
  done
  $RTGI render --scene "$scene" --size "$size" --gi rsm --rsm-exhaustive --rsm-size 16 --out "$DIR/${tag}_gi_rsm-exhaustive.pfm" --quiet $EXTRA
  $RTGI render --scene "$scene" --size "$size" --gi lpv --lpv-size 16 --out "$DIR/${tag}_gi_lpv.pfm" --quiet $EXTRA
  $RTGI render --scene "$scene" --size "$size" --gi vct --vct-size 32 --out "$DIR/${tag}_gi_vct.pfm" --quiet $EXTRA
  for gi in vpl-all vpl-clamped vpl-slc vpl-interleaved vpl-metalights; do
    $RTGI render --scene "$scene" --size "$size" --gi "$gi" --vpls 4096 --out "$DIR/${tag}_gi_$gi.pfm" --quiet $EXTRA
  done
done
# Glossy materials: the direct light's GGX lobe and VCT's specular cone.
for gi in none vct; do
  $RTGI render --scene scenes/cornell_glossy.json --size 96x96 --gi "$gi" --vct-size 32 --out "$DIR/glossy_gi_$gi.pfm" --quiet $EXTRA
done
echo "render-matrix: $(ls "$DIR"/*.pfm | wc -l) images in $DIR"
