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
A second table combines the governor's single-pass errors otherwise than by their sum (a
Minkowski sum (sum e_i^p)^(1/p), p = 1.25, 1.5, 2; 1 - prod(1 - e_i), as SSIMs multiply) and gives
each form's rho and its worst selection regret at 30-70 % of the table's predicted range, the
regret as error_estimates.py takes it.
A third table, where the run's log lies beside the table (DIR/SCENE.csv and its selections),
tries one factor per render-scale level by which that level masks the other passes' errors,
estimate = e_scale + m(scale level) * sum of the others, fitted by least squares to the errors the
probes measured of the configurations shown up to the last selection (each probe frame draws the
best beside the configuration shown), shrunk toward 1 by MASK_PRIOR_PROBES probes and held in
[0.5, 1.5]. Fitted against the last selection's terms, it reads more than a running governor can:
built into the governor (round 15, reverted) the factors ranked as the sum did.

    python3 bench/evaluation/estimate_losses.py DIR/SCENE.truth.csv...
"""
import csv
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from error_estimates import regret  # noqa: E402
from evaluate import spearman  # noqa: E402


def read(path):
    truth, estimate, power = {}, {}, {}
    with open(path) as f:
        for row in csv.DictReader(f):
            levels = tuple(int(level) for level in row["configuration"].split(":"))
            truth[levels] = float(row["true_error"])
            if row["est_error"]:
                estimate[levels] = float(row["est_error"])
            if row.get("predicted_w"):
                power[levels] = float(row["predicted_w"])
    return truth, estimate, power


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


def table_name(path):
    """DIR/SCENE.truth.csv as DIR's own name and the file's: the rounds' tables side by side."""
    return os.path.join(os.path.basename(os.path.dirname(os.path.abspath(path))), os.path.basename(path))


def rho_of(table, truth):
    estimated, computed = [], []
    for levels, true_error in truth.items():
        estimated.append(sum(table[i][level] for i, level in enumerate(levels)))
        computed.append(true_error)
    return spearman(estimated, computed)


def minkowski(p):
    return lambda errors: sum(e ** p for e in errors) ** (1.0 / p)


FORMS = (("sum", minkowski(1.0)), ("Minkowski 1.25", minkowski(1.25)), ("Minkowski 1.5", minkowski(1.5)),
         ("Minkowski 2", minkowski(2.0)), ("1 - prod(1 - e)", lambda errors: 1.0 - math.prod(1.0 - e for e in errors)))
REGRET_SHARES = (0.3, 0.4, 0.5, 0.6, 0.7)


def worst_regret(estimated, truth, power):
    """The largest of error_estimates.regret over REGRET_SHARES of the predicted range; NaN where
    the table has no prediction of the best."""
    name = ":".join
    table = {name(map(str, c)): (power.get(c), estimated[c]) for c in truth}
    regrets = [regret(table, {name(map(str, c)): t for c, t in truth.items()}, share) for share in REGRET_SHARES]
    measured = [r for r in regrets if r == r]
    return max(measured) if measured else float("nan")


def forms_table(rows):
    """rows: (name, truth, single-pass table, power) per table; each form's rho and worst regret."""
    print()
    print("| table | " + " | ".join(name for name, _ in FORMS) + " |")
    print("|---|" + "---:|" * len(FORMS))
    for name, truth, table, power in rows:
        cells = []
        for _, combine in FORMS:
            estimated = {c: combine([max(0.0, table[i][level]) for i, level in enumerate(c) if level])
                         for c in truth}
            rho = spearman([estimated[c] for c in truth], list(truth.values()))
            cells.append(f"{rho:.3f} / {worst_regret(estimated, truth, power):.4f}")
        print(f"| {name} | " + " | ".join(cells) + " |")


MASK_PRIOR_PROBES = 4.0


def shown_errors(log_path, last_frame):
    """(configuration, measured error) of each probe frame's shown configuration up to last_frame."""
    by_frame = {}
    with open(log_path) as f:
        for row in csv.DictReader(f):
            if row.get("probe") and row.get("probe_error") and int(row["frame"]) <= last_frame:
                by_frame[int(row["frame"])] = (tuple(int(v) for v in row["configuration"].split(":")),
                                               float(row["probe_error"]))
    return [by_frame[frame] for frame in sorted(by_frame)]


def masking_factors(table, shown, lmax0):
    """m per render-scale level (the first pass), m(0) = 1."""
    factors = [1.0]
    for level in range(1, lmax0 + 1):
        num = den = 0.0
        count = 0
        for levels, measured in shown:
            if levels[0] != level:
                continue
            others = sum(table[i][l] for i, l in enumerate(levels) if i)
            num += (measured - table[0][level]) * others
            den += others * others
            count += 1
        fitted = min(1.5, max(0.5, num / den)) if den > 0 else 1.0
        factors.append(1.0 + (fitted - 1.0) * count / (count + MASK_PRIOR_PROBES))
    return factors


def masking_table(rows):
    """rows: (name, truth, single-pass table, power, path); the sum against the masked sum."""
    print()
    print("| table | probes of shown configurations | m per scale level | sum: rho / worst regret | masked |")
    print("|---|---:|---|---:|---:|")
    for name, truth, table, power, path in rows:
        base = path[: -len(".truth.csv")]
        log, selections = base + ".csv", base + ".csv.selections.csv"
        if not (os.path.exists(log) and os.path.exists(selections)):
            continue
        with open(selections) as f:
            last = max(int(row["frame"]) for row in csv.DictReader(f))
        shown = shown_errors(log, last)
        lmax0 = max(c[0] for c in truth)
        m = masking_factors(table, shown, lmax0)
        cells = []
        for factors in ([1.0] * (lmax0 + 1), m):
            estimated = {c: table[0][c[0]] + factors[c[0]] * sum(table[i][l] for i, l in enumerate(c) if i)
                         for c in truth}
            rho = spearman([estimated[c] for c in truth], list(truth.values()))
            cells.append(f"{rho:.3f} / {worst_regret(estimated, truth, power):.4f}")
        print(f"| {name} | {len(shown)} | " + ", ".join(f"{f:.2f}" for f in m) + " | " + " | ".join(cells) + " |")


def main():
    paths = sys.argv[1:]
    if not paths:
        print(__doc__, file=sys.stderr)
        return 2
    print("| table | governor | fresh (additive ceiling) | fresh cheapest, governor's k | governor's cheapest, fresh k |")
    print("|---|---:|---:|---:|---:|")
    forms = []
    for path in paths:
        truth, estimate, power = read(path)
        passes = len(next(iter(truth)))
        lmax = [max(levels[i] for levels in truth) for i in range(passes)]
        fresh = single_pass_table(truth, passes, lmax)
        governor = single_pass_table(estimate, passes, lmax)
        if any(v is None for row in fresh + governor for v in row):
            print(f"| {table_name(path)} | single-pass configurations missing | | | |")
            continue
        common = {c: t for c, t in truth.items() if c in estimate}
        own = spearman([estimate[c] for c in common], [common[c] for c in common])
        print(f"| {table_name(path)} | {own:.3f} | {rho_of(fresh, truth):.3f} | "
              f"{rho_of(rescaled(fresh, governor, lmax), truth):.3f} | "
              f"{rho_of(rescaled(governor, fresh, lmax), truth):.3f} |")
        forms.append((table_name(path), truth, governor, power, path))
    if forms:
        forms_table([row[:4] for row in forms])
        masking_table(forms)
    return 0


if __name__ == "__main__":
    sys.exit(main())
