#!/usr/bin/env python3
"""What the SSIM scale knob costs in accuracy on the demo's own frames (docs/ssim.md).

    scale_trade.py --demo BUILD/testapps/demo/demo --glbudget BUILD/cli/glbudget [--out DIR]
                   [--width 1920 --height 1080] [--scenes hall,sponza,valley,subway]

Renders each scene's frame in the best configuration and in cheaper ones (one pass at a time
at its cheapest level, then everything cheapest), and prints SSIM(best, cheaper) at full
resolution with the change that --scale 2 and --scale 4 make; then, since the governor ranks
configurations by their error e = 1 - SSIM, how many of each scene's pairs of configurations
a scale puts in the other order than full resolution does. The time each scale takes is
ssim_bench's (bench/quality/ssim_bench.cpp); `glbudget ssim` would add PNG decoding.
"""
import argparse
import os
import subprocess
import sys
import tempfile

PASSES = ["resolution", "base shading", "reflections", "shadows", "metals", "antialiasing"]


def render(demo, scene, config, width, height, frame, directory):
    subprocess.run([demo, "--scene", scene, "--width", str(width), "--height", str(height), "--frames", "1",
                    "--start-frame", str(frame), "--config", config, "--dump", directory],
                   check=True, capture_output=True, text=True)
    return os.path.join(directory, f"{scene}_c{config.replace(',', '')}_f{frame:05d}.png")


def ssim(glbudget, a, b, scale):
    result = subprocess.run([glbudget, "ssim", a, b, "--scale", str(scale)], check=True, capture_output=True, text=True)
    return float(result.stdout.split()[0])


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--demo", required=True)
    parser.add_argument("--glbudget", required=True)
    parser.add_argument("--out", help="keep the frames here")
    parser.add_argument("--width", type=int, default=1920)
    parser.add_argument("--height", type=int, default=1080)
    parser.add_argument("--frame", type=int, default=40, help="frame of the camera path")
    parser.add_argument("--scenes", default="hall,sponza,valley,subway")
    options = parser.parse_args()

    with tempfile.TemporaryDirectory() as scratch:
        directory = options.out or scratch
        os.makedirs(directory, exist_ok=True)
        print(f"demo frames at {options.width}x{options.height}, frame {options.frame}: "
              "SSIM(best, cheaper) and its change at --scale 2 and 4")
        print(f"{'scene':8s} {'cheaper configuration':34s} {'SSIM(1)':>9s} {'s=2 diff':>9s} {'s=4 diff':>9s}")
        worst = {2: 0.0, 4: 0.0}
        swapped = {2: 0, 4: 0}
        compared = 0
        for scene in options.scenes.split(","):
            best = render(options.demo, scene, "0,0,0,0,0,0", options.width, options.height, options.frame, directory)
            configs = [(",".join("2" if i == p else "0" for i in range(6)), f"{PASSES[p]} cheapest") for p in range(6)]
            configs.append(("2,2,2,2,2,2", "everything cheapest"))
            errors = []  # (e at scale 1, 2, 4) per configuration
            for config, name in configs:
                other = render(options.demo, scene, config, options.width, options.height, options.frame, directory)
                full = ssim(options.glbudget, best, other, 1)
                diffs = {s: ssim(options.glbudget, best, other, s) - full for s in (2, 4)}
                for s in diffs:
                    worst[s] = max(worst[s], abs(diffs[s]))
                print(f"{scene:8s} {name + ' ' + config:34s} {full:9.5f} {diffs[2]:+9.5f} {diffs[4]:+9.5f}")
                errors.append({1: 1 - full, 2: 1 - full - diffs[2], 4: 1 - full - diffs[4]})
            for i in range(len(errors)):
                for j in range(i + 1, len(errors)):
                    if errors[i][1] == errors[j][1]:
                        continue
                    compared += 1
                    for s in (2, 4):
                        swapped[s] += (errors[i][1] < errors[j][1]) != (errors[i][s] < errors[j][s])
        print(f"\nlargest |SSIM(s) - SSIM(1)|: scale 2 {worst[2]:.5f}, scale 4 {worst[4]:.5f}")
        print(f"pairs of configurations of a scene whose error order differs from full resolution's: "
              f"scale 2 {swapped[2]} of {compared}, scale 4 {swapped[4]} of {compared}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
