#!/usr/bin/env python3
"""Rarer quality probes at low frame rates (GLBUDGET_PROBE_STRETCH, governor/loop/governor.hpp
probe_stretch_gain), traded on the demo: per scene, the governed run under --power P% with the
governor free to ask for rarer probes and without, interleaved over --rounds, each as
evaluate.py runs it (the levels' costs from `glbudget calibrate --app`, paced at --fps, the cpu
sensor; best and cheapest run before and after for the measured range). Per run: mean power
after the first selection, the share of 1-s windows within the governor's budget and within
the window's own measured range, the share of windows holding a probe, the true error shown
(1 - SSIM of every --every-th frame against the best configuration's) and the governor's
estimated error of what it drew.

Writes DIR/probe-stretch.md.
Usage: probe_stretch.py BUILD_DIR --out DIR [--scenes valley,hall] [--budget 50] [--frames 600]
       [--rounds 2] [--fps 10] [--size 320x180] [--detail 0.2] [--keep]
"""
import argparse
import os
import statistics
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from evaluate import (MANIFEST, PROFILE, ROOT, Evaluation, frames_of, is_probe, mean, number, settled_start,  # noqa: E402
                      shadow_note, timed_windows)


def probe_windows(log, start, fps):
    """Share of 1-s windows of the log's time from `start` (evaluate.timed_windows) that hold a
    probe frame or the frame reading it back."""
    frames = frames_of(log)
    probes = {f for f, r in frames.items() if is_probe(r)}
    windows = timed_windows(frames, start, 1.0)
    held = sum(any(f in probes or f - 1 in probes for f in window) for window, _, _ in windows)
    return held / len(windows) if windows else float("nan"), len(probes)


