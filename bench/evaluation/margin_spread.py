#!/usr/bin/env python3
"""The part of a selection's margin kept for the sensor's scatter against how far windows really
fell from what the selection counted on.

For every 1-s window of a governed run after its first selection (the evaluation's windows), d is
the mean power of its frames without a probe and the two after one, less the weighed power of the
selection in force (what the selection counted on for its configuration), and the scatter part of
the margin is the selection's margin less its part for the probes (z times the spread the
governor measured). Per run: the spread that part stands for (its median over the windows, over
z), the standard deviation of d, and the share of windows whose d went over that part, which the
margin aims to keep at 1 - keep share; then the same over all runs, split by whether the selected
configuration had been drawn before its selection.

    python3 bench/evaluation/margin_spread.py [--keep-share 0.98] DIR...

DIR is an evaluation's output whose logs were kept (`scripts/evaluate --keep-logs DIR/logs`)."""
import argparse
import glob
import os
import statistics
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from evaluate import frames_of  # noqa: E402
from probe_windows import windows_of  # noqa: E402


def normal_quantile(p):
    return statistics.NormalDist().inv_cdf(p)


def run_rows(log):
    """(drawn before, d, scatter margin) of each window with a selection in force and frames
    without a probe."""
    first_drawn = {}
    for f, r in sorted(frames_of(log).items()):
        first_drawn.setdefault(r["configuration"], f)
    rows = []
    for numbers, power, budget, sel, at, probes, base in windows_of(log):
        if base != base:
            continue
        drawn = first_drawn.get(sel["configuration"], at) < at
        probe_margin = float(sel["probe_margin_w"]) if sel.get("probe_margin_w") else 0.0
        rows.append((drawn, base - float(sel["weighed_w"]), float(sel["margin_w"]) - probe_margin))
    return rows


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--keep-share", type=float, default=0.98)
    parser.add_argument("dirs", nargs="+")
    args = parser.parse_args()
    z = normal_quantile(args.keep_share)
    everything = []
    print("| evaluation | run | windows | spread kept for (W) | d: mean / standard deviation (W) "
          "| windows with d over the scatter margin |")
    print("|---|---|---:|---:|---|---:|")
    for d in args.dirs:
        logs = [log for log in sorted(glob.glob(os.path.join(d, "logs", "*_p[0-9]*.csv")))
                if not log.endswith(".selections.csv")]
        for log in logs:
            rows = run_rows(log)
            if len(rows) < 2:
                continue
            everything += rows
            ds = [r[1] for r in rows]
            kept = statistics.median(r[2] for r in rows) / z
            over = sum(r[1] > r[2] for r in rows) / len(rows)
            print(f"| {os.path.basename(os.path.normpath(d))} | {os.path.basename(log)[:-4]} | {len(rows)} | "
                  f"{kept:.2f} | {statistics.mean(ds):+.2f} / {statistics.pstdev(ds):.2f} | {over:.2f} |")
    print("\n| chosen configuration | windows | spread kept for, median (W) | d: mean / standard deviation (W) "
          "| windows with d over the scatter margin |")
    print("|---|---:|---:|---|---:|")
    for drawn, name in ((True, "drawn before"), (False, "new")):
        rows = [r for r in everything if r[0] == drawn]
        if len(rows) < 2:
            continue
        ds = [r[1] for r in rows]
        print(f"| {name} | {len(rows)} | {statistics.median(r[2] for r in rows) / z:.2f} | "
              f"{statistics.mean(ds):+.2f} / {statistics.pstdev(ds):.2f} | "
              f"{sum(r[1] > r[2] for r in rows) / len(rows):.3f} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
