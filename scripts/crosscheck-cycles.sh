#!/bin/sh
# crosscheck-cycles.sh — `rtgi reference` against Blender's Cycles on the
# Cornell box (scripts/cycles_cornell.py builds it from the published facts),
# for full GI, one bounce and direct light. Each renderer renders two
# independent seeds, so that the noise of a comparison is measured beside it:
# if both are unbiased, Cycles against rtgi differs by about as much as each
# differs from itself (relmse ≈ the mean of the two noise lines), and the
# mean ratios sit within the noise lines' spread of 1. Both sample pixel
# centres only (rtgi --no-jitter, Cycles' box filter 0.01 px wide): Cycles'
# 1-pixel box filter spreads a few samples past the pixel (the pixels beyond
# the floor's front edge get light), which alone moved the mean ratio by
# 0.24% and is not what this checks.
#   scripts/crosscheck-cycles.sh [OUT_DIR] [SIZE] [SPP]   (default out/crosscheck 128x128 1024)
# Needs Debian's blender (apt install blender); run from the checkout's root.
set -eu
out=${1:-out/crosscheck}
size=${2:-128x128}
spp=${3:-1024}
facts=${RTGI_CORNELL_FACTS:-../shared/assets/cornell/cornell_box_facts.json}
rtgi=${RTGI:-build/rtgi}
command -v blender >/dev/null || { echo "crosscheck-cycles.sh: blender is not installed (apt install blender)" >&2; exit 1; }
[ -r "$facts" ] || { echo "crosscheck-cycles.sh: $facts: cannot read the Cornell box facts" >&2; exit 1; }
mkdir -p "$out"
for mode in full one-bounce direct; do
    case $mode in full) bounces=64 ;; one-bounce) bounces=1 ;; direct) bounces=0 ;; esac
    for seed in 1 2; do
        blender -b --factory-startup -noaudio -P scripts/cycles_cornell.py -- --facts "$facts" --size "$size" \
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
