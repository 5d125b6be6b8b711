#!/usr/bin/env python3
"""What quality probes cost (issue 14), each figure against a baseline in the same run.

The demo under the shim with its manifest, forced to a middle configuration (so that probe
frames draw two streams, s0 and one s_i^lmax), unpaced, with probes every PERIOD frames and
without. Per-frame time comes from the difference of a long and a short run (start-up
cancels); the probe frame's own time from the log's time_ns (the swap-to-swap interval of a
probe frame against the median of the others). Runs are interleaved (rounds) so drift in the
machine's load hits every case alike.
"default" in --periods leaves GLBUDGET_PROBE_PERIOD unset with a budget in force (probes every
10 frames until every pass has been probed, then every 60), the configuration still forced.
--ssim cpu,gpu measures each period with each place of the probe frames' comparison
(GLBUDGET_PROBE_SSIM: the governor thread beside the app, or the app's compute shaders);
--follow 1,0 with streams that follow until their first different call, and drawn whole
(GLBUDGET_PROBE_FOLLOW).
Usage: probe_overhead.py BUILD_DIR [--rounds N] [--scene S] [--size WxH] [--periods 10,30,default]
                         [--ssim auto|cpu|gpu,...] [--follow 1,0] [--config LEVELS]
"""
import csv
import os
import statistics
import tempfile

from demo_bench import MANIFEST, PROFILE, Build, clean_environment, parser, run


def frame_intervals(log):
    """Swap-to-swap interval (s) and probe flag per frame, from the shim's log."""
    times, probe = {}, {}
    with open(log) as f:
        for row in csv.DictReader(f):
            frame = int(row["frame"])
            times[frame] = int(row["time_ns"])
            probe[frame] = row.get("probe") == "1"
    frames = sorted(times)
    return [((times[b] - times[a]) * 1e-9, probe[b]) for a, b in zip(frames, frames[1:])]


def main():
    ap = parser(__doc__, rounds=3, frames=60)
    ap.add_argument("--periods", default="10,30")
    ap.add_argument("--config", default="1,0,0,1,0,0")
    ap.add_argument("--ssim", default="auto")
    ap.add_argument("--follow", default="1")
    a = ap.parse_args()
    modes = a.ssim.split(",")
    follows = a.follow.split(",")
    build = Build(a)
    shimmed = dict(clean_environment(), LD_PRELOAD=build.shim, GLBUDGET_SENSOR="cpu", GLBUDGET_CONFIG=MANIFEST,
                   GLBUDGET_FORCE=a.config)
    cases = {"no probes": dict(shimmed, GLBUDGET_PROBE_PERIOD="0")}
    for p in a.periods.split(","):
        if p == "default":
            # A budget starts the governor and so the default probes; at 100 % it draws the best
            # configuration (one probe stream), so its baseline is the same run without probes.
            governed = dict(shimmed, GLBUDGET_POWER="100%", GLBUDGET_PROFILE=PROFILE)
            cases["governed, none"] = dict(governed, GLBUDGET_PROBE_PERIOD="0")
        for mode in modes:
            for follow in follows:
                suffix = (f", {mode}" if len(modes) > 1 else "") + (f", follow {follow}" if len(follows) > 1 else "")
                knobs = dict(GLBUDGET_PROBE_SSIM=mode, GLBUDGET_PROBE_FOLLOW=follow)
                if p == "default":
                    cases[f"governed, default{suffix}"] = dict(governed, **knobs)
                else:
                    cases[f"probes every {p}{suffix}"] = dict(shimmed, GLBUDGET_PROBE_PERIOD=p, **knobs)
    args = build.demo_cmd()
    per_frame = {name: [] for name in cases}
    probe_ratio = {name: [] for name in cases}
    with tempfile.TemporaryDirectory() as tmp:
        for _ in range(a.rounds):
            for name, env in cases.items():
                log = os.path.join(tmp, "log.csv")
                long = run(args + ["--frames", str(a.frames)], dict(env, GLBUDGET_LOG=log))
                short = run(args + ["--frames", "5"], env)
                per_frame[name].append((long - short) / (a.frames - 5))
                intervals = frame_intervals(log)[5:]
                plain = [t for t, p in intervals if not p]
                probes = [t for t, p in intervals if p]
                if plain and probes:
                    probe_ratio[name].append(statistics.median(probes) / statistics.median(plain))
    def baseline_of(name):
        return statistics.median(per_frame["governed, none" if name.startswith("governed") else "no probes"])
    print(f"demo {a.scene} {a.size}, detail 0.2, forced {a.config}, {a.frames} frames unpaced, {a.rounds} rounds")
    print(f"{'case':<26}{'ms/frame':>10}{'vs none':>9}{'probe frame / other':>21}")
    for name in cases:
        ms = statistics.median(per_frame[name]) * 1e3
        ratio = statistics.median(probe_ratio[name]) if probe_ratio[name] else float("nan")
        print(f"{name:<26}{ms:>10.1f}{ms / (baseline_of(name) * 1e3):>9.2f}{ratio:>21.2f}")


if __name__ == "__main__":
    main()
