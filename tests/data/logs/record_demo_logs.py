#!/usr/bin/env python3
"""Records the replay logs of the power model from the demo renderer under the shim.

For each scene: the variant table comes from instrumentation dumps (GLBUDGET_DUMP) of three
runs that draw every knob at level 0, 1 and 2; then the scene is rendered under the shim with
the cpu power sensor, paced, in a sequence of configurations that move every knob (render
scale, shadow-map size and reflections off change how many fragments are drawn, the other
levels what each costs), each run continuing the camera path of the one before, and the logs
are joined into one (frames renumbered in order, a
`configuration` column saying which configuration drew each frame, as the governor logs
what it applied) so that the replay sees configuration changes as a running app would.
Writes, per scene, into OUTDIR: demo_<scene>.csv, demo_<scene>.variants.json, and one
demo_<sensor>.profile.json (P_m, P_M of the sensor's range, and the saturation counts).
The committed logs use the cpu estimate, the only source on a machine without a GPU. On a
machine with a real sensor, record with it to check the model against real power, e.g.
`--sensor rapl:domain=uncore --p-min 1.5 --p-max 15` (the range from the GPU's idle and
maximum power, until `glbudget calibrate` measures it).
Usage: record_demo_logs.py BUILD_DIR OUTDIR [--scenes hall,subway] [--frames 40] [--fps 2]
                           [--sensor cpu] [--p-min W --p-max W] [--width 320 --height 180]
                           [--detail 0.05] [--tables DIR] [--in-process]
"""
import argparse
import csv
import json
import os
import subprocess
import tempfile

# The demo's knobs in its --config order; they are the variant table's passes, so a
# configuration column in that order is a configuration of the table's space (3^6 = 729).
KNOBS = ["resolution", "base", "reflections", "shadows", "metals", "antialiasing"]
RENDER_SCALE = [1.0, 0.8, 0.6]          # testapps/demo/config.cpp
SHADOW_MAP = [2048, 1024, 512]
# Programs by a text of their fragment shader (testapps/demo/shaders) -> the knob they belong
# to; the upscale pass has no knob and stays outside the space.
MARKERS = [("Shadow map: depth only", "shadows"), ("SHADING_MODEL", "base"),
           ("METAL_SAMPLES", "metals"), ("u_kernel_taps", "reflections"),
           ("FXAA_STEPS", "antialiasing"), ("Reinhard", None)]
# Levels that skip the pass: reflections and antialiasing at 2 are off.
OFF = {("reflections", 2), ("antialiasing", 2)}
# The recorded sequence (resolution, base, reflections, shadows, metals, antialiasing).
CONFIGS = ["0,0,0,0,0,0", "0,2,0,0,2,0", "1,0,0,1,0,0", "2,1,1,2,1,1",
           "0,0,2,0,1,2", "2,2,2,2,2,2", "1,1,0,0,0,1", "0,0,0,0,0,0"]
WIDTH, HEIGHT, DETAIL = 320, 180, 0.05  # what the committed logs were recorded at


def demo_args():
    return ["--detail", str(DETAIL), "--width", str(WIDTH), "--height", str(HEIGHT)]


def run_demo(build, scene, config, frames, env, start_frame=0):
    demo = os.path.join(build, "testapps/demo/demo")
    full_env = dict(os.environ, LD_PRELOAD=os.path.join(build, "interpose/libglbudget.so"), **env)
    subprocess.run([demo, "--scene", scene, "--frames", str(frames), "--start-frame", str(start_frame),
                    "--config", config] + demo_args(), env=full_env, check=True, capture_output=True)


def knob_of(fragment_source):
    for marker, knob in MARKERS:
        if marker in fragment_source:
            return knob
    return None


def scaled_fraction(scale):
    # The demo rounds the scaled framebuffer's size (renderer.cpp).
    return round(WIDTH * scale) * round(HEIGHT * scale) / float(WIDTH * HEIGHT)


def manifest_path():
    return os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "../../../testapps/demo/glbudget.toml"))


