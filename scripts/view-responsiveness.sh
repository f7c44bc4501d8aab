#!/bin/sh
# view-responsiveness.sh — the window during a real slow frame and while
# idle, under a virtual X server: the second part of `rtgi view --ui-test`
# alone (RTGI_UI_TEST_ASYNC_ONLY=1) with no injected sleep
# (RTGI_UI_TEST_SLOW_S=0). It prints two lines:
#   ui-test: idle 1.00 s: scene frames +0, window redraws +0, loop passes +1
#   ui-test: slow frame: window redraws N during it (largest gap G s), ...; it took T s
# N > 0 and G well under T: the window went on drawing (and taking keys)
# while the frame was drawn; before the render thread it drew nothing
# until the frame was done.
#   scripts/view-responsiveness.sh [SCENE] [GI] [SIZE]
#       (default: scenes/sponza.json vpl-all 320x180)
# Run from the checkout's root after building; needs xvfb-run.
set -eu
scene=${1:-scenes/sponza.json}
gi=${2:-vpl-all}
size=${3:-320x180}
rtgi=${RTGI:-build/rtgi}
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
RTGI_UI_TEST_SLOW_S=0 RTGI_UI_TEST_ASYNC_ONLY=1 xvfb-run -a -s "-screen 0 1920x1080x24" \
    "$rtgi" view --scene "$scene" --gi "$gi" --size "$size" --quiet --ui-test "$dir" | grep '^ui-test:'
