#!/bin/sh
# bench-live-reference.sh — the window's live reference (issue 48, item 3):
# how long the path tracer converging in `rtgi view --live-reference` takes
# to reach a relMSE against a converged image, and how many frames per
# second the window draws while it runs. Runs the window's live script
# (--ui-test with --live-reference, src/ui/view_script.h) under Xvfb
# (DISPLAY if set, else a private Xvfb) RUNS times and prints its numbers.
#   scripts/bench-live-reference.sh [RTGI] [OUT_DIR]
# Environment (defaults in brackets):
#   SCENE [cornell]  SIZE [256x256]  THREADS [2]: the live reference's threads
#   TARGET [0.01]: the relMSE against REF to time
#   REF: the converged image (same scene, size and camera); else RTGI renders
#        one with REF_SPP [1024] spp, seed 1000 (the live reference's is 1)
#   BUSY_S [4]: seconds of frames asked for without pause while it converges
#   GI [none]: the window's technique during those frames
#   PRIORITY [idle]: the live reference's threads (--live-priority idle|normal)
#   RUNS [3]
# Lines: per run, the tracer's time from its start to the first image at
# most TARGET with the window idle ("idle"), the window's scene frames per
# second over BUSY_S while it converges from a restart ("busy"), and the
# time to TARGET during those frames; then their medians.
set -eu
rtgi=${1:-build/rtgi}
out=${2:-out/bench-live}
scene=${SCENE:-cornell}
size=${SIZE:-256x256}
threads=${THREADS:-2}
target=${TARGET:-0.01}
busy_s=${BUSY_S:-4}
gi=${GI:-none}
priority=${PRIORITY:-idle}
runs=${RUNS:-3}
mkdir -p "$out"
ref=${REF:-$out/converged_${scene##*/}_$size.pfm}
if [ ! -r "$ref" ]; then
    echo "rendering the converged image ($ref, ${REF_SPP:-1024} spp)..." >&2
    "$rtgi" reference --scene "$scene" --size "$size" --threads "$threads" --spp "${REF_SPP:-1024}" --seed 1000 \
        --quiet --out "$ref" >/dev/null
fi
xvfb_pid=
if [ -z "${DISPLAY:-}" ]; then
    exec 3>"$out/xvfb.display"
    Xvfb -displayfd 3 -nolisten tcp -screen 0 1600x1200x24 >/dev/null 2>&1 &
    xvfb_pid=$!
    trap 'kill $xvfb_pid 2>/dev/null' EXIT
    i=0
    while [ ! -s "$out/xvfb.display" ] && [ $i -lt 100 ]; do sleep 0.1; i=$((i + 1)); done
    DISPLAY=:$(head -n1 "$out/xvfb.display")
    export DISPLAY
fi
log=$out/runs.txt
: >"$log"
for run in $(seq "$runs"); do
    RTGI_UI_TEST_LIVE_TARGET=$target RTGI_UI_TEST_LIVE_BUSY_S=$busy_s RTGI_UI_TEST_LIVE_MAX_S=120 \
        "$rtgi" view --scene "$scene" --size "$size" --gi "$gi" --slow-ms 1e9 --live-reference \
        --live-threads "$threads" --live-priority "$priority" --compare "$ref" --ui-test "$out" >"$out/run.txt" 2>&1 ||
        { cat "$out/run.txt" >&2; exit 1; }
    idle=$(awk '/^ui-test: live converged: relMSE/ {for (i = 1; i <= NF; i++) if ($i == "after") print $(i - 2)}' \
        "$out/run.txt")
    fps=$(awk '/^ui-test: live busy/ {for (i = 1; i <= NF; i++) if ($i == "per") print substr($(i - 1), 2)}' \
        "$out/run.txt")
    busy=$(awk '/^ui-test: live busy/ {for (i = 1; i <= NF; i++) if ($i == "reached" && $(i + 1) == "at") print $(i + 2)}' \
        "$out/run.txt")
    echo "run $run: to relMSE $target idle ${idle:-(not reached)} s; busy: ${fps:-?} frames/s, to relMSE $target" \
        "${busy:-(not reached)} s"
    echo "${idle:--} ${fps:--} ${busy:--}" >>"$log"
done
med() { grep -v '^-$' | sort -n | awk '{a[NR] = $1} END {if (NR) print a[int((NR + 1) / 2)]; else print "-"}'; }
echo "scene $scene $size, $threads threads at priority $priority, gi $gi, $runs runs (medians); converged image: $ref"
echo "live_time_to_target_idle_s: $(awk '{print $1}' "$log" | med)"
echo "window_frames_per_s_busy: $(awk '{print $2}' "$log" | med)"
echo "live_time_to_target_busy_s: $(awk '{print $3}' "$log" | med)"
