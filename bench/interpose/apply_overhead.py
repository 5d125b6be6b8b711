#!/usr/bin/env python3
"""What applying configurations costs (issue 12), each figure against a baseline in the same run.

  1. frame time of the demo at its best configuration: without the shim, under the shim with
     no manifest, and under the shim with the demo's manifest loaded and nothing changed
     (GLBUDGET_FORCE at the best levels: every program shadowed, every uniform fanned out);
     per-frame time from the difference of a long and a short run, so start-up cancels;
  2. start-up: the time to build the variants of all the demo's programs, as the difference
     of a one-frame run with and without the manifest;
  3. frame times around switches: a GLBUDGET_FORCE list stepped every K frames, each switch's
     first frame against the larger of the two configurations' median frames (a switch that
     costs nothing lies between them: llvmpipe still finishes the old frame's rasterisation
     in the new frame's interval). Variants are compiled ahead at link time; the driver builds
     the shaders it blits with at the first blit of each kind, which the shim makes ahead on
     tiny images (GLBUDGET_WARM_BLITS, compared on and off, with its start-up cost); first
     visits are shown apart. Also with no manifest: the window's scale alone, 100/80/60/50 %.
Runs are interleaved (rounds), so drift in the machine's load hits every case alike.
Usage: apply_overhead.py BUILD_DIR [--rounds N] [--scene S] [--size WxH] [--switches "A;B;..."] [--every K]
                         [--switches-only]
"""
import csv
import os
import statistics
import tempfile

from demo_bench import MANIFEST, Build, clean_environment, parser, run


def main():
    ap = parser(__doc__, rounds=5, frames=40)
    ap.add_argument("--switches", default="0,0,0,0,0,0;2,2,2,2,2,2;1,1,1,1,1,1;0,2,1,0,2,1",
                    help="the configurations stepped through, ';' between them (GLBUDGET_FORCE's form)")
    ap.add_argument("--every", type=int, default=8, help="frames per configuration")
    ap.add_argument("--switches-only", action="store_true", help="only the frame times around switches")
    a = ap.parse_args()
    build = Build(a)
    shim, manifest = build.shim, MANIFEST
    base = clean_environment()
    cases = {
        "no shim": base,
        "shim, no manifest": dict(base, LD_PRELOAD=shim, GLBUDGET_SENSOR="cpu"),
        "shim, manifest, best levels": dict(base, LD_PRELOAD=shim, GLBUDGET_SENSOR="cpu", GLBUDGET_CONFIG=manifest,
                                            GLBUDGET_FORCE="0,0,0,0,0,0"),
    }

    demo_cmd = build.demo_cmd
    if not a.switches_only:
        frame_times(a, cases, demo_cmd)
    switch_times(a, shim, manifest, base, demo_cmd)


def frame_times(a, cases, demo_cmd):
    short, long_ = 1, 1 + a.frames
    times = {name: {"short": [], "long": []} for name in cases}
    for _ in range(a.rounds):
        for name, env in cases.items():
            times[name]["short"].append(run(demo_cmd(short), env))
            times[name]["long"].append(run(demo_cmd(long_), env))
    med = {n: {k: statistics.median(v) for k, v in t.items()} for n, t in times.items()}
    frame_ms = {n: (m["long"] - m["short"]) * 1e3 / a.frames for n, m in med.items()}
    print(f"{a.scene} at {a.size}, detail 0.2, best configuration; medians of {a.rounds} interleaved rounds")
    print(f"{'case':<32}{'ms/frame':>10}{'ratio':>8}{'1-frame run s':>15}{'start-up vs no shim s':>23}")
    for n in cases:
        print(f"{n:<32}{frame_ms[n]:>10.2f}{frame_ms[n] / frame_ms['no shim']:>8.3f}"
              f"{med[n]['short']:>15.3f}{med[n]['short'] - med['no shim']['short']:>23.3f}")
    build_s = med["shim, manifest, best levels"]["short"] - med["shim, no manifest"]["short"]
    print(f"variants of all the demo's programs built at start-up: {build_s * 1e3:.0f} ms "
          f"(one-frame run with the manifest minus without)")


