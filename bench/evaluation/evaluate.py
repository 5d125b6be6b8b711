#!/usr/bin/env python3
"""The paper's evaluation (§7) with the demo renderer on its four scenes, under the shim.

Per scene, paced at --fps with the cpu sensor (this machine's only power source, an estimate
from the process's CPU time):
  1. `glbudget calibrate --app`: the manifest levels' costs, then each level's power alone;
  2. the demo at its best (maximum quality) and its cheapest (minimum quality) configuration;
  3. the demo under `glbudget run --power P%` for each budget, with the manifest and the table.
It writes into --out:
  - evaluation.md: the tables below and the figures, with the command that made them;
  - fig13_power_error.png (the paper's Fig. 13): mean power and true error at maximum quality,
    minimum quality and each budget; true error = 1 - SSIM of every --every-th frame shown
    against the demo's own image of that frame at its best configuration;
  - fig12_power_time.png (Fig. 12): the first budget's run, measured and predicted power per
    frame against the budget, over time;
  - fig10_errors.png (Fig. 10): for --configurations configurations spread over the governor's
    estimated errors at its last selection (the middle budget's run), that estimate against the
    error computed from the demo's own image of the configuration at that selection's frame (1 - SSIM
    against its best);
    Spearman's rho and the mean absolute error per scene;
  - the power model against Vatjus-Anttila's on the recorded logs (tests/data/logs, replayed by
    bench/model/replay_summary.py).
Budgets kept are counted over 1-s windows of the log's time after the first selection and its
transition, as a power meter reads them (each frame's power over its own interval, so that a
probe frame that overruns its slot counts for every slot it fills): against the budget the
governor logged (a share of its predicted range) and against the same share of the measured
range (cheapest + P% of best - cheapest). Mean powers are energy over time likewise.

Usage: evaluate.py BUILD_DIR --out DIR [--quick] [--scenes hall,sponza,valley,subway]
       [--budgets 40,50,60] [--frames 200] [--fps 10] [--size 320x180] [--detail 0.2]
       [--feedback 1|0] [--costs measure|off|PATH] [--configurations 20] [--every 10]
--quick: Valley alone at 160x90, detail 0.05, shadow map 512, 80 frames, selections every 20 frames, 6
configurations: a check that every step runs (about two minutes), not a measurement.
"""
import argparse
import csv
import math
import os
import shutil
import statistics
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
MANIFEST = os.path.join(ROOT, "testapps/demo/glbudget.toml")
PROFILE = os.path.join(ROOT, "tests/data/logs/demo_cpu.profile.json")
KNOBS = "resolution, base, reflections, shadows, metals, antialiasing"


def shadow_note(a):
    """", shadow map N" where the demo's shadow map is not its default size."""
    size = getattr(a, "shadow_size", None)
    return f", shadow map {size}" if size else ""


def mean(values):
    values = [v for v in values if v is not None and not math.isnan(v)]
    return statistics.fmean(values) if values else float("nan")


def number(text):
    try:
        return float(text)
    except (TypeError, ValueError):
        return None


def is_probe(row):
    """A log row of a quality-probe frame (the log's probe column: 1 on probe frames, else empty)."""
    return row.get("probe") == "1"


def selection_frames(frames):
    """The frames of a governed log (frames_of) at which the governor selected, in order."""
    return sorted(f for f, r in frames.items() if r.get("decision") in ("select", "explore"))


def settled_start(frames, fps, frames_run):
    """The first frame a governed run's figures count: a second after its first selection (its
    transition done), or past the run's end where it never selected."""
    selected = selection_frames(frames)
    return (selected[0] if selected else frames_run) + int(fps) + 1


def windows_of(frames, start, size):
    """The frames from `start` in consecutive windows of `size` (a last partial one dropped)."""
    numbers = sorted(f for f in frames if f >= start)
    return [numbers[k:k + size] for k in range(0, len(numbers) - size + 1, size)]


def window_power_and_budget(frames, window):
    """A window of consecutive frames' power and the governor's budget in it, as evaluations
    before run M (2026-11-29) counted them: the plain means of its frames' `power_w` and
    `budget_w`. A probe frame that overran its slot counted as one frame; timed_windows.py
    compares this count with timed_windows'."""
    chunk = [frames[f] for f in window]
    return mean([number(r["power_w"]) for r in chunk]), mean([number(r.get("budget_w")) for r in chunk])


