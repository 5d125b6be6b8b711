#!/usr/bin/env python3
"""`glbudget calibrate --app` on the demo renderer with its manifest, checked against ground truth.

1. The measured table: every level of every pass the manifest changes is measured, and the
   levels' costs go the way their shaders do (metals' samples, the base shading models,
   reflections and FXAA off).
2. Ground truth: the demo itself can draw each level (its own --config builds that level's
   program). Its programs, instrumented by the shim (GLBUDGET_DUMP, no manifest), must execute
   what calibrate measured from the shim's variants, within 3 % per fragment (the camera path
   differs a little: the forced levels draw at other frames).
   With a profile, the app runs again with the cpu sensor, each level alone, and the costs of
   its frames are fitted into the table. Last, the error run: each level's error against the best
   by probes, and its ratio k to the pass's cheapest level's, which must be near the true ratio
   (the demo's own images of that level against its best, over five frames).
3. The shim reads the table: a governed run with GLBUDGET_COSTS names no problem; one with a
   table for another manifest (a pass with one level fewer) says which pass and runs on; and
   without --output the table lands where the shim looks ($XDG_CACHE_HOME/glbudget/demo.variants.json).
4. Bad input: no manifest, a program that does not exist, one that draws nothing: a
   `glbudget:` line and a non-zero status.
With --sanitized (the ASan build's command and shim): step 1's table only, smaller, with no
ground truth (minutes under the sanitizer), and a --power-frames too few to measure refused.
Usage: calibrate_app_test.py GLBUDGET DEMO MANIFEST PROFILE WORK_DIR [--sanitized]
"""
import glob
import json
import os
import shutil
import subprocess
import sys

glbudget, demo, manifest, profile, work = sys.argv[1:6]
SANITIZED = sys.argv[6:] == ["--sanitized"]
# The shadow map at a quarter of its default side: at these sizes its depth pass was half of
# each frame's time, and its levels still halve and quarter it.
DEMO_ARGS = ["--scene", "hall", "--detail", "0.05", "--shadow-size", "512", "--width", "96" if SANITIZED else "160",
             "--height", "54" if SANITIZED else "90"]
failures = []


def check(condition, what):
    if not condition:
        failures.append(what)
        print("FAIL:", what, flush=True)


def finish():
    print("ok" if not failures else f"{len(failures)} failure(s)")
    sys.exit(1 if failures else 0)


def clean_env(**extra):
    env = {k: v for k, v in os.environ.items() if not k.startswith("GLBUDGET_") and k != "LD_PRELOAD"}
    env["XDG_CACHE_HOME"] = os.path.join(work, "cache")
    env["XDG_CONFIG_HOME"] = os.path.join(work, "config")
    env.update(extra)
    return env


def calibrate(args, env=None):
    return subprocess.run([glbudget, "calibrate", "--app"] + args, env=env or clean_env(), capture_output=True,
                          text=True, timeout=300)


shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)

# 1. The table.
table_path = os.path.join(work, "demo.variants.json")
POWER_FRAMES = 4 if SANITIZED else 11  # the sanitizer's demo draws a frame in a quarter of a second
r = calibrate(["--config", manifest, "--frames", "6", "--power-frames", str(POWER_FRAMES), "--error-probes", "2" if SANITIZED else "3",
               "--sensor", "cpu",
               "--profile", profile, "--output", table_path, "--", demo] + DEMO_ARGS + ["--frames", "100000"])
print(r.stdout, r.stderr)
check(r.returncode == 0, f"calibrate --app exit status {r.returncode}")
table = json.load(open(table_path))
passes = {p["name"]: p["levels"] for p in table["passes"]}
check(list(passes) == ["resolution", "base", "reflections", "shadows", "metals", "antialiasing"],
      f"passes in manifest order: {list(passes)}")
for name, levels in passes.items():
    for i, level in enumerate(levels):
        if "hashes" in level:
            check(level.get("measured") is True, f"{name} level {i} measured")
