#!/usr/bin/env python3
"""What each selection's configuration drew against what the governor weighed it at, by how far it
was from the configurations the run had drawn before (issue 13).

For every selection in governed logs (LOG.selections.csv, the row marked selected), the mean power
of the first ten frames drawn at the chosen configuration after it and before the next selection
(probe frames and the two after each left out, as the governor leaves them out) less the
selection's weighed_w for it. Selections followed by fewer than eight such frames are skipped.
Grouped by whether the configuration had been drawn before in the run, else by the number of
passes in which it differs from the nearest configuration drawn before. A guard on configurations
never measured aims at the upper quantile of the new groups' spread. "Past the room" counts the
first frames that drew more over their weighed power than the selection's margin less its part
for the probes (margin_w - probe_margin_w: the spread's and the windows' overshoot, which is what
the frames without probes had to fit in).

    python3 bench/evaluation/selection_surprises.py DIR... [--list 1.0]

DIR is an evaluation's output whose logs were kept (`scripts/evaluate --keep-logs DIR/logs`);
--list W also lists every selection whose configuration drew more than W over its weighed power.
"""
import argparse
import glob
import os
import statistics
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from evaluate import frames_of, number  # noqa: E402
from interactions import measured_after, selection_tables  # noqa: E402

FIRST_FRAMES = 10
LEAST_FRAMES = 8


def distance(a, b):
    return sum(x != y for x, y in zip(a.split(":"), b.split(":")))


def surprises(log):
    """[(group, first frames' mean less weighed, whole period's mean less weighed, frame, configuration)]."""
    frames = frames_of(log)
    tables = selection_tables(log + ".selections.csv")
    chosen = sorted(frame for frame, (_, configuration, _) in tables.items() if configuration)
    out = []
    for k, frame in enumerate(chosen):
        _, configuration, row = tables[frame]
        weighed = number(row["weighed_w"])
        following = chosen[k + 1] if k + 1 < len(chosen) else max(frames) + 1
        first = measured_after(frames, configuration, frame, following, most=FIRST_FRAMES, least=LEAST_FRAMES)
        whole = measured_after(frames, configuration, frame, following, most=None, least=LEAST_FRAMES)
        if first is None or weighed is None:
            continue
        before = {r["configuration"] for f, r in frames.items() if f <= frame}
        if configuration in before:
            group = "drawn before"
        else:
            passes = min((distance(configuration, b) for b in before), default=0)
            group = f"new, {passes} pass{'es' if passes != 1 else ''} from the nearest drawn" if passes < 3 \
                else "new, 3 passes or more from the nearest drawn"
        room, for_probes = number(row["margin_w"]), number(row.get("probe_margin_w"))
        if room is not None and for_probes is not None:
            room -= for_probes
        out.append((group, first - weighed, whole - weighed, frame, configuration, room))
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("dirs", nargs="+")
    ap.add_argument("--list", type=float, default=None, metavar="W")
    a = ap.parse_args()
    rows = []
    for d in a.dirs:
        for log in sorted(glob.glob(os.path.join(d, "logs", "*_p[0-9][0-9].csv"))):
            if os.path.exists(log + ".selections.csv"):
                rows += [(os.path.basename(log),) + s for s in surprises(log)]
    if not rows:
        print("glbudget: no governed logs with selections under " + ", ".join(a.dirs), file=sys.stderr)
        return 1
    print("| chosen configuration | selections | mean (W) | standard deviation (W) | largest (W) | past the room |")
    print("|---|---:|---:|---:|---:|---:|")
    for group in sorted({r[1] for r in rows}):
        values = [r[2] for r in rows if r[1] == group]
        past = sum(1 for r in rows if r[1] == group and r[6] is not None and r[2] > r[6])
        print(f"| {group} | {len(values)} | {statistics.mean(values):+.2f} | {statistics.pstdev(values):.2f} | "
              f"{max(values):+.2f} | {past} ({past / len(values):.0%}) |")
    if a.list is not None:
        print()
        print("| run | selection | configuration | group | first frames − weighed (W) | period − weighed (W) |")
        print("|---|---:|---|---|---:|---:|")
        for log, group, first, whole, frame, configuration, _ in rows:
            if first > a.list:
                print(f"| {log} | {frame} | `{configuration}` | {group} | {first:+.2f} | {whole:+.2f} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
