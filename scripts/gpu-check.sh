#!/bin/sh
# gpu-check.sh — one command for a machine with a GPU: every number of
# docs/gpu.md in under 4 minutes on an NVIDIA H100, printed as Markdown.
#   1. the device (nvidia-smi when present) and GL renderer;
#   2. every technique's cold, steady and steady-GPU frame at 1920x1080
#      with PCSS on the Cornell box and on Sponza (scripts/frame-times.sh),
#      and the steady frame's passes (GPU ms from timer queries) on Sponza;
#   3. the 3840x2160 frame without GI;
#   4. VCT's voxelization per method (--vct-voxelize raster, compute): the
#      first one's GPU and wall ms from `render --timings`, and with
#      tests/vct_voxelize_bench (VCT_BENCH) the revoxelization after a move,
#      medians of alternated rounds, on the Cornell box and Sponza;
#   5. the two G-buffer passes (--gbuffer raster, visibility) alternated
#      on the Cornell box and Sponza at SIZE (scripts/gbuffer-ab.sh): which
#      one `--gbuffer auto` should pick on this device class;
#   6. `rtgi probe` (what the device sustains on gather-shaped work).
#   scripts/gpu-check.sh [OUT_DIR]        (default out/gpu-check; the tables also go to OUT_DIR/gpu-check.md)
#   FRAMES=10 SIZE=1920x1080 GI="none rsm vct" scripts/gpu-check.sh    (the defaults, and a subset)
# Run from the checkout's root after building (or with RTGI=path/to/rtgi:
# a binary built elsewhere runs with the shared libraries it was bundled
# with, LD_LIBRARY_PATH=DIR, see docs/gpu.md). Sponza rows need
# ../shared/assets/sponza (scenes/sponza_nave.json); they are skipped without it.
set -eu
out=${1:-out/gpu-check}
frames=${FRAMES:-10}
size=${SIZE:-1920x1080}
rtgi=${RTGI:-build/rtgi}
vct_bench=${VCT_BENCH:-build/tests/vct_voxelize_bench}
gi=${GI:-"none rsm rsm-interp rsm-interleaved vpl-clamped vpl-slc vpl-interleaved vpl-metalights vpl-all lpv vct"}
mkdir -p "$out"
report="$out/gpu-check.md"
log=$(mktemp)
trap 'rm -f "$log"' EXIT
export RTGI_GPU_BUDGET_MIB=${RTGI_GPU_BUDGET_MIB:-32768} # a data-centre GPU holds 4K frames and large RSMs
start=$(date +%s)
{
    echo "# rtgi gpu-check, $(date -u +%Y-%m-%dT%H:%M:%SZ), $("$rtgi" --version)"
    echo
    if command -v nvidia-smi >/dev/null 2>&1; then
        nvidia-smi --query-gpu=name,driver_version,clocks.max.sm,memory.total --format=csv,noheader |
            sed 's/^/device: /'
    fi
    "$rtgi" render --size 16x16 --timings --frames 1 --quiet --out "$out/probe.png" | sed -n 's/^renderer: /GL renderer: /p'
    echo
    for scene in cornell scenes/sponza_nave.json; do
        if [ "$scene" != cornell ] && [ ! -r ../shared/assets/sponza/Sponza.gltf ]; then
            echo "($scene: ../shared/assets/sponza is absent: skipped)"
            continue
        fi
        echo "## $scene, $size"
        echo
        GI="$gi" RTGI="$rtgi" scripts/frame-times.sh "$scene" "$size" pcss "$frames"
        echo
    done
    if [ -r ../shared/assets/sponza/Sponza.gltf ]; then
        echo "## Sponza $size, steady frame, GPU ms per pass (timer queries)"
        echo
        echo "| --gi | passes |"
        echo "|---|---|"
        for g in $gi; do
            "$rtgi" render --scene scenes/sponza_nave.json --size "$size" --gi "$g" --timings --frames "$frames" \
                --quiet --out "$out/pass.png" >"$log"
            # steady_PASS_ms: timer queries on a GPU (wall times on a software rasterizer)
            passes=$(sed -n 's/^steady_\(.*\)_ms: \(.*\)/\1 \2/p' "$log" | grep -v '^total ' |
                awk '{printf "%s %.2f, ", $1, $2}')
            echo "| $g | ${passes%, } |"
        done
        echo
    fi
    echo "## 3840x2160, no GI"
    echo
    GI=none RTGI="$rtgi" scripts/frame-times.sh cornell 3840x2160 pcss "$frames" | tail -n 1
    if [ -r ../shared/assets/sponza/Sponza.gltf ]; then
        GI=none RTGI="$rtgi" scripts/frame-times.sh scenes/sponza_nave.json 3840x2160 pcss "$frames" | tail -n 1
    fi
    echo
    echo "## VCT voxelization per method, $size"
    echo
    echo "| scene | --vct-voxelize | first: GPU ms | first: wall ms |"
    echo "|---|---|---|---|"
    for scene in cornell scenes/sponza_nave.json; do
        [ "$scene" = cornell ] || [ -r ../shared/assets/sponza/Sponza.gltf ] || continue
        for m in raster compute; do
            "$rtgi" render --scene "$scene" --size "$size" --gi vct --vct-voxelize "$m" --timings --frames 1 \
                --quiet --out "$out/voxelize.png" >"$log"
            gpu=$(sed -n 's/^  vct_voxelize  *\([0-9.]*\) .*once$/\1/p' "$log")
            wall=$(sed -n 's/^vct_voxelize_wall_ms: //p' "$log")
            echo "| $scene | $m | $gpu | $wall |"
        done
    done
    echo
    if [ -x "$vct_bench" ]; then
        # revoxelizations after a move (no compilation), raster and compute alternating
        for scene in cornell scenes/sponza_nave.json; do
            [ "$scene" = cornell ] || [ -r ../shared/assets/sponza/Sponza.gltf ] || continue
            echo '```'
            "$vct_bench" "$scene" "$size" 5
            echo '```'
        done
        echo
    fi
    echo "## G-buffer: raster vs visibility, $size, medians of 3 alternated runs (steady, --gi none)"
    echo
    CASES="cornell|$size scenes/sponza_nave.json|$size" RTGI="$rtgi" scripts/gbuffer-ab.sh 3 "$frames"
    echo
    echo "## rtgi probe"
    echo
    echo '```'
    "$rtgi" probe --quiet
    echo '```'
    echo
    echo "(gpu-check took $(( $(date +%s) - start )) s)"
} | tee "$report"
