#!/usr/bin/env python3
"""The figures only a real GPU gives (issue 17), in one run on a machine lent for minutes.

Run by scripts/gpu-measure on the GPU machine, over the bundle scripts/gpu-bundle made:
  real_gpu.py ROOT OUTDIR [--seconds 420] [--detail 1.0] [--sensor nvml] [--stages ...]
Stages, each skipped when the time left cannot hold it (the summary says which ran):
  1. the GPU: name, driver, power limit, idle power from the energy counter over 3 s;
  2. smoke: the demo without and with the shim (nvml sensor); the log must carry real power;
  3. speed: frame time of the demo unpaced at 1920x1080 and 3840x2160, with and without the
     shim, interleaved (the shim's overhead on a real driver); picks the recording's size and
     pace (of --sizes, the largest whose best configuration draws at 30 fps or more, paced at about
     60 % of its unpaced rate, so configurations differ in GPU load);
  4. record: tests/data/logs/record_demo_logs.py with --sensor nvml --in-process, every scene;
  5. govern: Hall (--govern-scenes) under no budget, then GLBUDGET_POWER 40/50/60 % (nvml, the
     recording's variant table and profile, or --govern-from's);
  6. repeat: the recording again with the same variant tables (NVML's repeatability);
  7. gpu_ssim_bench.
A thread samples energy, power, temperature and clocks every 100 ms into gpu_trace.csv, the
stage named on each row. Writes OUTDIR/summary.md, OUTDIR/summary.json, OUTDIR/gpu_trace.csv and
OUTDIR/results.tar.gz (logs and recordings).
"""
import argparse
import csv
import json
import os
import subprocess
import sys
import tarfile
import threading
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import governed_runs  # noqa: E402  (the windows counted as scripts/evaluate counts them)

SCENES = ["hall", "sponza", "valley", "subway"]
BEST, CHEAPEST = "0,0,0,0,0,0", "2,2,2,2,2,2"


class Gpu:
    """NVML through pynvml (nvidia-ml-py), where the image has it."""

    def __init__(self):
        self.ok = False
        try:
            import pynvml
            self.n = pynvml
            pynvml.nvmlInit()
            self.h = pynvml.nvmlDeviceGetHandleByIndex(0)
            self.ok = True
        except Exception as e:  # noqa: BLE001 - any failure means: no NVML from python
            self.error = str(e)

    def _try(self, f, *args, default=None):
        try:
            return f(*args)
        except Exception:  # noqa: BLE001
            return default

    def info(self):
        if not self.ok:
            return {"nvml": "unavailable: " + self.error}
        n, h = self.n, self.h
        text = lambda v: v.decode() if isinstance(v, bytes) else v  # noqa: E731
        return {"name": text(self._try(n.nvmlDeviceGetName, h)),
                "driver": text(self._try(n.nvmlSystemGetDriverVersion)),
                "power_limit_w": (self._try(n.nvmlDeviceGetEnforcedPowerLimit, h, default=0) or 0) / 1000.0,
                "temperature_c": self._try(n.nvmlDeviceGetTemperature, h, n.NVML_TEMPERATURE_GPU),
                "sm_mhz": self._try(n.nvmlDeviceGetClockInfo, h, n.NVML_CLOCK_SM),
                "memory_mhz": self._try(n.nvmlDeviceGetClockInfo, h, n.NVML_CLOCK_MEM)}

    def sample(self):
        n, h = self.n, self.h
        return (self._try(n.nvmlDeviceGetTotalEnergyConsumption, h), self._try(n.nvmlDeviceGetPowerUsage, h),
                self._try(n.nvmlDeviceGetTemperature, h, n.NVML_TEMPERATURE_GPU),
                self._try(n.nvmlDeviceGetClockInfo, h, n.NVML_CLOCK_SM),
                self._try(n.nvmlDeviceGetClockInfo, h, n.NVML_CLOCK_MEM),
                self._try(lambda: n.nvmlDeviceGetUtilizationRates(h).gpu))

    def energy_j(self):
        return self.n.nvmlDeviceGetTotalEnergyConsumption(self.h) / 1000.0


