#!/usr/bin/env python3
"""The quality probes' two knobs traded (issue 14): the SSIM's scale (GLBUDGET_PROBE_SCALE)
and the probe period (GLBUDGET_PROBE_PERIOD), against what they cost and how good the error
estimates they give the governor are.

Per scene, each level's costs measured once by `glbudget calibrate --app`; then per setting:
  - accuracy: error_estimates.py's study with the setting in the governed run's environment:
    at the governor's last selection, every configuration's estimated error against the true
    error of the demo's own image of that frame (all 729): Spearman rho, mean absolute error,
    the worst selection regret over the budgets;
  - staleness, from that run's log: the share of frames that were probe frames, and how old
    the estimates were at the last selection: frames since each pass's last probe at its
    cheapest level before it (the logged probe streams; passes never probed, not being in the
    scene, left out), their mean and the oldest;
  - cost: probe_overhead.py's measure, the demo unpaced at a middle configuration with the
    setting against the same without probes (a long run less a short one, so start-up cancels;
    rounds interleaved), the mean frame time's ratio.
The period's default is 10 frames until every pass has been probed, then 60, but no longer than
lets each pass in the scene be probed within GLBUDGET_PROBE_MAX_AGE_S (max_age=S; the default
10 s, 0: no bound); the scale's is Wang's rule for the frame (1 below 384 pixels on the short
side); the order's (order=turn or weighted) is turn (weighted: in turn until each has been
probed, then the largest error × age).

Writes DIR/probe-trades.md.
Usage: probe_trades.py BUILD_DIR --out DIR [--scenes hall,subway] [--settings default,scale=2,...]
       [--rounds 2] [--quick]  (and error_estimates.py's --frames, --fps, --size, --detail, ...)
"""
import csv
import os
import statistics
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
sys.path.insert(0, os.path.join(HERE, "..", "interpose"))
from error_estimates import Study  # noqa: E402
from evaluate import (MANIFEST, energy_mean_from, frames_of, is_probe, mean, number, parse_study_arguments,  # noqa: E402
                      settled_start, shadow_note, study_arguments, timed_windows)
from demo_bench import clean_environment, run  # noqa: E402

SETTINGS = "default,scale=2,scale=4,period=10,period=30,period=60,period=120"
MIDDLE = "1,0,0,1,0,0"  # probe_overhead.py's forced configuration: two probe streams drawn


KNOBS = {"scale": "GLBUDGET_PROBE_SCALE", "period": "GLBUDGET_PROBE_PERIOD", "order": "GLBUDGET_PROBE_ORDER",
         "max_age": "GLBUDGET_PROBE_MAX_AGE_S", "sweep": "GLBUDGET_PROBE_SWEEP"}


def setting_env(setting):
    """GLBUDGET_* of a setting: 'default', 'scale=S', 'period=P', 'order=turn|weighted',
    'max_age=S' or 'sweep=0|1'."""
    if setting == "default":
        return {}
    knob, _, value = setting.partition("=")
    return {KNOBS[knob]: value}


def staleness(log, frame):
    """(share of probe frames, mean and oldest age at `frame` of each pass's last probe before it).
    Passes never probed (not in the scene) are left out."""
    frames, probes, last = set(), set(), {}
    with open(log) as f:
        for row in csv.DictReader(f):  # a row per pass and frame
            at = int(row["frame"])
            frames.add(at)
            if not is_probe(row):
                continue
            probes.add(at)
            for stream in filter(None, (row.get("probe_streams") or "").split(";")):
                levels = stream.split("=")[0].split(":")
                changed = [i for i, level in enumerate(levels) if level != "0"]
                if len(changed) == 1 and at < frame:
                    last[changed[0]] = max(last.get(changed[0], 0), at)
    share = len(probes) / len(frames) if frames else float("nan")
    ages = [frame - at for at in last.values()]
    if not ages:
        return share, float("nan"), float("inf")
    return share, statistics.mean(ages), max(ages)


def budget_kept(log, fps, frames_run):
    """(mean power, share of 1-s windows at or under the governor's budget, mean estimated error of
    the frames shown) from a second after the first selection to the end, as evaluate.py counts;
    NaN where the run never selected."""
    frames = frames_of(log)
    start = settled_start(frames, fps, frames_run)
    numbers = sorted(f for f in frames if f >= start)
    windows = timed_windows(frames, start, 1.0)
    within = sum(p <= b for _, p, b in windows)
    power = energy_mean_from(frames, start)
    error = mean([number(frames[f].get("est_error")) for f in numbers])
    return power, within / len(windows) if windows else float("nan"), error


class Trades(Study):
    """error_estimates.py's study, the levels' costs measured once per scene."""

    def __init__(self, a, tmp):
        super().__init__(a, tmp)
        self.costs = {}

    def level_costs(self, scene):
        if scene not in self.costs:
            self.costs[scene] = super().level_costs(scene)
        return self.costs[scene]

    def overhead(self, scene, settings):
        """{setting: mean unpaced frame time / the same without probes}, rounds interleaved; NaN
        with --rounds 0 (settings that draw the same probes, as the order's, cost the same)."""
        if self.a.rounds == 0:
            return {s: float("nan") for s in settings}
        shim = os.path.join(self.a.build, "interpose/libglbudget.so")
        base = dict(clean_environment(), LD_PRELOAD=shim, GLBUDGET_SENSOR="cpu", GLBUDGET_CONFIG=MANIFEST,
                    GLBUDGET_FORCE=MIDDLE)
        cases = {"none": dict(base, GLBUDGET_PROBE_PERIOD="0")}
        for s in settings:
            env = dict(base, **setting_env(s))
            if "GLBUDGET_PROBE_PERIOD" not in env:
                env["GLBUDGET_PROBE_PERIOD"] = "60"  # ungoverned, the default would be none
            cases[s] = env
        long_frames = self.a.overhead_frames
        cmd = [self.demo, "--scene", scene, "--detail", str(self.a.detail), "--width", self.width, "--height",
               self.height] + self.shadow_args()
        per_frame = {name: [] for name in cases}
        for _ in range(self.a.rounds):
            for name, env in cases.items():
                long = run(cmd + ["--frames", str(long_frames)], env)
                short = run(cmd + ["--frames", "5"], env)
                per_frame[name].append((long - short) / (long_frames - 5))
        none = statistics.median(per_frame["none"])
        return {s: statistics.median(per_frame[s]) / none for s in settings}


