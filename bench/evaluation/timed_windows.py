#!/usr/bin/env python3
"""The governed runs' windows kept, counted as a power meter counts them and as evaluations before
2026-11-30 counted them, from kept logs.

Before 2026-11-30 scripts/evaluate counted a window as `--fps` consecutive frames and its power as
the plain mean of those frames' powers. A frame that overruns its slot at the app's pace (a probe
frame: 140-250 ms at 10 fps on the demo's Hall) counted there as one frame of ten though it lasts
two or three slots, and the frame after it, shortened while the pacing catches up, counted as a
whole one. A meter reads energy over time, as scripts/evaluate now does (evaluate.timed_windows):
each run after its first selection's transition in windows of `--window` seconds of the log's own
time, each window's energy (each frame's power times the part of its interval inside the window)
over its length, against the governor's budget in force over the same time. Both counts are
printed per scene and budget.

Usage: timed_windows.py LOGS_DIR [LOGS_DIR ...] [--fps 10] [--window 1.0] [--budgets 40,50,60]
LOGS_DIR: what `scripts/evaluate --keep-logs DIR` kept (SCENE_pBUDGET.csv).
"""
import argparse
import os

from evaluate import frames_of, settled_start, timed_windows, window_power_and_budget, windows_of

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
    """evaluate.py's count (since 2026-11-30): windows of `window_s` seconds of the log's time."""
    windows = timed_windows(frames, start, window_s)
    return sum(p <= b for _, p, b in windows) / len(windows) if windows else float("nan")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("logs", nargs="+")
    ap.add_argument("--fps", type=float, default=10.0)
    ap.add_argument("--window", type=float, default=1.0)
    ap.add_argument("--budgets", default="40,50,60")
    a = ap.parse_args()
    print("| logs | scene | windows kept, frames (before 2026-11-30) | windows kept, time (a meter, evaluate.py) |")
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