def switch_times(a, shim, manifest, base, demo_cmd):
    """A for K frames, B for K frames, ..., three times round; with the blits of a switch warmed
    ahead (the default) and without (GLBUDGET_WARM_BLITS=0); with the demo's manifest and with
    none (the window's scale, the built-in knob, stepped through its four levels)."""
    k = a.every
    cases = [("the demo's manifest", manifest, a.switches.split(";")), ("no manifest (the window alone)", None,
                                                                       ["0", "1", "2", "3"])]
    for label, config, configs in cases:
        for warm in ("1", "0"):
            env = dict(base, LD_PRELOAD=shim, GLBUDGET_SENSOR="cpu", GLBUDGET_FORCE=";".join(configs),
                       GLBUDGET_FORCE_EVERY=str(k), GLBUDGET_WARM_BLITS=warm)
            if config:
                env["GLBUDGET_CONFIG"] = config
            print(f"\n{label}, GLBUDGET_WARM_BLITS={warm}:")
            one_switch_run(env, configs, k, demo_cmd)
        # What warming costs at start-up: a one-frame run with and without it, interleaved.
        starts = {"1": [], "0": []}
        for _ in range(a.rounds):
            for warm in starts:
                env = dict(base, LD_PRELOAD=shim, GLBUDGET_SENSOR="cpu", GLBUDGET_FORCE=";".join(configs),
                           GLBUDGET_FORCE_EVERY=str(k), GLBUDGET_WARM_BLITS=warm)
                if config:
                    env["GLBUDGET_CONFIG"] = config
                starts[warm].append(run(demo_cmd(1), env))
        added = (statistics.median(starts["1"]) - statistics.median(starts["0"])) * 1e3
        print(f"{label}: a one-frame run takes {added:.0f} ms longer with the blits warmed "
              f"(medians of {a.rounds} interleaved rounds)")


def one_switch_run(env, configs, k, demo_cmd):
    with tempfile.TemporaryDirectory() as tmp:
        log = os.path.join(tmp, "switch.csv")
        run(demo_cmd(k * len(configs) * 3 + 1), dict(env, GLBUDGET_LOG=log))
        swaps = {}
        with open(log) as f:
            for row in csv.DictReader(f):
                swaps[int(row["frame"])] = (int(row["time_ns"]), row["configuration"])
    frames = sorted(swaps)
    durations = {f: (swaps[f][0] - swaps[f - 1][0]) / 1e6 for f in frames if f - 1 in swaps}
    by_config = {}
    for f, d in durations.items():
        by_config.setdefault(swaps[f][1], []).append(d)
    medians = {c: statistics.median(v) for c, v in by_config.items()}
    worst = 0.0
    print(f"switches every {k} frames through {len(configs)} configurations (frame time: swap to swap; "
          f"the first frame after a switch against the larger median of the old and the new configuration)")
    print(f"{'frame':>6} {'from':<14}{'to':<14}{'ms':>9}{'median ms':>11}{'ratio':>8}  visit")
    seen = {swaps[frames[0]][1]}
    worst_first = 0.0
    for f in frames:
        if f - 1 in swaps and f in durations and swaps[f][1] != swaps[f - 1][1]:
            old, new = swaps[f - 1][1], swaps[f][1]
            reference = max(medians[old], medians[new])
            ratio = durations[f] / reference
            first = new not in seen
            seen.add(new)
            if first:
                worst_first = max(worst_first, ratio)
            else:
                worst = max(worst, ratio)
            print(f"{f:>6} {old:<14}{new:<14}{durations[f]:>9.2f}{reference:>11.2f}{ratio:>8.2f}  {'first' if first else 'again'}")
    print(f"largest ratio at a switch: {worst:.2f} on later visits, {worst_first:.2f} on first visits "
          f"(target: none above 1.5)")


if __name__ == "__main__":
    main()
