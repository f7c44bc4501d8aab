#!/bin/sh
# shadow-artefacts.sh — acne and peter-panning of the shadow settings as
# measured shares (SPEC §2), against the path tracer's direct light: renders
# the scene's direct light once without shadows and once per setting, then
# `rtgi compare --unshadowed` counts, over the pixels the reference sees
# fully lit, the share a setting darkens (false_shadow: acne) and, over
# those it sees fully shadowed, the share it lights (false_lit:
# peter-panning and leaks). Prints a Markdown table.
#   scripts/shadow-artefacts.sh [SCENE] [SIZE] [SPP] [OUT_DIR]
#       (default: cornell 128x128 1024 out/shadow-artefacts)
#   SETTINGS="--shadow hard --bias-const 0;--shadow pcss" scripts/shadow-artefacts.sh
#       (';'-separated render options per row; the default sweeps the biases)
# Run from the checkout's root after building.
set -eu
scene=${1:-cornell}
size=${2:-128x128}
spp=${3:-1024}
out=${4:-out/shadow-artefacts}
rtgi=${RTGI:-build/rtgi}
settings=${SETTINGS:-"--shadow hard --bias-const 0 --bias-slope 0;\
--shadow hard --bias-slope 0;\
--shadow hard --bias-slope 0.5;\
--shadow hard;\
--shadow hard --bias-const 0.05;\
--shadow hard --bias-slope 20;\
--shadow hard --bias-slope 100;\
--shadow pcf;\
--shadow pcss;\
--shadow pcf --filter-bias legacy;\
--shadow pcss --filter-bias legacy"}
mkdir -p "$out"
"$rtgi" reference --scene "$scene" --mode direct --size "$size" --spp "$spp" --quiet \
    --out "$out/reference.pfm" --emitter-mask "$out/mask.png" >/dev/null
"$rtgi" render --scene "$scene" --size "$size" --shadow none --quiet --out "$out/unshadowed.pfm"
echo "$scene, $size, direct-light reference $spp spp ($("$rtgi" --version))"
echo
echo "| render options | fully lit px | false shadow | fully shadowed px | false lit |"
echo "|---|---|---|---|---|"
echo "$settings" | tr ';' '\n' | while read -r opts; do
    [ -n "$opts" ] || continue
    # shellcheck disable=SC2086 # the options are words
    "$rtgi" render --scene "$scene" --size "$size" $opts --quiet --out "$out/test.pfm"
    "$rtgi" compare "$out/test.pfm" "$out/reference.pfm" --unshadowed "$out/unshadowed.pfm" \
        --mask-emitters "$out/mask.png" --metric rmse |
        awk -v o="$opts" '/^shadow_lit_pixels:/{l=$2} /^shadow_shadowed_pixels:/{s=$2}
            /^false_shadow:/{fs=$2} /^false_lit:/{fl=$2}
            END{printf "| `%s` | %s | %.4f | %s | %.4f |\n", o, l, fs, s, fl}'
done
