#!/usr/bin/env python3
"""The 1-s windows of governed runs against the margin the governor kept for them: for every
window over its budget, the selection it ran under (the selected configuration's weighed power,
the margin beside it, the budget), its frames' mean power without the probe and the two frames
after one (which share its read-back), and what the probe added; then, per run, the excess of
every window holding one probe over its own frames without it (median, 90th percentile, largest)
beside the selections' median margin, and, where the log has it (`probe_margin_w`), the part of
the margin kept for the probes and the windows whose probe drew more than that part.

    python3 bench/evaluation/probe_windows.py DIR...

DIR is an evaluation's output whose logs were kept (`scripts/evaluate --keep-logs DIR/logs`).
Windows are the evaluation's (timed_windows: energy over each second after the first
selection)."""
import csv
import glob
import os
import statistics
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from evaluate import frames_of, is_probe, settled_start, timed_windows  # noqa: E402

PROBE_SPAN = 3  # the probe frame and the two after it (apply/governing.cpp)


def selections_of(log):
    selected = {}
    with open(log + ".selections.csv") as f:
        for row in csv.DictReader(f):
            if row["selected"] == "1":
                selected[int(row["frame"])] = row
    return selected


def windows_of(log):
    """(frames, power, budget, the selection in force, probe frames, mean power without them)."""
    frames = frames_of(log)
    selected = selections_of(log)
    start = settled_start(frames, 10, max(frames) + 1)
    for numbers, power, budget in timed_windows(frames, start, 1.0):
        at = max((f for f in selected if f <= numbers[0]), default=None)
        if at is None:
            continue
        probes = [f for f in numbers if is_probe(frames[f])]
        near = {f + k for f in probes for k in range(PROBE_SPAN)}
        base = [float(frames[f]["power_w"]) for f in numbers if f not in near and frames[f].get("power_w")]
        yield numbers, power, budget, selected[at], at, probes, statistics.mean(base) if base else float("nan")


def main():
    dirs = sys.argv[1:]
    if not dirs:
        print(__doc__, file=sys.stderr)
        return 2
    for d in dirs:
        logs = sorted(glob.glob(os.path.join(d, "logs", "*_p[0-9]*.csv")))
        logs = [log for log in logs if not log.endswith(".selections.csv")]
        print(f"## {d}\n\nWindows over the budget:\n")
        print("| run | frames | over (W) | selection | weighed (W) | margin (W) | budget (W) | mean without probes (W) "
              "| its distance from weighed (W) | probes | window − mean without (W) |")
        print("|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
        per_run = []
        for log in logs:
            run = os.path.basename(log)[:-4]
            excess, margins, probe_margins, beyond = [], [], [], 0
            for numbers, power, budget, sel, at, probes, base in windows_of(log):
                weighed, margin = float(sel["weighed_w"]), float(sel["margin_w"])
                probe_margin = float(sel["probe_margin_w"]) if sel.get("probe_margin_w") else float("nan")
                if len(probes) == 1 and base == base:
                    excess.append(power - base)
                    margins.append(margin)
                    probe_margins.append(probe_margin)
                    beyond += power - base > probe_margin
                if power > budget:
                    print(f"| {run} | {numbers[0]}–{numbers[-1]} | {power - budget:.2f} | {at} | {weighed:.2f} | "
                          f"{margin:.2f} | {budget:.2f} | {base:.2f} | {base - weighed:+.2f} | {len(probes)} | "
                          f"{power - base:.2f} |")
            if excess:
                excess.sort()
                per_run.append((run, len(excess), statistics.median(excess), excess[int(0.9 * len(excess))],
                                excess[-1], statistics.median(margins), statistics.median(probe_margins), beyond))
        print("\nWindows holding one probe:\n")
        print("| run | windows | excess over the window's own frames: median / 90th percentile / largest (W) "
              "| selections' margin, median (W) | of it for the probes, median (W) | windows whose excess was over it |")
        print("|---|---:|---|---:|---:|---:|")
        for run, n, median, p90, largest, margin, probe_margin, beyond in per_run:
            known = probe_margin == probe_margin
            print(f"| {run} | {n} | {median:.2f} / {p90:.2f} / {largest:.2f} | {margin:.2f} | "
                  f"{f'{probe_margin:.2f}' if known else '–'} | {beyond if known else '–'} |")
        print()
    return 0


if __name__ == "__main__":
    sys.exit(main())
