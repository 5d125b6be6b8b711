#!/usr/bin/env python3
"""What the governor's first selection counted on, against what it drew, in governed runs.

Under a power budget the first selection is made on a model fitted on the frames of the
configuration the app started in (its best), and on one window measured there: no window has yet
shown how far the predictions of other configurations miss. For each governed log, the first
selection's chosen configuration, its table's predictions (the log's .selections.csv: every
configuration's prediction as the selection weighed it, corrected, without the first-step
discount), and the mean measured power of its frames from when the transition arrived there
until the second selection (probe frames and the two after each left out, as the governor
leaves them out); the share of its predicted saving below the best that was realised; and the
1-s windows counted as scripts/evaluate counts them (from a second after the first selection)
up to the second selection, with those over the budget.

Usage: first_selections.py [--fps 10] DIR [DIR ...]
DIRs as `scripts/evaluate --keep-logs DIR` keeps them (DIR/SCENE_pNN.csv and its .selections.csv).
"""
import argparse
import glob
import os
import statistics
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from evaluate import frames_of, selection_frames, settled_start, timed_windows  # noqa: E402
from interactions import measured_after, selection_tables  # noqa: E402


def first_selection(log, fps):
    frames = frames_of(log)
    tables = selection_tables(log + ".selections.csv")
    made = sorted(frame for frame, (_, chosen, _) in tables.items() if chosen)
    selected = selection_frames(frames)
    if not made or not selected:
        return None
    frame = made[0]
    table, chosen, row = tables[frame]
    best = ":".join(["0"] * len(chosen.split(":")))
    second = selected[1] if len(selected) > 1 else max(frames) + 1
    measured = measured_after(frames, chosen, frame, second, most=None, least=1)
    # The windows scripts/evaluate counts, up to the second selection.
    before_second = {f: r for f, r in frames.items() if f < second}
    windows = over = 0
    for _, power, budget in timed_windows(before_second, settled_start(frames, fps, max(frames) + 1), 1.0):
        windows += 1
        over += power > budget
    measured = float("nan") if measured is None else measured
    best_w, chosen_w = table.get(best, float("nan")), table[chosen]
    saving = best_w - chosen_w
    return {"log": log, "frame": frame, "chosen": chosen, "best_w": best_w, "predicted_w": chosen_w,
            "measured_w": measured, "budget_w": float(row["budget_w"]), "margin_w": float(row["margin_w"]),
            "realised": (best_w - measured) / saving if saving > 0 else float("nan"),
            "windows": windows, "over": over}


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("dirs", nargs="+")
    ap.add_argument("--fps", type=float, default=10.0)
    a = ap.parse_args()
    for d in a.dirs:
        results = []
        for log in sorted(glob.glob(os.path.join(d, "*_p[0-9]*.csv"))):
            if log.endswith(".selections.csv") or not os.path.exists(log + ".selections.csv"):
                continue
            r = first_selection(log, a.fps)
            if r is None:
                print(f"{log}: no selection")
                continue
            results.append(r)
            print(f"{os.path.basename(log):16s} frame {r['frame']:4d} {r['chosen']:12s} best {r['best_w']:5.1f} W, "
                  f"predicted {r['predicted_w']:5.1f}, measured {r['measured_w']:5.1f}, budget {r['budget_w']:5.1f} "
                  f"(margin {r['margin_w']:4.1f}); saving realised {r['realised']:5.2f}; windows over before the "
                  f"second selection {r['over']} of {r['windows']}")
        if not results:
            continue
        realised = [r["realised"] for r in results if r["realised"] == r["realised"]]
        print(f"{d}: {len(results)} runs; drew over the budget {sum(r['measured_w'] > r['budget_w'] for r in results)}; "
              f"saving realised median {statistics.median(realised):.2f} (min {min(realised):.2f}); windows over "
              f"before the second selection {sum(r['over'] for r in results)} of {sum(r['windows'] for r in results)} "
              f"in {sum(r['over'] > 0 for r in results)} runs")


if __name__ == "__main__":
    main()
