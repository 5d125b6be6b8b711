#!/usr/bin/env python3
"""The governed runs' windows kept, counted as a power meter counts them and as evaluations
before run M (2026-11-29) counted them, from kept logs.

Before run M scripts/evaluate counted a window as `--fps` consecutive frames and its power as
the plain mean of those frames' powers. A frame that overruns its slot at the app's pace (a probe
frame: 140-250 ms at 10 fps on the demo's Hall) counted there as one frame of ten though it lasts
two or three slots, and the frame after it, shortened while the pacing catches up, counted as a
whole one. A meter reads energy over time, as scripts/evaluate now does (evaluate.timed_windows):
each run after its first selection's transition in windows of `--window` seconds of the log's own
time, each window's energy (each frame's power times the part of its interval inside the window)
over its length, against the governor's budget in force over the same time. Both counts are
printed per scene and budget, and then each probe's excess counted a frame each and by time (what
the governor's loop::ProbeOverhead counted before run M, and counts since), and by time for
probes shown at the best configuration and elsewhere (the governor keeps those apart since run P:
a probe shown at the best draws no stream of the best).

Usage: timed_windows.py LOGS_DIR [LOGS_DIR ...] [--fps 10] [--window 1.0] [--budgets 40,50,60] [--split FRAME]
LOGS_DIR: what `scripts/evaluate --keep-logs DIR` kept (SCENE_pBUDGET.csv).
"""
import argparse
import os
import statistics

from evaluate import (frames_of, is_probe, number, settled_start, timed_windows, window_power_and_budget,
                      windows_of)

SCENES = ("hall", "sponza", "valley", "subway")


def frame_counted(frames, start, fps):
    """evaluate.py's count: windows of `fps` frames, the plain mean of their powers."""
    kept = total = 0
    for window in windows_of(frames, start, max(1, int(fps))):
        p, b = window_power_and_budget(frames, window)
        total += 1
        kept += p <= b
    return kept / total if total else float("nan")


def time_counted(frames, start, window_s):
    """evaluate.py's count (since run M, 2026-11-29): windows of `window_s` seconds of the log's time."""
    windows = timed_windows(frames, start, window_s)
    return sum(p <= b for _, p, b in windows) / len(windows) if windows else float("nan")


def probe_excess(frames):
    """Each probe's excess over the mean of the nine frames before it (none a probe's span), over
    its frame and the two after it, counted a frame each and by time (each frame's excess times
    its interval over the median interval of the frames before): their means and count, and the
    excesses by time of the probes shown at the best configuration and of those shown elsewhere."""
    by_frame, by_time, at_best, away = [], [], [], []
    probes = {f for f, r in frames.items() if is_probe(r)}
    for f in sorted(probes):
        if not all(g in frames for g in (f - 1, f, f + 1, f + 2)):
            continue
        before = [g for g in range(f - 9, f) if g - 1 in frames and g in frames
                  and not probes & {g, g - 1, g - 2} and number(frames[g]["power_w"]) is not None]
        if len(before) < 5:
            continue
        base = statistics.fmean(number(frames[g]["power_w"]) for g in before)
        slot = statistics.median(int(frames[g]["time_ns"]) - int(frames[g - 1]["time_ns"]) for g in before)
        span = [(number(frames[g]["power_w"]), int(frames[g]["time_ns"]) - int(frames[g - 1]["time_ns"]))
                for g in (f, f + 1, f + 2)]
        if slot <= 0 or any(p is None for p, _ in span):
            continue
        by_frame.append(sum(p - base for p, _ in span))
        by_time.append(sum((p - base) * interval / slot for p, interval in span))
        (at_best if shown_best(frames[f]) else away).append(by_time[-1])
    if not by_frame:
        return float("nan"), float("nan"), 0, at_best, away
    return statistics.fmean(by_frame), statistics.fmean(by_time), len(by_frame), at_best, away