def variant_table(build, scene, through_manifest=False):
    """through_manifest: the levels drawn by the shim's variants (GLBUDGET_FORCE through the
    demo's manifest), as --in-process records them, not by the demo's own --config: a variant's
    source, and so its hash, differs from the demo's own build of that level."""
    # (knob, level) -> {hashes, invocation-weighted sums of the costs}
    found = {}
    for level in range(3):
        config = ",".join([str(level)] * len(KNOBS))
        with tempfile.TemporaryDirectory() as dump:
            if through_manifest:
                run_demo(build, scene, CONFIGS[0], 3,
                         {"GLBUDGET_DUMP": dump, "GLBUDGET_CONFIG": manifest_path(), "GLBUDGET_FORCE": config})
            else:
                run_demo(build, scene, config, 3, {"GLBUDGET_DUMP": dump})
            index = json.load(open(os.path.join(dump, "index.json")))
            for program in index["programs"]:
                figures = json.load(open(os.path.join(dump, program["file"])))
                stages = {s["stage"]: s for s in figures["stages"]}
                frag = stages.get("fragment")
                if not frag or not frag.get("measured") or frag["measured"]["invocations"] == 0:
                    continue  # not drawn in this run
                source = open(os.path.join(dump, "shader-%s.fragment.glsl" % frag["shader"])).read()
                knob = knob_of(source)
                if knob is None:
                    continue
                # Several programs can draw one knob's pass (the skinned soldiers' variants of
                # the base and shadow programs): costs are averaged by invocations.
                entry = found.setdefault((knob, level), {"hashes": [], "v": 0.0, "iv": 0.0, "f": 0.0,
                                                          "if": 0.0, "tf": 0.0})
                # A level that only holds uniforms is dumped as "<program>-level<N>"; the log
                # names what it draws by the app's program.
                entry["hashes"].append(program["hash"].split("-level")[0])
                vert = (stages.get("vertex") or {}).get("measured") or {}
                nv = vert.get("invocations", 0)
                entry["v"] += nv
                entry["iv"] += nv * vert.get("instructions_per_invocation", 0.0)
                nf = frag["measured"]["invocations"]
                entry["f"] += nf
                entry["if"] += nf * frag["measured"]["instructions_per_invocation"]
                entry["tf"] += nf * frag["measured"]["texel_accesses_per_invocation"]
    passes = []
    for knob in KNOBS:
        pass_entry = {"name": knob, "levels": []}
        if knob == "resolution":
            pass_entry["scales"] = ["base", "metals", "reflections"]
            pass_entry["levels"] = [{"fragment_scale": scaled_fraction(s)} for s in RENDER_SCALE]
            passes.append(pass_entry)
            continue
        if knob == "shadows":
            pass_entry["scales"] = ["shadows"]
        for level in range(3):
            if (knob, level) in OFF:
                pass_entry["levels"].append({"draws": False})
                continue
            entry = found.get((knob, level))
            out = {"hashes": sorted(set(entry["hashes"]))} if entry else {}
            if entry:
                out["ins_v"] = entry["iv"] / entry["v"] if entry["v"] else 0.0
                out["ins_f"] = entry["if"] / entry["f"] if entry["f"] else 0.0
                out["tex_f"] = entry["tf"] / entry["f"] if entry["f"] else 0.0
            if knob == "shadows":
                out["fragment_scale"] = (SHADOW_MAP[level] / SHADOW_MAP[0]) ** 2
            pass_entry["levels"].append(out)
        if any(level.get("hashes") for level in pass_entry["levels"]):
            passes.append(pass_entry)  # the scene draws this pass
    return {"passes": passes}


def join_logs(runs, names, out_csv):
    """runs: (log path, the demo's --config or None where the shim's own column says) in order."""
    rows, header, next_frame = [], None, 1
    for path, config in runs:
        with open(path) as f:
            reader = csv.reader(f)
            header = next(reader)
            # The shim logs the levels of its own manifest (the render scale alone when it
            # has none); the demo's own --config is what drew those frames.
            if "configuration" not in header:
                header.append("configuration")
            column = header.index("configuration")
            numbered = {}
            for row in reader:
                frame = numbered.setdefault(row[0], next_frame + len(numbered))
                row = ([str(frame)] + row[1:] + [""])[:len(header)]
                levels = dict(zip(KNOBS, (config or row[column].replace(":", ",")).split(",")))
                row[column] = ":".join(levels[name] for name in names)
                rows.append(row)
            next_frame += len(numbered)
    with open(out_csv, "w", newline="") as f:
        writer = csv.writer(f)
        writer.writerow(header)
        writer.writerows(rows)


