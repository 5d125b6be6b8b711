#!/usr/bin/env python3
"""The shim's cost on an app nobody here wrote: glmark2, against a baseline in the same run.

Runs glmark2's default benchmark list (glmark2-x11, under xvfb-run) in three modes, interleaved
round by round so drift in machine load hits all alike:
  plain  - without the shim,
  log    - LD_PRELOAD=libglbudget.so, GLBUDGET_LOG (per-pass queries, the log thread, cpu sensor),
  dump   - as log, plus GLBUDGET_DUMP (every shader instrumented: a measurement mode).
Prints each mode's median glmark2 score and, per benchmark, the median FPS ratio to plain:
their geometric mean and the lowest. A last row compares plain's even rounds with its odd ones:
the noise floor of the same figures, on the same machine in the same run.
Usage: glmark2_overhead.py BUILD_DIR [--rounds N] [--duration S] [--size WxH]
"""
import argparse
import math
import os
import re
import shutil
import statistics
import subprocess
import tempfile

BENCH_LINE = re.compile(r"^(\[.*?\] .*?): FPS: (\d+)")


def run_glmark2(size, duration, env):
    cmd = ["xvfb-run", "-a", "-s", "-screen 0 640x480x24",
           "glmark2", "-s", size, "-b", f":duration={duration}"]
    out = subprocess.run(cmd, env=env, capture_output=True, text=True, check=True).stdout
    fps = {}
    score = None
    for line in out.splitlines():
        if m := BENCH_LINE.match(line):
            fps[m.group(1)] = float(m.group(2))
        elif "glmark2 Score:" in line:
            score = float(line.split(":")[1])
    if score is None or not fps:
        raise RuntimeError(f"glmark2 printed no score:\n{out}")
    return score, fps


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("build")
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument("--duration", type=float, default=0.5)
    ap.add_argument("--size", default="320x240")
    a = ap.parse_args()
    if not shutil.which("glmark2"):
        raise SystemExit("glmark2_overhead: glmark2 not found (Debian package glmark2-x11)")
    shim = os.path.join(os.path.abspath(a.build), "interpose/libglbudget.so")
    base = {k: v for k, v in os.environ.items() if k != "LD_PRELOAD" and not k.startswith("GLBUDGET_")}
    work = tempfile.mkdtemp(prefix="glmark2_overhead_")
    modes = {
        "plain": base,
        "log": dict(base, LD_PRELOAD=shim, GLBUDGET_LOG=os.path.join(work, "log.csv")),
        "dump": dict(base, LD_PRELOAD=shim, GLBUDGET_LOG=os.path.join(work, "dump.csv"),
                     GLBUDGET_DUMP=os.path.join(work, "dump")),
    }
    os.makedirs(os.path.join(work, "dump"))
    scores = {m: [] for m in modes}
    fps = {m: [] for m in modes}
    for _ in range(a.rounds):
        for mode, env in modes.items():
            s, f = run_glmark2(a.size, a.duration, env)
            scores[mode].append(s)
            fps[mode].append(f)
    shutil.rmtree(work)

    print(f"glmark2 default list at {a.size}, {a.duration} s per benchmark, {a.rounds} interleaved rounds")
    print(f"{'mode':<12}{'score':>8}{'ratio':>8}{'FPS ratio, geo. mean':>22}{'lowest':>8}  lowest benchmark")
    names = list(fps["plain"][0])

    def row(label, runs, score_runs, base_runs, base_scores):
        ratios = {n: statistics.median(r[n] for r in runs) / statistics.median(r[n] for r in base_runs)
                  for n in names}
        geo = math.exp(statistics.fmean(math.log(r) for r in ratios.values()))
        low = min(ratios, key=ratios.get)
        score = statistics.median(score_runs)
        ratio = score / statistics.median(base_scores)
        print(f"{label:<12}{score:>8.0f}{ratio:>8.3f}{geo:>22.3f}{ratios[low]:>8.3f}  {low}")

    for mode in modes:
        row(mode, fps[mode], scores[mode], fps["plain"], scores["plain"])
    if a.rounds >= 2:
        row("plain/plain", fps["plain"][0::2], scores["plain"][0::2], fps["plain"][1::2], scores["plain"][1::2])


if __name__ == "__main__":
    main()
