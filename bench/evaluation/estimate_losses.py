#!/usr/bin/env python3
"""Where the governor's error estimates lose their ranking (issue 14), from the tables
error_estimates.py writes (DIR/SCENE.truth.csv: every configuration's true error at the last
selection's frame and the governor's estimate there).

The estimate of a configuration is additive over passes (paper §6.2): each pass's error at its
cheapest level, probed some frames before the selection, and the levels between it by the
ratio k measured by `glbudget calibrate --app`. Its Spearman rho against the truth is put beside
four additive estimates built from the table itself:
  - fresh: every pass's single-pass true error at every level, at that very frame (what
    additivity alone allows: the ceiling);
  - fresh cheapest, governor's k: the frame's own error of each pass at its cheapest level, the
    levels between by the governor's ratios (what the ratios k cost);
  - governor's cheapest, fresh k: the governor's (probed, so older) error at the cheapest level,
    the levels between by that frame's own ratios (what staleness costs);
  - the governor's own single-pass estimates summed (its estimate, as a check).

    python3 bench/evaluation/estimate_losses.py DIR/SCENE.truth.csv...
"""
import csv
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from evaluate import spearman  # noqa: E402


def read(path):
    truth, estimate = {}, {}
    with open(path) as f:
        for row in csv.DictReader(f):
            levels = tuple(int(level) for level in row["configuration"].split(":"))
            truth[levels] = float(row["true_error"])
            if row["est_error"]:
                estimate[levels] = float(row["est_error"])
    return truth, estimate


def single_pass_table(errors, passes, lmax):
    """[pass][level] errors of each pass alone at each level (level 0: 0); None where missing."""
    table = []
    for i in range(passes):
        row = [0.0]
        for level in range(1, lmax[i] + 1):
            alone = tuple(level if j == i else 0 for j in range(passes))
            row.append(errors.get(alone))
        table.append(row)
    return table


def rescaled(cheapest_from, ratios_from, lmax):
    """Each pass at its cheapest level from one table, the levels between by the other's ratios."""
    out = []
    for i, (a, b) in enumerate(zip(cheapest_from, ratios_from)):
        top_a, top_b = a[lmax[i]], b[lmax[i]]
        row = [0.0]
        for level in range(1, lmax[i] + 1):
            ratio = b[level] / top_b if top_b else (1.0 if level == lmax[i] else 0.0)
            row.append(top_a * ratio)
        out.append(row)
    return out


def rho_of(table, truth):
    estimated, computed = [], []
    for levels, true_error in truth.items():
        estimated.append(sum(table[i][level] for i, level in enumerate(levels)))
        computed.append(true_error)
    return spearman(estimated, computed)


def main():
    paths = sys.argv[1:]
    if not paths:
        print(__doc__, file=sys.stderr)
        return 2
    print("| table | governor | fresh (additive ceiling) | fresh cheapest, governor's k | governor's cheapest, fresh k |")
    print("|---|---:|---:|---:|---:|")
    for path in paths:
        truth, estimate = read(path)
        passes = len(next(iter(truth)))
        lmax = [max(levels[i] for levels in truth) for i in range(passes)]
        fresh = single_pass_table(truth, passes, lmax)
        governor = single_pass_table(estimate, passes, lmax)
        if any(v is None for row in fresh + governor for v in row):
            print(f"| {path} | single-pass configurations missing | | | |")
            continue
        common = {c: t for c, t in truth.items() if c in estimate}
        own = spearman([estimate[c] for c in common], [common[c] for c in common])
        print(f"| {os.path.basename(path)} | {own:.3f} | {rho_of(fresh, truth):.3f} | "
              f"{rho_of(rescaled(fresh, governor, lmax), truth):.3f} | "
              f"{rho_of(rescaled(governor, fresh, lmax), truth):.3f} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
