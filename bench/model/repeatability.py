#!/usr/bin/env python3
"""How far the same frames' power moves between two recordings of the same sequence.

Both directories hold demo_<scene>.csv recorded by tests/data/logs/record_demo_logs.py with
the same configurations, frame counts and camera path, so frame n draws the same counts in
both. Prints per scene the difference of the measured power between the two recordings:
per frame, over 30-frame averages within a configuration run, and of each run's mean. A model
whose coefficients come from frames measured minutes earlier (every reused prediction) meets
this difference as error however right it is.
Usage: repeatability.py DIR_A DIR_B [--scenes hall,sponza,valley,subway] [--average 30]
"""
import argparse
import csv
import gzip
import os
import statistics


def frame_powers(path):
    """frame -> (configuration, power) for frames with a power reading."""
    out = {}
    if not os.path.exists(path) and os.path.exists(path + ".gz"):
        path += ".gz"  # a recording kept compressed (tests/data/logs/h100/repeat)
    with (gzip.open(path, "rt") if path.endswith(".gz") else open(path)) as f:
        for row in csv.DictReader(f):
            # 0 W: no energy counted for the frame (a sensor's first moments), not a reading
            if row.get("power_w") and float(row["power_w"]) > 0:
                out[int(row["frame"])] = (row.get("configuration", ""), float(row["power_w"]))
    return out


def runs_of(frames):
    """Lists of consecutive frame numbers drawn in one configuration."""
    runs, last = [], None
    for n in sorted(frames):
        configuration = frames[n][0]
        if last is None or configuration != last[0] or n != last[1] + 1:
            runs.append([])
        runs[-1].append(n)
        last = (configuration, n)
    return runs


def relative(a, b):
    return abs(a - b) / ((a + b) / 2.0) * 100.0


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("dir_a")
    ap.add_argument("dir_b")
    ap.add_argument("--scenes", default="hall,sponza,valley,subway")
    ap.add_argument("--average", type=int, default=30)
    a = ap.parse_args()
    print("| scene | per frame | %d-frame averages | run means | frames |" % a.average)
    print("|---|---|---|---|---|")
    for scene in a.scenes.split(","):
        first = frame_powers(os.path.join(a.dir_a, "demo_%s.csv" % scene))
        second = frame_powers(os.path.join(a.dir_b, "demo_%s.csv" % scene))
        common = {n: first[n] for n in first if n in second and second[n][0] == first[n][0]}
        per_frame = [relative(first[n][1], second[n][1]) for n in common]
        averaged, run_means = [], []
        for run in runs_of(common):
            pa = [first[n][1] for n in run]
            pb = [second[n][1] for n in run]
            if len(run) < a.average:
                continue  # a frame or two cut off by a frame without a reading: no run mean
            run_means.append(relative(statistics.mean(pa), statistics.mean(pb)))
            for start in range(0, len(run) - a.average + 1):
                averaged.append(relative(statistics.mean(pa[start:start + a.average]),
                                         statistics.mean(pb[start:start + a.average])))
        print("| %s | %.2f %% | %.2f %% | %.2f %% (max %.2f %%) | %d |" % (
            scene, statistics.mean(per_frame), statistics.mean(averaged) if averaged else float("nan"),
            statistics.mean(run_means), max(run_means), len(common)))


if __name__ == "__main__":
    main()
