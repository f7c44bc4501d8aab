#!/usr/bin/env bash
# Where voxel cone tracing puts the light (issue 44): for the Cornell box
# (256²) and Sponza (320×180, scenes/sponza.json), the indirect ratio
# Σ(vct − none) / Σ(one-bounce − direct) (luminance, emitter pixels left
# out) over the whole image, per surface the camera sees (material and
# face, scripts/region_ratios.c) and the range over the 16×9 blocks whose
# reference indirect light is above the median; and relMSE against
# one-bounce of vct, rsm and --gi none (Cornell: the target is vct < 2.5×
# rsm). References are path-traced once into DIR and reused.
# Usage: scripts/vct-regions.sh [DIR] [-- extra render options for vct]
#   e.g. scripts/vct-regions.sh out/vct-regions -- --vct-size 64
# Environment: RTGI (default build/rtgi), REGIONS (build/tests/region_ratios),
# SPP (reference samples per pixel, default 256 Cornell, 64 Sponza),
# SCENES ("cornell sponza").
set -euo pipefail
cd "$(dirname "$0")/.."
DIR=out/vct-regions
if [ $# -gt 0 ] && [ "$1" != "--" ]; then DIR=$1; shift; fi
[ "${1:-}" = "--" ] && shift
EXTRA=("$@")
RTGI=${RTGI:-build/rtgi}
REGIONS=${REGIONS:-build/tests/region_ratios}
SCENES=${SCENES:-cornell sponza}
[ -x "$REGIONS" ] || cmake --build build --target region_ratios >/dev/null
mkdir -p "$DIR"

relmse() { $RTGI compare "$1" "$2" --metric relmse --mask-emitters "$3" --block 0 | awk '/^relmse:/ {print $2}'; }

for tag in $SCENES; do
  case $tag in
    cornell) scene=cornell; size=256x256; spp=${SPP:-256} ;;
    sponza) scene=scenes/sponza.json; size=320x180; spp=${SPP:-64}
            [ -f ../shared/assets/sponza/Sponza.gltf ] || { echo "sponza: no asset, skipped"; continue; } ;;
    *) echo "unknown scene $tag"; exit 2 ;;
  esac
  p=$DIR/$tag
  for mode in direct one-bounce; do
    [ -f "${p}_ref_$mode.pfm" ] ||
      $RTGI reference --scene "$scene" --size "$size" --mode $mode --spp "$spp" --out "${p}_ref_$mode.pfm" \
        --emitter-mask "${p}_emitters.png" --quiet
  done
  $RTGI render --scene "$scene" --size "$size" --gi none --out "${p}_none.pfm" --quiet
  $RTGI render --scene "$scene" --size "$size" --gi rsm --out "${p}_rsm.pfm" --quiet
  $RTGI render --scene "$scene" --size "$size" --gi vct "${EXTRA[@]}" --out "${p}_vct.pfm" --png "${p}_vct.png" --quiet
  echo "== $tag $size, vct ${EXTRA[*]:-(defaults)} against one-bounce"
  r_none=$(relmse "${p}_none.pfm" "${p}_ref_one-bounce.pfm" "${p}_emitters.png")
  r_rsm=$(relmse "${p}_rsm.pfm" "${p}_ref_one-bounce.pfm" "${p}_emitters.png")
  r_vct=$(relmse "${p}_vct.pfm" "${p}_ref_one-bounce.pfm" "${p}_emitters.png")
  awk -v n="$r_none" -v r="$r_rsm" -v v="$r_vct" \
    'BEGIN { printf "relmse: none %.4f  rsm %.4f  vct %.4f  (vct/rsm %.2f)\n", n, r, v, v / r }'
  for t in rsm vct; do
    echo "-- $t indirect ratio"
    $REGIONS "$scene" "${p}_$t.pfm" "${p}_none.pfm" "${p}_ref_one-bounce.pfm" "${p}_ref_direct.pfm" \
      $([ "$tag" = sponza ] && echo 400 || echo 40) | { [ "$tag" = sponza ] && head -14 || cat; }
  done
done
