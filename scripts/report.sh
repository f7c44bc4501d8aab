#!/usr/bin/env bash
# Generates an HTML report: every technique's image beside the path-traced
# reference, with its error heat map (FLIP), RMSE / relMSE / SSIM / FLIP
# against the full and the one-bounce-novis references, and its GPU time
# per pass. Usage: scripts/report.sh [SCENE] [WxH] [SPP]  → out/report/<scene>_<size>/index.html
set -euo pipefail
cd "$(dirname "$0")/.."
SCENE=${1:-cornell}
SIZE=${2:-256x256}
SPP=${3:-256}
RTGI=build/rtgi
tag=$(basename "$SCENE" | tr -c 'A-Za-z0-9\n' '_')_$SIZE
DIR=out/report/$tag
mkdir -p "$DIR"
for mode in full one-bounce-novis; do
  if [ ! -f "$DIR/ref_$mode.pfm" ]; then
    echo "reference $mode ($SPP spp)..." >&2
    $RTGI reference --scene "$SCENE" --size "$SIZE" --mode $mode --spp "$SPP" --out "$DIR/ref_$mode.pfm" \
      --png "$DIR/ref_$mode.png" --quiet > "$DIR/ref_$mode.txt"
  fi
done
techniques=(
  "hard shadows, no GI|--shadow hard --gi none"
  "PCF, no GI|--shadow pcf --gi none"
  "PCSS, no GI|--shadow pcss --gi none"
  "PCSS + RSM (importance, default)|--shadow pcss --gi rsm"
  "PCSS + RSM (paper weights)|--shadow pcss --gi rsm --rsm-weighting paper"
  "PCSS + RSM (unbiased)|--shadow pcss --gi rsm --rsm-weighting unbiased --rsm-rmax 2"
  "PCSS + RSM interpolated|--shadow pcss --gi rsm-interp"
  "PCSS + RSM interleaved 4×4|--shadow pcss --gi rsm-interleaved"
  "PCSS + VPL brute force (16K)|--shadow pcss --gi vpl-all --vpls 16384"
  "PCSS + VPL clamped (16K)|--shadow pcss --gi vpl-clamped --vpls 16384"
  "PCSS + stochastic light culling (16K)|--shadow pcss --gi vpl-slc --vpls 16384"
  "PCSS + metalights (16K)|--shadow pcss --gi vpl-metalights --vpls 16384"
  "PCSS + LPV 32³ (defaults)|--shadow pcss --gi lpv"
  "PCSS + LPV 16³, 8 steps|--shadow pcss --gi lpv --lpv-size 16 --lpv-iterations 8"
  "PCSS + LPV 32³, 3 cascades|--shadow pcss --gi lpv --lpv-cascades 3"
)
rows=""
i=0
for t in "${techniques[@]}"; do
  name=${t%%|*}
  opts=${t#*|}
  i=$((i + 1))
  echo "$name..." >&2
  # shellcheck disable=SC2086
  timing=$($RTGI render --scene "$SCENE" --size "$SIZE" $opts --timings --frames 1 --out "$DIR/t$i.pfm" \
    --png "$DIR/t$i.png" --quiet)
  full=$($RTGI compare "$DIR/t$i.pfm" "$DIR/ref_full.pfm" --heatmap "$DIR/t${i}_flip.png" --exposure 3)
  novis=$($RTGI compare "$DIR/t$i.pfm" "$DIR/ref_one-bounce-novis.pfm" --metric relmse)
  get() { echo "$1" | awk -v k="$2:" '$1 == k {printf "%.4f", $2}'; }
  passes=$(echo "$timing" | awk '/^  [a-z_]+ +[0-9.]+ +[0-9.]+$/ && $1 != "total" && $1 != "pass" {printf "%s%s&nbsp;%.1f", sep, $1, $2; sep=", "}')
  total=$(echo "$timing" | awk '$1 == "total" {printf "%.1f", $2}')
  rows="$rows<tr><td>$name<br><code>$opts</code></td><td><img src=\"t$i.png\"></td><td><img src=\"t${i}_flip.png\"></td>"
  rows="$rows<td>$(get "$full" rmse)</td><td>$(get "$full" relmse)</td><td>$(get "$full" ssim)</td><td>$(get "$full" flip)</td>"
  rows="$rows<td>$(get "$novis" relmse)</td><td><b>$total</b><br><small>$passes</small></td></tr>"$'\n'
done
renderer=$(echo "$timing" | awk -F': ' '/^renderer:/ {print $2}')
cat > "$DIR/index.html" <<HTML
<!doctype html>
<html><head><meta charset="utf-8"><title>rtgi report — $SCENE $SIZE</title>
<style>
body { font-family: sans-serif; margin: 2em; }
table { border-collapse: collapse; } td, th { border: 1px solid #ccc; padding: 4px 8px; vertical-align: top; }
img { width: 192px; image-rendering: pixelated; } code { font-size: 80%; }
</style></head><body>
<h1>rtgi report: $SCENE at $SIZE</h1>
<p>Renderer: $renderer. References: path-traced with $SPP samples per pixel,
<a href="ref_full.png">full global illumination</a> and
<a href="ref_one-bounce-novis.png">one bounce without visibility on the bounce</a>
(what RSM and VPL techniques compute). Errors are against the full reference unless
the column says otherwise; FLIP and SSIM at exposure 3; the heat map is FLIP.
GPU times are milliseconds from timer queries, one frame after a warm-up.</p>
<table>
<tr><th>technique</th><th>image</th><th>FLIP map</th><th>RMSE</th><th>relMSE</th><th>SSIM</th><th>FLIP</th>
<th>relMSE vs one-bounce-novis</th><th>GPU ms (per pass)</th></tr>
<tr><td>reference (full)</td><td><img src="ref_full.png"></td><td></td><td>0</td><td>0</td><td>1</td><td>0</td><td></td>
<td>$(awk '/^time_s/ {print $2}' "$DIR/ref_full.txt") s CPU, $(awk '/^rays_per_s/ {printf "%.1f", $2/1e6}' "$DIR/ref_full.txt") Mrays/s</td></tr>
$rows</table></body></html>
HTML
echo "wrote $DIR/index.html" >&2
