#!/usr/bin/env python3
"""Probe schedules replayed offline against every frame's true errors (issue 14): how the
period between probes, the order of the passes and the shown image's measured error would rank
the 729 configurations, without the noise of one governed run's timing.

A governed run probes one pass every P frames once each has been probed (the shim's age bound
makes P = GLBUDGET_PROBE_MAX_AGE_S x fps / passes in the scene at low frame rates), and the
governor estimates every configuration from each pass's latest probe (§6.2). Which frames the
probes fall on and where the selection lands move ρ by 0.01-0.03 between live runs; here the
same schedules are replayed over the same frames for every setting.

Per scene (the demo at 320x180, detail 0.2, unpaced: frames are the same images at any speed):
  1. every frame's true error of each pass alone at each of its cheaper levels, and of every
     pass at its cheapest (the image a governor at the bottom of its range shows), against the
     best configuration's image of that frame (`glbudget ssim`);
  2. every configuration's true error at the truth frames (`demo --all-configs`);
  3. the level ratios k (e_i(l) / e_i(lmax), what `glbudget calibrate --app` measures): the
     median over the frames;
  4. for each period P and order: the first sweep (each pass in the scene, 10 frames apart),
     then a probe every P frames, started at several phases; at each truth frame, the additive
     estimate from each pass's latest probe (its cheapest level, the others by k) against the
     truth: Spearman's ρ. Reported per scene and period: the mean ρ, the lowest, and the share
     of (phase, frame) pairs under 0.95.
Orders: turn (the shim's default: the pass probed longest ago), weighted (the largest error ×
age), trend (turn, each pass's error carried to the frame along the line through its last two
probes: tried on 2026-11-29 and not landed, docs/evaluation/probes/probe-order.md), and filtered: turn, with each pass's estimate updated between its probes from the error
the probe frame measured of the image shown (all passes at their cheapest), by a Kalman filter
over the passes' cheapest-level errors (each a random walk whose step is 5 % of itself per
sqrt(frame)) and the shown configuration's ratio of measured to additive error (a slow random
walk in log): tried on 2026-11-29 and not landed (docs/evaluation/probes/probe-order.md).

With --logs, the probes of governed runs (error_estimates.py's SCENE.csv, at the same size)
are replayed too, as they came, with the shown configurations they measured: turn's estimate is
then the governor's own (but for k), and trend's and filtered's what they would have made of them.

Writes DIR/probe-schedules.md; keeps the per-frame errors in DIR/series_SCENE.json and the
truths in DIR/truth/ (reused when there: the first run renders about 6 minutes a scene here).
Usage: probe_schedules.py BUILD_DIR --out DIR [--scenes hall,sponza,valley,subway]
       [--frames 200] [--truth-frames 70,85,...,190] [--periods 10,15,17,20,25]
       [--orders turn,weighted,trend,filtered] [--phases 5] [--logs DIR,DIR,...]
"""
import argparse
import csv
import itertools
import json
import math
import os
import statistics
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from evaluate import is_probe, spearman  # noqa: E402

PASSES = 6
LEVELS = 3
CHEAPEST = LEVELS - 1
BEST = (0,) * PASSES
FIRST_PERIOD = 10  # the shim's first sweep: one pass every 10 frames until each is probed
SIZE, DETAIL = ("320", "180"), "0.2"


def alone(i, level):
    return tuple(level if j == i else 0 for j in range(PASSES))


def clean_env():
    return {k: v for k, v in os.environ.items() if not k.startswith("GLBUDGET_") and k != "LD_PRELOAD"}


def demo(build, scene, frames, extra):
    subprocess.run([os.path.join(build, "testapps/demo/demo"), "--scene", scene, "--detail", DETAIL, "--width",
                    SIZE[0], "--height", SIZE[1], "--frames", str(frames)] + extra, check=True, env=clean_env(),
                   stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)


def ssim_errors(build, best, others):
    """{path: 1 - SSIM(best, path)} in one glbudget process."""
    out = subprocess.run([os.path.join(build, "cli/glbudget"), "ssim", best] + others, capture_output=True,
                         text=True, check=True).stdout
    errors = {}
    for line in out.splitlines():
        value, _, path = line.partition("\t")
        errors[path] = 1.0 - float(value)
    return errors


