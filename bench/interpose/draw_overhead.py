#!/usr/bin/env python3
"""Draw-call overhead of the shim, measured in one run against a baseline in the same run.

Runs the draw-heavy probe (20,000 one-pixel draws per frame) alternately without and with
libglbudget.so preloaded, several times each, and prints median frame times, their ratio,
and the added CPU time per draw:
  - in one pass  (every draw stays in the current pass: the hot path),
  - alternating  (two programs, a pass change before every draw: query end/begin each time).
Usage: draw_overhead.py BUILD_DIR [--rounds N] [--draws N]
"""
import argparse
import os
import statistics
import subprocess
import sys


def frame_ms(cmd, env):
    out = subprocess.run(cmd, env=env, capture_output=True, text=True, check=True).stdout
    for line in out.splitlines():
        if line.startswith("frame_ms"):
            return float(line.split()[1])
    raise RuntimeError(f"no frame_ms in output of {cmd}")


def measure(build, draws, passes, run, rounds, frames):
    probe = os.path.join(build, "testapps/probes/probe_drawheavy")
    shim = os.path.join(build, "interpose/libglbudget.so")
    cmd = [probe, "--draws", str(draws), "--passes", str(passes), "--run", str(run), "--frames", str(frames)]
    base_env = {k: v for k, v in os.environ.items() if k != "LD_PRELOAD" and not k.startswith("GLBUDGET_")}
    shim_env = dict(base_env, LD_PRELOAD=shim)
    plain, with_shim = [], []
    for _ in range(rounds):  # interleaved, so drift in machine load hits both alike
        plain.append(frame_ms(cmd, base_env))
        with_shim.append(frame_ms(cmd, shim_env))
    p, s = statistics.median(plain), statistics.median(with_shim)
    return p, s


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("build")
    ap.add_argument("--rounds", type=int, default=7)
    ap.add_argument("--draws", type=int, default=20000)
    ap.add_argument("--frames", type=int, default=30)
    a = ap.parse_args()
    print(f"draw-heavy probe: {a.draws} draws/frame, {a.frames} frames, median of {a.rounds} interleaved runs")
    print(f"{'case':<34}{'plain ms':>10}{'shim ms':>10}{'ratio':>8}{'ns/draw':>10}")
    for name, passes, run in [("one pass (no pass change)", 1, a.draws),
                              ("pass change before every draw", 2, 1)]:
        p, s = measure(a.build, a.draws, passes, run, a.rounds, a.frames)
        per_draw_ns = (s - p) * 1e6 / a.draws
        print(f"{name:<34}{p:>10.3f}{s:>10.3f}{s / p:>8.4f}{per_draw_ns:>10.1f}")
    sys.stdout.flush()


if __name__ == "__main__":
    main()
