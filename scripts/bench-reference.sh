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
# Times are the reference's own time_s (wall clock of the render, without
# loading the scene or building the BVH) and cpu_s (CPU seconds of the BVH
# build and the render, all threads; a build without that line, e.g. an old
# one, gets the process's CPU time from /usr/bin/time). On a shared machine
# CPU seconds are the steadier measure; compare the two builds of one run,
# not numbers of different runs.
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
            /usr/bin/time -f '%U %S' -o "$out/cpu.txt" "$bin" reference --scene "$scene" --size "$size" \
                --threads "$threads" --spp "$spp" --seed 1 --quiet --out "$img" >"$out/run.txt"
            t=$(awk '/^time_s:/{print $2}' "$out/run.txt")
            c=$(awk '/^cpu_s:/{print $2}' "$out/run.txt")
            [ -n "$c" ] || c=$(awk '{print $1 + $2}' "$out/cpu.txt")
            r=$(awk '/^rays_per_s:/{print $2}' "$out/run.txt")
            e=$("$new" compare "$img" "$ref" --metric relmse --quiet | awk '/^relmse:/{print $2}')
            echo "$which $spp $t $r $e $c" >>"$log"
        done
    done
done
echo "scene $scene $size, $threads threads, $reps runs each (medians); converged image: $ref"
printf '%-4s %6s %9s %9s %11s %13s %11s %13s %10s\n' build spp time_s cpu_s ms_per_spp cpu_ms_per_spp \
    Mrays_per_s Mrays_per_cpu_s relmse
for which in old new; do
    for spp in $spps; do
        awk -v w="$which" -v s="$spp" '$1 == w && $2 == s {print $3, $4, $5, $6}' "$log" |
            awk -v w="$which" -v s="$spp" '
                function median(a, n,   i, k, x) {
                    for (i = 1; i <= n; i++) for (k = i + 1; k <= n; k++) if (a[k] < a[i]) { x = a[i]; a[i] = a[k]; a[k] = x }
                    return a[int((n + 1) / 2)]
                }
                {t[NR] = $1; r[NR] = $2; e = $3; c[NR] = $4; rays[NR] = $1 * $2}
                END {
                    tm = median(t, NR); cm = median(c, NR); ry = median(rays, NR)
                    printf "%-4s %6d %9.3f %9.3f %11.2f %13.2f %11.3f %13.3f %10.6f\n", w, s, tm, cm, 1000 * tm / s,
                        1000 * cm / s, ry / tm / 1e6, ry / cm / 1e6, e
                }'
    done
done | tee "$out/table.txt"
# Equal error: the time each build needs to reach OLD's relMSE at
# TARGET_SPP, interpolated log-log between its two nearest spp; in wall
# seconds (time_s) and in CPU seconds (cpu_s).
for col in 3 4; do
awk -v ts="$target_spp" -v col="$col" '
    { b = $1; n[b]++; s[b, n[b]] = $2; t[b, n[b]] = $col; e[b, n[b]] = $9 }
    END {
        for (i = 1; i <= n["old"]; i++) if (s["old", i] == ts) target = e["old", i]
        if (target == "") { print "equal error: no run of OLD at " ts " spp"; exit }
        printf "equal error in %s: relMSE %.6f (OLD at %d spp)\n", col == 3 ? "wall seconds" : "CPU seconds", target, ts
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
        printf "equal-error speedup new/old (%s): %.2fx\n", col == 3 ? "wall" : "CPU", tt["old"] / tt["new"]
    }' "$out/table.txt"
done