class Trace(threading.Thread):
    def __init__(self, gpu, path):
        super().__init__(daemon=True)
        self.gpu, self.stage, self.stop = gpu, "start", False
        self.file = open(path, "w", newline="")
        self.writer = csv.writer(self.file)
        self.writer.writerow(["t_s", "stage", "energy_mj", "power_mw", "temperature_c", "sm_mhz", "memory_mhz",
                              "utilization_pct"])
        self.t0 = time.monotonic()

    def run(self):
        while not self.stop:
            row = self.gpu.sample()
            self.writer.writerow(["%.3f" % (time.monotonic() - self.t0), self.stage] + list(row))
            time.sleep(0.1)
        self.file.close()


class Bench:
    def __init__(self, a):
        self.root, self.out, self.a = a.root, a.out, a
        self.bundle = os.path.join(a.root, ".gpu")
        self.demo = os.path.join(self.bundle, "testapps/demo/demo")
        self.shim = os.path.join(self.bundle, "interpose/libglbudget.so")
        self.deadline = time.monotonic() + a.seconds
        self.summary = {"stages": {}, "skipped": []}
        self.lines = []
        base = {k: v for k, v in os.environ.items() if not k.startswith("GLBUDGET_") and k != "LD_PRELOAD"}
        base["LD_LIBRARY_PATH"] = os.environ.get("GLBUDGET_GPU_LIBRARY_PATH", "")
        self.env = base
        self.gpu = Gpu()
        self.trace = Trace(self.gpu, os.path.join(self.out, "gpu_trace.csv")) if self.gpu.ok else None

    def left(self):
        return self.deadline - time.monotonic()

    def say(self, text):
        print(text, flush=True)
        self.lines.append(text)

    def stage(self, name):
        if self.trace:
            self.trace.stage = name
        self.say("\n## %s (%.0f s left)" % (name, self.left()))

    def run(self, args, extra=None, shim=True, timeout=120, name=None):
        env = dict(self.env, **(extra or {}))
        if shim:
            env["LD_PRELOAD"] = self.shim
        start = time.monotonic()
        try:
            p = subprocess.run(args, env=env, capture_output=True, text=True, timeout=max(1, min(timeout, self.left())))
            rc, out, err = p.returncode, p.stdout, p.stderr
        except subprocess.TimeoutExpired as e:
            rc, out, err = "timeout", (e.stdout or b"").decode(errors="replace") if isinstance(e.stdout, bytes) else (e.stdout or ""), \
                (e.stderr or b"").decode(errors="replace") if isinstance(e.stderr, bytes) else (e.stderr or "")
        wall = time.monotonic() - start
        if name:
            with open(os.path.join(self.out, "logs", name + ".txt"), "w") as f:
                f.write("$ %s\nrc %s, %.2f s\n--- stdout\n%s\n--- stderr\n%s\n" % (" ".join(args), rc, wall, out, err))
        return rc, wall, out, err

    def demo_args(self, scene, width, height, frames, config=BEST, start=0):
        return [self.demo, "--scene", scene, "--width", str(width), "--height", str(height), "--detail",
                str(self.a.detail), "--frames", str(frames), "--config", config, "--start-frame", str(start)]

    # 1 ------------------------------------------------------------------------------------
    def info(self):
        self.stage("gpu")
        info = self.gpu.info()
        if self.gpu.ok:
            time.sleep(2)
            e0, t0 = self.gpu.energy_j(), time.monotonic()
            time.sleep(3)
            info["idle_w"] = (self.gpu.energy_j() - e0) / (time.monotonic() - t0)
        self.summary["gpu"] = info
        self.say(json.dumps(info))
        return True

    # 2 ------------------------------------------------------------------------------------
    def smoke(self):
        self.stage("smoke")
        width, height = self.a.size_list[0]
        rc, wall, out, err = self.run(self.demo_args("hall", width, height, 30), shim=False, name="smoke_plain")
        self.say("demo without the shim: rc %s in %.1f s; %s" % (rc, wall, (out + err).strip()[:400]))
        log = os.path.join(self.out, "logs", "smoke.csv")
        rc2, wall2, out2, err2 = self.run(self.demo_args("hall", width, height, 60),
                                          {"GLBUDGET_SENSOR": self.a.sensor, "GLBUDGET_LOG": log}, name="smoke_shim")
        self.say("demo under the shim: rc %s in %.1f s; stderr: %s" % (rc2, wall2, err2.strip()[:600]))
        rows = list(csv.DictReader(open(log))) if os.path.exists(log) else []
        frames = {r["frame"] for r in rows}
        powered = [r for r in rows if r.get("power_w")]
        passes = {r["pass"] for r in rows}
        result = {"plain_rc": rc, "shim_rc": rc2, "frames": len(frames), "passes": len(passes),
                  "rows_with_power": len(powered), "sensor": rows[-1].get("sensor") if rows else None,
                  "power_w_mean": sum(float(r["power_w"]) for r in powered) / len(powered) if powered else None,
                  "fragments_first_frame": sum(float(r["fragments"] or 0) for r in rows if r["frame"] == "2")}
        self.summary["stages"]["smoke"] = result
        self.say(json.dumps(result))
        return rc2 == 0 and len(frames) > 0

    # 3 ------------------------------------------------------------------------------------
    def frame_time(self, scene, width, height, shim, config=BEST, short=20, long=200):
        """Unpaced seconds per frame: two runs' difference, so start-up cancels."""
        extra = {"GLBUDGET_SENSOR": self.a.sensor, "GLBUDGET_LOG": os.path.join(self.out, "logs", "speed.csv")}
        _, t_short, _, _ = self.run(self.demo_args(scene, width, height, short, config), extra, shim=shim)
        rc, t_long, _, _ = self.run(self.demo_args(scene, width, height, long, config), extra, shim=shim)
        return (t_long - t_short) / (long - short) if rc == 0 else None, t_short

    def speed(self):
        self.stage("speed")
        result = {}
        sizes = self.a.size_list
        for width, height in sizes:
            for config in [BEST, CHEAPEST]:
                t, startup = self.frame_time("hall", width, height, shim=False, config=config)
                result["%dx%d %s" % (width, height, config)] = t
                self.say("hall %dx%d %s unpaced: %s ms/frame (start-up and 20 frames %.2f s)" %
                         (width, height, config, "%.2f" % (t * 1e3) if t else "failed", startup))
        size = sizes[0]
        for width, height in sizes[1:]:
            t = result.get("%dx%d %s" % (width, height, BEST))
            if t and t <= 1 / 30.0:
                size = (width, height)
        best = result.get("%dx%d %s" % (size[0], size[1], BEST)) or 1 / 30.0
        fps = max(10, min(60, int(0.6 / best)))
        # The shim's overhead: plain and shimmed runs interleaved, twice.
        overhead = {"plain": [], "shim": []}
        for _ in range(2):
            for kind in ["plain", "shim"]:
                t, _ = self.frame_time("hall", size[0], size[1], shim=(kind == "shim"), long=300)
                if t:
                    overhead[kind].append(t * 1e3)
        result["overhead_ms"] = overhead
        self.say("shim overhead at %dx%d, ms/frame: plain %s, shim %s" % (size[0], size[1], overhead["plain"],
                                                                        overhead["shim"]))
        result["record_size"], result["record_fps"] = list(size), fps
        self.summary["stages"]["speed"] = result
        self.size, self.fps = size, fps
        self.say("recording at %dx%d paced at %d fps" % (size[0], size[1], fps))
        return True

    # 4, 6 ---------------------------------------------------------------------------------
    def record(self, folder, tables=None, per_scene_s=45):
        recorder = os.path.join(self.root, "tests/data/logs/record_demo_logs.py")
        target = os.path.join(self.out, folder)
        frames = max(45, int(round(self.a.config_seconds * self.fps)))
        power_limit = self.summary["gpu"].get("power_limit_w") or 700.0
        idle = self.summary["gpu"].get("idle_w") or 60.0
        done = []
        for scene in SCENES:
            if self.left() < per_scene_s:
                self.summary["skipped"].append("%s %s" % (folder, scene))
                continue
            args = [sys.executable, recorder, self.bundle, target, "--scenes", scene, "--sensor", self.a.sensor,
                    "--p-min", "%.1f" % idle, "--p-max", "%.1f" % power_limit, "--width", str(self.size[0]),
                    "--height", str(self.size[1]), "--detail", str(self.a.detail), "--frames", str(frames),
                    "--fps", str(self.fps)] + (["--tables", tables] if tables else []) + \
                (["--in-process"] if self.a.in_process else [])
            rc, wall, out, err = self.run(args, shim=False, timeout=per_scene_s * 3, name="%s_%s" % (folder, scene))
            self.say("%s %s: rc %s in %.0f s %s" % (folder, scene, rc, wall, err.strip()[-300:]))
            if rc == 0:
                done.append(scene)
                self.say(self.scene_power(os.path.join(target, "demo_%s.csv" % scene)))
        self.summary["stages"][folder] = {"scenes": done, "frames_per_configuration": frames, "fps": self.fps,
                                          "size": list(self.size)}
        return bool(done)

    @staticmethod
    def scene_power(path):
        by_config = {}
        for r in csv.DictReader(open(path)):
            if r.get("power_w"):
                by_config.setdefault(r["configuration"], {})[r["frame"]] = float(r["power_w"])
        return "  W per configuration: " + ", ".join(
            "%s %.1f" % (c, sum(v.values()) / len(v)) for c, v in by_config.items())

    # 5 ------------------------------------------------------------------------------------
    def govern(self):
        """Each of --govern-scenes under no budget, then each of --budgets, one process a run.

        The variant table and profile come from this run's recording, or from --govern-from
        (a recording made before, e.g. tests/data/logs/h100), so a short loan can skip recording."""
        self.stage("govern")
        rec = self.a.govern_from or os.path.join(self.out, "rec1")
        seconds = self.a.govern_seconds
        results = {}
        for scene in self.a.govern_scenes.split(","):
            costs = os.path.join(rec, "demo_%s.variants.json" % scene)
            profile = os.path.join(rec, "demo_%s.profile.json" % self.a.sensor.split(":")[0])
            if not (os.path.exists(costs) and os.path.exists(profile)):
                self.summary["skipped"].append("govern (no recording of %s in %s)" % (scene, rec))
                continue
            frames = int(seconds * self.fps)
            common = {"GLBUDGET_SENSOR": self.a.sensor, "GLBUDGET_FPS": str(self.fps),
                      "GLBUDGET_CONFIG": os.path.join(self.root, "testapps/demo/glbudget.toml"),
                      "GLBUDGET_COSTS": costs, "GLBUDGET_PROFILE": profile, "GLBUDGET_TRANSITION_S": "1"}
            common.update(kv.split("=", 1) for kv in self.a.govern_set)
            for budget in ["none"] + self.a.budgets.split(","):
                if self.left() < seconds + 15:
                    self.summary["skipped"].append("govern %s %s" % (scene, budget))
                    continue
                tag = "%s_%s" % (scene, budget.rstrip("%"))
                log = os.path.join(self.out, "gov", tag + ".csv")
                extra = dict(common, GLBUDGET_LOG=log)
                if budget != "none":
                    extra["GLBUDGET_POWER"] = budget
                rc, wall, out, err = self.run(self.demo_args(scene, self.size[0], self.size[1], frames), extra,
                                              timeout=seconds * 3, name="gov_" + tag)
                none_log = os.path.join(self.out, "gov", scene + "_none.csv")
                results[tag] = dict(self.governed_figures(log, none_log), rc=rc, wall_s=wall)
                self.say("%s %s: %s; stderr: %s" % (scene, budget, json.dumps(results[tag]), err.strip()[-300:]))
        self.summary["stages"]["govern"] = results
        return True

    def governed_figures(self, log, none_log):
        """The run's frames, probes and last budget, and for a budgeted run its 1-s windows and
        mean power as bench/gpu/governed_runs.py counts them (scripts/evaluate's way: a meter's
        windows from a second after the first selection, against the budget in force)."""
        if not os.path.exists(log):
            return {}
        rows = list(csv.DictReader(open(log)))
        if not rows:
            return {"frames": 0}
        last = max(rows, key=lambda r: int(r["frame"]))
        out = {"frames": len({r["frame"] for r in rows}),
               "budget_w": float(last["budget_w"]) if last.get("budget_w") else None,
               "last_configuration": last.get("configuration"),
               "probe_frames": len({r["frame"] for r in rows if r.get("probe") not in (None, "", "0")})}
        if out["budget_w"] is None:
            return out
        try:
            f = governed_runs.figures(log, none_log, self.fps, 1.0)
        except (ValueError, KeyError, ZeroDivisionError) as e:
            out["figures_error"] = repr(e)
            return out
        out.update(windows=f["windows"], windows_kept=f["kept"], mean_w=f["power"], unbudgeted_w=f["none"],
                   selections=f["selections"])
        return out

    # 7 ------------------------------------------------------------------------------------
    def ssim(self):
        self.stage("gpu ssim")
        bench = os.path.join(self.bundle, "bench/quality/gpu_ssim_bench")
        rc, wall, out, err = self.run([bench, "--seconds", "0.2", "--rounds", "2"], shim=False,
                                      timeout=min(90, self.left() - 10), name="gpu_ssim_bench")
        self.say("rc %s in %.0f s\n%s" % (rc, wall, out.strip()[-2500:]))
        self.summary["stages"]["gpu_ssim"] = {"rc": rc}
        return rc == 0

    def finish(self):
        if self.trace:
            self.trace.stop = True
            self.trace.join(1)
        json.dump(self.summary, open(os.path.join(self.out, "summary.json"), "w"), indent=1, default=str)
        open(os.path.join(self.out, "summary.md"), "w").write("\n".join(self.lines) + "\n")
        with tarfile.open(os.path.join(self.out, "results.tar.gz"), "w:gz") as tar:
            for name in ["logs", "rec1", "rec2", "gov"]:
                path = os.path.join(self.out, name)
                if os.path.isdir(path):
                    tar.add(path, arcname=name)
                    subprocess.run(["rm", "-rf", path])


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("root")
    ap.add_argument("out")
    ap.add_argument("--seconds", type=float, default=420, help="the whole run's time (default 420)")
    ap.add_argument("--detail", type=float, default=1.0, help="the demo's scene detail (default 1.0)")
    ap.add_argument("--sensor", default="nvml", help="GLBUDGET_SENSOR (default nvml; cpu for a dry run)")
    ap.add_argument("--sizes", default="1920x1080,3840x2160",
                    help="frame sizes tried, smallest first; the largest drawn at 30 fps or more is recorded")
    ap.add_argument("--fps", type=int, help="record and govern paced at this rate, at the first of --sizes "
                                            "(skips the speed stage)")
    ap.add_argument("--config-seconds", type=float, default=4, help="recorded seconds per configuration (default 4)")
    ap.add_argument("--in-process", action=argparse.BooleanOptionalAction, default=True,
                    help="record each scene in one run stepping through the configurations (GLBUDGET_FORCE; "
                         "default), not one run per configuration: NVML's counter can stand still for a new "
                         "process's first second")
    ap.add_argument("--tables", help="variant tables measured before (skips the instrumented runs)")
    ap.add_argument("--stages", default="smoke,speed,record,govern,repeat,ssim")
    ap.add_argument("--govern-scenes", default="hall", help="scenes governed, comma-separated (default hall)")
    ap.add_argument("--govern-seconds", type=float, default=20, help="seconds each governed run (default 20)")
    ap.add_argument("--budgets", default="40%,50%,60%", help="GLBUDGET_POWER values after the run without one")
    ap.add_argument("--govern-from", help="variant tables and profile recorded before (default: this run's rec1)")
    ap.add_argument("--govern-set", action="append", default=[], metavar="KEY=VALUE",
                    help="a GLBUDGET_ variable for every governed run (repeatable)")
    a = ap.parse_args()
    a.size_list = [tuple(int(v) for v in size.split("x")) for size in a.sizes.split(",")]
    for sub in ["logs", "gov"]:
        os.makedirs(os.path.join(a.out, sub), exist_ok=True)
    b = Bench(a)
    if b.trace:
        b.trace.start()
    stages = a.stages.split(",")
    b.size, b.fps = a.size_list[0], 30
    try:
        b.info()
        if "smoke" in stages and not b.smoke():
            b.say("the shim does not log on this machine: stopping")
            return
        if a.fps:
            b.fps = a.fps  # paced as told, at the first of --sizes, without the speed stage
        elif "speed" in stages:
            b.speed()
        if "record" in stages:
            b.stage("record")
            b.record("rec1", tables=a.tables, per_scene_s=a.config_seconds * 8 + 10)
        if "govern" in stages:
            b.govern()
        if "repeat" in stages and os.path.isdir(os.path.join(a.out, "rec1")):
            b.stage("repeat")
            b.record("rec2", tables=a.tables or os.path.join(a.out, "rec1"), per_scene_s=a.config_seconds * 8 + 10)
        if "ssim" in stages and b.left() > 20:
            b.ssim()
    finally:
        b.finish()


if __name__ == "__main__":
    main()
