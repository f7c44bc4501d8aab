#!/usr/bin/env bash
# Where each GI technique's bounce lands (issue 44): against the path
# tracer's `reference --mode one-bounce`, the indirect ratio
# Σ(tech − none)/Σ(ref − direct) (luminance) of the whole image, the relMSE
# (and --gi none's), the lowest and highest 16×9 block whose reference
# bounce is above the median, and on the Cornell box the ratio of every
# surface in view (build/tests/gi_regions: the masks of test_fidelity.c).
# Emitter pixels and their neighbours are left out. Prints one Markdown
# table per scene; the references are rendered once into DIR and reused.
#
# Usage: scripts/gi-regions.sh [DIR]            (default: out/gi-regions)
# Environment:
#   RTGI=build/rtgi         the renderer measured
#   BEFORE=PATH             also a row for another rtgi binary's `--gi lpv`
#                           with its own defaults (e.g. a build of the
#                           commit before a change)
#   BEFORE_GI=lpv           the technique of that row (e.g. vct)
#   ROWS="label|args;..."   the rows (default below); args go to `render`
#   CORNELL=256x256 CORNELL_SPP=256 SPONZA=320x180 SPONZA_SPP=64
#   SHADOW=pcss             the render's --shadow (the reference is the same
#                           area light either way; it cancels in tech − none)
#   LAMBERTIAN=1            also Sponza with every material Lambertian
#                           (metallic 0, specular 0: a scene file written into
#                           DIR with python3), where the path tracer's bounce
#                           has no glossy paths a diffuse bounce cannot have
set -euo pipefail
cd "$(dirname "$0")/.."
DIR=${1:-out/gi-regions}
RTGI=${RTGI:-build/rtgi}
TOOL=build/tests/gi_regions
SHADOW=${SHADOW:-pcss}
BEFORE_GI=${BEFORE_GI:-lpv}
CORNELL=${CORNELL:-256x256}
CORNELL_SPP=${CORNELL_SPP:-256}
SPONZA=${SPONZA:-320x180}
SPONZA_SPP=${SPONZA_SPP:-64}
# The paper's LPV (propagation through 5 faces, one light group, the
# RSM's geometry only, 32³, the grid size in steps: the defaults before
# issue 44) next to today's defaults, with rsm as the control.
ROWS=${ROWS:-"rsm|--gi rsm;lpv|--gi lpv;lpv, the paper's faces (old defaults)|--gi lpv --lpv-propagation faces --lpv-groups 1 --lpv-gbuffer-occlusion off --lpv-size 32;lpv 32³|--gi lpv --lpv-size 32;lpv 1 light group|--gi lpv --lpv-groups 1;lpv, RSM geometry only|--gi lpv --lpv-gbuffer-occlusion off"}
for f in "$RTGI" "$TOOL"; do
  [ -x "$f" ] || { echo "gi-regions: $f missing (make build)" >&2; exit 1; }
done
mkdir -p "$DIR"

scenes=("cornell|cornell|$CORNELL|$CORNELL_SPP|--surfaces")
if [ -f ../shared/assets/sponza/Sponza.gltf ]; then
  scenes+=("sponza|scenes/sponza_nave.json|$SPONZA|$SPONZA_SPP|")
  if [ "${LAMBERTIAN:-0}" = 1 ]; then
    python3 - "$DIR/sponza_lambertian.json" <<'PY'
import json, os, sys
scene = json.load(open("scenes/sponza_nave.json"))
gltf = os.path.abspath(os.path.join("scenes", scene["mesh"]))
names = [m["name"] for m in json.load(open(gltf))["materials"] if m.get("name")]
scene["mesh"] = gltf
scene["materials"] = {n: {"metallic": 0, "specular": 0} for n in names}
json.dump(scene, open(sys.argv[1], "w"), indent=1)
PY
    scenes+=("sponza-lambertian|$DIR/sponza_lambertian.json|$SPONZA|$SPONZA_SPP|")
  fi
else
  echo "gi-regions: Sponza not found under ../shared/assets/sponza: Cornell only" >&2
fi

for sc in "${scenes[@]}"; do
  IFS='|' read -r tag scene size spp surfaces <<<"$sc"
  base="$DIR/${tag}_${size}"
  for mode in one-bounce direct; do
    ref="${base}_${mode}_${spp}spp.pfm"
    [ -f "$ref" ] || "$RTGI" reference --scene "$scene" --mode "$mode" --spp "$spp" --size "$size" --out "$ref" --quiet
  done
  "$RTGI" render --scene "$scene" --size "$size" --shadow "$SHADOW" --gi none --out "${base}_none.pfm" --quiet
  echo
  echo "### $tag $size (reference one-bounce, $spp spp; --shadow $SHADOW)"
  echo
  header=--header
  IFS=';' read -ra rows <<<"$ROWS"
  [ -n "${BEFORE:-}" ] && rows+=("$BEFORE_GI, $BEFORE|BEFORE")
  for row in "${rows[@]}"; do
    label=${row%%|*}
    args=${row#*|}
    img="${base}_$(echo "$label" | tr -c 'A-Za-z0-9' '_').pfm"
    if [ "$args" = BEFORE ]; then
      "$BEFORE" render --scene "$scene" --size "$size" --shadow "$SHADOW" --gi "$BEFORE_GI" --out "$img" --quiet
    else
      # shellcheck disable=SC2086 # args are words
      "$RTGI" render --scene "$scene" --size "$size" --shadow "$SHADOW" $args --out "$img" --quiet
    fi
    # shellcheck disable=SC2086
    "$TOOL" "$scene" "$img" "${base}_none.pfm" "${base}_one-bounce_${spp}spp.pfm" "${base}_direct_${spp}spp.pfm" \
      $surfaces $header --row "$label"
    header=
  done
done
