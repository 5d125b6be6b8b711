#!/usr/bin/env python3
"""`glbudget ssim --gpu` (GpuSsim in an EGL surfaceless context) against `glbudget ssim` (the
CPU path) on PNG pairs: 8-bit RGB, RGBA, grey and 16-bit grey files, sizes from 1x1 up, scales
1, 2 and 4. Both print one number with nine decimals; they agree within 1e-4. Without an
OpenGL context --gpu says so on one `glbudget: ` line and exits 2.

usage: gpu_cli_test.py path/to/glbudget
"""
import os
import re
import subprocess
import sys
import tempfile

import numpy as np
from PIL import Image

TOLERANCE = 1e-4


def frame(width, height, rng):
    """A smooth colour frame with an edge and some texture."""
    y, x = np.mgrid[0:height, 0:width].astype(np.float64)
    base = 40 + 150 * x / max(width - 1, 1) * (1 - 0.4 * y / max(height - 1, 1))
    disc = (x - 0.6 * width) ** 2 + (y - 0.4 * height) ** 2 < (0.2 * min(width, height)) ** 2
    base = np.where(disc, 220.0, base) + 6 * rng.standard_normal((height, width))
    return np.clip(np.stack([base, 0.8 * base + 20, 255 - base], -1), 0, 255)


def noisy(image, sigma, rng):
    return np.clip(image + rng.normal(0, sigma, image.shape), 0, 255)


def pairs(rng):
    f = frame(320, 180, rng)
    yield "rgb frame vs noise", f.astype(np.uint8), noisy(f, 10, rng).astype(np.uint8), "RGB"
    g = frame(97, 61, rng)[..., 0]
    yield "grey frame vs noise", g.astype(np.uint8), noisy(g, 12, rng).astype(np.uint8), "L"
    rgba = np.concatenate([f, rng.integers(0, 256, f.shape[:2] + (1,))], -1)
    rgba2 = np.concatenate([noisy(f, 5, rng), rng.integers(0, 256, f.shape[:2] + (1,))], -1)
    yield "rgba (alpha ignored)", rgba.astype(np.uint8), rgba2.astype(np.uint8), "RGBA"
    g16 = (frame(130, 70, rng)[..., 1] * 257).astype(np.uint16)
    g16b = np.clip(g16.astype(np.int64) + rng.integers(-2000, 2000, g16.shape), 0, 65535).astype(np.uint16)
    yield "16-bit grey", g16, g16b, "I;16"
    yield "random 7x5", rng.integers(0, 256, (5, 7, 3)).astype(np.uint8), \
        rng.integers(0, 256, (5, 7, 3)).astype(np.uint8), "RGB"
    yield "1x1", np.array([[[10, 200, 30]]], np.uint8), np.array([[[40, 180, 90]]], np.uint8), "RGB"
    yield "identical", f.astype(np.uint8), f.astype(np.uint8), "RGB"


def run(glbudget, args, env=None):
    return subprocess.run([glbudget, "ssim", *args], capture_output=True, text=True, env=env)


def main():
    glbudget = sys.argv[1]
    rng = np.random.default_rng(14)
    failures, worst = [], 0.0
    with tempfile.TemporaryDirectory() as directory:
        paths = []
        for index, (name, a, b, mode) in enumerate(pairs(rng)):
            pa, pb = (os.path.join(directory, f"{index}{side}.png") for side in "ab")
            Image.fromarray(a, mode).save(pa)
            Image.fromarray(b, mode).save(pb)
            paths.append((pa, pb))
            for scale in ("1", "2", "4"):
                cpu = run(glbudget, [pa, pb, "--scale", scale])
                gpu = run(glbudget, [pa, pb, "--scale", scale, "--gpu"])
                if cpu.returncode or gpu.returncode or not re.fullmatch(r"-?\d\.\d{9}\n", gpu.stdout):
                    failures.append(f"{name} scale {scale}: cpu {cpu.returncode} {cpu.stdout!r} {cpu.stderr!r}, "
                                    f"gpu {gpu.returncode} {gpu.stdout!r} {gpu.stderr!r}")
                    continue
                diff = abs(float(gpu.stdout) - float(cpu.stdout))
                worst = max(worst, diff)
                print(f"{name:24s} scale {scale}  cpu {cpu.stdout.strip():>12s}  gpu {gpu.stdout.strip():>12s}"
                      f"  |diff| {diff:.1e}")
                if diff > TOLERANCE or (name == "identical" and gpu.stdout != "1.000000000\n"):
                    failures.append(f"{name} scale {scale}: cpu {cpu.stdout.strip()} gpu {gpu.stdout.strip()}")
        print(f"max |gpu - cpu| = {worst:.1e}")

        # No EGL vendor library, hence no surfaceless platform: a clear refusal.
        env = dict(os.environ, __EGL_VENDOR_LIBRARY_FILENAMES="/nonexistent/egl_vendor.json")
        refused = run(glbudget, [*paths[0], "--gpu"], env)
        lines = refused.stderr.splitlines()
        if refused.returncode != 2 or refused.stdout or len(lines) != 1 or \
                not lines[0].startswith("glbudget: no OpenGL context for --gpu"):
            failures.append(f"without EGL: status {refused.returncode}, {refused.stdout!r}, {refused.stderr!r}")
        # Bad input is still refused before any context is made.
        bad = run(glbudget, [paths[0][0], paths[1][0], "--gpu"])
        if bad.returncode != 2 or not bad.stderr.startswith("glbudget: "):
            failures.append(f"different sizes with --gpu: status {bad.returncode}, {bad.stderr!r}")
    for failure in failures:
        print("FAILED:", failure)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
