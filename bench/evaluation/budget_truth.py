#!/usr/bin/env python3
"""How close the governor's budget is to the one the true range gives: at each selection, the
budget it logged against the share of the range from the cheapest configuration's power to the
best's, each measured in its own run of the evaluation (frames 100-600, energy over time),
per scene and budget; the mean absolute difference over selections up to a frame (default 350,
when a 600-frame run's first frames, the only ones drawn at the best, leave the model's 300-frame
history) and after it, and each run's largest difference after it.

    python3 bench/evaluation/budget_truth.py DIR... [--after 350]

DIR is an evaluation's output whose logs were kept (`scripts/evaluate --keep-logs DIR/logs`):
DIR/logs/SCENE_pNN.csv.selections.csv, SCENE_best.csv and SCENE_cheapest.csv. The true range is
a whole run's mean, so a scene whose load moves along its path moves the truth too; the figure
is for comparing evaluations of the same scenes."""
import argparse
import os
import statistics

from budget_steps import BUDGETS, SCENES, budgets_at_selections
from evaluate import energy_mean, frames_of, spans_of


def mean_power(path, first=100, last=600):
    """A reference run's mean power over frames first..last, as the evaluation takes it: energy
    over time."""
    frames = frames_of(path)
    return energy_mean(spans_of(frames, [f for f in frames if first <= f <= last]))


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("dirs", nargs="+")
    parser.add_argument("--after", type=int, default=350)
    args = parser.parse_args()
    for d in args.dirs:
        logs = os.path.join(d, "logs")
        early, late, worst = [], [], []
        for scene in SCENES:
            best_log, cheapest_log = (os.path.join(logs, f"{scene}_{end}.csv") for end in ("best", "cheapest"))
            if not (os.path.exists(best_log) and os.path.exists(cheapest_log)):
                continue
            best, cheapest = mean_power(best_log), mean_power(cheapest_log)
            for budget in BUDGETS:
                path = os.path.join(logs, f"{scene}_p{budget}.csv.selections.csv")
                if not os.path.exists(path):
                    continue
                share = budget / 100
                true_w = (1 - share) * cheapest + share * best
                budgets = budgets_at_selections(path)
                before = [b - true_w for f, b in budgets.items() if f <= args.after]
                after = [b - true_w for f, b in budgets.items() if f > args.after]
                early += [abs(e) for e in before]
                late += [abs(e) for e in after]
                largest = max(after, key=abs) if after else float("nan")
                worst.append(f"{scene} {budget} %: {largest:+.1f}")
        if not early and not late:
            print(f"{d}: no selections with the best's and the cheapest's runs beside them")
            continue
        mean = lambda xs: f"{statistics.mean(xs):.2f}" if xs else "-"
        print(f"{d}: |budget - true| mean up to frame {args.after} {mean(early)} W, after it {mean(late)} W; "
              f"largest after it: {', '.join(worst)}")


if __name__ == "__main__":
    main()