def spans_of(frames, numbers=None):
    """(frame, begin_s, end_s, power_w) of each frame with power whose previous frame is logged: its
    power held over its own interval, from the previous frame's end to its own."""
    spans = []
    for f in sorted(frames if numbers is None else numbers):
        if f not in frames or f - 1 not in frames:
            continue
        begin, end = int(frames[f - 1]["time_ns"]) * 1e-9, int(frames[f]["time_ns"]) * 1e-9
        p = number(frames[f]["power_w"])
        if end > begin and p is not None:
            spans.append((f, begin, end, p))
    return spans


def energy_mean(spans):
    """The mean power over the spans' time: their energy over their length (NaN when empty)."""
    length = sum(end - begin for _, begin, end, _ in spans)
    return sum(p * (end - begin) for _, begin, end, p in spans) / length if length > 0 else float("nan")


def energy_mean_from(frames, first):
    """The mean power, energy over time, of the frames from `first` on."""
    return energy_mean(spans_of(frames, [f for f in frames if f >= first]))


def timed_windows(frames, start, window_s):
    """A power meter's windows: consecutive windows of `window_s` seconds of the log's time from
    the end of frame start - 1 (a last partial one dropped). Each is (frames, power_w, budget_w):
    the frames whose intervals overlap it, its energy over its length (each frame's power over
    the part of its interval inside the window), and the governor's budget over the same time."""
    spans = [s for s in spans_of(frames) if s[0] >= start]
    windows = []
    if not spans:
        return windows
    t, first = spans[0][1], 0
    while t + window_s <= spans[-1][2]:
        while first < len(spans) and spans[first][2] <= t:
            first += 1
        energy = length = budget = budget_length = 0.0
        numbers = []
        for f, begin, end, p in spans[first:]:
            if begin >= t + window_s:
                break
            overlap = min(end, t + window_s) - max(begin, t)
            if overlap <= 0:
                continue
            numbers.append(f)
            energy += p * overlap
            length += overlap
            b = number(frames[f].get("budget_w"))
            if b is not None:
                budget += b * overlap
                budget_length += overlap
        if length > 0 and budget_length > 0:
            windows.append((numbers, energy / length, budget / budget_length))
        t += window_s
    return windows


def frames_of(path):
    """The log's rows, one per frame (the first row of each frame carries the frame's columns)."""
    frames = {}
    with open(path) as f:
        for row in csv.DictReader(f):
            frames.setdefault(int(row["frame"]), row)
    return frames


def ranks(values):
    order = sorted(range(len(values)), key=lambda i: values[i])
    out = [0.0] * len(values)
    i = 0
    while i < len(order):
        j = i
        while j + 1 < len(order) and values[order[j + 1]] == values[order[i]]:
            j += 1
        for k in range(i, j + 1):
            out[order[k]] = (i + j) / 2.0
        i = j + 1
    return out


def spearman(a, b):
    if len(a) < 3:
        return float("nan")
    ra, rb = ranks(a), ranks(b)
    ma, mb = statistics.fmean(ra), statistics.fmean(rb)
    cov = sum((x - ma) * (y - mb) for x, y in zip(ra, rb))
    va = math.sqrt(sum((x - ma) ** 2 for x in ra))
    vb = math.sqrt(sum((y - mb) ** 2 for y in rb))
    return cov / (va * vb) if va > 0 and vb > 0 else float("nan")


