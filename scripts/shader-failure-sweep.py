#!/usr/bin/env python3
"""Breaks every shader program variant rtgi builds, one at a time, and checks
that `render` then fails: exit status non-zero and no output file.

For each configuration below, `render --verbose` lists the programs it builds
("building LABEL: FILES [DEFINES]"). For each variant not seen before, a copy
of shaders/ gets `#error` appended to the variant's own stage (its fragment,
geometry or compute file; the vertex file where it has no other), guarded by
`#if defined(D1) && ...` over the variant's defines, so that only that
variant (and those with more defines) fails to build; the configuration is
rendered again from that copy with --shader-dir. A variant whose failure is
lost (a technique that draws on without it, or a specialised program that
falls back to a general one) shows as BAD.

Usage: scripts/shader-failure-sweep.py [WORK_DIR] [RTGI]
About 5 minutes on one llvmpipe thread (LP_NUM_THREADS=1). Exit 1 if any
variant is BAD or a configuration does not render unbroken.
"""
import os
import re
import shutil
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
WORK = sys.argv[1] if len(sys.argv) > 1 else "/tmp/rtgi-shader-sweep"
RTGI = sys.argv[2] if len(sys.argv) > 2 else os.path.join(ROOT, "build", "rtgi")
SCENES = os.path.join(ROOT, "scenes")

CONFIGS = [
    ["--gi", "none", "--shadow", "pcss"], ["--gi", "none", "--shadow", "pcf"], ["--gi", "none", "--shadow", "hard"],
    ["--gi", "rsm"], ["--gi", "rsm", "--rsm-weighting", "paper"], ["--gi", "rsm", "--rsm-weighting", "unbiased"],
    ["--gi", "rsm", "--rsm-exhaustive", "--rsm-size", "32"], ["--gi", "rsm-interp"], ["--gi", "rsm-interleaved"],
    ["--gi", "vpl-all"], ["--gi", "vpl-slc"], ["--gi", "vpl-clamped"], ["--gi", "vpl-interleaved"],
    ["--gi", "vpl-metalights"],
    ["--gi", "lpv"], ["--gi", "lpv", "--lpv-inject", "points"], ["--gi", "lpv", "--lpv-gbuffer-occlusion", "on"],
    ["--gi", "lpv", "--lpv-cascades", "2"], ["--gi", "lpv", "--lpv-occlusion", "off"],
    ["--gi", "vct"], ["--gi", "vct", "--vct-bounces", "2"], ["--gi", "vct", "--vct-aniso", "off"],
    ["--gi", "vct", "--vct-levels", "2"], ["--gi", "vct", "--vct-trace-scale", "1"],
    ["--gi", "vpl-slc", "--scene", os.path.join(SCENES, "cornell_point.json")],
    ["--gi", "vct", "--scene", os.path.join(SCENES, "cornell_glossy.json")],
    ["--gi", "rsm", "--scene", os.path.join(SCENES, "parity", "rsm_spot.json")],
    ["--gi", "vpl-slc", "--scene", os.path.join(SCENES, "parity", "pcf_sun.json")],
    ["--gi", "rsm-interp", "--scene", os.path.join(SCENES, "parity", "pcss_spot.json")],
]


def render(out, args, shader_dir=None):
    if os.path.exists(out):
        os.remove(out)
    cmd = [RTGI, "render", "--size", "16x16", "--frames", "2", "--out", out] + args
    if shader_dir:
        cmd += ["--shader-dir", shader_dir]
    p = subprocess.run(cmd, capture_output=True, text=True, timeout=600)
    return p.returncode, p.stderr


def main():
    os.makedirs(WORK, exist_ok=True)
    out = os.path.join(WORK, "out.pfm")
    copy = os.path.join(WORK, "shaders")
    seen, bad = set(), 0
    for cfg in CONFIGS:
        rc, err = render(out, cfg + ["--verbose"])
        if rc != 0:
            print("UNBROKEN FAILS", " ".join(cfg), err.strip().splitlines()[-1:], flush=True)
            bad += 1
            continue
        for label, files, defines in re.findall(r"building (\S+): (.*?) \[(.*?)\]", err):
            if (files, defines) in seen:
                continue
            seen.add((files, defines))
            stages = files.split()
            own = [f for f in stages if not f.endswith(".vert")] or stages
            names = [d.split()[0] for d in defines.split(", ") if d]
            guard = " && ".join("defined(%s)" % n for n in names) or "1"
            shutil.rmtree(copy, ignore_errors=True)
            shutil.copytree(os.path.join(ROOT, "shaders"), copy)
            with open(os.path.join(copy, own[-1]), "a") as f:
                f.write("\n#if %s\n#error broken by the sweep\n#endif\n" % guard)
            rc, err2 = render(out, cfg, copy)
            ok = rc != 0 and not os.path.exists(out)
            bad += not ok
            print("ok " if ok else "BAD", " ".join(cfg), label, own[-1], "[%s]" % defines, "exit", rc, flush=True)
    print("%d variants broken, %d BAD" % (len(seen), bad))
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