ins = {name: [level.get("ins_f", 0.0) for level in levels] for name, levels in passes.items()}
tex = {name: [level.get("tex_f", 0.0) for level in levels] for name, levels in passes.items()}
check(ins["metals"][0] > 5 * ins["metals"][1] > 5 * ins["metals"][2] / 2 and ins["metals"][2] > 0,
      f"metals: 60 > 6 > 2 samples per fragment: {ins['metals']}")
check(tex["metals"][0] > tex["metals"][1] > tex["metals"][2], f"metals texels fall with samples: {tex['metals']}")
check(ins["base"][0] > ins["base"][1] > ins["base"][2], f"base: microfacet > point lights > cheap: {ins['base']}")
check(ins["reflections"][0] > ins["reflections"][1] > 10 * ins["reflections"][2],
      f"reflections: 64 samples > 16 > off: {ins['reflections']}")
check(ins["antialiasing"][2] < ins["antialiasing"][0] / 10, f"FXAA off is a copy: {ins['antialiasing']}")
check(ins["shadows"][0] == ins["shadows"][1] == ins["shadows"][2],
      f"shadow-map sizes draw one program: {ins['shadows']}")
check([l.get("fragment_scale", 1.0) for l in passes["resolution"]] == [1.0, 0.8 ** 2, 0.6 ** 2],
      "the render scale's fragment scales")
check(passes["reflections"][1].get("hashes") == passes["reflections"][0].get("hashes"),
      "a level that only holds uniforms keeps the app program's log name")
# The power run: each level alone, the cheapest (the range's bottom), their power, and the costs
# fitted from them.
costs = table.get("platform_costs", {})
check(sorted(costs) == ["batch", "fragment", "instruction", "texel", "vertex"] and
      all(v >= 0 for v in costs.values()), f"platform costs fitted: {costs}")
configurations = [c["configuration"] for c in table.get("power", {}).get("configurations", [])]
check(len(configurations) == 14 and configurations[0] == "0:0:0:0:0:0" and "0:0:0:0:2:0" in configurations and
      configurations[-1] == "2:2:2:2:2:2",
      f"level 0, each of the 12 other levels alone, then the cheapest: {configurations}")
check(all(c["power_w"] > 0 and c["frames"] >= 2 for c in table["power"]["configurations"]), "each one's power")
# Measured in short blocks, round after round, the second half of the rounds the first's mirror
# image: 11 power frames are 9 measured, three a block of five, in four rounds (4 are 2, in two
# rounds of blocks of three); every configuration's frames lie about the run's middle (one block
# each, in order, put them from about 0.04 to 0.96).
power = table["power"]
rounds, block = (2, 3) if POWER_FRAMES == 4 else (4, 5)
check(power.get("rounds") == rounds and power.get("block_frames") == block,
      f"{rounds} rounds of blocks of {block} frames: {power.get('rounds')}, {power.get('block_frames')}")
check(all(c["frames"] >= rounds * (block - 2) - 1 for c in power["configurations"]),
      f"each configuration's frames from every round: {[c['frames'] for c in power['configurations']]}")
places = {c["configuration"]: c.get("mean_place", -1) for c in power["configurations"]}
check(all(0.4 <= p <= 0.6 for p in places.values()), f"each configuration's frames centred on the run: {places}")

# The error run: each level's error against the best, probed, and k = e(l) / e(lmax).
measured_errors = table.get("errors", {}).get("levels", [])
check(len(measured_errors) == 12 and all(e["probes"] >= 2 and e["error"] >= 0 for e in measured_errors),
      f"each of the 12 levels below the best probed: {measured_errors}")
ratios = {name: [level.get("error_ratio") for level in levels[1:]] for name, levels in passes.items()}
check(all(k[-1] == 1.0 and k[0] is not None and 0.0 <= k[0] < 1.0 for k in ratios.values()),
      f"k of each pass's cheapest level 1, the middle one in [0, 1): {ratios}")
