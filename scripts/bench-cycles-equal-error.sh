#!/bin/sh
# bench-cycles-equal-error.sh — the time `rtgi reference` and Blender's
# Cycles need to reach the same error on the Cornell box, measured against
# a converged Cycles image (issue 48's target: rtgi ≥ 3× faster).
#   scripts/bench-cycles-equal-error.sh RTGI [OLD_RTGI] [OUT_DIR]
# Environment (defaults in brackets):
#   SIZE [256x256]  THREADS [2]  REPS [3]: runs of each (renderer, spp),
#   alternated, medians kept
#   CYCLES_SPPS ["32 64 128"]  RTGI_SPPS ["16 32 64 128"]
#   REF: the converged image; else Cycles renders one with REF_SPP [1024]
#        spp and seed 1000 into OUT_DIR/cycles_ref.exr (kept: delete it to
#        make it anew); the timed runs use seed 1
#   TARGET_SPP [64]: the equal-error target is Cycles' relMSE at this spp
#   JITTER [0]: 1 jitters in the pixel (Cycles: a box filter one pixel
#        wide), else both sample pixel centres (rtgi --no-jitter, Cycles'
#        box 0.01 px wide), as crosscheck-cycles.sh does: Cycles' 1-px box
#        spreads samples past the pixel (the image is 0.25% darker than
#        rtgi's: a difference of filters that would floor the error).
# 64 bounces, no adaptive sampling, denoising or clamping. Times, wall and
# CPU: rtgi's time_s (the render, without the BVH build) and cpu_s (the BVH
# build and the render, all threads); Blender's own "Time:" of the render
# (scene sync, BVH and samples, without Blender's start-up) and the CPU
# seconds of the Blender process less those of a 1-spp render of the same
# scene (its start-up, Python, scene set-up and sync; run once per round).
# On a shared machine CPU seconds are the steadier measure; compare the
# ratio of one run, not seconds of different runs.
set -eu
new=$1
old=${2:-}
out=${3:-out/bench-cycles}
size=${SIZE:-256x256}
threads=${THREADS:-2}
reps=${REPS:-3}
cspps=${CYCLES_SPPS:-32 64 128}
rspps=${RTGI_SPPS:-16 32 64 128}
target_spp=${TARGET_SPP:-64}
facts=${RTGI_CORNELL_FACTS:-../shared/assets/cornell/cornell_box_facts.json}
command -v blender >/dev/null || { echo "bench-cycles-equal-error.sh: blender is not installed (apt install blender)" >&2; exit 1; }
[ -r "$facts" ] || { echo "bench-cycles-equal-error.sh: $facts: cannot read the Cornell box facts" >&2; exit 1; }
mkdir -p "$out"
if [ "${JITTER:-0}" = 1 ]; then fw=1; nj=; else fw=0.01; nj=--no-jitter; fi

# cycles SPP SEED OUT.exr: renders; prints Blender's render time and the
# process's CPU seconds.
cycles() {
    /usr/bin/time -f '%U %S' -o "$out/cpu.txt" blender -b --factory-startup -noaudio --python-exit-code 1 \
        -P scripts/cycles_cornell.py -- --facts "$facts" --size "$size" --spp "$1" --seed "$2" --threads "$threads" \
        --bounces 64 --filter-width "$fw" --out "$3" >"$out/cycles.log" 2>&1 ||
        { echo "bench-cycles-equal-error.sh: blender failed: $out/cycles.log" >&2; exit 1; }
    t=$(awk '/^ *Time: [0-9]/{split($2, t, ":"); s = t[1] * 60 + t[2]} END{print s}' "$out/cycles.log")
    echo "$t $(awk '{print $1 + $2}' "$out/cpu.txt")"
}

ref=${REF:-$out/cycles_ref.exr}
[ -r "$ref" ] || cycles "${REF_SPP:-1024}" 1000 "$ref" >/dev/null
relmse() { "$new" compare "$1" "$ref" --metric relmse --quiet | awk '/^relmse:/{print $2}'; }

