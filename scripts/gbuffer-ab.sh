#!/bin/sh
# gbuffer-ab.sh — the two G-buffer passes side by side on this device:
# `--gbuffer raster` (the scene drawn with its materials, pass_gbuffer) and
# `--gbuffer visibility` (triangle ids resolved in compute, pass_vbuffer),
# alternated run by run (raster, visibility, raster, ...) so that both see
# the same machine load, on the Cornell box and Sponza's nave
# (deferred frames, --gi none). Prints, per scene, the medians over the
# rounds of the steady frames' G-buffer pass and whole frame (ms; GPU
# timer queries on a GPU, wall time on llvmpipe) and visibility / raster.
# With CPU=1 instead: the process's CPU seconds (user + sys, all of
# llvmpipe's threads) per frame, from a run of 1 and one of FRAMES frames
# (--timings: each a cold and a steady frame) — what a software
# rasterizer spends, robust to other processes' load where wall time is not.
#   scripts/gbuffer-ab.sh [ROUNDS] [FRAMES]          (default 5 rounds of 3 frames)
#   CPU=1 scripts/gbuffer-ab.sh 2 6
#   CASES="cornell|256x256 scenes/sponza_nave.json|640x360" scripts/gbuffer-ab.sh   (the default cases)
# Run from the checkout's root after building (RTGI=path/to/rtgi for another binary).
set -eu
rounds=${1:-5}
frames=${2:-3}
rtgi=${RTGI:-build/rtgi}
cases=${CASES:-"cornell|256x256 scenes/sponza_nave.json|640x360"}
log=$(mktemp)
img=$(mktemp --suffix=.png)
trap 'rm -f "$log" "$img" "$log".*' EXIT
median() { sort -g | awk '{v[NR] = $1} END {if (NR == 0) print "—"; else if (NR % 2) print v[(NR + 1) / 2]; else printf "%.3f\n", (v[NR / 2] + v[NR / 2 + 1]) / 2}'; }
cpu=${CPU:-0}
# CPU seconds of one frame pair of `render` with arguments "$@" (CPU=1).
cpu_per_frame() {
    a=$( { /usr/bin/time -f "%U %S" "$rtgi" render "$@" --frames 1 --warmup 0 --timings --quiet --out "$img" >/dev/null; } 2>&1 | tail -n 1)
    b=$( { /usr/bin/time -f "%U %S" "$rtgi" render "$@" --frames "$frames" --warmup 0 --timings --quiet --out "$img" >/dev/null; } 2>&1 | tail -n 1)
    echo "$a $b" | awk -v n="$frames" '{printf "%.4f\n", ($3 + $4 - $1 - $2) / (n - 1)}'
}
if [ "$cpu" = 1 ]; then
    echo "| scene | size | raster CPU s/frame | visibility CPU s/frame | ratio |"
    echo "|---|---|---|---|---|"
else
    echo "| scene | size | raster gbuffer ms | visibility gbuffer ms | ratio | raster frame ms | visibility frame ms | ratio |"
    echo "|---|---|---|---|---|---|---|---|"
fi
for c in $cases; do
    scene=${c%%|*}
    size=${c#*|}
    case $scene in *sponza*) [ -r ../shared/assets/sponza/Sponza.gltf ] || continue ;; esac
    for g in raster visibility; do : >"$log.$g.pass"; : >"$log.$g.frame"; done
    r=0
    while [ $r -lt "$rounds" ]; do
        for g in raster visibility; do
            if [ "$cpu" = 1 ]; then
                cpu_per_frame --scene "$scene" --size "$size" --gi none --shading deferred --gbuffer $g >>"$log.$g.pass"
                continue
            fi
            "$rtgi" render --scene "$scene" --size "$size" --gi none --shading deferred --gbuffer $g --timings \
                --frames "$frames" --quiet --out "$img" >"$log"
            sed -n 's/^steady_gbuffer_ms: //p' "$log" >>"$log.$g.pass"
            sed -n 's/^frame_steady_ms: //p' "$log" >>"$log.$g.frame"
        done
        r=$((r + 1))
    done
    rp=$(median <"$log.raster.pass"); vp=$(median <"$log.visibility.pass")
    if [ "$cpu" = 1 ]; then
        echo "| $scene | $size | $rp | $vp | $(awk "BEGIN {printf \"%.2f\", $vp / $rp}") |"
        continue
    fi
    rf=$(median <"$log.raster.frame"); vf=$(median <"$log.visibility.frame")
    echo "| $scene | $size | $rp | $vp | $(awk "BEGIN {printf \"%.2f\", $vp / $rp}") | $rf | $vf |" \
         "$(awk "BEGIN {printf \"%.2f\", $vf / $rf}") |"
done
