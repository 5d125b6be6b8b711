#!/usr/bin/env python3
"""The dual problem (issue 13): the demo under `glbudget run --error E`, the lowest power whose
estimated error stays under E, on its four scenes.

Per scene, as the paper's evaluation runs it (evaluate.py: paced at --fps, the cpu sensor, the
levels' costs measured by `glbudget calibrate --app` first): the best configuration, then one
governed run per error budget (and per --error-feedback setting, interleaved), every --every-th
frame dumped. For each budget: the mean power
after the first selection and its transition against the best's, the true error of what was
shown (1 - SSIM of each dumped frame against the best configuration's image of the same frame,
the demo's camera path being a function of the frame number), its mean, its largest and the
share of dumped frames at or under E, and the configuration the run ended in.

Writes DIR/error-budgets.md.
Usage: error_budgets.py BUILD_DIR --out DIR [--scenes hall,sponza,valley,subway]
       [--error-budgets 0.01,0.02,0.04] [--frames 200] [--fps 10] [--size 320x180] [--detail 0.2]
       [--costs measure|off|PATH] [--every 10] [--error-feedback 1|0|0,1] [--quick]
"""
import os
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from evaluate import (MANIFEST, PROFILE, Evaluation, frames_of, mean, number, parse_study_arguments,  # noqa: E402
                      selection_frames, settled_start, shadow_note, study_arguments)


class ErrorBudgets(Evaluation):
    def scene(self, scene):
        a = self.a
        self.governed_env["GLBUDGET_COSTS"] = self.level_costs(scene)
        truth = os.path.join(self.tmp, f"{scene}_truth")
        self.quiet(self.common(scene) + ["--dump", truth, "--dump-every", str(a.every)])
        best = frames_of(self.run(scene, "best", ["--force", "0,0,0,0,0,0", "--config", MANIFEST]))
        rows = []
        for budget, feedback in [(b, f) for b in a.error_budgets for f in a.error_feedback]:
            self.governed_env["GLBUDGET_ERROR_FEEDBACK"] = feedback
            shown = os.path.join(self.tmp, f"{scene}_e{budget}_f{feedback}_shown")
            frames = frames_of(self.run(scene, f"e{budget}_f{feedback}", ["--error", budget, "--profile", PROFILE,
                                                                         "--config", MANIFEST], governed=True,
                                        dump=shown))
            selected = selection_frames(frames)
            start = settled_start(frames, a.fps, a.frames)
            settled = [f for f in frames if f >= start]
            power = mean([number(frames[f]["power_w"]) for f in settled])
            best_w = mean([number(best[f]["power_w"]) for f in settled if f in best])
            # Only frames shown after the first selection and its transition: before it the run
            # draws its best configuration, whose error is 0 by definition.
            errors = self.true_errors_after(truth, shown, start)
            rows.append({"scene": scene, "budget": float(budget), "feedback": feedback, "power_w": power,
                         "best_w": best_w,
                         "saved": 1.0 - power / best_w if best_w else float("nan"), "error": mean(errors),
                         "largest": max(errors) if errors else float("nan"),
                         "within": (sum(e <= float(budget) for e in errors) / len(errors)) if errors else float("nan"),
                         "frames": len(errors), "final": frames[max(frames)]["configuration"] if frames else "",
                         "selections": len(selected)})
            print(format_row(rows[-1]), flush=True)
        return rows

    def true_errors_after(self, truth_dir, shown_dir, start):
        """1 - SSIM of each frame shown from `start` on against the best's same frame."""
        truth = {name.rsplit("_f", 1)[1]: name for name in os.listdir(truth_dir)}
        pairs = []
        for name in sorted(os.listdir(shown_dir)):
            key = name.rsplit("_f", 1)[1]
            if int(key.split(".")[0]) >= start and key in truth:
                pairs.append((os.path.join(truth_dir, truth[key]), os.path.join(shown_dir, name)))
        errors = [self.ssim_error(reference, image) for reference, image in pairs]
        return [e for e in errors if e is not None]


def format_row(r):
    feedback = "on" if r["feedback"] == "1" else "off"
    return (f"| {r['scene']} | {r['budget']:g} | {feedback} | {r['power_w']:.1f} | {r['best_w']:.1f} | "
            f"{100 * r['saved']:.0f} % | {r['error']:.4f} | {r['largest']:.4f} | {r['within']:.2f} ({r['frames']}) | "
            f"{r['selections']} | {r['final']} |")


def write(rows, a, command):
    lines = ["# Error budgets: the lowest power under an estimated-error budget", "", "```sh", command, "```", "",
             f"Each scene at {a.size}, detail {a.detail}{shadow_note(a)}, {a.frames} frames paced at {a.fps:g} fps, the cpu sensor, "
             f"level costs {a.costs}, selections every {a.select_frames} frames, 1-s transitions, probes at the "
             "shim's default. Power and error from the first selection and its transition on; power against the "
             "best configuration's run over the same frames; true error: 1 − SSIM of every "
             f"{a.every}th frame shown against the best configuration's image of that frame; within: the share of "
             "those frames whose true error is at or under the budget (their count in brackets). Error feedback: "
             "GLBUDGET_ERROR_FEEDBACK, the estimates corrected by the errors probes measured of what was shown.",
             "", "| scene | error budget | error feedback | power (W) | best (W) | saved | true error (mean) | largest "
             "| within | selections | last configuration |",
             "|---|---:|---|---:|---:|---:|---:|---:|---:|---:|---|"]
    lines += [format_row(r) for r in rows]
    lines.append("")
    with open(os.path.join(a.out, "error-budgets.md"), "w") as f:
        f.write("\n".join(lines))


def main():
    ap = study_arguments(__doc__.splitlines()[0], "hall,sponza,valley,subway")
    ap.add_argument("--error-budgets", default="0.01,0.02,0.04")
    ap.add_argument("--every", type=int, default=10, help="dump every K-th frame for the true error")
    ap.add_argument("--error-feedback", default="1", help="GLBUDGET_ERROR_FEEDBACK of the governed runs: 1, 0, or "
                    "0,1 for both, interleaved")
    a, command = parse_study_arguments(ap, "error_budgets.py")
    a.error_budgets = ("0.02" if a.quick else a.error_budgets).split(",")
    a.error_feedback = a.error_feedback.split(",")
    if any(f not in ("0", "1") for f in a.error_feedback):
        ap.error("--error-feedback: 1, 0 or 0,1")
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        study = ErrorBudgets(a, tmp)
        for scene in a.scenes.split(","):
            rows += study.scene(scene)
    write(rows, a, command)
    print(f"error budgets: {os.path.join(a.out, 'error-budgets.md')}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