log=$out/runs.txt
: >"$log"
for rep in $(seq "$reps"); do
    base=$(cycles 1 1 "$out/cycles_1.exr" | awk '{print $2}')
    for spp in $cspps; do
        set -- $(cycles "$spp" 1 "$out/cycles_$spp.exr")
        echo "cycles $spp $1 $(echo "$2 $base" | awk '{print $1 - $2}') $(relmse "$out/cycles_$spp.exr")" >>"$log"
    done
    for spp in $rspps; do
        for which in new old; do
            eval bin=\$$which
            [ -n "$bin" ] || continue
            "$bin" reference --size "$size" --threads "$threads" --spp "$spp" --seed 1 $nj --quiet \
                --out "$out/${which}_$spp.pfm" >"$out/run.txt"
            t=$(awk '/^time_s:/{print $2}' "$out/run.txt")
            c=$(awk '/^cpu_s:/{print $2}' "$out/run.txt")
            echo "$which $spp $t $c $(relmse "$out/${which}_$spp.pfm")" >>"$log"
        done
    done
done
echo "Cornell $size, $threads threads, filter width $fw px, $reps runs each (median times); error against $ref"
printf '%-7s %6s %9s %9s %11s %15s %10s\n' who spp time_s cpu_s ms_per_spp cpu_ms_per_spp relmse
for who in cycles old new; do
    for spp in $(echo $cspps $rspps | tr ' ' '\n' | sort -nu); do
        awk -v w="$who" -v s="$spp" '$1 == w && $2 == s {print $3, $4, $5}' "$log" |
            awk -v w="$who" -v s="$spp" '
                function median(a, n,   i, k, x) {
                    for (i = 1; i <= n; i++) for (k = i + 1; k <= n; k++) if (a[k] < a[i]) { x = a[i]; a[i] = a[k]; a[k] = x }
                    return a[int((n + 1) / 2)]
                }
                {t[NR] = $1; c[NR] = $2; e = $3}
                END { if (NR) { tm = median(t, NR); cm = median(c, NR)
                      printf "%-7s %6d %9.3f %9.3f %11.2f %15.2f %10.6f\n", w, s, tm, cm, 1000 * tm / s, 1000 * cm / s, e } }'
    done
done | tee "$out/table.txt"
# The time each renderer needs for Cycles' relMSE at TARGET_SPP, log-log
# between its two runs around it (relMSE ∝ time^-k locally; past the last
# run, extrapolated from the last two), in wall and in CPU seconds, and the
# ratio.
for col in 3 4; do
awk -v ts="$target_spp" -v col="$col" '
    $2 ~ /^[0-9]+$/ { w = $1; n[w]++; s[w, n[w]] = $2; t[w, n[w]] = $col; e[w, n[w]] = $7 }
    function at(w,   i, a, b, k) {
        if (n[w] < 2) return -1
        for (i = 1; i < n[w]; i++) {
            a = i; b = i + 1
            if (e[w, b] <= target) break
        }
        k = log(e[w, b] / e[w, a]) / log(t[w, b] / t[w, a])
        return t[w, a] * exp(log(target / e[w, a]) / k)
    }
    END {
        for (i = 1; i <= n["cycles"]; i++) if (s["cycles", i] == ts) target = e["cycles", i]
        if (target == "") { print "equal error: no Cycles run at " ts " spp"; exit }
        tc = at("cycles")
        printf "equal error in %s: relMSE %.6f (Cycles at %d spp): Cycles %.3f s", col == 3 ? "wall seconds" : "CPU seconds",
            target, ts, tc
        for (w in n) if (w != "cycles") { tw = at(w); printf ", %s %.3f s (%.2fx faster)", w, tw, tc / tw }
        print ""
    }' "$out/table.txt"
done | tee -a "$out/table.txt"
