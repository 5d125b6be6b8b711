#!/usr/bin/env python3
"""How a combination of calibrated levels is best predicted (GLBUDGET_LEVEL_INTERACTIONS), judged
on what governed runs measured.

For each selection in each governed log: the configuration it chose, and the mean measured power
of its first frames drawn before the next selection (up to 10, at least 5; probe frames and the
two after each left out, as the governor leaves them out) against three predictions of it made
from the selection's own table (the log's .selections.csv, every configuration's corrected
prediction):
  - as run: the table's own value (the run-time model's combination where the run had
    GLBUDGET_LEVEL_INTERACTIONS=model);
  - additive: the best's prediction plus each of the configuration's levels' change alone;
  - calibrated: the additive one plus the table's interaction (its value less the additive one)
    scaled to the calibrated cheapest, within [0, 1] of it (model/additive_levels.hpp).
The calibrated cheapest is scaled to the table's best as the governor scales it
(P_m + k (cheapest - P_m), k the best's power now above P_m over the calibrated best's).
A prediction under the measured power lets the governor draw over its budget: the count of
those more than 2 W under is given beside the bias and the mean absolute error, for all chosen
configurations and for those the run had not drawn before.

Usage: interactions.py --costs SCENE.variants.json [--p-min 10] LOG.csv [LOG.csv ...]
Logs and costs as `evaluate.py --keep-logs DIR` keeps them (DIR/SCENE_pNN.csv and its
.selections.csv, DIR/SCENE.variants.json).
"""
import argparse
import csv
import json
import os
import statistics
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from evaluate import frames_of, is_probe, number  # noqa: E402

PASSES = 6
BEST = ":".join(["0"] * PASSES)


def selection_tables(path, column="predicted_w"):
    """{frame: ({configuration: its `column`}, chosen configuration, the chosen row (its budget_w,
    margin_w))}; chosen and its row None where the table marks none."""
    tables = {}
    with open(path) as f:
        for row in csv.DictReader(f):
            table, chosen = tables.setdefault(int(row["frame"]), ({}, [None]))
            table[row["configuration"]] = float(row[column])
            if row["selected"] == "1":
                chosen[0] = row
    return {frame: (table, chosen[0] and chosen[0]["configuration"], chosen[0])
            for frame, (table, chosen) in tables.items()}


def single(configuration_levels, pass_index, level):
    levels = [0] * len(configuration_levels)
    levels[pass_index] = level
    return ":".join(map(str, levels))


def summed(table, configuration):
    """The best's prediction plus each level's change alone."""
    levels = list(map(int, configuration.split(":")))
    best = table[BEST]
    return best + sum(table[single(levels, i, level)] - best for i, level in enumerate(levels) if level)


def interaction_share(interaction, wanted):
    if interaction == 0 or not all(map(lambda v: v == v and abs(v) != float("inf"), (interaction, wanted))):
        return 0.0
    return min(1.0, max(0.0, wanted / interaction))


def measured_after(frames, configuration, start, end, most=10, least=5):
    """Mean power of up to `most` frames (None: all) drawn in `configuration` in (start, end), probe
    frames and the two after each left out; None with fewer than `least`."""
    powers, last_probe = [], -10
    for frame in range(start + 1, end):
        row = frames.get(frame)
        if row is None:
            continue
        if is_probe(row):
            last_probe = frame
            continue
        if frame - last_probe <= 2 or row["configuration"] != configuration:
            continue
        power = number(row["power_w"])
        if power is not None:
            powers.append(power)
        if most and len(powers) >= most:
            break
    return statistics.mean(powers) if powers and len(powers) >= least else None


def predictions(log, calibrated_best, calibrated_cheapest, p_min):
    """(drawn before, measured, as run, additive, calibrated) per selection of the log."""
    frames, tables = frames_of(log), selection_tables(log + ".selections.csv")
    selections = sorted(tables)
    last = max(frames) + 1 if frames else 0
    seen, out = set(), []
    cheapest = ":".join(["2"] * PASSES)
    for k, frame in enumerate(selections):
        table, chosen, _ = tables[frame]
        end = selections[k + 1] if k + 1 < len(selections) else last
        if chosen and cheapest in table:
            scale = (table[BEST] - p_min) / (calibrated_best - p_min)
            low = p_min + scale * min(max(calibrated_cheapest - p_min, 0.0), calibrated_best - p_min)
            share = interaction_share(table[cheapest] - summed(table, cheapest), low - summed(table, cheapest))
            measured = measured_after(frames, chosen, frame, end)
            if measured is not None:
                additive = summed(table, chosen)
                out.append((chosen in seen, measured, table[chosen], additive,
                            additive + share * (table[chosen] - additive)))
        seen.update(frames[f]["configuration"] for f in range(frame, end) if f in frames)
    return out


def describe(rows, column):
    errors = [r[column] - r[1] for r in rows]
    return (f"bias {statistics.mean(errors):+.2f} W, mean abs. {statistics.mean(map(abs, errors)):.2f} W, "
            f"{sum(e < -2.0 for e in errors)} under by > 2 W")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("logs", nargs="+")
    ap.add_argument("--costs", required=True, help="the scene's level costs from glbudget calibrate --app")
    ap.add_argument("--p-min", type=float, default=10.0, help="the profile's P_m (the cpu sensor's: 10 W)")
    a = ap.parse_args()
    with open(a.costs) as f:
        measured = {c["configuration"]: c["power_w"] for c in json.load(f)["power"]["configurations"]}
    cheapest = ":".join(["2"] * PASSES)
    if BEST not in measured or cheapest not in measured:
        sys.exit(f"interactions.py: {a.costs} has no measured best or cheapest configuration")
    rows = []
    for log in a.logs:
        rows += predictions(log, measured[BEST], measured[cheapest], a.p_min)
    for label, subset in (("all chosen", rows), ("not drawn before", [r for r in rows if not r[0]])):
        if not subset:
            continue
        print(f"{label} ({len(subset)}):")
        for name, column in (("as run", 2), ("additive", 3), ("calibrated", 4)):
            print(f"  {name:10s} {describe(subset, column)}")


if __name__ == "__main__":
    main()
