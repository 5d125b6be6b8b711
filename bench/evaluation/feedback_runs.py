#!/usr/bin/env python3
"""Repeated governed runs of the demo, to weigh a change to the power feedback
(governor/loop/power_feedback.hpp) against the cpu estimate's run-to-run scatter. Per scene the
levels are calibrated once (`glbudget calibrate --app`, as evaluate.py does), then the run under
--power P% is made --rounds times. Per run, from its log alone (no reference runs, no images):

- windows: the share of 1-s windows from the first selection on whose mean measured power is
  within the mean budget the governor gave (as evaluate.py counts "within the governor's budget");
- refit step: the mean change of the corrected prediction of the configuration drawn, the 10
  frames after a refit against the 10 before, in one configuration;
- residual: the root mean square of (measured - corrected prediction) over 1-s windows of one
  configuration without a probe or a transition;
- margin: the mean margin the selections kept under the budget (the log's selections table);
- power, budget and the governor's estimated error of what it drew, means from the first
  selection on.

Run it at two commits (a `git worktree` of the older one, built) for a before and after, or
with --settings for a switch of one build (each round runs every setting in turn, interleaved).
Writes DIR/feedback-runs.md.
Usage: feedback_runs.py BUILD_DIR --out DIR [--runs sponza:50,hall:40,valley:40] [--rounds 3]
       [--settings default,GLBUDGET_FEEDBACK=0] [--frames 600] [--fps 10] [--size 320x180]
       [--detail 0.2]
"""
import argparse
import csv
import math
import os
import statistics
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from evaluate import (MANIFEST, PROFILE, ROOT, Evaluation, energy_mean_from, frames_of, mean,  # noqa: E402
                      is_probe, number, selection_frames, shadow_note, timed_windows)


def first_selection(frames):
    selected = selection_frames(frames)
    return selected[0] if selected else None


