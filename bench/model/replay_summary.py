#!/usr/bin/env python3
"""Replays every recorded demo log (tests/data/logs/demo_<scene>.csv) through
`glbudget replay`, with the fit over several configurations and with the paper's path only
(--paper), and prints one markdown table of the MAPE figures the README shows.
Usage: replay_summary.py BUILD_DIR [LOG_DIR] [extra `glbudget replay` flags...]
"""
import os
import subprocess
import sys

SCENES = ["hall", "sponza", "valley", "subway"]
ROWS = [("ours", "all", "30-frame"), ("vatjus-anttila", "all", "30-frame"), ("ours", "fitted", "per frame"), ("ours", "reused", "per frame"), ("ours", "reused", "30-frame"),
        ("ours", "switch", "next run"), ("vatjus-anttila", "reused", "per frame"),
        ("vatjus-anttila", "switch", "next run"), ("no change", "switch", "next run"),
        ("noise floor", "all", "per frame"),
        ("noise floor", "all", "30-frame")]


def replay(build, logs, scene, extra):
    glbudget = os.path.join(build, "cli/glbudget")
    base = os.path.join(logs, "demo_" + scene)
    out = subprocess.run([glbudget, "replay", base + ".csv", "--profile", os.path.join(logs, "demo_cpu.profile.json"),
                          "--variants", base + ".variants.json"] + extra,
                         check=True, capture_output=True, text=True).stdout
    figures = {}
    for line in out.splitlines():
        words = line.split()
        for model, frames, scope in ROWS:
            head = model.split() + [frames] + scope.split()
            if words[:len(head)] == head:
                figures[(model, frames, scope)] = (int(words[len(head)]), float(words[len(head) + 1]))
    return figures


def main():
    build = sys.argv[1]
    logs = sys.argv[2] if len(sys.argv) > 2 else os.path.join(os.path.dirname(__file__), "../../tests/data/logs")
    extra = sys.argv[3:]
    print("| scene | fit | " + " | ".join("%s %s (%s)" % row for row in ROWS) + " |")
    print("|---|---|" + "---:|" * len(ROWS))
    for scene in SCENES:
        for label, flags in (("several configurations", []), ("paper (one window)", ["--paper"])):
            figures = replay(build, logs, scene, extra + flags)
            cells = ["%.2f %%" % figures[row][1] if row in figures and figures[row][0] > 0 else "–" for row in ROWS]
            print("| %s | %s | %s |" % (scene.capitalize(), label, " | ".join(cells)))


if __name__ == "__main__":
    main()