def study_arguments(description, scenes):
    """The arguments of a study built on the evaluation's runs (error_estimates.py,
    error_budgets.py, probe_trades.py): the build, --out, the scenes and how each run is made."""
    ap = argparse.ArgumentParser(description=description)
    ap.add_argument("build")
    ap.add_argument("--out", required=True)
    ap.add_argument("--scenes", default=scenes)
    ap.add_argument("--frames", type=int, default=200)
    ap.add_argument("--fps", type=float, default=10.0)
    ap.add_argument("--size", default="320x180")
    ap.add_argument("--detail", type=float, default=0.2)
    ap.add_argument("--shadow-size", type=int, default=None, help="the demo's shadow map at its best (default 2048)")
    ap.add_argument("--select-frames", type=int, default=60)
    ap.add_argument("--costs", default="measure", help="the levels' costs: 'measure' (glbudget calibrate --app "
                    "on each scene first), 'off', or a path")
    ap.add_argument("--calibrate-frames", type=int, default=20, help="frames per level of glbudget calibrate --app")
    ap.add_argument("--feedback", default="1", choices=["0", "1"], help="GLBUDGET_FEEDBACK of the governed runs")
    ap.add_argument("--quick", action="store_true", help="one scene, small: checks every step runs")
    ap.add_argument("--set", action="append", default=[], metavar="GLBUDGET_NAME=VALUE",
                    help="a setting of the governed runs (repeatable)")
    return ap


def parse_study_arguments(ap, script):
    """Parsed, --quick applied (Valley at 160x90, detail 0.05, 80 frames, costs off), --out made;
    also the command line that reproduces the run, for the study's page."""
    a = ap.parse_args()
    if a.quick:
        a.scenes, a.size, a.detail, a.frames, a.select_frames, a.costs = "valley", "160x90", 0.05, 80, 20, "off"
        a.shadow_size = a.shadow_size or 512
    given_build, a.build = a.build, os.path.abspath(a.build)
    os.makedirs(a.out, exist_ok=True)
    # The other arguments as given, so that the page says how to make it again.
    rest, skip, build_seen = [], False, False
    for arg in sys.argv[1:]:
        if skip:
            skip = False
        elif arg == "--out":
            skip = True
        elif arg == given_build and not build_seen:
            build_seen = True
        elif not arg.startswith("--out="):
            rest.append(arg)
    command = " ".join([f"python3 bench/evaluation/{script} build --out", os.path.relpath(a.out, ROOT)] + rest)
    return a, command


def governed_settings(a):
    """{GLBUDGET_NAME: value} the command line gives the governed runs only: --keep-share, and
    each --set NAME=VALUE."""
    settings = {}
    if getattr(a, "keep_share", None):
        settings["GLBUDGET_KEEP_SHARE"] = a.keep_share
    for item in getattr(a, "set", None) or []:
        name, sep, value = item.partition("=")
        if not sep or not name.startswith("GLBUDGET_"):
            raise SystemExit(f"evaluate.py: --set takes GLBUDGET_NAME=VALUE, not {item!r}")
        settings[name] = value
    return settings


def settings_note(a):
    """', GLBUDGET_A=x, GLBUDGET_B=y' of governed_settings."""
    return "".join(f", {k}={v}" for k, v in sorted(governed_settings(a).items()))