def levels_name(c):
    return "".join(str(x) for x in c)


def series(build, scene, frames, out):
    """{frame: {configuration: true error}} of the single-pass configurations and all-cheapest."""
    path = os.path.join(out, f"series_{scene}.json")
    if os.path.exists(path):
        data = json.load(open(path))
        if data["frames"] >= frames:
            return {int(f): {tuple(map(int, c)): e for c, e in v.items()} for f, v in data["series"].items()}
    configs = [BEST] + [alone(i, l) for i in range(PASSES) for l in range(1, LEVELS)] + [(CHEAPEST,) * PASSES]
    with tempfile.TemporaryDirectory() as tmp:
        for c in configs:
            demo(build, scene, frames, ["--config", ",".join(map(str, c)), "--dump", os.path.join(tmp, levels_name(c)),
                                        "--dump-every", "1"])

        def image(c, f):
            return os.path.join(tmp, levels_name(c), f"{scene}_c{levels_name(c)}_f{f:05d}.png")

        result = {}
        for f in range(frames):
            if not os.path.exists(image(BEST, f)):
                continue
            errors = ssim_errors(build, image(BEST, f), [image(c, f) for c in configs[1:]])
            result[f] = {c: errors.get(image(c, f), 0.0) for c in configs[1:]}
    json.dump({"frames": frames, "series": {f: {levels_name(c): e for c, e in v.items()} for f, v in result.items()}},
              open(path, "w"))
    return result


def truth(build, scene, frame, out):
    """{configuration: true error} of all 729 at `frame`."""
    path = os.path.join(out, "truth", f"{scene}_{frame}.json")
    if os.path.exists(path):
        return {tuple(int(x) for x in c.replace(":", "")): e for c, e in json.load(open(path)).items()}
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with tempfile.TemporaryDirectory() as tmp:
        demo(build, scene, 1, ["--start-frame", str(frame), "--all-configs", "--dump", tmp])
        by = {tuple(map(int, name.rsplit("_c", 1)[1].split("_f")[0])): os.path.join(tmp, name) for name in os.listdir(tmp)}
        errors = ssim_errors(build, by[BEST], [p for c, p in by.items() if c != BEST])
        result = {c: 0.0 if c == BEST else errors[p] for c, p in by.items() if c == BEST or p in errors}
    json.dump({levels_name(c): e for c, e in result.items()}, open(path, "w"))
    return result


def level_ratios(s):
    """k[i][l] = median over frames of e_i(l) / e_i(lmax); 0 at level 0, 1 at the cheapest."""
    k = []
    for i in range(PASSES):
        row = [0.0]
        for level in range(1, CHEAPEST):
            ratios = [v[alone(i, level)] / v[alone(i, CHEAPEST)] for v in s.values() if v[alone(i, CHEAPEST)] > 1e-4]
            row.append(statistics.median(ratios) if ratios else level / CHEAPEST)
        k.append(row + [1.0])
    return k


def rank_correlation(estimates, truth):
    """Spearman's ρ of the estimates against the truth over the truth's configurations."""
    configurations = sorted(truth)
    return spearman([estimates[c] for c in configurations], [truth[c] for c in configurations])


class Turn:
    """Each pass's latest probe; the next probe takes the pass probed longest ago."""

    def __init__(self, k, active):
        self.k, self.active = k, active
        self.x = [0.0] * PASSES
        self.at = [0] * PASSES

    def probe(self, frame, i, error):
        self.x[i], self.at[i] = error, frame

    def shown(self, frame, configuration, error):
        pass

    def pick(self, frame):
        return max(self.active, key=lambda i: (frame - self.at[i], -i))

    def value(self, i, frame):
        return self.x[i]

    def estimates(self, frame):
        x = [self.value(i, frame) for i in range(PASSES)]
        out = {}
        for c in itertools.product(range(LEVELS), repeat=PASSES):
            out[c] = sum(self.k[i][c[i]] * x[i] for i in range(PASSES))
        return out


