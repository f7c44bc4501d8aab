#!/bin/bash
# frames-ab.sh — every technique's cold and steady frame in two builds, on
# this device, alternated run by run (old, new, old, ...) so that both see
# the same machine load: `render --shadow pcss --timings --frames 3` per
# technique, case and rep; prints per case a table of the medians of
# frame_cold_ms and frame_steady_ms and their ratios new/old (issue 46's
# "no technique slower" check; docs/performance.md, "llvmpipe against
# a3d3f6b").
#   scripts/frames-ab.sh OLD_RTGI NEW_RTGI [REPS]       (default 3 reps)
#   GI="vct" NEWARGS="--vct-cones 6" scripts/frames-ab.sh old/rtgi build/rtgi 5
# GI: the techniques (default: every one); CASES: "scene:WxH ..." (default
# the Cornell box at 256² and Sponza's nave at 640×360; an old build needs
# a scene file in the layout it reads); NEWARGS: options given to the new
# build alone (a setting the old one lacked, or its old value).
set -u
if [ $# -lt 2 ]; then
    echo "usage: scripts/frames-ab.sh OLD_RTGI NEW_RTGI [REPS]" >&2
    exit 2
fi
old=$1 new=$2 reps=${3:-3}
gi=${GI:-"none rsm rsm-interp rsm-interleaved vpl-clamped vpl-slc vpl-interleaved vpl-metalights vpl-all lpv vct"}
cases=${CASES:-"cornell:256x256 scenes/sponza_nave.json:640x360"}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
median() { sort -g | awk '{a[NR] = $1} END {print (NR % 2 ? a[(NR + 1) / 2] : (a[NR / 2] + a[NR / 2 + 1]) / 2)}'; }
for c in $cases; do
    scene=${c%%:*} size=${c##*:}
    echo "## $scene $size, --shadow pcss, --frames 3, $reps reps alternated (ms)"
    echo "| --gi | cold old | cold new | ratio | steady old | steady new | ratio |"
    echo "|---|---|---|---|---|---|---|"
    for g in $gi; do
        : > "$tmp/old_c"; : > "$tmp/new_c"; : > "$tmp/old_s"; : > "$tmp/new_s"
        for r in $(seq "$reps"); do
            for b in old new; do
                exe=$old extra=""
                if [ $b = new ]; then exe=$new extra=${NEWARGS:-}; fi
                # shellcheck disable=SC2086 # NEWARGS is a list of options
                if ! "$exe" render --scene "$scene" --size "$size" --gi "$g" --shadow pcss --timings --frames 3 \
                        --quiet $extra --out "$tmp/frame.pfm" > "$tmp/log" 2>&1; then
                    echo "frames-ab.sh: $exe render --scene $scene --gi $g failed:" >&2
                    tail -3 "$tmp/log" >&2
                    exit 1
                fi
                sed -n 's/^frame_cold_ms: \([0-9.]*\).*/\1/p' "$tmp/log" | head -1 >> "$tmp/${b}_c"
                sed -n 's/^frame_steady_ms: \([0-9.]*\).*/\1/p' "$tmp/log" | head -1 >> "$tmp/${b}_s"
            done
        done
        oc=$(median < "$tmp/old_c") nc=$(median < "$tmp/new_c") os=$(median < "$tmp/old_s") ns=$(median < "$tmp/new_s")
        echo "| $g | $oc | $nc | $(awk -v a="$oc" -v b="$nc" 'BEGIN {printf "%.2f", b / a}') | $os | $ns |" \
             "$(awk -v a="$os" -v b="$ns" 'BEGIN {printf "%.2f", b / a}') |"
    done
done
