#!/usr/bin/python3
"""Plots a replay of a recorded demo log like the paper's Figure 3: measured power per frame,
our model's prediction and the Vatjus-Anttila baseline's, with the configuration runs marked.
Our model runs with the platform costs calibrated on the other three scenes' logs, as in the
README's first rows (replay_summary.py); --no-costs plots it without them.
Usage: plot_replay.py BUILD_DIR SCENE OUT.png [LOG_DIR] [--no-costs]   (needs python3-matplotlib)
"""
import csv
import os
import subprocess
import sys
import tempfile

import matplotlib

from replay_summary import calibrate_without, recording_profile, sensor_of

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main():
    args = [a for a in sys.argv[1:] if a != "--no-costs"]
    costs = "--no-costs" not in sys.argv
    build, scene, out = args[:3]
    logs = args[3] if len(args) > 3 else os.path.join(os.path.dirname(__file__), "../../tests/data/logs")
    base = os.path.join(logs, "demo_" + scene)
    with tempfile.NamedTemporaryFile(suffix=".csv") as frames_csv, \
            tempfile.NamedTemporaryFile(suffix=".json") as calibrated:
        profile = recording_profile(logs)
        if costs and calibrate_without(build, logs, scene, calibrated.name):
            profile = calibrated.name
        subprocess.run([os.path.join(build, "cli/glbudget"), "replay", base + ".csv", "--profile", profile,
                        "--variants", base + ".variants.json", "--frames-csv", frames_csv.name],
                       check=True, capture_output=True)
        rows = list(csv.DictReader(open(frames_csv.name)))
    configurations = {}
    with open(base + ".csv") as log:
        for row in csv.DictReader(log):
            configurations.setdefault(int(row["frame"]), row.get("configuration", ""))
    frame = [int(r["frame"]) for r in rows]
    fig, ax = plt.subplots(figsize=(10, 3.6))
    ax.plot(frame, [float(r["measured_w"]) for r in rows], color="0.55", lw=1, label="measured (%s sensor)" % sensor_of(logs))
    ax.plot(frame, [float(r["ours_w"]) for r in rows], color="tab:blue", lw=1.4, label="ours")
    ax.plot(frame, [float(r["baseline_w"]) for r in rows], color="tab:orange", lw=1.2, ls="--",
            label="Vatjus-Anttila 2013")
    previous = None
    for f in sorted(configurations):
        if configurations[f] != previous:
            ax.axvline(f, color="0.85", lw=0.8, zorder=0)
            ax.text(f + 1, ax.get_ylim()[1], configurations[f], fontsize=7, va="top", color="0.4")
            previous = configurations[f]
    ax.set_xlabel("frame")
    ax.set_ylabel("power (W)")
    ax.set_title("%s: replay of the recorded log (configurations marked)%s" %
                 (scene.capitalize(), ", ours with costs calibrated on the other scenes" if costs else ""))
    ax.legend(loc="lower left", fontsize=8)
    fig.tight_layout()
    fig.savefig(out, dpi=110)


if __name__ == "__main__":
    main()