class Weighted(Turn):
    """The shim's GLBUDGET_PROBE_ORDER=weighted (governor/loop/probe_order.hpp)."""

    def pick(self, frame):
        floor = max(0.002, max(self.x[i] for i in self.active) / 10)
        return max(self.active, key=lambda i: (max(self.x[i], floor) * (frame - self.at[i]), -i))


class Trend(Turn):
    """Turn's order; each pass's error carried to the frame along the line through its last two
    probes (held within [0, 2x] of its latest)."""

    def __init__(self, k, active):
        super().__init__(k, active)
        self.before = [None] * PASSES  # (frame, error) of the probe before the latest

    def probe(self, frame, i, error):
        self.before[i] = (self.at[i], self.x[i]) if self.at[i] else None
        super().probe(frame, i, error)

    def value(self, i, frame):
        if self.before[i] is None or frame <= self.at[i] or self.at[i] <= self.before[i][0]:
            return self.x[i]
        slope = (self.x[i] - self.before[i][1]) / (self.at[i] - self.before[i][0])
        return min(2 * self.x[i], max(0.0, self.x[i] + slope * (frame - self.at[i])))


class Filtered(Turn):
    """Turn's order; between probes, each pass's estimate moved by the shown image's measured
    error (an extended Kalman filter over x = e_i(lmax) and the shown configuration's log ratio
    of measured to additive error)."""
    drift, floor, probe_noise, shown_noise, ratio_spread, ratio_drift = 0.05, 0.002, 1e-4, 0.03, 0.3, 0.003

    def __init__(self, k, active):
        super().__init__(k, active)
        self.P = [[0.0] * PASSES for _ in range(PASSES)]
        self.t = 0
        self.ratio = {}
        self.known = [i not in active for i in range(PASSES)]

    def advance(self, frame):
        dt = frame - self.t
        if dt <= 0:
            return
        for i in range(PASSES):
            if self.known[i] and i in self.active:
                step = self.drift * max(self.x[i], self.floor)
                self.P[i][i] += step * step * dt
        for c, (log, var) in self.ratio.items():
            self.ratio[c] = (log, var + self.ratio_drift ** 2 * dt)
        self.t = frame

    def update(self, h, innovation, noise, extra_var=0.0):
        ph = [sum(self.P[i][j] * h[j] for j in range(PASSES)) for i in range(PASSES)]
        s = sum(h[i] * ph[i] for i in range(PASSES)) + noise + extra_var
        gain = [p / s for p in ph]
        self.x = [max(0.0, self.x[i] + gain[i] * innovation) for i in range(PASSES)]
        self.P = [[self.P[i][j] - gain[i] * ph[j] for j in range(PASSES)] for i in range(PASSES)]
        return s

    def probe(self, frame, i, error):
        super().probe(frame, i, error)
        self.advance(frame)
        noise = (self.probe_noise * max(error, self.floor)) ** 2
        if not self.known[i]:
            self.known[i] = True
            for j in range(PASSES):
                self.P[i][j] = self.P[j][i] = 0.0
            self.x[i], self.P[i][i] = error, noise
            return
        h = [1.0 if j == i else 0.0 for j in range(PASSES)]
        self.update(h, error - self.x[i], noise)

    def shown(self, frame, configuration, error):
        if not all(self.known) or configuration == BEST:
            return
        self.advance(frame)
        a = [self.k[i][configuration[i]] for i in range(PASSES)]
        total = sum(a[i] * self.x[i] for i in range(PASSES))
        if total <= 0:
            return
        log, var = self.ratio.get(configuration, (0.0, self.ratio_spread ** 2))
        predicted = math.exp(log) * total
        innovation = math.log(error + self.floor) - math.log(predicted + self.floor)
        scale = predicted / (predicted + self.floor)
        h = [scale * a[i] / total for i in range(PASSES)]
        s = self.update(h, innovation, self.shown_noise ** 2, var)
        self.ratio[configuration] = (log + var / s * innovation, var - var * var / s)


