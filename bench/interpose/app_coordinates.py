#!/usr/bin/env python3
"""Shaders in the app's pixels against shaders as written, at 60 % (docs/app_coordinates.md).

probe_offscreen's compose pass finds its texels from gl_FragCoord in three ways (--compose
fragcoord|fetch|size); each is drawn under the shim at 60 % with the default manifest
(shader_coordinates = "app") and with one saying "scaled", and its image compared by SSIM with
the unscaled run's. glmark2's scenes that read gl_FragCoord are run at 60 % with quality
probes both ways: the mean of the probes' error (1 - SSIM against the best configuration).
Usage: app_coordinates.py BUILD_DIR [--size N] [--glmark2-seconds S]
"""
import argparse
import csv
import os
import subprocess
import sys
import tempfile
import time

import numpy as np
from skimage.metrics import structural_similarity

SCENES = ["conditionals", "function", "loop", "ideas"]


def read_ppm(path):
    with open(path, "rb") as f:
        data = f.read()
    header = data.split(maxsplit=4)
    width, height = int(header[1]), int(header[2])
    pixels = np.frombuffer(data[len(data) - width * height * 3:], np.uint8)
    return pixels.reshape(height, width, 3)


def luma_ssim(a, b):
    weights = [0.299, 0.587, 0.114]
    return structural_similarity(a.astype(float) @ weights, b.astype(float) @ weights, data_range=255)


def main():
    p = argparse.ArgumentParser()
    p.add_argument("build")
    p.add_argument("--size", default="128")
    p.add_argument("--glmark2-seconds", type=int, default=3)
    args = p.parse_args()
    shim = os.path.join(args.build, "interpose", "libglbudget.so")
    probe = os.path.join(args.build, "testapps", "probes", "probe_offscreen")
    tmp = tempfile.mkdtemp(prefix="app_coordinates_")
    scaled_manifest = os.path.join(tmp, "scaled.toml")
    with open(scaled_manifest, "w") as f:
        f.write('shader_coordinates = "scaled"\n[[pass]]\nname = "other"\n')
    ways = {"app": {"GLBUDGET_FORCE": "2"},
            "scaled": {"GLBUDGET_FORCE": "2,0", "GLBUDGET_CONFIG": scaled_manifest}}
    base_env = {k: v for k, v in os.environ.items() if not k.startswith("GLBUDGET_")}

    print("probe_offscreen at 60 %: SSIM against the unscaled image")
    print("| compose | as written | in the app's pixels |")
    print("|---|---:|---:|")
    for mode in ["fragcoord", "fetch", "size"]:
        command = [probe, "--frames", "3", "--size", args.size, "--compose", mode, "--out"]
        plain = os.path.join(tmp, "plain.ppm")
        subprocess.run(command + [plain], env=base_env, check=True)
        ssim = {}
        for way, settings in ways.items():
            out = os.path.join(tmp, way + ".ppm")
            env = dict(base_env, LD_PRELOAD=shim, GLBUDGET_SENSOR="cpu", **settings)
            subprocess.run(command + [out], env=env, check=True)
            ssim[way] = luma_ssim(read_ppm(plain), read_ppm(out))
        print(f"| {mode} | {ssim['scaled']:.3f} | {ssim['app']:.3f} |")

    display = ":93"
    xvfb = subprocess.Popen(["Xvfb", display, "-screen", "0", "640x480x24"], stdout=subprocess.DEVNULL,
                            stderr=subprocess.DEVNULL)
    time.sleep(1)
    try:
        print("\nglmark2 -s 320x240 at 60 %, probes every 5 frames: mean probe error")
        print("| scene | as written | in the app's pixels |")
        print("|---|---:|---:|")
        for scene in SCENES:
            error = {}
            for way, settings in ways.items():
                log = os.path.join(tmp, f"{scene}_{way}.csv")
                env = dict(base_env, DISPLAY=display, LD_PRELOAD=shim, GLBUDGET_SENSOR="cpu",
                           GLBUDGET_PROBE_PERIOD="5", GLBUDGET_LOG=log, **settings)
                subprocess.run(["glmark2", "-s", "320x240", "-b", f"{scene}:duration={args.glmark2_seconds}"],
                               env=env, check=True, stdout=subprocess.DEVNULL)
                with open(log) as f:
                    values = [float(r["probe_error"]) for r in csv.DictReader(f) if r["probe_error"]]
                error[way] = sum(values) / len(values) if values else float("nan")
            print(f"| {scene} | {error['scaled']:.3f} | {error['app']:.3f} |")
    finally:
        xvfb.terminate()
    return 0


if __name__ == "__main__":
    sys.exit(main())
