#!/usr/bin/env python3
"""What the governor costs the app's frames (issue 13: the render thread's added time per frame
with the governor running, goal <= 1 %), against a baseline in the same run.

The demo under the shim with its manifest, unpaced, logging with the cpu sensor, in two cases:
  - "logging": no budget, the shim observes only;
  - "governor": GLBUDGET_POWER=100% with the same profile and no probes, so the governor thread
    runs (fits, predicts all configurations, selects) while the configuration stays the best:
    the frames draw the same work and only the governor's own cost differs.
Per-frame time comes from the difference of a long and a short run (start-up cancels); runs
are interleaved (rounds) so drift in the machine's load hits both cases alike. The governor's
thread shares the machine's cores with the app's (llvmpipe renders on both here), so this is
its whole cost to the frame rate, not only the hand-over on the render thread.
Usage: governor_overhead.py BUILD_DIR [--rounds N] [--scene S] [--size WxH] [--frames N]
"""
import os
import statistics
import tempfile

from demo_bench import MANIFEST, PROFILE, Build, clean_environment, parser, run


def main():
    a = parser(__doc__, rounds=5, frames=300).parse_args()
    build = Build(a)
    logging = dict(clean_environment(), LD_PRELOAD=build.shim, GLBUDGET_SENSOR="cpu", GLBUDGET_CONFIG=MANIFEST,
                   GLBUDGET_COSTS="off")
    cases = {
        "logging": logging,
        "governor": dict(logging, GLBUDGET_POWER="100%", GLBUDGET_PROBE_PERIOD="0", GLBUDGET_SELECT_FRAMES="30",
                         GLBUDGET_PROFILE=PROFILE),
    }
    args = build.demo_cmd()
    per_frame = {name: [] for name in cases}
    with tempfile.TemporaryDirectory() as tmp:
        for _ in range(a.rounds):
            for name, env in cases.items():
                env = dict(env, GLBUDGET_LOG=os.path.join(tmp, name + ".csv"))
                long = run(args + ["--frames", str(a.frames)], env)
                short = run(args + ["--frames", "10"], env)
                per_frame[name].append((long - short) / (a.frames - 10))
    print(f"demo {a.scene} {a.size}, detail 0.2, best configuration, {a.frames} frames unpaced, {a.rounds} rounds; "
          f"the governor selects every 30 frames")
    print(f"{'case':<12}{'ms/frame':>10}{'vs logging':>12}{'rounds (ms/frame)':>40}")
    baseline = statistics.median(per_frame["logging"])
    for name in cases:
        ms = statistics.median(per_frame[name]) * 1e3
        rounds = " ".join(f"{t * 1e3:.2f}" for t in per_frame[name])
        print(f"{name:<12}{ms:>10.2f}{ms / (baseline * 1e3):>12.3f}{rounds:>40}")


if __name__ == "__main__":
    main()