ORDERS = {"turn": Turn, "weighted": Weighted, "trend": Trend, "filtered": Filtered}


def replay(order, k, s, period, phase, frames, truths):
    """ρ at each truth frame for one schedule."""
    active = [i for i in range(PASSES) if max(v[alone(i, CHEAPEST)] for v in s.values()) > 1e-6]
    p = order(k, active)
    shown = (CHEAPEST,) * PASSES
    probes = [(FIRST_PERIOD * (n + 1), i) for n, i in enumerate(active)]
    t = probes[-1][0] + period + phase
    while t < max(frames):
        probes.append((t, None))
        t += period
    rho, pending = {}, sorted(frames)
    for t, i in probes:
        while pending and pending[0] <= t:
            f = pending.pop(0)
            rho[f] = rank_correlation(p.estimates(f), truths[f])
        if t not in s:
            continue
        i = p.pick(t) if i is None else i
        p.probe(t, i, s[t][alone(i, CHEAPEST)])
        p.shown(t, shown, s[t][shown])
    for f in pending:
        rho[f] = rank_correlation(p.estimates(f), truths[f])
    return rho


def log_probes(path):
    """[(frame, shown configuration, its measured error or None, [(probe configuration, error)])] of
    a governed run's log (glbudget run --log), one per probe frame."""
    parse = lambda text: tuple(int(x) for x in text.split(":"))  # noqa: E731
    out, seen = [], set()
    with open(path) as f:
        for row in csv.DictReader(f):
            if not is_probe(row) or int(row["frame"]) in seen:
                continue
            seen.add(int(row["frame"]))
            streams = []
            for item in filter(None, row["probe_streams"].split(";")):
                c, _, e = item.partition("=")
                streams.append((parse(c), float(e)))
            shown_error = float(row["probe_error"]) if row["probe_error"] else None
            out.append((int(row["frame"]), parse(row["configuration"]), shown_error, streams))
    return sorted(out)


def only_pass(c):
    changed = [i for i in range(PASSES) if c[i] != 0]
    return changed[0] if len(changed) == 1 and c[changed[0]] == CHEAPEST else -1


