#!/usr/bin/env python3
"""Records the replay logs of the power model from the demo renderer under the shim.

For each scene: the variant table comes from instrumentation dumps (GLBUDGET_DUMP) of runs
that draw every level of the shader-variant passes (base shading, metals); then the scene is
rendered under the shim with the cpu power sensor, paced, in five configurations one after the
other, and the logs are joined into one (frames renumbered in order) so that the replay sees
configuration changes as a running app would. Writes, per scene, into OUTDIR:
  demo_<scene>.csv, demo_<scene>.variants.json, and one demo_cpu.profile.json.
Usage: record_demo_logs.py BUILD_DIR OUTDIR [--scenes hall,subway] [--frames 45] [--fps 2]
"""
import argparse
import csv
import json
import os
import re
import subprocess
import tempfile

# Demo passes by a text of their fragment shader (testapps/demo/shaders), and how a level
# reads in the source. Passes whose program is the same at every level have one level here.
PASSES = [
    ("shadows", "Shadow map: depth only", None),
    ("base", "SHADING_MODEL", ("SHADING_MODEL", ["2", "1", "0"])),
    ("metals", "METAL_SAMPLES", ("METAL_SAMPLES", ["60", "6", "2"])),
    ("reflections", "u_kernel_taps", None),
    ("upscale", "Reinhard", None),
    ("fxaa", "FXAA_STEPS", ("FXAA_STEPS", ["32", "2"])),
]
# Configurations recorded, in order: (resolution, base, reflections, shadows, metals, aa).
# Only shader-variant knobs change, the case the model's reuse (paper §5.4) is about.
CONFIGS = ["0,0,0,0,0,0", "0,1,0,0,1,0", "0,2,0,0,2,0", "0,0,0,0,2,0", "0,2,0,0,0,0"]
DEMO_ARGS = ["--detail", "0.05", "--width", "128", "--height", "72"]


def run_demo(build, scene, config, frames, env):
    demo = os.path.join(build, "testapps/demo/demo")
    full_env = dict(os.environ, LD_PRELOAD=os.path.join(build, "interpose/libglbudget.so"), **env)
    subprocess.run([demo, "--scene", scene, "--frames", str(frames), "--config", config] + DEMO_ARGS,
                   env=full_env, check=True, capture_output=True)


def classify(source):
    for name, marker, level_define in PASSES:
        if marker in source:
            if level_define is None:
                return name, 0
            define, values = level_define
            m = re.search(r"#define\s+%s\s+(\S+)" % define, source)
            return name, values.index(m.group(1)) if m and m.group(1) in values else 0
    return None, None


def variant_table(build, scene):
    levels = {}  # (pass, level) -> {hash, ins_v, ins_f, tex_f}
    for config in ["0,0,0,0,0,0", "0,1,0,0,1,1", "0,2,0,0,2,0"]:
        with tempfile.TemporaryDirectory() as dump:
            run_demo(build, scene, config, 3, {"GLBUDGET_DUMP": dump})
            index = json.load(open(os.path.join(dump, "index.json")))
            for program in index["programs"]:
                figures = json.load(open(os.path.join(dump, program["file"])))
                stages = {s["stage"]: s for s in figures["stages"]}
                frag = stages.get("fragment")
                if not frag or not frag.get("measured") or frag["measured"]["invocations"] == 0:
                    continue  # not drawn in this run
                source = open(os.path.join(dump, "shader-%s.fragment.glsl" % frag["shader"])).read()
                name, level = classify(source)
                if name is None or "#define SKINNED" in source:
                    continue  # skinned variants: only the Subway soldiers, named apart below
                vert = stages.get("vertex", {}).get("measured") or {}
                levels[(name, level)] = {
                    "hash": program["hash"],
                    "ins_v": vert.get("instructions_per_invocation", 0.0),
                    "ins_f": frag["measured"]["instructions_per_invocation"],
                    "tex_f": frag["measured"]["texel_accesses_per_invocation"],
                }
    passes = []
    for name, _, _ in PASSES:
        found = [levels[(name, l)] for l in range(3) if (name, l) in levels]
        if found:
            passes.append({"name": name, "levels": found})
    return {"passes": passes}


def record(build, scene, frames, fps, out_csv):
    rows, header, next_frame = [], None, 1
    for config in CONFIGS:
        with tempfile.NamedTemporaryFile(suffix=".csv") as log:
            run_demo(build, scene, config, frames,
                     {"GLBUDGET_LOG": log.name, "GLBUDGET_SENSOR": "cpu", "GLBUDGET_FPS": str(fps)})
            with open(log.name) as f:
                reader = csv.reader(f)
                header = next(reader)
                numbered = {}
                for row in reader:
                    frame = numbered.setdefault(row[0], next_frame + len(numbered))
                    rows.append([str(frame)] + row[1:])
                next_frame += len(numbered)
    with open(out_csv, "w", newline="") as f:
        writer = csv.writer(f)
        writer.writerow(header)
        writer.writerows(rows)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("build")
    ap.add_argument("outdir")
    ap.add_argument("--scenes", default="hall,sponza,valley,subway")
    ap.add_argument("--frames", type=int, default=45)
    ap.add_argument("--fps", type=float, default=2)
    a = ap.parse_args()
    os.makedirs(a.outdir, exist_ok=True)
    # The cpu sensor's range (its defaults) and counts that saturate this machine's llvmpipe
    # at the paced rate: they only scale the fitted coefficients.
    profile = {"p_min_w": 10.0, "p_max_w": 45.0,
               "saturation": {"batches": 5000.0, "vertices": 5.0e6, "fragments": 2.0e8}}
    json.dump(profile, open(os.path.join(a.outdir, "demo_cpu.profile.json"), "w"), indent=1)
    for scene in a.scenes.split(","):
        table = variant_table(a.build, scene)
        json.dump(table, open(os.path.join(a.outdir, "demo_%s.variants.json" % scene), "w"), indent=1)
        record(a.build, scene, a.frames, a.fps, os.path.join(a.outdir, "demo_%s.csv" % scene))
        print("recorded", scene)


if __name__ == "__main__":
    main()
