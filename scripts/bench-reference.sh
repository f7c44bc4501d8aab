#!/bin/sh
# bench-reference.sh — the path tracer's speed and its error per second,
# two builds side by side: rays/s, time per sample per pixel, and the time
# each needs to reach the same relMSE against a converged image.
#   scripts/bench-reference.sh OLD_RTGI NEW_RTGI [OUT_DIR]
# Environment (defaults in brackets):
#   SCENE [cornell]  SIZE [256x256]  THREADS [2]  SPPS ["16 32 64 128"]
#   REPS [3]: runs of each (binary, spp), alternating OLD and NEW, medians kept
#   REF: the converged image; else NEW renders one with REF_SPP [4096] spp
#        and seed 1000 (the timed runs use seed 1)
#   TARGET_SPP [64]: the equal-error target is OLD's relMSE at this spp
# Times are the reference's own time_s (the render, without loading the
# scene or building the BVH). The machine is shared: compare the two
# columns of one run, not numbers of different runs.
set -eu
old=$1
new=$2
out=${3:-out/bench-reference}
scene=${SCENE:-cornell}
size=${SIZE:-256x256}
threads=${THREADS:-2}
spps=${SPPS:-16 32 64 128}
reps=${REPS:-3}
target_spp=${TARGET_SPP:-64}
mkdir -p "$out"
ref=${REF:-$out/converged.pfm}
if [ ! -r "$ref" ]; then
    "$new" reference --scene "$scene" --size "$size" --threads "$threads" --spp "${REF_SPP:-4096}" --seed 1000 \
        --quiet --out "$ref" >/dev/null
fi
log=$out/runs.txt
: >"$log"
for rep in $(seq "$reps"); do
    for spp in $spps; do
        for which in old new; do
            eval bin=\$$which
            img=$out/${which}_$spp.pfm
            "$bin" reference --scene "$scene" --size "$size" --threads "$threads" --spp "$spp" --seed 1 --quiet \
                --out "$img" >"$out/run.txt"
            t=$(awk '/^time_s:/{print $2}' "$out/run.txt")
            r=$(awk '/^rays_per_s:/{print $2}' "$out/run.txt")
            e=$("$new" compare "$img" "$ref" --metric relmse --quiet | awk '/^relmse:/{print $2}')
            echo "$which $spp $t $r $e" >>"$log"
        done
    done
done
echo "scene $scene $size, $threads threads, $reps runs each (medians); converged image: $ref"
printf '%-4s %6s %10s %12s %12s %12s\n' build spp time_s ms_per_spp Mrays_per_s relmse
for which in old new; do
    for spp in $spps; do
        awk -v w="$which" -v s="$spp" '$1 == w && $2 == s {print $3, $4, $5}' "$log" | sort -n |
            awk -v w="$which" -v s="$spp" -v n="$reps" '
                {t[NR] = $1; r[NR] = $2; e = $3}
                END {
                    m = int((NR + 1) / 2)
                    # rays/s: the median of its own column
                    for (i = 1; i <= NR; i++) rr[i] = r[i]
                    for (i = 1; i <= NR; i++) for (k = i + 1; k <= NR; k++) if (rr[k] < rr[i]) { x = rr[i]; rr[i] = rr[k]; rr[k] = x }
                    printf "%-4s %6d %10.3f %12.2f %12.3f %12.6f\n", w, s, t[m], 1000 * t[m] / s, rr[m] / 1e6, e
                }'
    done
done | tee "$out/table.txt"
# Equal error: the time each build needs to reach OLD's relMSE at
# TARGET_SPP, interpolated log-log between its two nearest spp.
awk -v ts="$target_spp" '
    { b = $1; n[b]++; s[b, n[b]] = $2; t[b, n[b]] = $3; e[b, n[b]] = $6 }
    END {
        for (i = 1; i <= n["old"]; i++) if (s["old", i] == ts) target = e["old", i]
        if (target == "") { print "equal error: no run of OLD at " ts " spp"; exit }
        printf "equal error: relMSE %.6f (OLD at %d spp)\n", target, ts
        for (bi = 0; bi < 2; bi++) {
            b = bi ? "new" : "old"; found = 0
            for (i = 1; i < n[b]; i++) {
                e0 = e[b, i]; e1 = e[b, i + 1]
                if ((e0 >= target && e1 <= target) || (e0 <= target && e1 >= target)) {
                    f = (log(target) - log(e0)) / (log(e1) - log(e0))
                    tt[b] = exp(log(t[b, i]) + f * (log(t[b, i + 1]) - log(t[b, i])))
                    sp = exp(log(s[b, i]) + f * (log(s[b, i + 1]) - log(s[b, i])))
                    printf "  %s reaches it in %.3f s (%.1f spp)\n", b, tt[b], sp
                    found = 1; break
                }
            }
            if (!found) {
                # outside the measured range: extrapolate from the lowest spp with error ∝ 1/spp
                tt[b] = t[b, 1] * e[b, 1] / target
                printf "  %s reaches it in %.3f s (extrapolated as 1/spp from %d spp)\n", b, tt[b], s[b, 1]
            }
        }
        printf "equal-error speedup new/old: %.2fx\n", tt["old"] / tt["new"]
    }' "$out/table.txt"