def replay_log(order, k, probes, frames, truths):
    """ρ at each truth frame after the log's first sweep, its probes replayed in `order`'s
    estimates (the shown configurations as they were)."""
    active = sorted({only_pass(c) for _, _, _, streams in probes for c, _ in streams} - {-1})
    p = order(k, active)
    rho, probed = {}, set()
    pending = sorted(frames)
    for t, shown, shown_error, streams in probes:
        while pending and pending[0] <= t:
            f = pending.pop(0)
            if probed >= set(active):
                rho[f] = rank_correlation(p.estimates(f), truths[f])
        for c, e in streams:
            if only_pass(c) >= 0:
                p.probe(t, only_pass(c), e)
                probed.add(only_pass(c))
        if shown_error is not None and only_pass(shown) >= 0:
            p.probe(t, only_pass(shown), shown_error)
        elif shown_error is not None:
            p.shown(t, shown, shown_error)
    for f in pending:
        if probed >= set(active):
            rho[f] = rank_correlation(p.estimates(f), truths[f])
    return rho


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("build")
    ap.add_argument("--out", required=True)
    ap.add_argument("--scenes", default="hall,sponza,valley,subway")
    ap.add_argument("--frames", type=int, default=200)
    ap.add_argument("--truth-frames", default="70,85,100,115,130,145,160,175,190")
    ap.add_argument("--periods", default="10,15,17,20,25")
    ap.add_argument("--orders", default="turn,weighted,filtered")
    ap.add_argument("--phases", type=int, default=5, help="starts of the settled probes per period")
    ap.add_argument("--logs", default="", help="folders of governed runs' logs (SCENE.csv, as error_estimates.py "
                    "keeps them at the demo's size): their probes replayed as they came, in turn's and filtered's estimates")
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    frames = [int(x) for x in a.truth_frames.split(",")]
    periods = [int(x) for x in a.periods.split(",")]
    orders = a.orders.split(",")
    rows, log_rows = [], []
    for scene in a.scenes.split(","):
        s = series(a.build, scene, a.frames, a.out)
        truths = {f: truth(a.build, scene, f, a.out) for f in frames}
        k = level_ratios(s)
        fresh = []
        for f in frames:
            est = {c: sum(truths[f][alone(i, c[i])] if c[i] else 0.0 for i in range(PASSES)) for c in truths[f]}
            fresh.append(rank_correlation(est, truths[f]))
        for period in periods:
            for order in orders:
                values = []
                for phase in range(0, period, max(1, period // a.phases)):
                    values += list(replay(ORDERS[order], k, s, period, phase, frames, truths).values())
                rows.append((scene, period, order, statistics.fmean(values), min(values),
                             sum(v < 0.95 for v in values) / len(values), statistics.fmean(fresh)))
                print(f"{scene} period {period} {order}: mean rho {rows[-1][3]:.3f}, lowest {rows[-1][4]:.3f}, "
                      f"under 0.95 {rows[-1][5]:.2f}", flush=True)
        logs = [os.path.join(d, f"{scene}.csv") for d in filter(None, a.logs.split(","))]
        logs = [log for log in logs if os.path.exists(log)]
        for order in ("turn", "trend", "filtered") if logs else ():
            values = []
            for log in logs:
                values += list(replay_log(ORDERS[order], k, log_probes(log), frames, truths).values())
            log_rows.append((scene, len(logs), order, statistics.fmean(values), min(values),
                             sum(v < 0.95 for v in values) / len(values), len(values)))
            print(f"{scene} {len(logs)} logs {order}: mean rho {log_rows[-1][3]:.3f}, lowest {log_rows[-1][4]:.3f}, "
                  f"under 0.95 {log_rows[-1][5]:.2f}", flush=True)
    command = "python3 bench/evaluation/probe_schedules.py build --out " + os.path.relpath(a.out) + \
        "".join(f" --{n.replace('_', '-')} {getattr(a, n)}" for n in ("scenes", "periods", "orders", "logs")
                if getattr(a, n) != ap.get_default(n))
    lines = ["# Probe schedules replayed against every frame's true errors", "", "```sh", command, "```", "",
             f"The demo at {SIZE[0]}x{SIZE[1]}, detail {DETAIL}, frames 0-{a.frames - 1}; truth (all 729 configurations) "
             f"at frames {a.truth_frames}. After the first sweep (a pass every {FIRST_PERIOD} frames), a probe every "
             f"P frames from {a.phases} phases; at each truth frame, Spearman's ρ of the additive estimate from each "
             "pass's latest probe (levels between by the median ratio k) against the truth. Fresh: the additive estimate "
             "from that frame's own single-pass errors (no staleness).", "",
             "| scene | P (frames) | order | mean ρ | lowest ρ | share under 0.95 | fresh: mean ρ |",
             "|---|---:|---|---:|---:|---:|---:|"]
    lines += [f"| {r[0]} | {r[1]} | {r[2]} | {r[3]:.3f} | {r[4]:.3f} | {r[5]:.2f} | {r[6]:.3f} |" for r in rows]
    if log_rows:
        lines += ["", "Governed runs' own probes (--logs), replayed as they came, at the truth frames after each run's "
                  "first sweep: turn is the governor's estimate (each pass's latest probe; levels between by the median "
                  "k here), filtered moves it between probes by the error measured of the image shown.", "",
                  "| scene | runs | estimate | mean ρ | lowest ρ | share under 0.95 | (run, frame) pairs |",
                  "|---|---:|---|---:|---:|---:|---:|"]
        lines += [f"| {r[0]} | {r[1]} | {r[2]} | {r[3]:.3f} | {r[4]:.3f} | {r[5]:.2f} | {r[6]} |" for r in log_rows]
    with open(os.path.join(a.out, "probe-schedules.md"), "w") as f:
        f.write("\n".join(lines) + "\n")
    print("wrote", os.path.join(a.out, "probe-schedules.md"))


if __name__ == "__main__":
    main()
