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
# 64 bounces, no adaptive sampling, denoising or clamping. Times: rtgi's
# time_s (the render, without the BVH build) and
# Blender's own "Time:" of the render (scene sync, BVH and samples, without
# Blender's start-up). The machine may be shared: compare the ratio of one
# run, not seconds of different runs.
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

# cycles SPP SEED OUT.exr: renders; prints Blender's render time in seconds.
cycles() {
    blender -b --factory-startup -noaudio --python-exit-code 1 -P scripts/cycles_cornell.py -- --facts "$facts" \
        --size "$size" --spp "$1" --seed "$2" --threads "$threads" --bounces 64 --filter-width "$fw" --out "$3" >"$out/cycles.log" 2>&1 ||
        { echo "bench-cycles-equal-error.sh: blender failed: $out/cycles.log" >&2; exit 1; }
    awk '/^ *Time: [0-9]/{split($2, t, ":"); s = t[1] * 60 + t[2]} END{print s}' "$out/cycles.log"
}

ref=${REF:-$out/cycles_ref.exr}
[ -r "$ref" ] || cycles "${REF_SPP:-1024}" 1000 "$ref" >/dev/null
relmse() { "$new" compare "$1" "$ref" --metric relmse --quiet | awk '/^relmse:/{print $2}'; }

log=$out/runs.txt
: >"$log"
for rep in $(seq "$reps"); do
    for spp in $cspps; do
        t=$(cycles "$spp" 1 "$out/cycles_$spp.exr")
        echo "cycles $spp $t $(relmse "$out/cycles_$spp.exr")" >>"$log"
    done
    for spp in $rspps; do
        for which in new old; do
            eval bin=\$$which
            [ -n "$bin" ] || continue
            "$bin" reference --size "$size" --threads "$threads" --spp "$spp" --seed 1 $nj --quiet \
                --out "$out/${which}_$spp.pfm" >"$out/run.txt"
            t=$(awk '/^time_s:/{print $2}' "$out/run.txt")
            echo "$which $spp $t $(relmse "$out/${which}_$spp.pfm")" >>"$log"
        done
    done
done
echo "Cornell $size, $threads threads, filter width $fw px, $reps runs each (median time); error against $ref"
printf '%-7s %6s %9s %11s %10s\n' who spp time_s ms_per_spp relmse
for who in cycles old new; do
    for spp in $(echo $cspps $rspps | tr ' ' '\n' | sort -nu); do
        awk -v w="$who" -v s="$spp" '$1 == w && $2 == s {print $3, $4}' "$log" | sort -n |
            awk -v w="$who" -v s="$spp" '{t[NR] = $1; e = $2}
                END { if (NR) printf "%-7s %6d %9.3f %11.2f %10.6f\n", w, s, t[int((NR + 1) / 2)],
                      1000 * t[int((NR + 1) / 2)] / s, e }'
    done
done | sort -k1,1 -k2,2n -s | tee "$out/table.txt"
# The time each renderer needs for Cycles' relMSE at TARGET_SPP, log-log
# between its two nearest spp (relMSE ∝ spp^-k locally), and the ratio.
awk -v ts="$target_spp" '
    { w = $1; n[w]++; s[w, n[w]] = $2; t[w, n[w]] = $3; e[w, n[w]] = $5 }
    function at(w,   i, a, b) {
        # The two runs around the target, else the two nearest (extrapolated).
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
        printf "equal error: relMSE %.6f (Cycles at %d spp): Cycles %.3f s", target, ts, tc
        for (w in n) if (w != "cycles") { tw = at(w); printf ", %s %.3f s (%.2fx faster than Cycles)", w, tw, tc / tw }
        print ""
    }' "$out/table.txt" | tee -a "$out/table.txt"
