#!/usr/bin/env python3
"""Writes a SYNTHETIC frame log for testing the power-model replay (not a recording).

The log has the shim's CSV format (GLBUDGET_LOG plus the power columns) for a six-pass
renderer with three levels per pass, whose power follows a hidden model of the paper's form
exactly (k_v = chi*Ins_v, k_f = chi*Ins_f + psi*Tex_f, per-pass k_b) plus Gaussian sensor
noise. Halfway through, the camera enters another area where the passes' shares of the work
change (more reflections and metal, fewer shadows). The configuration changes every 60 frames, so a replay sees both frames in the fitted
configuration and frames whose prediction reuses the coefficients. A small fixed-function
pass (an overlay) is outside the variant table. gpu_ns is left empty ("not measured").

Outputs, next to this script: synthetic_six_pass.csv, synthetic_six_pass.variants.json,
synthetic_six_pass.profile.json. Deterministic: rerunning reproduces them byte for byte.
"""
import hashlib
import json
import math
import os
import random

HERE = os.path.dirname(os.path.abspath(__file__))
NAME = "synthetic_six_pass"
FRAMES = 300
FRAMES_PER_CONFIGURATION = 60
NOISE_W = 0.2
PROFILE = {"p_min_w": 20.0, "p_max_w": 60.0,
           "saturation": {"batches": 5000.0, "vertices": 3.0e7, "fragments": 4.0e8}}
CHI, PSI = 0.02, 0.3
PASSES = ["resolution", "shading", "reflections", "shadows", "metals", "antialiasing"]
CONFIGURATIONS = [[1, 1, 1, 1, 1, 1], [0, 2, 1, 0, 2, 1], [2, 2, 2, 2, 2, 2],
                  [0, 0, 0, 0, 0, 0], [1, 0, 2, 1, 0, 2]]
# Per-pass factor on batches and fragments in the second area (from frame AREA_CHANGE on).
AREA_CHANGE = 150
SECOND_AREA = [1.0, 0.6, 3.0, 0.3, 1.5, 1.0]
OVERLAY = {"pass": "fixed-function", "k": (0.2, 0.1, 0.5), "counts": (2, 8, 1.0e5)}


def variant_hash(pass_name, level):
    return hashlib.sha1(f"synthetic {pass_name} level {level}".encode()).hexdigest()[:16]


def variant_cost(i, level):
    quality = 3 - level
    return {"ins_v": 20.0 + 4.0 * i, "ins_f": 40.0 * quality + 15.0 * i, "tex_f": quality + (i % 2)}


def pass_counts(rng, i, t):
    phase = 0.05 * t * (1.0 + 0.37 * i) + i
    wave = 1.0 + 0.6 * math.sin(phase)
    other = 1.0 + 0.5 * math.cos(1.7 * phase + 0.3)
    jitter = lambda: rng.uniform(0.9, 1.1)
    area = SECOND_AREA[i] if t >= AREA_CHANGE else 1.0
    return (round(300.0 * area * wave * jitter()), round(1.0e6 * other * jitter()),
            round(2.0e7 * area * wave * other * jitter()))


def alpha(k, counts):
    s = PROFILE["saturation"]
    return (k[0] * counts[0] / s["batches"] + k[1] * counts[1] / s["vertices"]
            + k[2] * counts[2] / s["fragments"])


def main():
    rng = random.Random(20261122)
    rows = ["frame,time_ns,context,pass,batches,vertices,fragments,primitives,gpu_ns,power_w,energy_j,sensor"]
    energy = 0.0
    frame_seconds = 1.0 / 30.0
    for t in range(FRAMES):
        configuration = CONFIGURATIONS[(t // FRAMES_PER_CONFIGURATION) % len(CONFIGURATIONS)]
        passes, total_alpha = [], 0.0
        for i, name in enumerate(PASSES):
            level = configuration[i]
            cost = variant_cost(i, level)
            k = (0.5 + 0.2 * i, CHI * cost["ins_v"], CHI * cost["ins_f"] + PSI * cost["tex_f"])
            counts = pass_counts(rng, i, t)
            total_alpha += alpha(k, counts)
            passes.append((variant_hash(name, level), counts))
        passes.append((OVERLAY["pass"], OVERLAY["counts"]))
        total_alpha += alpha(OVERLAY["k"], OVERLAY["counts"])
        power = PROFILE["p_min_w"] + (PROFILE["p_max_w"] - PROFILE["p_min_w"]) * -math.expm1(-total_alpha)
        power += rng.gauss(0.0, NOISE_W)
        energy += power * frame_seconds
        for pass_hash, (b, v, f) in passes:
            rows.append(f"{t},{round(t * frame_seconds * 1e9)},0x1,{pass_hash},{b},{v},{int(f)},"
                        f"{v // 3},,{power:.4f},{energy:.4f},synthetic")
    with open(os.path.join(HERE, NAME + ".csv"), "w") as out:
        out.write("\n".join(rows) + "\n")

    table = {"passes": [{"name": name, "levels": [dict(hash=variant_hash(name, level), **variant_cost(i, level))
                                                    for level in range(3)]}
                        for i, name in enumerate(PASSES)]}
    with open(os.path.join(HERE, NAME + ".variants.json"), "w") as out:
        json.dump(table, out, indent=1)
        out.write("\n")
    with open(os.path.join(HERE, NAME + ".profile.json"), "w") as out:
        json.dump(PROFILE, out, indent=1)
        out.write("\n")


if __name__ == "__main__":
    main()