# Too few power frames: each switch's first two are left out, so nothing past the first
# configuration would be measured.
r = calibrate(["--config", manifest, "--power-frames", "2", "--", demo])
check(r.returncode == 2 and "--power-frames 2 is not 0 (no power run) or a number of frames in [3," in r.stderr,
      f"--power-frames 2 measures nothing past the first configuration: {r.stderr!r}")
if SANITIZED:
    finish()

# Ground truth for k: the demo's own images with one pass at a level, against its best, over
# five frames (1 - SSIM by `glbudget ssim`). The calibrated k must be near it, and nearer than
# the stand-in l / lmax = 0.5 taken together.
truth_dir = os.path.join(work, "truth_errors")
configs = ["0,0,0,0,0,0"] + [",".join(str(l) if j == i else "0" for j in range(6)) for i in range(6) for l in (1, 2)]
for config in configs:
    subprocess.run([demo] + DEMO_ARGS + ["--frames", "21", "--config", config, "--dump", truth_dir], check=True,
                   capture_output=True, env=clean_env())
truth = {config: 0.0 for config in configs[1:]}
frames = range(4, 21, 4)
for f in frames:  # each frame's images of the 12 levels against its best, in one command
    image = lambda config: os.path.join(truth_dir, f"hall_c{config.replace(',', '')}_f{f:05d}.png")
    out = subprocess.run([glbudget, "ssim", image(configs[0])] + [image(c) for c in configs[1:]], capture_output=True,
                         text=True, check=True).stdout.splitlines()
    for config, line in zip(configs[1:], out):
        truth[config] += (1 - float(line.split()[0])) / len(frames)
calibrated_off = stand_in_off = 0.0
for i, name in enumerate(passes):
    e = [truth[",".join(str(l) if j == i else "0" for j in range(6))] for l in (1, 2)]
    k_true = e[0] / e[1]
    k = ratios[name][0]
    print(f"{name}: k calibrated {k:.3f}, true {k_true:.3f} (errors {e[0]:.5f} / {e[1]:.5f})")
    check(k is not None and abs(k - k_true) <= 0.15, f"{name}: k {k} against the true {k_true:.3f}")
    calibrated_off += abs((k or 0.0) - k_true)
    stand_in_off += abs(0.5 - k_true)
check(calibrated_off < stand_in_off / 2, f"calibrated k off by {calibrated_off:.3f} in all, l / lmax by {stand_in_off:.3f}")

# 2. Ground truth: the demo's own programs at each of its levels.
MARKERS = {"metals": "METAL_SAMPLES", "base": "SHADING_MODEL", "reflections": "u_kernel_taps",
           "antialiasing": "FXAA_STEPS"}
for level in (0, 1, 2):
    dump = os.path.join(work, f"truth{level}")
    config = ",".join([str(level)] * 6)
    subprocess.run([demo] + DEMO_ARGS + ["--frames", "8", "--config", config],
                   env=clean_env(LD_PRELOAD=os.path.join(os.path.dirname(os.path.dirname(glbudget)),
                                                         "interpose/libglbudget.so"), GLBUDGET_DUMP=dump),
                   check=True, capture_output=True)
    for name, marker in MARKERS.items():
        if name in ("reflections", "antialiasing") and level == 2:
            continue  # the demo skips these passes at 2; the manifest draws a copy instead
        invocations = instructions = 0.0
        for f in glob.glob(os.path.join(dump, "program-*.json")):
            program = json.load(open(f))
            stages = {s["stage"]: s for s in program["stages"]}
            fragment = stages.get("fragment")
            if not fragment or not fragment.get("measured") or not fragment["measured"]["invocations"]:
                continue
            def source_of(stage):
                path = os.path.join(dump, f"shader-{stages[stage]['shader']}.{stage}.glsl") if stage in stages else ""
                return open(path).read() if path and os.path.exists(path) else ""
            source, vertex_source = source_of("fragment"), source_of("vertex")
            if marker not in source and marker not in vertex_source:
                continue
            m = fragment["measured"]
            invocations += m["invocations"]
            instructions += m["invocations"] * m["instructions_per_invocation"]
        check(invocations > 0, f"the demo's own {name} program at level {level} drew")
        if invocations > 0:
            truth = instructions / invocations
            measured = ins[name][level]
            check(abs(measured - truth) <= 0.03 * truth,
                  f"{name} level {level}: calibrate measured {measured:.1f} instructions per fragment, "
                  f"the demo's own program {truth:.1f}")
            print(f"{name} level {level}: calibrated {measured:.1f}, the demo's own {truth:.1f}")

