#!/bin/sh
# crosscheck-cycles.sh — `rtgi reference` against Blender's Cycles on the
# Cornell box (scripts/cycles_cornell.py builds it from the published facts),
# for full GI, one bounce and direct light; or, given a scene file with a
# glTF mesh (e.g. scenes/sponza_nave.json), on that scene with its materials made
# Lambertian (scripts/cycles_mesh.py), for full GI and direct light, and
# the indirect light as their difference. Each renderer renders two
# independent seeds, so that the noise of a comparison is measured beside it:
# if both are unbiased, Cycles against rtgi differs by about as much as each
# differs from itself (relmse ≈ the mean of the two noise lines), and the
# mean ratios sit within the noise lines' spread of 1. Both sample pixel
# centres only (rtgi --no-jitter, Cycles' box filter 0.01 px wide): Cycles'
# 1-pixel box filter spreads a few samples past the pixel (the pixels beyond
# the floor's front edge get light), which alone moved the mean ratio by
# 0.24% and is not what this checks.
#   scripts/crosscheck-cycles.sh [OUT_DIR] [SIZE] [SPP] [SCENE.json]
#   (default out/crosscheck 128x128 1024, the Cornell box)
# With a scene, CYCLES_TEXTURES=byte renders Cycles' own 8-bit texture path
# (which filters sRGB-encoded texels: 0.3-0.5% darker per lookup) instead
# of textures decoded before filtering as rtgi does (docs/measuring-sponza.md).
# Needs Debian's blender (apt install blender; python3-numpy for a glTF
# mesh); run from the checkout's root.
set -eu
out=${1:-out/crosscheck}
size=${2:-128x128}
spp=${3:-1024}
scene=${4:-}
facts=${RTGI_CORNELL_FACTS:-../shared/assets/cornell/cornell_box_facts.json}
rtgi=${RTGI:-build/rtgi}
command -v blender >/dev/null || { echo "crosscheck-cycles.sh: blender is not installed (apt install blender)" >&2; exit 1; }
mkdir -p "$out"

# mean_ratio_rgb of compare A B, as "r g b".
ratio() { "$rtgi" compare "$1" "$2" | awk '/^mean_ratio_rgb:/{print $2, $3, $4}'; }

if [ -n "$scene" ]; then
    [ -r "$scene" ] || { echo "crosscheck-cycles.sh: $scene: cannot read the scene file" >&2; exit 1; }
    tex=${CYCLES_TEXTURES:-float}
    # The scene with every material of its glTF file Lambertian (metallic 0,
    # specular 0) and its mesh path absolute: what both renderers render.
    python3 - "$scene" "$out/scene_lambert.json" <<'PY' || exit 1
import json, os, sys
src, dst = sys.argv[1], sys.argv[2]
doc = json.load(open(src))
if "mesh" not in doc or not doc["mesh"].lower().endswith(".gltf"):
    sys.exit("crosscheck-cycles.sh: %s: needs a \"mesh\" that is a .gltf file" % src)
doc["mesh"] = os.path.abspath(os.path.join(os.path.dirname(src), doc["mesh"]))
mats = doc.setdefault("materials", {})
for m in json.load(open(doc["mesh"])).get("materials", []):
    mats.setdefault(m.get("name", ""), {}).update({"metallic": 0, "specular": 0})
