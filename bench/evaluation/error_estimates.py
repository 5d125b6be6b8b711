#!/usr/bin/env python3
"""The governor's error estimates against ground truth over the whole configuration space
(issue 14, paper §6.2 and Fig. 10 with every configuration instead of a sample).

Per scene of the demo:
  1. the demo under `glbudget run --power P%` (probes at the shim's default, paced at --fps,
     the cpu sensor), its level costs measured first by `glbudget calibrate --app` unless
     --costs says otherwise; the governor's last selection logs every configuration's
     predicted power and estimated error (additive over passes from its latest probes);
  2. the demo's own image of that frame in all 729 configurations (`demo --all-configs`);
     true error = 1 - SSIM of each against the best configuration's (`glbudget ssim`, one
     process for all);
  3. Spearman's rho and the mean absolute error between estimated and true error, and the
     selection regret at each budget: the true error of the configuration the estimates pick
     among those the governor predicts within the budget, less the lowest true error among
     them (the estimates' cost in quality, the power predictions held fixed);
  4. the same two for the additive estimate made of that frame's own single-pass errors (each
     pass alone at each of its levels, from the 729 images): every pass probed at that very
     frame at every level, so that only additivity is left; what falls short of it is the
     probes' staleness and the levels' error ratios k.
Budgets are shares of the range of the selection's predictions (the cheapest to the best).

Writes DIR/error-estimates.md and DIR/error_estimates.png, each governed run's log as
DIR/SCENE.csv (with its .selections.csv), and every configuration's true and estimated error at
the last selection as DIR/SCENE.truth.csv. With --selections all, every selection after the first
is measured (steps 2-4 at its frame; the only one where the run made one), each a row, its truth
as DIR/SCENE.fFRAME.truth.csv.
Usage: error_estimates.py BUILD_DIR --out DIR [--scenes hall,sponza,valley,subway]
       [--budget 50] [--regret-budgets 30,40,50,60,70] [--frames 200] [--fps 10] [--size 320x180]
       [--detail 0.2] [--costs measure|off|PATH] [--selections last|all] [--quick]
"""
import csv
import os
import shutil
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from evaluate import (MANIFEST, PROFILE, KNOBS, Evaluation, mean, number, parse_study_arguments,  # noqa: E402
                      shadow_note, spearman, study_arguments)

BEST = "0:0:0:0:0:0"


def selection_tables(selections_csv):
    """{frame: {configuration: (predicted_w, est_error)}}, one table per selection in the log."""
    tables = {}
    with open(selections_csv) as f:
        for r in csv.DictReader(f):
            tables.setdefault(int(r["frame"]), {})[r["configuration"]] = (number(r["predicted_w"]),
                                                                          number(r["est_error"]))
    return tables


def last_selection(selections_csv):
    """{configuration: (predicted_w, est_error)} at the log's last selection, and its frame."""
    tables = selection_tables(selections_csv)
    if not tables:
        return {}, None
    last = max(tables)
    return tables[last], last


def regret(table, truth, share):
    """The regret of picking by estimated error within a share of the predicted range."""
    power = {c: p for c, (p, _) in table.items() if p is not None and c in truth}
    if BEST not in power:
        return float("nan")
    low, high = min(power.values()), power[BEST]
    budget = low + share * (high - low)
    feasible = [c for c, p in power.items() if p <= budget]
    if not feasible:
        return float("nan")
    picked = min(feasible, key=lambda c: (table[c][1], power[c]))
    return truth[picked] - min(truth[c] for c in feasible)


def fresh_sums(truth):
    """{configuration: the sum of its passes' single-pass true errors at their levels} (paper
    §6.2's estimate from errors all measured at this frame); configurations whose single-pass
    images are missing are left out."""
    passes = len(BEST.split(":"))
    sums = {}
    for c in truth:
        levels, total = c.split(":"), 0.0
        for i, level in enumerate(levels):
            if level == "0":
                continue
            alone = ":".join(level if j == i else "0" for j in range(passes))
            if alone not in truth:
                break
            total += truth[alone]
        else:
            sums[c] = total
    return sums