def estimated_error(log, start):
    rows = frames_of(log)
    return mean([number(r.get("est_error")) for f, r in rows.items() if f >= start])


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("build")
    ap.add_argument("--out", required=True)
    ap.add_argument("--scenes", default="valley,hall")
    ap.add_argument("--budget", default="50")
    ap.add_argument("--frames", type=int, default=600)
    ap.add_argument("--rounds", type=int, default=2)
    ap.add_argument("--fps", type=float, default=10.0)
    ap.add_argument("--size", default="320x180")
    ap.add_argument("--detail", type=float, default=0.2)
    ap.add_argument("--every", type=int, default=10)
    ap.add_argument("--keep", action="store_true", help="keep the logs and images under --out/runs")
    ap.add_argument("--knob", default="GLBUDGET_PROBE_STRETCH",
                    help="the variable traded (e.g. GLBUDGET_PROBE_MAX_AGE_S); its two --values interleaved")
    ap.add_argument("--values", default="1,0", help="the knob's two values, the default's first")
    a = ap.parse_args()
    values = tuple(a.values.split(","))
    a.build = os.path.abspath(a.build)
    a.costs, a.feedback, a.select_frames, a.calibrate_frames, a.budgets = "measure", "1", 60, 20, a.budget
    os.makedirs(a.out, exist_ok=True)
    command = "python3 bench/evaluation/probe_stretch.py " + " ".join(
        os.path.relpath(x, ROOT) if os.path.isabs(x) and x.startswith(ROOT) else x for x in sys.argv[1:])
    rows = []
    kept = os.path.join(os.path.abspath(a.out), "runs")
    if a.keep:
        os.makedirs(kept, exist_ok=True)
    with tempfile.TemporaryDirectory() as scratch:
        tmp = kept if a.keep else scratch
        ev = Evaluation(a, tmp)
        for scene in a.scenes.split(","):
            ev.governed_env["GLBUDGET_COSTS"] = ev.level_costs(scene)
            truth = os.path.join(tmp, f"{scene}_truth")
            ev.quiet(ev.common(scene) + ["--dump", truth, "--dump-every", str(a.every)])
            references = {"best": [], "cheapest": []}
            force = {"best": "0,0,0,0,0,0", "cheapest": "2,2,2,2,2,2"}

            def measure_range(tag):
                for which in ("best", "cheapest"):
                    references[which].append(
                        frames_of(ev.run(scene, f"{which}_{tag}", ["--force", force[which], "--config", MANIFEST])))

            measure_range("before")
            runs = []
            for r in range(a.rounds):
                for stretch in values if r % 2 == 0 else values[::-1]:
                    ev.governed_env[a.knob] = stretch
                    shown = os.path.join(tmp, f"{scene}_{stretch}_{r}_shown")
                    log = ev.run(scene, f"s{stretch}_{r}", ["--power", f"{a.budget}%", "--profile", PROFILE,
                                                           "--config", MANIFEST], governed=True, dump=shown)
                    runs.append((stretch, r, log, shown))
            measure_range("after")
            tail = lambda frames: [number(x["power_w"]) for f, x in frames.items() if f > a.frames // 2]
            result = {"references": references,
                      "best_w": mean([mean(tail(f)) for f in references["best"]]),
                      "cheapest_w": mean([mean(tail(f)) for f in references["cheapest"]])}
            for stretch, r, log, shown in runs:
                g = ev.governed(scene, a.budget, log, truth, shown, result)
                frames = frames_of(log)
                start = settled_start(frames, a.fps, a.frames)
                held, probes = probe_windows(log, start, a.fps)
                rows.append({"scene": scene, "stretch": stretch, "round": r, "power_w": g["power_w"],
                             "saved": 1 - g["power_w"] / result["best_w"], "within": g["within"],
                             "within_window": g["within_window"], "probe_windows": held, "probes": probes,
                             "error": g["error"], "est_error": estimated_error(log, start)})
                print(f"{scene} stretch {stretch} round {r}: {g['power_w']:.1f} W, windows {g['within']:.2f} / "
                      f"{g['within_window']:.2f}, probe windows {held:.2f} ({probes} probes), true error "
                      f"{g['error']:.4f}, estimated {rows[-1]['est_error']:.4f}", flush=True)
    lines = ["# Rarer probes at low frame rates", "", "```sh", command, "```", "",
             f"The demo at {a.size}, detail {a.detail}{shadow_note(a)}, {a.frames} frames paced at {a.fps:g} fps under "
             f"`--power {a.budget}%`, cpu sensor, level costs from `glbudget calibrate --app`, selections every "
             f"{a.select_frames} frames; " + (
                 "`GLBUDGET_PROBE_STRETCH=1` (the default: the governor may ask for rarer probes) against `0` (probes "
                 "every 60 frames once settled)" if a.knob == "GLBUDGET_PROBE_STRETCH" else
                 f"`{a.knob}` at " + " against ".join(values)) + ", interleaved. Windows: 1-s windows after the "
             "first selection within the governor's budget / within the window's own measured range. Probe windows: "
             "windows holding a probe frame or the frame that reads it back.", "",
             f"| scene | {a.knob} | round | mean W | saved | windows | probe windows (probes) | true error | estimated error |",
             "|---|---|---:|---:|---:|---|---|---:|---:|"]
    for x in rows:
        lines.append(f"| {x['scene']} | {x['stretch']} | {x['round']} | {x['power_w']:.1f} | {x['saved']:.0%} | "
                     f"{x['within']:.2f} / {x['within_window']:.2f} | {x['probe_windows']:.2f} ({x['probes']}) | "
                     f"{x['error']:.4f} | {x['est_error']:.4f} |")
    lines += ["", "Means over the rounds:", "", f"| scene | {a.knob} | mean W | windows | probe windows | true error |",
              "|---|---|---:|---|---:|---:|"]
    for scene in a.scenes.split(","):
        for stretch in values:
            sel = [x for x in rows if x["scene"] == scene and x["stretch"] == stretch]
            if not sel:
                continue
            m = lambda k: statistics.fmean(x[k] for x in sel)
            lines.append(f"| {scene} | {stretch} | {m('power_w'):.1f} | {m('within'):.2f} / {m('within_window'):.2f} | "
                         f"{m('probe_windows'):.2f} | {m('error'):.4f} |")
    with open(os.path.join(a.out, "probe-stretch.md"), "w") as f:
        f.write("\n".join(lines) + "\n")
    print(f"written {os.path.join(a.out, 'probe-stretch.md')}")


if __name__ == "__main__":
    main()