def summarise(log, fps):
    frames = frames_of(log)
    first = first_selection(frames)
    if first is None:
        return None
    start = first + max(1, int(fps)) + 1  # as evaluate.py: after the first selection's transition began
    within = total = 0
    residuals = []
    for window, power, budget in timed_windows(frames, start, 1.0):
        rows = [frames[f] for f in window]
        total += 1
        within += power <= budget
        predicted = [number(r.get("predicted_w")) for r in rows]
        if (len({r["configuration"] for r in rows}) == 1 and None not in predicted
                and not any(is_probe(r) or r.get("decision") == "transition" for r in rows)):
            residuals.append(power - mean(predicted))
    steps = []
    numbers = sorted(frames)
    for i, f in enumerate(numbers):
        if frames[f].get("decision") != "refit" or i < 10 or i + 10 >= len(numbers):
            continue
        around = [frames[numbers[j]] for j in range(i - 10, i + 11) if j != i]
        predicted = [number(r.get("predicted_w")) for r in around]
        if len({r["configuration"] for r in around}) != 1 or None in predicted:
            continue
        steps.append(abs(mean(predicted[10:]) - mean(predicted[:10])))
    margins = []
    try:
        with open(log + ".selections.csv") as f:
            margins = [float(r["margin_w"]) for r in csv.DictReader(f) if r["selected"] == "1"]
    except (OSError, KeyError, ValueError):
        pass
    after = [frames[f] for f in frames if f >= start]
    return {"within": within / total if total else float("nan"), "windows": total,
            "step": statistics.fmean(steps) if steps else float("nan"), "refits": len(steps),
            "residual": math.sqrt(statistics.fmean(r * r for r in residuals)) if residuals else float("nan"),
            "margin": statistics.fmean(margins) if margins else float("nan"),
            "power": energy_mean_from(frames, start),
            "budget": mean([number(r.get("budget_w")) for r in after]),
            "est_error": mean([number(r.get("est_error")) for r in after])}


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("build")
    ap.add_argument("--out", required=True)
    ap.add_argument("--runs", default="sponza:50,hall:40,valley:40", help="scene:budget, comma separated")
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--settings", default="default",
                    help="comma separated: 'default' or GLBUDGET_X=V[;GLBUDGET_Y=W] for the governed runs")
    ap.add_argument("--frames", type=int, default=600)
    ap.add_argument("--fps", type=float, default=10.0)
    ap.add_argument("--size", default="320x180")
    ap.add_argument("--detail", type=float, default=0.2)
    a = ap.parse_args()
    a.build = os.path.abspath(a.build)
    a.costs, a.feedback, a.select_frames, a.calibrate_frames, a.every = "measure", "1", 60, 20, 10
    os.makedirs(a.out, exist_ok=True)
    command = "python3 bench/evaluation/feedback_runs.py " + " ".join(
        os.path.relpath(x, ROOT) if os.path.isabs(x) and x.startswith(ROOT) else x for x in sys.argv[1:])
    specs = [tuple(s.split(":")) for s in a.runs.split(",")]
    settings = a.settings.split(",")

    def setting_env(setting):
        return {} if setting == "default" else dict(kv.split("=", 1) for kv in setting.split(";"))
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        ev = Evaluation(a, tmp)
        costs = {}
        for scene, budget in specs:
            if scene not in costs:
                costs[scene] = ev.level_costs(scene)
        plain_env = dict(ev.governed_env)
        for r in range(a.rounds):
            for scene, budget in specs:
                for k, setting in enumerate(settings):
                    ev.governed_env = dict(plain_env, GLBUDGET_COSTS=costs[scene], **setting_env(setting))
                    log = ev.run(scene, f"p{budget}_{r}_{k}", ["--power", f"{budget}%", "--profile", PROFILE,
                                                               "--config", MANIFEST], governed=True)
                    s = summarise(log, a.fps)
                    if s is None:
                        print(f"{scene} {budget}% {setting} round {r}: no selection", flush=True)
                        continue
                    rows.append(dict(s, scene=scene, share=budget, round=r, setting=setting))
                    print(f"{scene} {budget}% {setting} round {r}: windows {s['within']:.2f} of {s['windows']}, "
                          f"refit step {s['step']:.2f} W ({s['refits']}), residual {s['residual']:.2f} W, margin "
                          f"{s['margin']:.2f} W, {s['power']:.1f} W against {s['budget']:.1f} W, estimated error "
                          f"{s['est_error']:.4f}", flush=True)
    lines = ["# Repeated governed runs: the power feedback", "", "```sh", command, "```", "",
             f"The demo at {a.size}, detail {a.detail}{shadow_note(a)}, {a.frames} frames paced at {a.fps:g} fps, cpu sensor, level "
             f"costs from `glbudget calibrate --app` (once per scene), selections every {a.select_frames} frames. "
             "Windows: 1-s windows from the first selection on within the governor's budget. Refit step: mean change "
             "of the drawn configuration's corrected prediction across a refit (10 frames each side). Residual: RMS "
             "of measured less corrected prediction over 1-s windows of one configuration. Margin: mean kept under "
             "the budget at the selections.", "",
             "| scene | budget | setting | round | windows | refit step W | residual W | margin W | mean W | budget W "
             "| est. error |",
             "|---|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|"]
    for x in rows:
        lines.append(f"| {x['scene']} | {x['share']} % | {x['setting']} | {x['round']} | {x['within']:.2f} | "
                     f"{x['step']:.2f} | "
                     f"{x['residual']:.2f} | {x['margin']:.2f} | {x['power']:.1f} | {x['budget']:.1f} | "
                     f"{x['est_error']:.4f} |")
    lines += ["", "Means over the rounds:", "",
              "| scene | budget | setting | windows (lowest) | refit step W | residual W | margin W | mean W | "
              "est. error |",
              "|---|---:|---|---:|---:|---:|---:|---:|---:|"]
    for scene, budget in specs:
        for setting in settings:
            sel = [x for x in rows if x["scene"] == scene and x["share"] == budget and x["setting"] == setting]
            if not sel:
                continue
            m = lambda k: statistics.fmean(x[k] for x in sel if not math.isnan(x[k])) if any(
                not math.isnan(x[k]) for x in sel) else float("nan")
            lines.append(f"| {scene} | {budget} % | {setting} | {m('within'):.2f} ({min(x['within'] for x in sel):.2f}) "
                         f"| {m('step'):.2f} | {m('residual'):.2f} | {m('margin'):.2f} | {m('power'):.1f} | "
                         f"{m('est_error'):.4f} |")
    with open(os.path.join(a.out, "feedback-runs.md"), "w") as f:
        f.write("\n".join(lines) + "\n")
    print(f"written {os.path.join(a.out, 'feedback-runs.md')}")


if __name__ == "__main__":
    main()