class Study(Evaluation):
    """The evaluation's runs (its binaries, sizes and environments), for another question."""

    def scene(self, scene):
        a = self.a
        env = dict(self.governed_env, GLBUDGET_COSTS=self.level_costs(scene))
        log = os.path.join(self.tmp, f"{scene}.csv")
        self.quiet([self.glbudget, "run", "--fps", str(a.fps), "--log", log, "--power", f"{a.budget}%", "--profile",
                    PROFILE, "--config", MANIFEST, "--"] + self.common(scene, a.frames), env)
        # The governed run's log beside the results: when each pass was probed, and what it measured.
        os.makedirs(a.out, exist_ok=True)
        for suffix in ("", ".selections.csv"):
            if os.path.exists(log + suffix):
                shutil.copyfile(log + suffix, os.path.join(a.out, f"{scene}.csv{suffix}"))
        tables = selection_tables(log + ".selections.csv") if os.path.exists(log + ".selections.csv") else {}
        if not tables:
            return [{"scene": scene, "error": "no selection in the governed run"}]
        # The last selection, or with --selections all every one after the first (the first weighs
        # the first probes, all of one moment).
        frames = sorted(tables)[1:] if getattr(a, "selections", "last") == "all" and len(tables) > 1 else [max(tables)]
        return [self.at_selection(scene, frame, tables[frame], frame == max(tables)) for frame in frames]

    def at_selection(self, scene, frame, table, last):
        """The estimates of the selection at `frame` against that frame's truth."""
        a = self.a
        # One folder per frame: a study that runs a scene again (probe_trades.py) must not mix
        # another frame's images into this one's truth.
        images = os.path.join(self.tmp, f"{scene}_all_f{frame}")
        self.quiet(self.common(scene, 1) + ["--start-frame", str(frame), "--all-configs", "--dump", images])
        by_config = {}
        for name in os.listdir(images):
            levels = name.rsplit("_c", 1)[1].split("_f")[0]
            by_config[":".join(levels)] = os.path.join(images, name)
        others = [path for c, path in by_config.items() if c != BEST]
        errors = self.ssim_errors(by_config[BEST], others)
        truth = {c: 0.0 if c == BEST else errors[path] for c, path in by_config.items() if c == BEST or path in errors}
        # Every configuration's true and estimated error at that frame beside the log, for studies
        # of the estimate's form offline (how the passes' errors combine).
        with open(os.path.join(a.out, f"{scene}.truth.csv" if last else f"{scene}.f{frame}.truth.csv"), "w") as f:
            f.write("configuration,true_error,est_error,predicted_w\n")
            for c in sorted(truth):
                predicted, estimated = table.get(c, (None, None))
                f.write(f"{c},{truth[c]:.6f},{'' if estimated is None else estimated},"
                        f"{'' if predicted is None else predicted}\n")
        pairs = [(table[c][1], truth[c]) for c in truth if c in table and table[c][1] is not None]
        estimated, computed = [p[0] for p in pairs], [p[1] for p in pairs]
        sums = fresh_sums(truth)
        fresh = {c: (table[c][0], sums[c]) for c in sums if c in table}
        return {"scene": scene, "frame": frame, "configurations": len(pairs),
                "rho_fresh": spearman([fresh[c][1] for c in fresh], [truth[c] for c in fresh]),
                "regret_fresh": max((regret(fresh, truth, b / 100.0) for b in a.regret_budgets), default=float("nan")),
                "rho": spearman(estimated, computed),
                "mae": mean([abs(e - t) for e, t in pairs]),
                "largest": max((abs(e - t) for e, t in pairs), default=float("nan")),
                "regret": {b: regret(table, truth, b / 100.0) for b in a.regret_budgets},
                "pairs": pairs}


