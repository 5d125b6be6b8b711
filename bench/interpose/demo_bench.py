"""What the demo overhead benchmarks share (apply_overhead.py, probe_overhead.py,
governor_overhead.py): their common options, the paths of the build, a clean environment, and
a run of a command timed from outside."""
import argparse
import os
import subprocess
import time

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
MANIFEST = os.path.join(ROOT, "testapps/demo/glbudget.toml")
PROFILE = os.path.join(ROOT, "tests/data/logs/demo_cpu.profile.json")


def run(cmd, env):
    """Wall time of one run (s); the command's output is dropped, a failure raises."""
    start = time.perf_counter()
    subprocess.run(cmd, env=env, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    return time.perf_counter() - start


def parser(doc, rounds, frames):
    """BUILD_DIR, --rounds, --scene, --size and --frames; the script adds its own."""
    ap = argparse.ArgumentParser(description=doc, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("build")
    ap.add_argument("--rounds", type=int, default=rounds)
    ap.add_argument("--scene", default="hall")
    ap.add_argument("--size", default="320x180")
    ap.add_argument("--frames", type=int, default=frames)
    return ap


class Build:
    """The demo and the shim of a build tree, and the demo's command line at a.size."""

    def __init__(self, a):
        self.demo = os.path.join(a.build, "testapps/demo/demo")
        self.shim = os.path.join(a.build, "interpose/libglbudget.so")
        self.width, self.height = a.size.split("x")
        self.scene = a.scene

    def demo_cmd(self, frames=None):
        cmd = [self.demo, "--scene", self.scene, "--detail", "0.2", "--width", self.width, "--height", self.height]
        return cmd + (["--frames", str(frames)] if frames is not None else [])


def clean_environment():
    """This process's environment without the shim or any GLBUDGET_ variable."""
    return {k: v for k, v in os.environ.items() if k != "LD_PRELOAD" and not k.startswith("GLBUDGET_")}
