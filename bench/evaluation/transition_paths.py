#!/usr/bin/env python3
"""The configurations governed runs drew on their way between two selected ones, against what the
selection that started the transition weighed them at (issue 13).

For every selection in governed logs (LOG.selections.csv, the row marked selected) whose chosen
configuration differs from the one drawn at it: the configurations drawn after it and before the
next selection other than those two ends (probe frames left out). Each is counted, and counted
again where the selection weighed it over the dearer end, and where it weighed it over the budget
less the margin it kept for the sensor's spread (margin_w - probe_margin_w). The paper's temporal
filter blends the levels of every pass at once; the ordered transition (GLBUDGET_TRANSITION_ORDER,
the default from 2026-12-03) takes the same steps cheapest first.

    python3 bench/evaluation/transition_paths.py DIR...

DIR is an evaluation's output whose logs were kept (`scripts/evaluate --keep-logs DIR/logs`).
"""
import glob
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from evaluate import frames_of, is_probe  # noqa: E402
from interactions import selection_tables  # noqa: E402


def transitions(log):
    """[(intermediates, over the dearer end, over budget - spread margin)] per transition."""
    frames = frames_of(log)
    tables = {frame: (table, row) for frame, (table, _, row) in
              selection_tables(log + ".selections.csv", "weighed_w").items() if row}
    starts = sorted(tables)
    out = []
    for k, start in enumerate(starts):
        table, row = tables[start]
        end = starts[k + 1] if k + 1 < len(starts) else max(frames) + 1
        if start not in frames:
            continue
        source, target = frames[start]["configuration"], row["configuration"]
        if source == target:
            continue
        drawn = []
        for f in range(start + 1, end):
            if f not in frames or is_probe(frames[f]):
                continue
            c = frames[f]["configuration"]
            if c == target:
                break
            if c != source and c not in drawn:
                drawn.append(c)
        if source not in table or target not in table:
            continue
        dearer_end = max(table[source], table[target])
        room = float(row["budget_w"]) - (float(row["margin_w"]) - float(row["probe_margin_w"] or 0))
        weighed = [table[c] for c in drawn if c in table]
        out.append((len(weighed), sum(w > dearer_end for w in weighed), sum(w > room for w in weighed)))
    return out


def main():
    dirs = sys.argv[1:]
    if not dirs:
        print(__doc__, file=sys.stderr)
        return 2
    print("| runs | transitions | configurations drawn between the ends | weighed over the dearer end "
          "| weighed over the budget less the spread's margin |")
    print("|---|---:|---:|---:|---:|")
    for d in dirs:
        found = []
        for log in sorted(glob.glob(os.path.join(d, "logs", "*_p[0-9]*.csv"))):
            if log.endswith(".selections.csv") or not os.path.exists(log + ".selections.csv"):
                continue
            found += transitions(log)
        between = sum(t[0] for t in found)
        print(f"| {d} | {len(found)} | {between} | {sum(t[1] for t in found)} | {sum(t[2] for t in found)} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
