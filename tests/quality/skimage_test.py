#!/usr/bin/env python3
"""`glbudget ssim` against scikit-image on generated image pairs (docs/ssim.md).

    skimage_test.py GLBUDGET [--keep DIR]

Writes PNG pairs: rendered-like frames against noisy, blurred, shifted, re-rendered at half
resolution, banded and JPEG-compressed versions of themselves, identical pairs, constant,
black and white images, grey, RGBA and 16-bit files, sizes from 1x1 to 4096x4096, and the
scale knob at 2 and 4. Each pair's SSIM from `GLBUDGET ssim A B --scale S` must agree within
1e-4 with skimage.metrics.structural_similarity(gaussian_weights=True, sigma=1.5,
use_sample_covariance=False, data_range=255) of the same Rec. 709 luma (box-averaged first
for scales 2 and 4). Where skimage refuses (a side under 11 pixels), the expectation is our
documented extension computed here with scipy: the same filter, the crop cut to (n - 1) // 2.
Also checks that bad input exits with status 2 and one line `glbudget: ...` on stderr.
Prints a table; exits 1 on any failure.
"""
import argparse
import functools
import io
import os
import subprocess
import sys
import tempfile

import numpy as np
from PIL import Image
from scipy.ndimage import gaussian_filter
from skimage.metrics import structural_similarity

TOLERANCE = 1e-4
SIGMA, TRUNCATE, RADIUS = 1.5, 3.5, 5
C1, C2 = (0.01 * 255) ** 2, (0.03 * 255) ** 2


# ---- images -------------------------------------------------------------------------------

@functools.lru_cache(maxsize=None)
def rendered(width, height, shift=0.0, seed=0):
    """A rendered-like RGB frame: sky gradient, checkered floor in perspective, lit spheres.
    Cached (several pairs share a frame); callers never write into it."""
    v, u = np.mgrid[0:height, 0:width].astype(np.float64)
    u = (u + 0.5 + shift) / width
    v = (v + 0.5) / height
    aspect = width / height
    horizon = 0.42
    sky = np.stack([90 + 60 * v / horizon, 140 + 70 * v / horizon, 230 - 20 * v / horizon], axis=-1)
    depth = 0.25 / np.maximum(v - horizon, 1e-3)
    checker = ((np.floor((u - 0.5) * aspect * depth * 6) + np.floor(depth * 6)) % 2)[..., None]
    fog = np.minimum(1.0, depth / 12)[..., None]
    floor = (checker * np.array([60, 50, 40]) + (1 - checker) * np.array([180, 170, 150])) * (1 - fog) + fog * 190
    image = np.where((v < horizon)[..., None], sky, floor)
    rng = np.random.default_rng(seed)
    image += rng.normal(0, 2.0, image.shape)  # texture grain
    for cx, cy, r, colour in ((0.3, 0.6, 0.14, (220, 80, 60)), (0.62, 0.55, 0.1, (70, 200, 90)),
                              (0.8, 0.75, 0.07, (200, 200, 230))):
        dx, dy = (u - cx) * aspect / r, (v - cy) / r
        r2 = dx * dx + dy * dy
        nz = np.sqrt(np.maximum(0, 1 - r2))
        lambert = np.maximum(0, -0.5 * dx - 0.6 * dy + 0.62 * nz)
        specular = np.maximum(0, -0.3 * dx - 0.4 * dy + 0.87 * nz) ** 40
        shaded = np.array(colour) * (0.1 + 0.9 * lambert)[..., None] + 255 * specular[..., None]
        image = np.where((r2 < 1)[..., None], shaded, image)
    frame = to_u8(image)
    frame.flags.writeable = False
    return frame


def to_u8(image):
    return np.clip(np.round(image), 0, 255).astype(np.uint8)


def noisy(image, sigma, seed):
    return to_u8(image + np.random.default_rng(seed).normal(0, sigma, image.shape))


