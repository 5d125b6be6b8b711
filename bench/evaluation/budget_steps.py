#!/usr/bin/env python3
"""How steady the governor's budget is late in a run: the largest change of its budget between
two consecutive selections after a frame (default 350, when a 600-frame run's first frames, the
only ones drawn at the best, have left the model's 300-frame history), per scene and budget.
Under a share of the range the budget moves with the range's ends; a scene's own change moves
them little over a few seconds, so a large step is mostly the model's.

    python3 bench/evaluation/budget_steps.py DIR... [--after 350]

DIR is an evaluation's output whose logs were kept (`scripts/evaluate --keep-logs DIR/logs`):
DIR/logs/SCENE_pNN.csv.selections.csv."""
import argparse
import csv
import os

SCENES = ("hall", "sponza", "valley", "subway")
BUDGETS = (40, 50, 60)


def budgets_at_selections(path):
    budgets = {}
    with open(path, newline="") as f:
        for row in csv.DictReader(f):
            budgets[int(row["frame"])] = float(row["budget_w"])
    return budgets


def largest_step(budgets, after):
    frames = sorted(budgets)
    steps = [abs(budgets[b] - budgets[a]) for a, b in zip(frames, frames[1:]) if b > after]
    return max(steps) if steps else None


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("dirs", nargs="+")
    parser.add_argument("--after", type=int, default=350)
    args = parser.parse_args()
    columns = [f"{scene} {budget} %" for scene in SCENES for budget in BUDGETS]
    print("| run | " + " | ".join(columns) + " | mean | largest |")
    print("|---|" + "---:|" * (len(columns) + 2))
    for d in args.dirs:
        cells, found = [], []
        for scene in SCENES:
            for budget in BUDGETS:
                path = os.path.join(d, "logs", f"{scene}_p{budget}.csv.selections.csv")
                step = largest_step(budgets_at_selections(path), args.after) if os.path.exists(path) else None
                cells.append("" if step is None else f"{step:.1f}")
                if step is not None:
                    found.append(step)
        mean = f"{sum(found) / len(found):.2f}" if found else ""
        largest = f"{max(found):.1f}" if found else ""
        print(f"| {d} | " + " | ".join(cells) + f" | {mean} | {largest} |")


if __name__ == "__main__":
    main()
