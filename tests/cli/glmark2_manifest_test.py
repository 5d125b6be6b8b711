#!/usr/bin/env python3
"""The worked example of examples/glmark2: a manifest for a program nobody here wrote.

glmark2's Phong shading with four lights, under Xvfb:
1. each of the manifest's levels builds and draws (GLBUDGET_FORCE steps through them): glmark2
   exits 0, no `glbudget:` line about a variant, and the log names a different program per level;
2. `glbudget calibrate --app` measures the levels: per pixel, the fragment shader executes many
   instructions per fragment; per vertex, the vertex shader does the lighting and the fragment
   shader a copy; the power run lists level 0, each other level alone and the cheapest;
3. the levels draw different pictures: quality probes measure an error above zero for the pass's
   cheapest level.
Usage: glmark2_manifest_test.py GLBUDGET SHIM MANIFEST PROFILE WORK_DIR
"""
import csv
import json
import os
import shutil
import subprocess
import sys

glbudget, shim, manifest, profile, work = sys.argv[1:6]
BENCH = ["glmark2", "-s", "160x120", "-b", "shading:shading=phong:num-lights=4:duration=%s"]
failures = []


def check(condition, what):
    if not condition:
        failures.append(what)
        print("FAIL:", what, flush=True)


def env(**extra):
    e = {k: v for k, v in os.environ.items() if not k.startswith("GLBUDGET_") and k != "LD_PRELOAD"}
    e.update(extra)
    return e


def under_xvfb(args, **kw):
    return subprocess.run(["xvfb-run", "-a", "-s", "-screen 0 640x480x24"] + args, capture_output=True, text=True,
                          timeout=300, **kw)


if shutil.which("glmark2") is None or shutil.which("xvfb-run") is None:
    print("glmark2 or xvfb-run missing (scripts/packages.txt installs them)")
    sys.exit(1)
shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)

# 1. Every level builds and draws.
log = os.path.join(work, "forced.csv")
bench = BENCH[:-1] + [BENCH[-1] % "3"]
r = under_xvfb(bench, env=env(LD_PRELOAD=shim, GLBUDGET_CONFIG=manifest, GLBUDGET_FORCE="0,0;0,1;0,2",
                              GLBUDGET_FORCE_EVERY="20", GLBUDGET_LOG=log))
check(r.returncode == 0, f"glmark2 exit status {r.returncode}: {r.stderr[-500:]}")
lines = [l for l in r.stderr.splitlines() if l.startswith("glbudget:") and "power sensor" not in l]
check(not lines, f"no glbudget: line about the manifest or its variants: {lines}")
programs = {}
with open(log) as f:
    for row in csv.DictReader(f):
        programs.setdefault(row["configuration"], set()).add(row["pass"])
check(sorted(programs) == ["0:0", "0:1", "0:2"], f"the three levels drawn: {sorted(programs)}")
if len(programs) == 3:
    check(len(set(frozenset(p) for p in programs.values())) == 3, f"a program of its own per level: {programs}")

# 2. The levels' costs.
table_path = os.path.join(work, "glmark2.variants.json")
r = under_xvfb([glbudget, "calibrate", "--app", "--config", manifest, "--frames", "10", "--power-frames", "8",
                "--fps", "30", "--sensor", "cpu", "--profile", profile, "--output", table_path, "--"] +
               BENCH[:-1] + [BENCH[-1] % "300"], env=env())
print(r.stdout[-2000:], r.stderr[-1000:])
check(r.returncode == 0, f"calibrate --app exit status {r.returncode}")
if r.returncode == 0:
    table = json.load(open(table_path))
    phong = next(p for p in table["passes"] if p["name"] == "phong")["levels"]
    check(all(l.get("measured") for l in phong), f"every phong level measured: {phong}")
    check(phong[0]["ins_f"] > 50 * phong[1]["ins_f"] and phong[0]["ins_f"] > 50 * phong[2]["ins_f"],
          f"per pixel, the fragment shader does the lighting: {[l['ins_f'] for l in phong]}")
    check(phong[1]["ins_v"] > phong[2]["ins_v"] > phong[0]["ins_v"],
          f"per vertex, the vertex shader does it, the specular term the most: {[l['ins_v'] for l in phong]}")
    configurations = [c["configuration"] for c in table["power"]["configurations"]]
    check(configurations == ["0:0", "1:0", "2:0", "3:0", "0:1", "0:2", "3:2"],
          f"the power run's configurations: {configurations}")

# 3. The levels look different: a probe measures the cheapest level's error.
log = os.path.join(work, "probed.csv")
r = under_xvfb(BENCH[:-1] + [BENCH[-1] % "3"],
               env=env(LD_PRELOAD=shim, GLBUDGET_CONFIG=manifest, GLBUDGET_FORCE="0,2", GLBUDGET_PROBE_PERIOD="10",
                       GLBUDGET_LOG=log))
check(r.returncode == 0, f"probed run exit status {r.returncode}")
errors = []
with open(log) as f:
    for row in csv.DictReader(f):
        if row.get("probe_error"):
            errors.append(float(row["probe_error"]))
check(errors and min(errors) > 0.001, f"the diffuse-only level differs from glmark2's own image: {errors[:5]}")
print("probe errors of the cheapest level:", errors[:5])

print("ok" if not failures else f"{len(failures)} failure(s)")
sys.exit(1 if failures else 0)