def shown_best(row):
    """Whether the frame drew every pass at its best level (its probe drew no stream of the best)."""
    levels = row.get("configuration", "")
    return bool(levels) and all(level == "0" for level in levels.split(":"))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("logs", nargs="+")
    ap.add_argument("--fps", type=float, default=10.0)
    ap.add_argument("--window", type=float, default=1.0)
    ap.add_argument("--budgets", default="40,50,60")
    ap.add_argument("--split", type=int, default=None,
                    help="also count the windows over the budget (by time) that begin before and after this frame")
    a = ap.parse_args()
    budgets = a.budgets.split(",")
    # {logs: {scene: [(budget, frames, start)]}}, each log read once.
    runs = {}
    for logs in a.logs:
        for scene in SCENES:
            for budget in budgets:
                path = os.path.join(logs, f"{scene}_p{budget}.csv")
                if os.path.exists(path):
                    frames = frames_of(path)
                    runs.setdefault(logs, {}).setdefault(scene, []).append(
                        (budget, frames, settled_start(frames, a.fps, max(frames))))
    print("| logs | scene | windows kept, frames (before run M) | windows kept, time (a meter, evaluate.py) |")
    print("|---|---|---|---|")
    for logs, scenes in runs.items():
        for scene, cells in scenes.items():
            by_frames = [frame_counted(frames, start, a.fps) for _, frames, start in cells]
            by_time = [time_counted(frames, start, a.window) for _, frames, start in cells]
            print(f"| {logs} | {scene} | {' / '.join(f'{x:.2f}' for x in by_frames)} | "
                  f"{' / '.join(f'{x:.2f}' for x in by_time)} |")
    if a.split is not None:
        print()
        print(f"Windows over the budget (by time), beginning before / after frame {a.split}, all scenes and budgets:")
        print()
        for logs, scenes in runs.items():
            before = after = total = 0
            for cells in scenes.values():
                for _, frames, start in cells:
                    for window, p, b in timed_windows(frames, start, a.window):
                        total += 1
                        before += p > b and window[0] < a.split
                        after += p > b and window[0] >= a.split
            print(f"- {logs}: {before} / {after} of {total} windows")
    print()
    print("A probe's excess (its frame and the two after it over the nine frames before, W x frames), "
          "counted a frame each and by time, at each budget:")
    print()
    print("| logs | scene | probes | a frame each | by time | ratio |")
    print("|---|---|---|---|---|---|")
    # Each run's probe excesses, for both tables below.
    excess = {id(frames): probe_excess(frames) for scenes in runs.values() for cells in scenes.values()
              for _, frames, _ in cells}
    for logs, scenes in runs.items():
        for scene, runs_of_scene in scenes.items():
            cells = [excess[id(frames)][:3] for _, frames, _ in runs_of_scene]
            print(f"| {logs} | {scene} | {' / '.join(str(n) for _, _, n in cells)} | "
                  f"{' / '.join(f'{f:.1f}' for f, _, _ in cells)} | {' / '.join(f'{t:.1f}' for _, t, _ in cells)} | "
                  f"{' / '.join(f'{f / t:.2f}' if t else 'nan' for f, t, _ in cells)} |")
    print()
    print("A probe shown at the best configuration draws no stream of the best: its excess by time "
          f"(J at {a.fps:g} frames a second, the median and the number of probes) shown at the best and "
          "elsewhere, at each budget:")
    print()
    print("| logs | scene | shown at the best | shown elsewhere |")
    print("|---|---|---|---|")

    def median_j(excesses):
        return f"{statistics.median(excesses) / a.fps:.2f} ({len(excesses)})" if excesses else "– (0)"
    for logs, scenes in runs.items():
        for scene, runs_of_scene in scenes.items():
            cells = [excess[id(frames)][3:] for _, frames, _ in runs_of_scene]
            print(f"| {logs} | {scene} | {' / '.join(median_j(b) for b, _ in cells)} | "
                  f"{' / '.join(median_j(e) for _, e in cells)} |")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
