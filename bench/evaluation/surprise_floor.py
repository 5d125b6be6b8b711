#!/usr/bin/env python3
"""What a floor under the typical surprise (GLBUDGET_SURPRISE_FLOOR, loop/power_feedback.hpp)
would have changed in governed runs made without it: at every selection, each configuration not
yet drawn in the run is weighed at least at its prediction plus z * SHARE * P less the margin the
selection kept (P the chosen configuration's prediction, z the normal quantile of the keep share),
as the governor weighs it with the floor; the configuration of lowest estimated error that then
fits under budget - margin (else the lightest) is compared with the one taken.

    python3 bench/evaluation/surprise_floor.py DIR... [--shares 0.01,0.02,0.03] [--keep-share 0.98]

DIR is an evaluation's output whose logs were kept (`scripts/evaluate --keep-logs DIR/logs`). A
configuration counts as measured once 8 frames of it without a probe precede the selection (the
governor's own test, a closed 1-s window, is not in the log). Prints, per share, the selections it
would change and the mean change of estimated error over all selections, then each change."""
import argparse
import collections
import csv
import glob
import os
import statistics
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from evaluate import frames_of, is_probe, number  # noqa: E402

MEASURED_FRAMES = 8


def selections(log):
    """{frame: [rows of LOG.selections.csv at that frame]}."""
    out = collections.defaultdict(list)
    with open(log + ".selections.csv") as f:
        for row in csv.DictReader(f):
            out[int(row["frame"])].append(row)
    return out


def with_floor(log, share, z):
    """[(frame, configuration taken, its estimated error, configuration with the floor, its error)]."""
    frames = frames_of(log)
    out = []
    for at, rows in sorted(selections(log).items()):
        taken = [r for r in rows if r["selected"] == "1"]
        if not taken:
            continue
        taken = taken[0]
        drawn = collections.Counter(r["configuration"] for f, r in frames.items() if f < at and not is_probe(r))
        measured = {c for c, n in drawn.items() if n >= MEASURED_FRAMES}
        budget, margin, chosen_w = number(taken["budget_w"]), number(taken["margin_w"]), number(taken["predicted_w"])
        if None in (budget, margin, chosen_w):
            continue
        guard = max(0.0, z * share * chosen_w - margin)
        weighed = []
        for r in rows:
            w, p, e = number(r["weighed_w"]), number(r["predicted_w"]), number(r["est_error"])
            if None in (w, p, e):
                continue
            if r["configuration"] not in measured:
                w = max(w, p + guard)
            weighed.append((w, e, r["configuration"]))
        fits = [x for x in weighed if x[0] <= budget - margin]
        pick = min(fits, key=lambda x: (x[1], x[0])) if fits else min(weighed)
        out.append((at, taken["configuration"], number(taken["est_error"]), pick[2], pick[1]))
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("dirs", nargs="+")
    ap.add_argument("--shares", default="0.01,0.02,0.03")
    ap.add_argument("--keep-share", type=float, default=0.98)
    a = ap.parse_args()
    z = statistics.NormalDist().inv_cdf(a.keep_share)
    logs = [log for d in a.dirs for log in sorted(glob.glob(os.path.join(d, "logs", "*_p[0-9][0-9].csv")))
            if os.path.exists(log + ".selections.csv")]
    if not logs:
        print("glbudget: no governed logs with selections under " + ", ".join(a.dirs), file=sys.stderr)
        return 1
    changes = []
    print("| floor (share of power) | selections | changed | mean change of estimated error a selection |")
    print("|---:|---:|---:|---:|")
    for share in (float(s) for s in a.shares.split(",")):
        rows = [(log,) + r for log in logs for r in with_floor(log, share, z)]
        changed = [r for r in rows if r[2] != r[4]]
        change = sum(r[5] - r[3] for r in changed) / len(rows) if rows else 0.0
        print(f"| {share:g} | {len(rows)} | {len(changed)} | {change:+.4f} |")
        changes += [(share,) + r for r in changed]
    if changes:
        print("\n| floor | run | selection | taken | estimated error | with the floor | estimated error |")
        print("|---:|---|---:|---|---:|---|---:|")
        for share, log, at, c, e, pc, pe in changes:
            run = os.path.basename(os.path.dirname(os.path.dirname(log))) + "/" + os.path.basename(log)
            print(f"| {share:g} | {run} | {at} | `{c}` | {e:.4f} | `{pc}` | {pe:.4f} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
