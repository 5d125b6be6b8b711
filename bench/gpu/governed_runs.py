#!/usr/bin/env python3
"""The governed runs of bench/gpu/real_gpu.py's govern stage, counted as scripts/evaluate counts
the cpu runs: from a second after the first selection, 1-s windows of the log's time (a meter's
windows: each frame's power over its interval) against the governor's budget in force over the
same time; mean power over the same frames against the run without a budget.

Usage: governed_runs.py GOV_DIR [GOV_DIR ...] [--fps 44] [--window 1.0]
GOV_DIR: the `gov` folder of real_gpu.py's results.tar.gz (SCENE_none.csv, SCENE_40.csv, ...).
"""
import argparse
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "evaluation"))
from evaluate import (energy_mean_from, frames_of, is_probe, number, selection_frames, settled_start,  # noqa: E402
                      timed_windows)


def figures(path, none_path, fps, window_s):
    frames = frames_of(path)
    start = settled_start(frames, fps, max(frames) + 1)
    windows = timed_windows(frames, start, window_s)
    kept = sum(1 for _, p, b in windows if p <= b)
    budgets = [number(frames[f].get("budget_w")) for f in frames if f >= start]
    budgets = [b for b in budgets if b is not None]
    none = frames_of(none_path) if os.path.exists(none_path) else None
    power = energy_mean_from(frames, start)
    unbudgeted = energy_mean_from(none, start) if none else float("nan")
    over = [p - b for _, p, b in windows if p > b]
    return {"start": start, "windows": len(windows), "kept": kept, "power": power, "none": unbudgeted,
            "budget_lo": min(budgets, default=float("nan")), "budget_hi": max(budgets, default=float("nan")),
            "over_max": max(over, default=0.0), "selections": len(selection_frames(frames)),
            "probes": sum(1 for r in frames.values() if is_probe(r)),
            "last": frames[max(frames)].get("configuration")}


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("dirs", nargs="+")
    ap.add_argument("--fps", type=float, default=44)
    ap.add_argument("--window", type=float, default=1.0)
    a = ap.parse_args()
    print("| run | scene | budget | windows kept | share | mean power (W) | without a budget (W) | saved "
          "| budget over the run (W) | worst window over (W) | selections | probe frames | last configuration |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    for d in a.dirs:
        for name in sorted(os.listdir(d)):
            if not name.endswith(".csv") or name.endswith("_none.csv") or "selections" in name:
                continue
            scene, budget = name[:-4].rsplit("_", 1)
            f = figures(os.path.join(d, name), os.path.join(d, scene + "_none.csv"), a.fps, a.window)
            saved = 1 - f["power"] / f["none"] if f["none"] == f["none"] else float("nan")
            print("| %s | %s | %s %% | %d / %d | %.2f | %.1f | %.1f | %.0f %% | %.1f–%.1f | %.1f | %d | %d | %s |" % (
                d, scene, budget, f["kept"], f["windows"], f["kept"] / f["windows"] if f["windows"] else float("nan"),
                f["power"], f["none"], 100 * saved, f["budget_lo"], f["budget_hi"], f["over_max"], f["selections"],
                f["probes"], f["last"]))


if __name__ == "__main__":
    main()
