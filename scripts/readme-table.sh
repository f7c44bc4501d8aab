#!/bin/sh
# readme-table.sh — the README's technique table, from `rtgi bench`: every
# GI technique with PCSS, and the shadow techniques without GI, on the
# Cornell box at 256², each against the path tracer (GI: every bounce;
# shadows: direct light); its paper (the technique table's row), its mean
# frame on this device (cold: every light product rebuilt) and its error.
# The GPU column is docs/gpu.md's steady 1080p Sponza frame on an NVIDIA
# H100 (commit a3d3f6b; '—' where none was measured).
#   scripts/readme-table.sh [DIR] [SPP]      (default out/bench/table 1024)
# Reuses DIR's runs if they are there; prints Markdown rows on stdout.
set -eu
dir=${1:-out/bench/table}
spp=${2:-1024}
rtgi=${RTGI:-build/rtgi}
[ -f "$dir/gi/bench.json" ] || "$rtgi" bench --out "$dir/gi" --spp "$spp" --frames 3 --quiet >&2
[ -f "$dir/shadow/bench.json" ] ||
    "$rtgi" bench --out "$dir/shadow" --gi none --shadow hard,pcf,pcss --ref-mode direct --spp "$spp" --frames 3 --quiet >&2
python3 - "$dir/gi/bench.json" "$dir/shadow/bench.json" <<'PY'
import json, sys
h100 = {"none": 7.8, "rsm": 13.1, "rsm-interp": 11.0, "vpl-slc": 11.2, "lpv": 10.0, "vct": 10.8}
shadow_papers = {"hard": "Williams 1978, Casting curved shadows on curved surfaces",
                 "pcf": "Reeves et al. 1987, Rendering Antialiased Shadows with Depth Maps",
                 "pcss": "Fernando 2005, Percentage-Closer Soft Shadows"}
gi, sh = (json.load(open(p)) for p in sys.argv[1:3])
def row(name, paper, t, gpu):
    m = t["metrics"]
    print(f"| `{name}` | {paper} | {t['frame_ms']:.0f} | {gpu} | {m['relmse']:.4f} | {m['flip']:.3f} |")
for t in sh["techniques"]:
    row("--shadow " + t["shadow"], shadow_papers.get(t["shadow"], "-"), t, "—")
for t in gi["techniques"]:
    g = t["gi"]
    row("--gi " + g, t.get("paper", "-"), t, h100.get(g, "—"))
print(f"\nMeasured on {gi['gl_renderer']} at {gi['commit']}: references of {gi['spp']} spp "
      f"({gi['reference']['mode']} for --gi, {sh['reference']['mode']} for --shadow).")
PY