def write(results, a, command):
    lines = ["# Error estimates against ground truth, every configuration", "", "```sh", command, "```", "",
             f"Each scene at {a.size}, detail {a.detail}{shadow_note(a)}, {a.frames} frames paced at {a.fps:g} fps under "
             f"`glbudget run --power {a.budget}%` (the cpu sensor, quality probes at the shim's default, level costs "
             f"{a.costs}). At the governor's {'selections after the first' if a.selections == 'all' else 'last selection'} every configuration's estimated error (additive over "
             "passes from its latest probes, paper §6.2) against the true error of the demo's own image of that "
             "frame in that configuration (1 − SSIM against its best), all 729 configurations of "
             f"({KNOBS}).", "",
             "Regret at a budget: among the configurations the governor predicts within it (a share of the range "
             "of its predictions), the true error of the one the estimates pick less the lowest true error there: "
             "what the estimates cost in quality, the power predictions held fixed. Goal ≤ 0.005.", "",
             "Fresh: the same additive estimate made of the frame's own single-pass errors (each pass alone at "
             "each level, from the 729 images), as if every pass had been probed at that frame at every level; "
             "the gap to it is the probes' staleness and the levels' ratios k, what is left of it additivity.", "",
             "| scene | frame | configurations | Spearman ρ | mean abs. error | largest | "
             + " | ".join(f"regret {b} %" for b in a.regret_budgets) + " | fresh: ρ | fresh: worst regret |",
             "|---|---:|---:|---:|---:|---:|" + "---:|" * len(a.regret_budgets) + "---:|---:|"]
    for r in results:
        if "error" in r:
            lines.append(f"| {r['scene']} | {r['error']} |")
            continue
        lines.append(f"| {r['scene']} | {r['frame']} | {r['configurations']} | {r['rho']:.3f} | {r['mae']:.4f} | "
                     f"{r['largest']:.4f} | " + " | ".join(f"{r['regret'][b]:.4f}" for b in a.regret_budgets) +
                     f" | {r['rho_fresh']:.3f} | {r['regret_fresh']:.4f} |")
    lines += ["", "![estimated against true error](error_estimates.png)", ""]
    with open(os.path.join(a.out, "error-estimates.md"), "w") as f:
        f.write("\n".join(lines))


def plot(results, out):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(5.4, 4.8))
    top = 0.0
    for r in results:
        if r.get("pairs"):
            ax.scatter([p[1] for p in r["pairs"]], [p[0] for p in r["pairs"]], s=4, alpha=0.5,
                       label=f"{r['scene']} f{r['frame']} (ρ {r['rho']:.2f})")
            top = max(top, max(max(p) for p in r["pairs"]))
    ax.plot([0, top * 1.05 or 1], [0, top * 1.05 or 1], color="grey", lw=0.8)
    ax.set_xlabel("true error (1 - SSIM of the configuration's own image)")
    ax.set_ylabel("estimated error (governor's selection)")
    ax.legend(fontsize=8, markerscale=3)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "error_estimates.png"), dpi=100)
    plt.close(fig)


def main():
    ap = study_arguments(__doc__.splitlines()[0], "hall,sponza,valley,subway")
    ap.add_argument("--budget", type=int, default=50, help="the governed run's power budget, %%")
    ap.add_argument("--regret-budgets", default="30,40,50,60,70")
    ap.add_argument("--selections", default="last", choices=["last", "all"],
                    help="the selections measured: the run's last, or every one after its first")
    a, command = parse_study_arguments(ap, "error_estimates.py")
    a.regret_budgets = [int(b) for b in a.regret_budgets.split(",")]
    results = []
    with tempfile.TemporaryDirectory() as tmp:
        study = Study(a, tmp)
        for scene in a.scenes.split(","):
            for r in study.scene(scene):
                report(r, a.regret_budgets)
                results.append(r)
    plot(results, a.out)
    write(results, a, command)
    print(f"error estimates: {os.path.join(a.out, 'error-estimates.md')}")
    return 0 if all("error" not in r for r in results) else 1


def report(r, budgets):
    scene = r["scene"]
    if "error" in r:
        print(f"{scene}: {r['error']}", flush=True)
        return
    print(f"{scene}: frame {r['frame']}, {r['configurations']} configurations, rho {r['rho']:.3f}, "
          f"MAE {r['mae']:.4f}, regret " + ", ".join(f"{b} % {r['regret'][b]:.4f}" for b in budgets) +
          f"; fresh single-pass errors: rho {r['rho_fresh']:.3f}, worst regret {r['regret_fresh']:.4f}",
          flush=True)


if __name__ == "__main__":
    sys.exit(main())