def blurred(image):
    padded = np.pad(image.astype(np.float64), ((1, 1), (1, 1), (0, 0)), mode="edge")
    h, w = image.shape[:2]
    return to_u8(sum(padded[dy:dy + h, dx:dx + w] for dy in range(3) for dx in range(3)) / 9)


def half_resolution(width, height):
    """The render-scale knob: rendered at half size, upscaled bilinearly."""
    low = Image.fromarray(rendered(width // 2, height // 2))
    return np.asarray(low.resize((width, height), Image.BILINEAR))


@functools.lru_cache(maxsize=None)
def large(width, height, seed):
    """A rendered-like frame at a size where drawing it per pixel in numpy takes seconds: drawn
    at a quarter of each side, upscaled bicubically, with full-resolution grain. Cached."""
    low = Image.fromarray(rendered(width // 4, height // 4, seed=seed))
    frame = noisy(np.asarray(low.resize((width, height), Image.BICUBIC)), 2.0, seed)
    frame.flags.writeable = False
    return frame


def jpeg(image, quality):
    buffer = io.BytesIO()
    Image.fromarray(image).save(buffer, format="JPEG", quality=quality)
    return np.asarray(Image.open(io.BytesIO(buffer.getvalue())).convert("RGB"))


def constant(width, height, value, channels=3):
    return np.full((height, width, channels), value, np.uint8)


def random_rgb(width, height, seed):
    return np.random.default_rng(seed).integers(0, 256, (height, width, 3), dtype=np.uint8)


# ---- the expectation ------------------------------------------------------------------------

def luma(array):
    """Rec. 709 luma of 8-bit RGB code values; grey as it is; 16-bit scaled to [0, 255]."""
    values = array.astype(np.float64)
    if array.dtype == np.uint16:
        values *= 255.0 / 65535.0
    if values.ndim == 2:
        return values
    if values.shape[2] < 3:
        return values[..., 0]
    return 0.2126 * values[..., 0] + 0.7152 * values[..., 1] + 0.0722 * values[..., 2]


def box_downscale(image, scale):
    """Means of scale x scale blocks; the right and bottom blocks average what they cover."""
    h, w = image.shape
    H, W = -(-h // scale), -(-w // scale)
    padded = np.full((H * scale, W * scale), np.nan)
    padded[:h, :w] = image
    return np.nanmean(padded.reshape(H, scale, W, scale), axis=(1, 3))


def definition(x, y):
    """Our SSIM in numpy: skimage's formula, filter and crop, the crop cut on short axes."""
    def blur(image):
        return gaussian_filter(image, sigma=SIGMA, truncate=TRUNCATE, mode="reflect")
    ux, uy = blur(x), blur(y)
    vx, vy, vxy = blur(x * x) - ux * ux, blur(y * y) - uy * uy, blur(x * y) - ux * uy
    s = ((2 * ux * uy + C1) * (2 * vxy + C2)) / ((ux * ux + uy * uy + C1) * (vx + vy + C2))
    my, mx = (min(RADIUS, (n - 1) // 2) for n in s.shape)
    return s[my:s.shape[0] - my, mx:s.shape[1] - mx].mean(dtype=np.float64)


def expected(a, b, scale):
    x, y = luma(a), luma(b)
    if scale > 1:
        x, y = box_downscale(x, scale), box_downscale(y, scale)
    if min(x.shape) < 2 * RADIUS + 1:
        return definition(x, y), "definition", None
    reference = structural_similarity(x, y, gaussian_weights=True, sigma=SIGMA,
                                      use_sample_covariance=False, data_range=255)
    # The definition checked against skimage where both apply (the column's worst shows it),
    # except on the 4096x4096 pair: seconds, and the smaller pairs check the same formula.
    if x.size > 4_000_000:
        return reference, "skimage", None
    return reference, "skimage", abs(reference - definition(x, y))


# ---- the pairs ------------------------------------------------------------------------------

def pairs():
    frame = rendered(640, 360)
    big = rendered(1920, 1080)
    grey = luma(rendered(257, 129)).round().astype(np.uint8)
    return [
        ("frame vs noise sigma 8", frame, noisy(frame, 8, 1), 1),
        ("frame vs 3x3 blur", frame, blurred(frame), 1),
        ("frame vs camera moved 1 px", frame, rendered(640, 360, shift=1.0), 1),
        ("frame vs render scale 1/2", big, half_resolution(1920, 1080), 1),
        ("frame vs banding, 8 levels", big, to_u8(np.round(big / 32.0) * 32.0), 1),
        ("frame vs JPEG quality 30", rendered(1280, 720), jpeg(rendered(1280, 720), 30), 1),
        ("frame vs noise, --scale 2", frame, noisy(frame, 8, 1), 2),
        ("frame vs render 1/2, --scale 4", big, half_resolution(1920, 1080), 4),
        ("odd size, --scale 4", rendered(101, 77), noisy(rendered(101, 77), 20, 3), 4),
        ("4096x4096 frame vs noise", large(4096, 4096, 4), noisy(large(4096, 4096, 4), 6, 5), 1),
        ("identical frames", frame, frame.copy(), 1),
        ("identical 1x1", constant(1, 1, 77), constant(1, 1, 77), 1),
        ("different 1x1", constant(1, 1, 100), constant(1, 1, 120), 1),
        ("constant 100 vs 130", constant(256, 256, 100), constant(256, 256, 130), 1),
        ("black vs white", constant(64, 64, 0), constant(64, 64, 255), 1),
        ("black vs black", constant(64, 48, 0), constant(64, 48, 0), 1),
        ("white vs white, --scale 2", constant(33, 17, 255), constant(33, 17, 255), 2),
        ("random 3x5", random_rgb(5, 3, 6), random_rgb(5, 3, 7), 1),
        ("random 10x10", random_rgb(10, 10, 8), random_rgb(10, 10, 9), 1),
        ("random 11x11, skimage's least", random_rgb(11, 11, 10), random_rgb(11, 11, 11), 1),
        ("4096x1 strip", rendered(4096, 1), noisy(rendered(4096, 1), 10, 12), 1),
        ("odd 29x13 frame vs noise", rendered(29, 13), noisy(rendered(29, 13), 15, 13), 1),
        ("random noise 300x200", random_rgb(300, 200, 14), random_rgb(300, 200, 15), 1),
        ("grey PNG 257x129 vs noise", grey, noisy(grey[..., None], 10, 16)[..., 0], 1),
        ("RGBA PNG (alpha ignored)", np.dstack([frame, constant(640, 360, 255, 1)]),
         np.dstack([noisy(frame, 5, 17), constant(640, 360, 10, 1)]), 1),
        ("16-bit grey PNG", (grey.astype(np.uint16) * 257), (noisy(grey[..., None], 3, 18)[..., 0].astype(np.uint16) * 257 + 100), 1),
    ]


def write_png(path, array):
    # Little or no deflating: the 4096x4096 pair takes seconds even at level 1.
    level = 0 if array.size > 4_000_000 else 1
    if array.dtype == np.uint16:
        Image.fromarray(array.astype(np.uint16)).save(path, compress_level=level)  # mode I;16
    else:
        Image.fromarray(array).save(path, compress_level=level)


def run_glbudget(glbudget, *args):
    return subprocess.run([glbudget, "ssim", *args], capture_output=True, text=True, timeout=600)


def check_bad_input(glbudget, directory, a, b_other_size):
    """Each case: exit status 2 and exactly one stderr line starting `glbudget: `."""
    cases = [
        ("missing file", [os.path.join(directory, "no-such-image.png"), a]),
        ("different sizes", [a, b_other_size]),
        ("--scale 3", [a, a, "--scale", "3"]),
        ("--scale x", [a, a, "--scale", "x"]),
        ("--scale without value", [a, a, "--scale"]),
        ("one image", [a]),
    ]
    failures = 0
    print("\nbad input: exit status 2 and one line `glbudget: ...` on stderr")
    for name, args in cases:
        result = run_glbudget(glbudget, *args)
        lines = result.stderr.splitlines()
        ok = result.returncode == 2 and len(lines) == 1 and lines[0].startswith("glbudget: ") and not result.stdout
        failures += not ok
        print(f"  {'ok  ' if ok else 'FAIL'} {name:24s} status {result.returncode}: {result.stderr.strip()}")
    return failures


def check_batch(glbudget, directory, a, b, value):
    """Several images against one: a line each (SSIM, tab, path), in order; one that cannot be
    compared is said on stderr and the others still are, with exit status 2."""
    missing = os.path.join(directory, "no-such-image.png")
    result = run_glbudget(glbudget, a, b, a, missing, b)
    lines = [line.split("\t") for line in result.stdout.splitlines()]
    got = [(float(v), path) for v, path in lines] if all(len(line) == 2 for line in lines) else []
    ok = (result.returncode == 2 and len(result.stderr.splitlines()) == 1 and "no-such-image" in result.stderr
          and [path for _, path in got] == [b, a, b] and abs(got[0][0] - value) <= 1e-9
          and got[1][0] == 1.0 and got[2][0] == got[0][0])
    print(f"\nmany images against one: {'ok' if ok else 'FAIL'} (status {result.returncode}, {len(got)} lines)")
    return 0 if ok else 1


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("glbudget", help="the glbudget command")
    parser.add_argument("--keep", help="write the PNG pairs here and keep them")
    options = parser.parse_args()

    with tempfile.TemporaryDirectory() as scratch:
        directory = options.keep or scratch
        os.makedirs(directory, exist_ok=True)
        failures, worst, worst_check = 0, 0.0, 0.0
        print(f"{'pair':34s} {'size':>10s} {'scale':>5s} {'glbudget':>12s} {'expected':>12s} {'|diff|':>9s}  from")
        for index, (name, a, b, scale) in enumerate(pairs()):
            path_a = os.path.join(directory, f"pair{index:02d}_a.png")
            path_b = os.path.join(directory, f"pair{index:02d}_b.png")
            write_png(path_a, a)
            write_png(path_b, b)
            result = run_glbudget(options.glbudget, path_a, path_b, "--scale", str(scale))
            value, source, check = expected(a, b, scale)
            size = f"{a.shape[1]}x{a.shape[0]}"
            if result.returncode != 0:
                failures += 1
                print(f"{name:34s} {size:>10s} {scale:5d}  FAILED: {result.stderr.strip()}")
                continue
            ours = float(result.stdout.split()[0])
            diff = abs(ours - value)
            worst = max(worst, diff)
            if check is not None:
                worst_check = max(worst_check, check)
            bad = not diff <= TOLERANCE
            failures += bad
            print(f"{name:34s} {size:>10s} {scale:5d} {ours:12.8f} {value:12.8f} {diff:9.1e}  {source}{'  FAIL' if bad else ''}")
        print(f"\nmax |glbudget - expected| = {worst:.2e} (tolerance {TOLERANCE:g}); "
              f"max |numpy definition - skimage| = {worst_check:.2e}")
        other_size = os.path.join(directory, "other_size.png")
        write_png(other_size, constant(7, 5, 0))
        failures += check_bad_input(options.glbudget, directory, os.path.join(directory, "pair00_a.png"), other_size)
        a, b = os.path.join(directory, "pair00_a.png"), os.path.join(directory, "pair00_b.png")
        single = run_glbudget(options.glbudget, a, b)
        failures += check_batch(options.glbudget, directory, a, b, float(single.stdout.split()[0]))
    if failures:
        print(f"\n{failures} failure(s)")
        return 1
    print("\nall agree")
    return 0


if __name__ == "__main__":
    sys.exit(main())