class Evaluation:
    def __init__(self, a, tmp):
        self.a, self.tmp = a, tmp
        self.demo = os.path.join(a.build, "testapps/demo/demo")
        self.glbudget = os.path.join(a.build, "cli/glbudget")
        self.width, self.height = a.size.split("x")
        env = {k: v for k, v in os.environ.items() if not k.startswith("GLBUDGET_") and k != "LD_PRELOAD"}
        env.update(GLBUDGET_SENSOR="cpu", GLBUDGET_SELECT_FRAMES=str(a.select_frames), GLBUDGET_TRANSITION_S="1",
                   GLBUDGET_FEEDBACK=a.feedback)
        self.env = dict(env, GLBUDGET_PROBE_PERIOD="0")  # reference runs draw no probes
        self.governed_env = dict(env, **governed_settings(a))

    def common(self, scene, frames=None):
        return [self.demo, "--scene", scene, "--detail", str(self.a.detail), "--width", self.width,
                "--height", self.height, "--frames", str(frames or self.a.frames)] + self.shadow_args()

    def shadow_args(self):
        size = getattr(self.a, "shadow_size", None)
        return ["--shadow-size", str(size)] if size else []

    def quiet(self, cmd, env=None):
        """Runs cmd to its end, its output discarded; env: the reference runs' unless given."""
        subprocess.run(cmd, env=self.env if env is None else env, check=True, stdout=subprocess.DEVNULL,
                       stderr=subprocess.DEVNULL)

    def level_costs(self, scene):
        """GLBUDGET_COSTS for the governed runs of a scene: with --costs measure, the levels'
        costs and each level's power measured by `glbudget calibrate --app` first, as a user would,
        at the pace the app will run at under a budget; else --costs as given (off, or a path)."""
        a = self.a
        if a.costs != "measure":
            return a.costs
        costs = os.path.join(self.tmp, f"{scene}.variants.json")
        self.quiet([self.glbudget, "calibrate", "--app", "--config", MANIFEST, "--frames", str(a.calibrate_frames),
                    "--power-frames", str(a.calibrate_frames), "--fps", str(a.fps), "--sensor", "cpu", "--profile",
                    PROFILE, "--output", costs, "--"] + self.common(scene, 100000))
        return costs

    def ssim_errors(self, reference, images):
        """{image: 1 - SSIM against reference} for many images, in one `glbudget ssim` process."""
        out = subprocess.run([self.glbudget, "ssim", reference] + images, capture_output=True, text=True).stdout
        errors = {}
        for line in out.splitlines():
            value, _, path = line.partition("\t")
            try:
                errors[path] = 1.0 - float(value)
            except ValueError:
                pass
        return errors

    def ssim_error(self, reference, image):
        out = subprocess.run([self.glbudget, "ssim", reference, image], capture_output=True, text=True).stdout
        try:
            return 1.0 - float(out.split()[-1])
        except (ValueError, IndexError):
            return None

    def true_errors(self, truth_dir, shown_dir):
        """1 - SSIM of each dumped frame shown against the best configuration's same frame."""
        truth = {name.rsplit("_f", 1)[1]: name for name in os.listdir(truth_dir)}
        errors = []
        for name in sorted(os.listdir(shown_dir)):
            reference = truth.get(name.rsplit("_f", 1)[1])
            if reference:
                errors.append(self.ssim_error(os.path.join(truth_dir, reference), os.path.join(shown_dir, name)))
        return [e for e in errors if e is not None]

    def run(self, scene, name, extra, governed=False, dump=None):
        log = os.path.join(self.tmp, f"{scene}_{name}.csv")
        cmd = [self.glbudget, "run", "--fps", str(self.a.fps), "--log", log] + extra + ["--"] + self.common(scene)
        if dump:
            cmd += ["--dump", dump, "--dump-every", str(self.a.every)]
        self.quiet(cmd, self.governed_env if governed else self.env)
        return log

    def scene(self, scene):
        a, result = self.a, {"scene": scene}
        self.governed_env["GLBUDGET_COSTS"] = self.level_costs(scene)
        truth = os.path.join(self.tmp, f"{scene}_truth")
        self.quiet(self.common(scene) + ["--dump", truth, "--dump-every", str(a.every)])
        tail = lambda frames: energy_mean_from(frames, a.frames // 2 + 1)
        best = frames_of(self.run(scene, "best", ["--force", "0,0,0,0,0,0", "--config", MANIFEST]))
        cheapest_shown = os.path.join(self.tmp, f"{scene}_cheapest_shown")
        cheapest = frames_of(self.run(scene, "cheapest", ["--force", "2,2,2,2,2,2", "--config", MANIFEST],
                                      dump=cheapest_shown))
        result["best_w"], result["cheapest_w"] = tail(best), tail(cheapest)
        result["cheapest_error"] = mean(self.true_errors(truth, cheapest_shown))
        logs = []
        for budget in a.budgets.split(","):
            shown = os.path.join(self.tmp, f"{scene}_{budget}_shown")
            log = self.run(scene, f"p{budget}", ["--power", f"{budget}%", "--profile", PROFILE, "--config", MANIFEST],
                           governed=True, dump=shown)
            logs.append((budget, log, shown))
        # The cpu estimate drifts by several percent over minutes on this machine: the range is
        # measured before and after the governed runs, and its mean taken.
        best_after = frames_of(self.run(scene, "best_after", ["--force", "0,0,0,0,0,0", "--config", MANIFEST]))
        cheapest_after = frames_of(self.run(scene, "cheapest_after", ["--force", "2,2,2,2,2,2", "--config", MANIFEST]))
        result["best_before_after_w"] = (result["best_w"], tail(best_after))
        result["cheapest_before_after_w"] = (result["cheapest_w"], tail(cheapest_after))
        # The demo's camera path is a function of the frame number: frame f of every run shows
        # the same view, so each window's range can be measured on the same frames.
        result["references"] = {"best": (best, best_after), "cheapest": (cheapest, cheapest_after)}
        result["best_w"] = mean(list(result["best_before_after_w"]))
        result["cheapest_w"] = mean(list(result["cheapest_before_after_w"]))
        result["budgets"] = [self.governed(scene, budget, log, truth, shown, result) for budget, log, shown in logs]
        return result

    def governed(self, scene, budget, log, truth, shown, result):
        a, frames = self.a, frames_of(log)
        selected = selection_frames(frames)
        start = settled_start(frames, a.fps, a.frames)
        true_budget = result["cheapest_w"] + float(budget) / 100.0 * (result["best_w"] - result["cheapest_w"])
        windows = within = within_true = within_window = 0
        window_budgets = []  # (first frame, last frame, the window's measured range's budget)
        share = float(budget) / 100.0

        def reference_w(which, window):
            return mean([energy_mean(spans_of(run, window)) for run in result["references"][which]])

        for window, p, b in timed_windows(frames, start, 1.0):
            low, high = reference_w("cheapest", window), reference_w("best", window)
            windows += 1
            within += p <= b
            within_true += p <= true_budget
            within_window += p <= low + share * (high - low)
            window_budgets.append((window[0], window[-1], low + share * (high - low)))
        errors = self.true_errors(truth, shown)
        return {"budget": budget, "log": log, "selections": log + ".selections.csv",
                "power_w": energy_mean_from(frames, start),
                "windows": windows, "within": within / windows if windows else float("nan"),
                "within_true": within_true / windows if windows else float("nan"), "true_budget_w": true_budget,
                "within_window": within_window / windows if windows else float("nan"), "window_budgets": window_budgets,
                "error": mean(errors), "max_error": max(errors) if errors else float("nan"),
                "final": frames[max(frames)]["configuration"] if frames else "",
                "selections_made": len(selected)}

    def errors_against_estimates(self, scene, selections):
        """Fig. 10: the governor's estimated error of configurations at its last selection
        against the error computed from the demo's own image of each."""
        rows = []
        if os.path.exists(selections):
            with open(selections) as f:
                rows = list(csv.DictReader(f))
        if not rows:
            return []
        last = max(int(r["frame"]) for r in rows)
        estimates = sorted(((number(r["est_error"]), r["configuration"]) for r in rows if int(r["frame"]) == last
                            and number(r["est_error"]) is not None), key=lambda t: t[0])
        k = min(self.a.configurations, len(estimates))
        picked = [estimates[round(i * (len(estimates) - 1) / max(1, k - 1))] for i in range(k)]
        # The truth at the selection's own frame: the scene moves (Subway's soldiers), so an
        # image of another frame would measure the scene's change, not the estimate's error.
        at_selection = self.common(scene, 1) + ["--start-frame", str(last)]
        reference = os.path.join(self.tmp, f"{scene}_fig10_best")
        self.quiet(at_selection + ["--dump", reference])
        best_image = os.path.join(reference, sorted(os.listdir(reference))[-1])
        shown_images = []
        for estimate, configuration in dict((c, (e, c)) for e, c in picked).values():
            shown = os.path.join(self.tmp, f"{scene}_fig10_{configuration.replace(':', '')}")
            self.quiet(at_selection + ["--config", configuration.replace(":", ","), "--dump", shown])
            shown_images.append((configuration, estimate, os.path.join(shown, sorted(os.listdir(shown))[-1])))
        computed = self.ssim_errors(best_image, [path for _, _, path in shown_images])
        return [(configuration, estimate, computed[path]) for configuration, estimate, path in shown_images
                if path in computed]


def plot(results, fig10, out_dir, a):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    scenes = [r["scene"] for r in results]
    # Fig. 13: power and true error per scene, at max, min and each budget.
    labels = ["max quality", "min quality"] + [f"{b['budget']} %" for b in results[0]["budgets"]]
    fig, (ax_p, ax_e) = plt.subplots(1, 2, figsize=(11, 3.8))
    width = 0.8 / len(labels)
    for i, label in enumerate(labels):
        powers, errors = [], []
        for r in results:
            if i == 0:
                powers.append(r["best_w"]), errors.append(0.0)
            elif i == 1:
                powers.append(r["cheapest_w"]), errors.append(r["cheapest_error"])
            else:
                b = r["budgets"][i - 2]
                powers.append(b["power_w"]), errors.append(b["error"])
        xs = [j + (i - (len(labels) - 1) / 2) * width for j in range(len(scenes))]
        ax_p.bar(xs, powers, width, label=label)
        ax_e.bar(xs, errors, width, label=label)
    for ax, ylabel in ((ax_p, "mean power (W, cpu estimate)"), (ax_e, "true error (1 - SSIM)")):
        ax.set_xticks(range(len(scenes)))
        ax.set_xticklabels(scenes)
        ax.set_ylabel(ylabel)
    ax_p.legend(fontsize=8)
    fig.suptitle("Power and quality at maximum quality, minimum quality and under each budget")
    fig.tight_layout()
    fig.savefig(os.path.join(out_dir, "fig13_power_error.png"), dpi=100)
    plt.close(fig)

    # Fig. 12: the first budget's run over time.
    fig, axes = plt.subplots(len(results), 1, figsize=(10, 2.4 * len(results)), squeeze=False)
    for ax, r in zip(axes[:, 0], results):
        b = r["budgets"][0]
        frames = frames_of(b["log"])
        t0 = min(number(row["time_ns"]) for row in frames.values())
        t = [(number(frames[f]["time_ns"]) - t0) / 1e9 for f in sorted(frames)]
        series = lambda key: [number(frames[f].get(key)) for f in sorted(frames)]
        ax.plot(t, [p if p is not None else float("nan") for p in series("power_w")], lw=0.8, label="measured")
        ax.plot(t, [p if p is not None else float("nan") for p in series("predicted_w")], lw=0.8, label="predicted")
        ax.plot(t, [p if p is not None else float("nan") for p in series("budget_w")], lw=1.2, color="k",
                ls="--", label=f"budget ({b['budget']} %)")
        ax.axhline(b["true_budget_w"], color="r", lw=0.8, ls=":", label="run's measured range's budget")
        time_of = dict(zip(sorted(frames), t))
        for i, (first, last, watts) in enumerate(b["window_budgets"]):
            if first in time_of and last in time_of:
                ax.plot([time_of[first], time_of[last]], [watts, watts], color="r", lw=1.2,
                        label=None if i else "window's measured range's budget")
        ax.set_ylabel("power (W)")
        ax.set_title(r["scene"], fontsize=9, loc="left")
    axes[-1, 0].set_xlabel("time (s)")
    axes[0, 0].legend(fontsize=7, ncol=4)
    fig.tight_layout()
    fig.savefig(os.path.join(out_dir, "fig12_power_time.png"), dpi=100)
    plt.close(fig)

    # Fig. 10: estimated against computed error.
    fig, ax = plt.subplots(figsize=(5.2, 4.6))
    top = 0.0
    for scene, points in fig10.items():
        if points:
            ax.scatter([p[2] for p in points], [p[1] for p in points], s=14, label=scene)
            top = max(top, max(max(p[1], p[2]) for p in points))
    ax.plot([0, top * 1.05 or 1], [0, top * 1.05 or 1], color="grey", lw=0.8)
    ax.set_xlabel("computed error (1 - SSIM of the configuration's own image)")
    ax.set_ylabel("estimated error (governor, last selection)")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(out_dir, "fig10_errors.png"), dpi=100)
    plt.close(fig)