def record(build, scene, frames, fps, sensor, table, out_csv, in_process=False):
    names = [p["name"] for p in table["passes"]]
    env = {"GLBUDGET_SENSOR": sensor, "GLBUDGET_FPS": str(fps)}
    with tempfile.TemporaryDirectory() as tmp:
        if in_process:
            # One process steps through the configurations with the shim's manifest
            # (GLBUDGET_FORCE), as a governor switches: no start-up (a power sensor's own,
            # NVML's takes about a second) between configurations.
            log = os.path.join(tmp, "run.csv")
            run_demo(build, scene, CONFIGS[0], frames * len(CONFIGS),
                     dict(env, GLBUDGET_LOG=log, GLBUDGET_CONFIG=manifest_path(),
                          GLBUDGET_FORCE=";".join(CONFIGS), GLBUDGET_FORCE_EVERY=str(frames)))
            join_logs([(log, None)], names, out_csv)
            return
        runs, start = [], 0
        for i, config in enumerate(CONFIGS):
            # Each run continues the camera path where the previous one stopped, so the joined
            # log is one walk through the scene whose configuration changes along the way.
            log = os.path.join(tmp, "run%d.csv" % i)
            run_demo(build, scene, config, frames, dict(env, GLBUDGET_LOG=log), start_frame=start)
            runs.append((log, config))
            start += frames
        join_logs(runs, names, out_csv)


def main():
    global WIDTH, HEIGHT, DETAIL
    ap = argparse.ArgumentParser()
    ap.add_argument("build")
    ap.add_argument("outdir")
    ap.add_argument("--scenes", default="hall,sponza,valley,subway")
    ap.add_argument("--frames", type=int, default=40)
    ap.add_argument("--fps", type=float, default=2)
    ap.add_argument("--sensor", default="cpu", help="GLBUDGET_SENSOR for the recording (default: cpu)")
    ap.add_argument("--p-min", type=float, help="P_m of the profile, W (cpu: its idle default, 10)")
    ap.add_argument("--p-max", type=float, help="P_M of the profile, W (cpu: its max default, 45)")
    ap.add_argument("--width", type=int, default=WIDTH)
    ap.add_argument("--height", type=int, default=HEIGHT)
    ap.add_argument("--detail", type=float, default=DETAIL, help="the demo's scene detail")
    ap.add_argument("--in-process", action="store_true",
                    help="one run per scene, the shim stepping through the configurations (GLBUDGET_FORCE) "
                         "instead of one run per configuration")
    ap.add_argument("--tables", help="take each scene's variant table from DIR/demo_<scene>.variants.json "
                                     "(a recording made before, the same way) instead of measuring it")
    ap.add_argument("--tables-only", action="store_true", help="measure the variant tables, record nothing")
    a = ap.parse_args()
    WIDTH, HEIGHT, DETAIL = a.width, a.height, a.detail
    source = a.sensor.split(":")[0]
    if source == "cpu":
        p_min, p_max = (10.0 if a.p_min is None else a.p_min), (45.0 if a.p_max is None else a.p_max)
    elif a.p_min is None or a.p_max is None:
        ap.error("--sensor %s needs the sensor's range: --p-min W --p-max W" % a.sensor)
    else:
        p_min, p_max = a.p_min, a.p_max
    if not p_max > p_min:
        ap.error("--p-max must be above --p-min")
    os.makedirs(a.outdir, exist_ok=True)
    # The sensor's range and counts that saturate this machine's llvmpipe at the paced rate:
    # the counts only scale the fitted coefficients.
    profile = {"p_min_w": p_min, "p_max_w": p_max,
               "saturation": {"batches": 5000.0, "vertices": 5.0e6, "fragments": 2.0e8}}
    json.dump(profile, open(os.path.join(a.outdir, "demo_%s.profile.json" % source), "w"), indent=1)
    for scene in a.scenes.split(","):
        if a.tables:
            table = json.load(open(os.path.join(a.tables, "demo_%s.variants.json" % scene)))
        else:
            table = variant_table(a.build, scene, through_manifest=a.in_process)
        json.dump(table, open(os.path.join(a.outdir, "demo_%s.variants.json" % scene), "w"), indent=1)
        if a.tables_only:
            continue
        record(a.build, scene, a.frames, a.fps, a.sensor, table, os.path.join(a.outdir, "demo_%s.csv" % scene),
               a.in_process)
        print("recorded", scene, flush=True)


if __name__ == "__main__":
    main()