# 3. The shim reads it.
governed = clean_env(LD_PRELOAD=os.path.join(os.path.dirname(os.path.dirname(glbudget)), "interpose/libglbudget.so"),
                     GLBUDGET_CONFIG=manifest, GLBUDGET_POWER="50%", GLBUDGET_PROFILE=profile,
                     GLBUDGET_SENSOR="cpu", GLBUDGET_PROBE_PERIOD="0", GLBUDGET_COSTS=table_path)
r = subprocess.run([demo] + DEMO_ARGS + ["--frames", "4"], env=governed, capture_output=True, text=True)
check(r.returncode == 0, f"governed run with the table: exit {r.returncode}")
check("costs" not in r.stderr and "levels in the manifest" not in r.stderr,
      f"no complaint about the table: {r.stderr!r}")
other = json.load(open(table_path))
other["passes"][4]["levels"].pop()
other_path = os.path.join(work, "other.variants.json")
json.dump(other, open(other_path, "w"))
r = subprocess.run([demo] + DEMO_ARGS + ["--frames", "4"], env=dict(governed, GLBUDGET_COSTS=other_path),
                   capture_output=True, text=True)
check(r.returncode == 0, f"governed run with another manifest's table: exit {r.returncode}")
check("glbudget: " in r.stderr and "pass 'metals' has 3 levels in the manifest and 2 in the measured costs" in r.stderr,
      f"the mismatched pass is named: {r.stderr!r}")
without = dict(governed)
del without["GLBUDGET_COSTS"]
r = subprocess.run([demo] + DEMO_ARGS + ["--frames", "4"], env=without, capture_output=True, text=True)
check("glbudget calibrate --app" in r.stderr, f"without a table the shim says how to measure one: {r.stderr!r}")
r = calibrate(["--config", manifest, "--frames", "2", "--error-probes", "0", "--", demo] + DEMO_ARGS +
              ["--frames", "100000"])  # the error run is the first calibration's to check
default = os.path.join(work, "cache", "glbudget", "demo.variants.json")
check(r.returncode == 0 and os.path.exists(default), f"default output {default}: {r.returncode} {r.stderr!r}")
check("glbudget: calibrate --app: no platform profile" in r.stderr and "platform_costs" not in open(default).read(),
      f"without a profile the power run is skipped, and said so: {r.stderr!r}")
r = subprocess.run([demo] + DEMO_ARGS + ["--frames", "4"], env=without, capture_output=True, text=True)
check(r.returncode == 0 and "glbudget calibrate --app" not in r.stderr, f"the default table is found: {r.stderr!r}")

# 4. Bad input.
r = calibrate(["--", demo] + DEMO_ARGS)
check(r.returncode == 2 and r.stderr.startswith("glbudget: calibrate --app: no manifest for"),
      f"no manifest: {r.returncode} {r.stderr!r}")
r = calibrate(["--config", manifest, "--", "/no/such/program"])
check(r.returncode == 2 and "glbudget: calibrate --app: cannot run /no/such/program" in r.stderr,
      f"missing program: {r.returncode} {r.stderr!r}")
r = calibrate(["--config", manifest, "--frames", "2", "--", "true"])
check(r.returncode == 1 and "glbudget: calibrate --app: the app linked no program" in r.stderr,
      f"a program that draws nothing: {r.returncode} {r.stderr!r}")
r = calibrate(["--config", manifest, "--frames", "0", "--", "true"])
check(r.returncode == 2 and "glbudget: calibrate --app: --frames 0 is not" in r.stderr, f"--frames 0: {r.stderr!r}")
finish()