def replay_table(a):
    """The power model against Vatjus-Anttila's on the recorded logs."""
    r = subprocess.run([sys.executable, os.path.join(ROOT, "bench/model/replay_summary.py"), a.build],
                       capture_output=True, text=True)
    return r.stdout.strip() if r.returncode == 0 else f"(replay_summary.py failed: {r.stderr.strip()[-300:]})"


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("build")
    ap.add_argument("--out", required=True)
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--scenes", default=None)
    ap.add_argument("--budgets", default="40,50,60")
    ap.add_argument("--frames", type=int, default=None)
    ap.add_argument("--fps", type=float, default=10.0)
    ap.add_argument("--size", default=None)
    ap.add_argument("--detail", type=float, default=None)
    ap.add_argument("--shadow-size", type=int, default=None, help="the demo's shadow map at its best (default 2048)")
    ap.add_argument("--every", type=int, default=10, help="dump every K-th frame for the true error")
    ap.add_argument("--feedback", default="1", choices=["0", "1"],
                    help="GLBUDGET_FEEDBACK: 0 is the paper's open loop (no correction from measured power)")
    ap.add_argument("--keep-share", default=None,
                    help="GLBUDGET_KEEP_SHARE of the governed runs (the shim's default when not given)")
    ap.add_argument("--set", action="append", default=[], metavar="GLBUDGET_NAME=VALUE",
                    help="a setting of the governed runs (repeatable), e.g. GLBUDGET_PROBE_MAX_AGE_S=6")
    ap.add_argument("--costs", default="measure",
                    help="the levels' costs: 'measure' (glbudget calibrate --app on each scene first), 'off', or a path")
    ap.add_argument("--configurations", type=int, default=None, help="configurations in Fig. 10 per scene")
    ap.add_argument("--no-replay", action="store_true", help="leave out the model against Vatjus-Anttila")
    ap.add_argument("--keep-logs", default=None,
                    help="copy each scene's logs (reference and governed, with their selections) and level costs here")
    a = ap.parse_args()
    quick = a.quick
    a.scenes = a.scenes or ("valley" if quick else "hall,sponza,valley,subway")
    a.frames = a.frames or (80 if quick else 200)
    a.size = a.size or ("160x90" if quick else "320x180")
    a.detail = a.detail if a.detail is not None else (0.05 if quick else 0.2)
    # Small, a 2048² shadow map is half of each frame's time; the quick run checks the steps.
    a.shadow_size = a.shadow_size or (512 if quick else None)
    a.configurations = a.configurations or (6 if quick else 20)
    a.select_frames = 20 if quick else 60
    a.calibrate_frames = 6 if quick else 20
    os.makedirs(a.out, exist_ok=True)
    shown_args = [os.path.relpath(x, ROOT) if os.path.isabs(x) and x.startswith(ROOT) else x for x in sys.argv[1:]]
    command = "scripts/evaluate" + (" --quick" if quick else "") + "   # = python3 bench/evaluation/evaluate.py " + \
        " ".join(shown_args)
    print(f"demo at {a.size}, detail {a.detail}{shadow_note(a)}, {a.frames} frames paced at {a.fps:g} fps, cpu sensor (estimate); "
          f"select every {a.select_frames} frames, 1-s transitions; feedback {'on' if a.feedback == '1' else 'off'}; "
          f"level costs: {a.costs}{settings_note(a).replace(', ', '; ')}", flush=True)
    results, fig10 = [], {}
    with tempfile.TemporaryDirectory() as tmp:
        ev = Evaluation(a, tmp)
        for scene in a.scenes.split(","):
            r = ev.scene(scene)
            results.append(r)
            if a.keep_logs:
                keep_logs(tmp, scene, a.keep_logs)
            middle = r["budgets"][len(r["budgets"]) // 2]
            fig10[scene] = ev.errors_against_estimates(scene, middle["selections"])
            print(f"{scene}: best {r['best_w']:.1f} W, cheapest {r['cheapest_w']:.1f} W; " + "; ".join(
                f"{b['budget']} %: {b['power_w']:.1f} W, windows {b['within']:.2f} / {b['within_window']:.2f} / "
                f"{b['within_true']:.2f}, "
                f"error {b['error']:.4f}" for b in r["budgets"]), flush=True)
        plot(results, fig10, a.out, a)
    replay = "" if a.no_replay else replay_table(a)
    write_markdown(results, fig10, replay, command, a)
    print(f"evaluation: {os.path.join(a.out, 'evaluation.md')} and three figures")


def keep_logs(tmp, scene, to):
    """The scene's logs and level costs, which the temporary directory would take with it."""
    os.makedirs(to, exist_ok=True)
    for name in os.listdir(tmp):
        if name.startswith(scene) and (name.endswith(".csv") or name.endswith(".json")):
            shutil.copy(os.path.join(tmp, name), to)


def write_markdown(results, fig10, replay, command, a):
    lines = [f"# The paper's evaluation on the demo's scenes{' (quick check)' if a.quick else ''}", "",
             "```sh", command, "```", "",
             f"Each scene at {a.size}, detail {a.detail}{shadow_note(a)}, {a.frames} frames paced at {a.fps:g} fps, the cpu sensor's "
             f"estimate (P = 10 W + 35 W × the process's CPU share), selections every {a.select_frames} frames, 1-s "
             f"transitions, quality probes at the shim's default, correction from measured power "
             f"{'on' if a.feedback == '1' else 'off'}"
             f"{settings_note(a)}, level costs {a.costs} "
             f"({'glbudget calibrate --app per scene' if a.costs == 'measure' else 'none'}). "
             f"Configurations are levels of ({KNOBS}).", "",
             "## Power and quality (the paper's Fig. 13)", "",
             "Windows: the share of 1-s windows of the log's time after the first selection whose energy over "
             "their length (each frame's power over its own interval, probe frames included; mean powers likewise) "
             "is at or under the budget the governor logged (from its predicted range) / under the same "
             "share of the *measured* range of the window's own frames (cheapest + P % × (best − cheapest), the "
             "paper's budget, which follows the scene along the camera path) / of the whole run's measured range. "
             "Best and cheapest are each run before and after the "
             "governed runs (the estimate drifts by several percent over minutes) and their means taken, the two "
             "given in brackets. True error: 1 − SSIM of every "
             f"{a.every}th frame shown against the demo's own image of it at its best configuration.", "",
             "| scene | run | mean W | saved | true error (mean / max) | windows (governor / window's measured range / run's) | final configuration |",
             "|---|---|---:|---:|---|---|---|"]
    for r in results:
        ba, ca = r["best_before_after_w"], r["cheapest_before_after_w"]
        lines.append(f"| {r['scene']} | max quality | {r['best_w']:.1f} ({ba[0]:.1f}, {ba[1]:.1f}) | | 0 | | 0:0:0:0:0:0 |")
        lines.append(f"| {r['scene']} | min quality | {r['cheapest_w']:.1f} ({ca[0]:.1f}, {ca[1]:.1f}) | "
                     f"{1 - r['cheapest_w'] / r['best_w']:.0%} | "
                     f"{r['cheapest_error']:.4f} | | 2:2:2:2:2:2 |")
        for b in r["budgets"]:
            lines.append(f"| {r['scene']} | {b['budget']} % | {b['power_w']:.1f} | {1 - b['power_w'] / r['best_w']:.0%} | "
                         f"{b['error']:.4f} / {b['max_error']:.4f} | {b['within']:.2f} / {b['within_window']:.2f} / "
                         f"{b['within_true']:.2f} "
                         f"({b['windows']} windows) | {b['final']} |")
    lines += ["", "![Fig. 13](fig13_power_error.png)", "",
              "## Power over time (Fig. 12)", "",
              f"The {results[0]['budgets'][0]['budget']} % run of each scene: measured and predicted power per frame, the "
              "budget the governor logged, and the measured range's budget.", "",
              "![Fig. 12](fig12_power_time.png)", "",
              "## Estimated against computed error (Fig. 10)", "",
              "At the middle budget's last selection, configurations spread over the governor's estimated errors "
              "(from its quality probes, additive over passes, paper §6.2); computed: 1 − SSIM of the demo's own "
              "image of the configuration at the selection's frame against its best.", "",
              "| scene | configurations | Spearman ρ | mean absolute error | largest |", "|---|---:|---:|---:|---:|"]
    for scene, points in fig10.items():
        if points:
            diffs = [abs(p[1] - p[2]) for p in points]
            lines.append(f"| {scene} | {len(points)} | {spearman([p[1] for p in points], [p[2] for p in points]):.3f} | "
                         f"{statistics.fmean(diffs):.4f} | {max(diffs):.4f} |")
    lines += ["", "![Fig. 10](fig10_errors.png)", ""]
    if replay:
        lines += ["## The power model against Vatjus-Anttila", "",
                  "The recorded logs of `tests/data/logs` (each scene walked through eight configurations) replayed "
                  "through the run-time model and the baseline (`python3 bench/model/replay_summary.py build`; "
                  "MAPE, lower is better):", "", replay, ""]
    with open(os.path.join(a.out, "evaluation.md"), "w") as f:
        f.write("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
