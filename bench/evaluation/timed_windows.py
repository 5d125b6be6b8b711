#!/usr/bin/env python3
"""The governed runs' windows kept, counted as a power meter counts them, from kept logs.

scripts/evaluate counts a window as `--fps` consecutive frames and its power as the plain mean of
those frames' powers. A frame that overruns its slot at the app's pace (a probe frame: 140-250 ms
at 10 fps on the demo's Hall) counts there as one frame of ten though it lasts two or three
slots, and the frame after it, shortened while the pacing catches up, counts as a whole one. A
meter reads energy over time: this script splits each run after its first selection's transition
into windows of `--window` seconds of the log's own time and takes each window's energy (each
frame's power times the part of its interval inside the window) over its length, against the
governor's budget in force (the mean of its frames' `budget_w`). Both counts are printed per
scene and budget.

Usage: timed_windows.py LOGS_DIR [LOGS_DIR ...] [--fps 10] [--window 1.0] [--budgets 40,50,60]
LOGS_DIR: what `scripts/evaluate --keep-logs DIR` kept (SCENE_pBUDGET.csv).
"""
import argparse
import os
import statistics

from evaluate import frames_of, number, settled_start, window_power_and_budget, windows_of

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
    """Windows of `window_s` seconds of the log's time from the end of frame start - 1: each
    frame's power spread over its own interval (from the previous frame's end to its own)."""
    spans = []  # (begin_s, end_s, power_w, budget_w)
    for f in sorted(frames):
        if f < start or f - 1 not in frames:
            continue
        begin, end = int(frames[f - 1]["time_ns"]) * 1e-9, int(frames[f]["time_ns"]) * 1e-9
        p, b = number(frames[f]["power_w"]), number(frames[f]["budget_w"])
        if end > begin and p is not None and b is not None:
            spans.append((begin, end, p, b))
    if not spans:
        return float("nan")
    kept = total = 0
    t = spans[0][0]
    while t + window_s <= spans[-1][1]:
        energy = length = 0.0
        budgets = []
        for begin, end, p, b in spans:
            overlap = min(end, t + window_s) - max(begin, t)
            if overlap > 0:
                energy += p * overlap
                length += overlap
                budgets.append(b)
        if length > 0:
            total += 1
            kept += energy / length <= statistics.mean(budgets)
        t += window_s
    return kept / total if total else float("nan")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("logs", nargs="+")
    ap.add_argument("--fps", type=float, default=10.0)
    ap.add_argument("--window", type=float, default=1.0)
    ap.add_argument("--budgets", default="40,50,60")
    a = ap.parse_args()
    print("| logs | scene | windows kept, frames (evaluate.py) | windows kept, time (a meter) |")
    print("|---|---|---|---|")
    for logs in a.logs:
        for scene in SCENES:
            by_frames, by_time = [], []
            for budget in a.budgets.split(","):
                path = os.path.join(logs, f"{scene}_p{budget}.csv")
                if not os.path.exists(path):
                    continue
                frames = frames_of(path)
                start = settled_start(frames, a.fps, max(frames))
                by_frames.append(frame_counted(frames, start, a.fps))
                by_time.append(time_counted(frames, start, a.window))
            if by_frames:
                print(f"| {logs} | {scene} | {' / '.join(f'{x:.2f}' for x in by_frames)} | "
                      f"{' / '.join(f'{x:.2f}' for x in by_time)} |")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