json.dump(doc, open(dst, "w"), indent=1)
PY
    for mode in full direct; do
        case $mode in full) bounces=64 ;; direct) bounces=0 ;; esac
        for seed in 1 2; do
            blender -b --factory-startup -noaudio --python-exit-code 1 -P scripts/cycles_mesh.py -- --scene "$out/scene_lambert.json" \
                --size "$size" --spp "$spp" --seed "$seed" --bounces "$bounces" --filter-width 0.01 --textures "$tex" \
                --out "$out/cycles_${mode}_$seed.exr" >"$out/cycles_${mode}_$seed.log" 2>&1 ||
                { echo "crosscheck-cycles.sh: blender failed: $out/cycles_${mode}_$seed.log" >&2; exit 1; }
            "$rtgi" reference --scene "$out/scene_lambert.json" --mode "$mode" --size "$size" --spp "$spp" \
                --seed "$seed" --no-jitter --quiet --out "$out/rtgi_${mode}_$seed.pfm" >/dev/null
        done
        echo "== $mode, $size, $spp spp, Cycles textures $tex: Cycles against rtgi (seed 1, seed 2), then each against itself"
        for pair in "cycles_${mode}_1.exr rtgi_${mode}_1.pfm" "cycles_${mode}_2.exr rtgi_${mode}_2.pfm" \
                    "cycles_${mode}_1.exr cycles_${mode}_2.exr" "rtgi_${mode}_1.pfm rtgi_${mode}_2.pfm"; do
            set -- $pair
            printf '%-24s %-22s ' "$1" "$2"
            "$rtgi" compare "$out/$1" "$out/$2" | awk '/^(relmse|relmse_block|mean_ratio|mean_ratio_rgb):/{printf "%s", $0 "  "} END{print ""}'
        done
    done
    # Indirect = full − direct: (C_full − C_direct) / (R_full − R_direct)
    # per channel, from the ratios and rtgi's direct share of its full image.
    echo "== indirect (full − direct), Cycles over rtgi, per channel"
    for seed in 1 2; do
        f=$(ratio "$out/cycles_full_$seed.exr" "$out/rtgi_full_$seed.pfm")
        d=$(ratio "$out/cycles_direct_$seed.exr" "$out/rtgi_direct_$seed.pfm")
        q=$(ratio "$out/rtgi_direct_$seed.pfm" "$out/rtgi_full_$seed.pfm")
        echo "$seed $f $d $q" | awk '{printf "seed %d: %.4f %.4f %.4f  (direct share of rtgi'"'"'s full %.3f %.3f %.3f)\n", $1,
            ($2 - $5 * $8) / (1 - $8), ($3 - $6 * $9) / (1 - $9), ($4 - $7 * $10) / (1 - $10), $8, $9, $10}'
    done
    exit 0
fi
[ -r "$facts" ] || { echo "crosscheck-cycles.sh: $facts: cannot read the Cornell box facts" >&2; exit 1; }
for mode in full one-bounce direct; do
    case $mode in full) bounces=64 ;; one-bounce) bounces=1 ;; direct) bounces=0 ;; esac
    for seed in 1 2; do
        blender -b --factory-startup -noaudio --python-exit-code 1 -P scripts/cycles_cornell.py -- --facts "$facts" --size "$size" \
            --spp "$spp" --seed "$seed" --bounces "$bounces" --filter-width 0.01 --out "$out/cycles_${mode}_$seed.exr" \
            >"$out/cycles_${mode}_$seed.log" 2>&1 || { echo "crosscheck-cycles.sh: blender failed: $out/cycles_${mode}_$seed.log" >&2; exit 1; }
        "$rtgi" reference --mode "$mode" --size "$size" --spp "$spp" --seed "$seed" --no-jitter --quiet \
            --out "$out/rtgi_${mode}_$seed.pfm" --emitter-mask "$out/mask.png" >/dev/null
    done
    m="--mask-emitters $out/mask.png"
    echo "== $mode, $size, $spp spp: Cycles against rtgi (seed 1, seed 2), then each against itself"
    for pair in "cycles_${mode}_1.exr rtgi_${mode}_1.pfm" "cycles_${mode}_2.exr rtgi_${mode}_2.pfm" \
                "cycles_${mode}_1.exr cycles_${mode}_2.exr" "rtgi_${mode}_1.pfm rtgi_${mode}_2.pfm"; do
        set -- $pair
        printf '%-24s %-22s ' "$1" "$2"
        "$rtgi" compare "$out/$1" "$out/$2" $m | awk '/^(relmse|relmse_block|mean_ratio|mean_ratio_rgb):/{printf "%s", $0 "  "} END{print ""}'
    done
done
