#!/usr/bin/env bash
# Fails each of rtgi's own allocations in turn (scripts/alloc_failure_shim.c,
# LD_PRELOAD) while `rtgi render --size 16x16 ARGS...` runs, and checks
# every run (its stderr): a crash, an exit 0 with an image other than the unbroken
# run's, or an exit 1 with more than one stderr line or with an output
# file is printed; the sweep ends at the first k past the last allocation.
# Usage: scripts/alloc-failure-sweep.sh [ARGS...]   (e.g. --gi vct --vct-size 16)
# SWEEP_CMD=reference sweeps `rtgi reference` instead (give it --spp);
# SWEEP_EXT=png writes PNG (the encoder) instead of PFM.
# ALLOC_FROM=k starts at the k-th allocation (those before it are the
# same for every technique: about 850 with `--gi none`); ALLOC_STEP=s
# fails every s-th one only (for scenes of many allocations: Sponza).
# About 0.3 s a run; `render --gi none` makes about 870 allocations.
set -uo pipefail
cd "$(dirname "$0")/.."
RTGI=${RTGI:-build/rtgi}
WORK=$(mktemp -d)
trap 'rm -rf "$WORK"' EXIT
cc -O1 -shared -fPIC -o "$WORK/shim.so" scripts/alloc_failure_shim.c -ldl || exit 1
CMD=${SWEEP_CMD:-render}
EXT=${SWEEP_EXT:-pfm}
OOM_AT=0 OOM_COUNT="$WORK/count" LD_PRELOAD="$WORK/shim.so" "$RTGI" "$CMD" --size 16x16 --quiet \
  --out "$WORK/base.$EXT" "$@" >/dev/null || { echo "the unbroken run fails"; exit 1; }
echo "alloc-failure-sweep: the unbroken run makes $(cat "$WORK/count") allocations"
bad=0
for ((k = ${ALLOC_FROM:-1}; ; k += ${ALLOC_STEP:-1})); do
  rm -f "$WORK/out.$EXT" "$WORK/fired"
  err=$(OOM_AT=$k OOM_REPORT="$WORK/fired" LD_PRELOAD="$WORK/shim.so" "$RTGI" "$CMD" --size 16x16 --quiet \
        --out "$WORK/out.$EXT" "$@" 2>&1 >/dev/null)
  rc=$?
  if [ "$(cat "$WORK/fired" 2>/dev/null)" != 1 ] && [ $rc -lt 128 ]; then break; fi
  lines=$(printf '%s' "$err" | grep -c .)
  if [ $rc -ge 128 ]; then
    echo "allocation $k: crash (exit $rc): $(printf '%s' "$err" | tail -1)"; bad=$((bad + 1))
  elif [ $rc -eq 0 ] && ! cmp -s "$WORK/out.$EXT" "$WORK/base.$EXT"; then
    echo "allocation $k: exit 0 with another image: $(printf '%s' "$err" | tr '\n' '|')"; bad=$((bad + 1))
  elif [ $rc -ne 0 ] && { [ -e "$WORK/out.$EXT" ] || [ "$lines" -ne 1 ]; }; then
    echo "allocation $k: exit $rc, $lines lines$([ -e "$WORK/out.$EXT" ] && echo ', an output file'): $(printf '%s' "$err" | tr '\n' '|')"
    bad=$((bad + 1))
  fi
done
echo "alloc-failure-sweep: allocations ${ALLOC_FROM:-1} to $((k - 1))${ALLOC_STEP:+ (one in ${ALLOC_STEP})} failed in turn, $bad bad"
[ $bad -eq 0 ]
