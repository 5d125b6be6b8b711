#!/usr/bin/env python3
"""How far the top of a share's range (the best configuration's power now, as the governor took
it at each selection) was from what the best drew at those frames, and what holding it within a
band of the best's own measurement would have made of it (GovernorSettings::best_band).

The best's power at a selection's frame is that of the evaluation's own run of the best
configuration (SCENE_best.csv, the same frames paced alike: another run, so the sensor's
run-to-run scatter is in every figure), averaged over the 60 frames about it. The best's
measurement is the governed run's frames drawn at the best before its first selection (from
frame 10). A band b holds the top within b of that measurement's distance from P_m; 0 holds it
there; `none` is the top as logged.

    python3 bench/evaluation/range_top.py DIR... [--bands 0,0.05,0.1,0.2,none]

DIR is an evaluation's output whose logs were kept (`scripts/evaluate --keep-logs DIR/logs`)."""
import argparse
import csv
import glob
import json
import math
import os
import statistics
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from evaluate import frames_of  # noqa: E402


def power_of(row):
    value = row.get("power_w")
    return float(value) if value not in (None, "") else math.nan


def selections(run):
    tops = {}
    with open(run + ".selections.csv", newline="") as f:
        for row in csv.DictReader(f):
            tops.setdefault(int(row["frame"]), float(row["range_high_w"]))
    return tops


def p_min_of(logs, scene):
    with open(os.path.join(logs, f"{scene}.variants.json")) as f:
        profile = json.load(f)["power"]["profile"]
    with open(profile) as f:
        return json.load(f)["p_min_w"]


def run_points(logs):
    """(scene, budget, measured best, logged top, the best run's power) at every selection."""
    points = []
    for run in sorted(glob.glob(os.path.join(logs, "*_p[0-9]*.csv"))):
        if run.endswith(".selections.csv") or not os.path.exists(run + ".selections.csv"):
            continue
        scene, budget = os.path.basename(run)[:-4].split("_p")
        best_run = os.path.join(logs, f"{scene}_best.csv")
        if not os.path.exists(best_run):
            continue
        frames, best_frames = frames_of(run), frames_of(best_run)
        tops = selections(run)
        first = min(tops)
        at_best = [power_of(frames[f]) for f in range(10, first)
                   if f in frames and all(level == "0" for level in frames[f]["configuration"].split(":"))]
        at_best = [w for w in at_best if math.isfinite(w)]
        if not at_best:
            continue
        measured = statistics.mean(at_best)
        p_min = p_min_of(logs, scene)
        for frame, top in sorted(tops.items()):
            truth = [power_of(best_frames[f]) for f in range(frame - 30, frame + 30) if f in best_frames]
            truth = [w for w in truth if math.isfinite(w)]
            if truth:
                points.append((scene, budget, p_min, measured, top, statistics.mean(truth)))
    return points


def banded(point, band):
    _, _, p_min, measured, top, _ = point
    if band is None:
        return top
    width = band * abs(measured - p_min)
    return min(max(top, measured - width), measured + width)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("dirs", nargs="+")
    parser.add_argument("--bands", default="0,0.05,0.1,0.2,none")
    args = parser.parse_args()
    bands = [None if b == "none" else float(b) for b in args.bands.split(",")]
    points = []
    for d in args.dirs:
        logs = os.path.join(d, "logs") if os.path.isdir(os.path.join(d, "logs")) else d
        points += run_points(logs)
    if not points:
        sys.exit("range_top.py: no governed runs with selections and a run of the best in " + " ".join(args.dirs))
    print(f"{len(points)} selections in {len(args.dirs)} evaluations; the top's distance from the best's power (W)")
    print("| band | mean | 95th percentile | largest | mean signed |")
    print("|---|---:|---:|---:|---:|")
    for band in bands:
        gaps = [banded(p, band) - p[5] for p in points]
        magnitudes = sorted(abs(g) for g in gaps)
        p95 = magnitudes[min(len(magnitudes) - 1, int(0.95 * len(magnitudes)))]
        label = "none (as logged)" if band is None else f"{band:g}"
        print(f"| {label} | {statistics.mean(magnitudes):.2f} | {p95:.2f} | {magnitudes[-1]:.2f} | "
              f"{statistics.mean(gaps):+.2f} |")


if __name__ == "__main__":
    main()
