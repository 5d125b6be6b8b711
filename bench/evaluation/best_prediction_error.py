#!/usr/bin/env python3
"""The best configuration's corrected prediction at the governor's selections against its own
reference runs over the same frames: RMS error before and after a frame (default 350, when a
600-frame run's first frames have left the model's 300-frame history), per scene.

    python3 bench/evaluation/best_prediction_error.py DIR... [--split 350]

DIR is an evaluation's output whose logs were kept (`scripts/evaluate --keep-logs DIR/logs`):
DIR/logs/SCENE_pNN.csv.selections.csv and DIR/logs/SCENE_best.csv, SCENE_best_after.csv. The
reference is the mean of the two best runs' frames within 30 frames of the selection."""
import argparse
import csv
import math
import os

SCENES = ("hall", "sponza", "valley", "subway")


def frame_power(path):
    power = {}
    with open(path, newline="") as f:
        for row in csv.DictReader(f):
            frame = int(row["frame"])
            if frame not in power and row["power_w"]:
                power[frame] = float(row["power_w"])
    return power


def rms(errors):
    return math.sqrt(sum(e * e for e in errors) / len(errors)) if errors else float("nan")


def scene_errors(logs, scene, split):
    before_run = frame_power(os.path.join(logs, f"{scene}_best.csv"))
    after_run = frame_power(os.path.join(logs, f"{scene}_best_after.csv"))
    early, late = [], []
    for budget in (40, 50, 60):
        path = os.path.join(logs, f"{scene}_p{budget}.csv.selections.csv")
        if not os.path.exists(path):
            continue
        with open(path, newline="") as f:
            for row in csv.DictReader(f):
                if set(row["configuration"].split(":")) != {"0"}:
                    continue
                frame = int(row["frame"])
                near = [(before_run[k] + after_run[k]) / 2 for k in range(frame - 30, frame + 31)
                        if k in before_run and k in after_run]
                if near:
                    (early if frame <= split else late).append(float(row["predicted_w"]) - sum(near) / len(near))
    return early, late


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("dirs", nargs="+")
    parser.add_argument("--split", type=int, default=350)
    args = parser.parse_args()
    print(f"| run | scene | RMS before frame {args.split} (W) | after (W) | selections after |")
    print("|---|---|---:|---:|---:|")
    for d in args.dirs:
        logs = os.path.join(d, "logs")
        for scene in SCENES:
            if not os.path.exists(os.path.join(logs, f"{scene}_best.csv")):
                continue
            early, late = scene_errors(logs, scene, args.split)
            print(f"| {d} | {scene} | {rms(early):.1f} | {rms(late):.1f} | {len(late)} |")


if __name__ == "__main__":
    main()