def main():
    ap = study_arguments(__doc__.splitlines()[0], "hall,subway")
    ap.add_argument("--settings", default=SETTINGS)
    ap.add_argument("--budget", type=int, default=50, help="the governed runs' power budget, %%")
    ap.add_argument("--regret-budgets", default="30,40,50,60,70")
    ap.add_argument("--rounds", type=int, default=2, help="rounds of the unpaced overhead runs (0: none)")
    ap.add_argument("--overhead-frames", type=int, default=60)
    a, command = parse_study_arguments(ap, "probe_trades.py")
    if a.quick:
        a.settings, a.rounds, a.overhead_frames = "default,period=30", 1, 20
    a.regret_budgets = [int(b) for b in a.regret_budgets.split(",")]
    settings = a.settings.split(",")
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        trades = Trades(a, tmp)
        for scene in a.scenes.split(","):
            cost = trades.overhead(scene, settings)
            for s in settings:
                trades.governed_env = {k: v for k, v in trades.governed_env.items() if k not in KNOBS.values()}
                trades.governed_env.update(setting_env(s))
                r = trades.scene(scene)[-1]  # the last selection
                row = {"scene": scene, "setting": s, "overhead": cost[s]}
                if "error" in r:
                    row["error"] = r["error"]
                else:
                    share, mean_age, oldest = staleness(os.path.join(tmp, f"{scene}.csv"), r["frame"])
                    regrets = [v for v in r["regret"].values() if v == v]
                    power, kept, shown = budget_kept(os.path.join(tmp, f"{scene}.csv"), a.fps, a.frames)
                    row.update(frame=r["frame"], share=share, mean_age=mean_age, oldest=oldest, rho=r["rho"],
                               mae=r["mae"], regret=max(regrets) if regrets else float("nan"), power=power, kept=kept,
                               shown=shown)
                rows.append(row)
                print(format_row(row), flush=True)
    write(rows, a, command)
    print(f"probe trades: {os.path.join(a.out, 'probe-trades.md')}")
    return 0 if all("error" not in r for r in rows) else 1


def format_row(r):
    if "error" in r:
        return f"| {r['scene']} | {r['setting']} | {r['overhead']:.2f} | {r['error']} |"
    oldest = "never probed" if r["oldest"] == float("inf") else f"{r['oldest']:.0f}"
    mean_age = "–" if r["mean_age"] != r["mean_age"] else f"{r['mean_age']:.0f}"
    return (f"| {r['scene']} | {r['setting']} | {r['overhead']:.2f} | {r['share']:.3f} | {mean_age} | {oldest} | "
            f"{r['rho']:.3f} | {r['mae']:.4f} | {r['regret']:.4f} | {r['power']:.1f} | {r['kept']:.2f} | "
            f"{r['shown']:.4f} |")


def write(rows, a, command):
    lines = ["# The quality probes' knobs: scale, period and order against cost, staleness and accuracy", "",
             "```sh", command, "```", "",
             f"Each scene at {a.size}, detail {a.detail}{shadow_note(a)}. Accuracy and staleness from a governed run of {a.frames} "
             f"frames paced at {a.fps:g} fps under `--power {a.budget}%` with the setting (the cpu sensor, level "
             f"costs {a.costs}), at the governor's last selection, against the true error of all 729 "
             "configurations of that frame (as in [error-estimates.md](../estimates/error-estimates.md)); regret: "
             f"the worst over budgets {', '.join(map(str, a.regret_budgets))} % (goal ≤ 0.005). Frame time: the "
             f"demo unpaced, forced to {MIDDLE.replace(',', ':')}, {a.overhead_frames} frames less 5 (start-up "
             f"cancels), median of {a.rounds} interleaved rounds, against the same without probes (a setting "
             "without a period probes every 60 frames there: ungoverned, the shim's default is none). Age: frames "
             "from each pass's last probe at its cheapest level to the selection (passes never probed, not in the "
             "scene, left out; \"never probed\": no pass was). default: probes every 10 frames until each pass was "
             "probed, then every 60 (max_age=S: at most S seconds between two probes of a pass in the scene, "
             "`GLBUDGET_PROBE_MAX_AGE_S`), the passes in turn; SSIM at Wang's scale (1 at this size).",
             "",
             "Power, windows and error shown: the governed run from a second after its first selection, its mean "
             "power (W, the cpu estimate), the share of its 1-s windows at or under the governor's budget, and the "
             "mean estimated error of the frames shown.",
             "",
             "| scene | setting | frame time vs none | probe frames | mean age | oldest | Spearman ρ | mean abs. error "
             "| worst regret | power | windows kept | est. error shown |",
             "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
    lines += [format_row(r) for r in rows]
    lines.append("")
    with open(os.path.join(a.out, "probe-trades.md"), "w") as f:
        f.write("\n".join(lines))


if __name__ == "__main__":
    sys.exit(main())
