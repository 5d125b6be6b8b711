#!/usr/bin/env python3
"""Replays every recorded demo log (tests/data/logs/demo_<scene>.csv) through
`glbudget replay`: with the fit over several configurations, with it and the platform costs
calibrated by `glbudget costs` on the *other* three scenes' logs (never the replayed one), and
with the paper's path only (--paper); prints one markdown table of the MAPE figures the README
shows.
Usage: replay_summary.py BUILD_DIR [LOG_DIR] [extra `glbudget replay` flags...]
"""
import glob
import os
import subprocess
import sys
import tempfile

SCENES = ["hall", "sponza", "valley", "subway"]
ROWS = [("ours", "all", "30-frame"), ("vatjus-anttila", "all", "30-frame"), ("ours", "fitted", "per frame"), ("ours", "reused", "per frame"), ("ours", "reused", "30-frame"),
        ("ours", "switch", "next run"), ("vatjus-anttila", "reused", "per frame"),
        ("vatjus-anttila", "switch", "next run"), ("no change", "switch", "next run"),
        ("noise floor", "all", "per frame"),
        ("noise floor", "all", "30-frame")]


def recording_profile(logs):
    """The recording's profile: record_demo_logs.py writes one, demo_<sensor>.profile.json."""
    found = sorted(glob.glob(os.path.join(logs, "demo_*.profile.json")))
    if len(found) != 1:
        sys.exit("%s: expected one demo_<sensor>.profile.json, found %d" % (logs, len(found)))
    return found[0]


def sensor_of(logs):
    """The sensor the recording's profile is named after (cpu, rapl, nvml, ...)."""
    return os.path.basename(recording_profile(logs))[len("demo_"):-len(".profile.json")]


def recorded_scenes(logs):
    """The scenes the directory has a log of, in the README's order."""
    return [scene for scene in SCENES if os.path.exists(os.path.join(logs, "demo_%s.csv" % scene))]


def calibrate_without(build, logs, scene, out_profile):
    """The profile with costs fitted on every other recorded scene's log; False when there is
    no other scene to calibrate on."""
    others = [other for other in recorded_scenes(logs) if other != scene]
    if not others:
        return False
    args = [os.path.join(build, "cli/glbudget"), "costs", "--profile", recording_profile(logs),
            "--output", out_profile]
    for other in others:
        base = os.path.join(logs, "demo_" + other)
        args += ["--log", base + ".csv", "--variants", base + ".variants.json"]
    subprocess.run(args, check=True, capture_output=True)
    return True


def replay(build, logs, scene, extra, profile=None):
    glbudget = os.path.join(build, "cli/glbudget")
    base = os.path.join(logs, "demo_" + scene)
    profile = profile or recording_profile(logs)
    out = subprocess.run([glbudget, "replay", base + ".csv", "--profile", profile,
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
    calibrated = tempfile.mkdtemp()
    for scene in recorded_scenes(logs):
        profile = os.path.join(calibrated, scene + ".profile.json")
        fits = [("several configurations, no costs", [], None), ("paper (one window)", ["--paper"], None)]
        if calibrate_without(build, logs, scene, profile):
            fits.insert(0, ("several configurations, costs of the other scenes", [], profile))
        for label, flags, costs in fits:
            figures = replay(build, logs, scene, extra + flags, costs)
            cells = ["%.2f %%" % figures[row][1] if row in figures and figures[row][0] > 0 else "–" for row in ROWS]
            print("| %s | %s | %s |" % (scene.capitalize(), label, " | ".join(cells)))


if __name__ == "__main__":
    main()
