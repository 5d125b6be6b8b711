#!/usr/bin/env python3
"""bench/gpu/real_gpu.py's smoke and govern stages end to end on this machine (the cpu sensor,
a small frame): what a GPU loan runs, checked before a loan is spent on it. The bundle it expects
(ROOT/.gpu, as scripts/gpu-bundle lays it out) is made of links into the build; the governed runs
take the cpu recording's variant table and profile (--govern-from tests/data/logs). Then
bench/gpu/governed_runs.py counts the governed run's windows.
  real_gpu_dry_run_test.py SOURCE_DIR BUILD_DIR
"""
import json
import os
import subprocess
import sys
import tarfile
import tempfile

source, build = (os.path.abspath(p) for p in sys.argv[1:3])
with tempfile.TemporaryDirectory() as tmp:
    root = os.path.join(tmp, "root")
    for sub in ("bench", "testapps", "tests"):
        os.makedirs(root, exist_ok=True)
        os.symlink(os.path.join(source, sub), os.path.join(root, sub))
    bundle = os.path.join(root, ".gpu")
    os.makedirs(os.path.join(bundle, "testapps", "demo"))
    os.symlink(os.path.join(build, "interpose"), os.path.join(bundle, "interpose"))
    os.symlink(os.path.join(build, "testapps", "demo", "demo"), os.path.join(bundle, "testapps", "demo", "demo"))
    out = os.path.join(tmp, "out")
    cmd = [sys.executable, os.path.join(source, "bench", "gpu", "real_gpu.py"), root, out, "--sensor", "cpu",
           "--stages", "smoke,govern", "--fps", "10", "--sizes", "160x90", "--seconds", "150",
           "--govern-from", os.path.join(source, "tests", "data", "logs"), "--govern-scenes", "hall",
           "--govern-seconds", "14", "--budgets", "50%",
           # The first selection waits for a measured window at most this long after the fit
           # (200 frames by default, past this run's 140): under a loaded machine's noise the
           # run could end before it, with no windows to count.
           "--govern-set", "GLBUDGET_SELECT_FRAMES=60"]
    r = subprocess.run(cmd, capture_output=True, text=True, timeout=300)
    print(r.stdout[-3000:], r.stderr[-2000:])
    assert r.returncode == 0, "real_gpu.py failed"
    summary = json.load(open(os.path.join(out, "summary.json")))
    smoke = summary["stages"]["smoke"]
    assert smoke["shim_rc"] == 0 and smoke["frames"] == 60 and smoke["passes"] == 6, smoke
    governed = summary["stages"]["govern"]
    assert set(governed) == {"hall_none", "hall_50"}, governed
    assert governed["hall_none"]["probe_frames"] == 0 and governed["hall_none"]["budget_w"] is None, governed
    run = governed["hall_50"]
    assert run["rc"] == 0 and run["frames"] == 140 and run["probe_frames"] > 0 and run["budget_w"] > 0, run
    # The GPU machine's own summary counts windows as governed_runs.py does below.
    assert 0 <= run["windows_kept"] <= run["windows"] and run["windows"] >= 2 and run["mean_w"] > 0, run
    with tarfile.open(os.path.join(out, "results.tar.gz")) as tar:
        tar.extractall(os.path.join(tmp, "results"))
    table = subprocess.run([sys.executable, os.path.join(source, "bench", "gpu", "governed_runs.py"),
                            os.path.join(tmp, "results", "gov"), "--fps", "10"], capture_output=True, text=True)
    print(table.stdout, table.stderr)
    rows = [line for line in table.stdout.splitlines() if "| hall | 50 % |" in line]
    assert table.returncode == 0 and len(rows) == 1, table.stdout
    kept, windows = rows[0].split("|")[4].split("/")
    assert (int(kept), int(windows)) == (run["windows_kept"], run["windows"]), (rows[0], run)
print("real_gpu dry run: ok")
