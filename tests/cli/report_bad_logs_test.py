#!/usr/bin/env python3
"""`glbudget report` on good and bad logs: exit status, the `glbudget:` messages, and the
PNGs that still come out where the data allows.

Usage: report_bad_logs_test.py GLBUDGET WORK_DIR
The logs are written here: a small governed run of two passes (18 columns, and 20 with the
probe columns), its selections file, and broken copies of it.
"""
import math
import os
import re
import shutil
import subprocess
import sys

import matplotlib.image

HEADER = ("frame,time_ns,context,pass,batches,vertices,fragments,primitives,gpu_ns,power_w,energy_j,sensor,"
          "sensor_dropped,configuration,predicted_w,budget_w,est_error,decision")
OLD_COLUMNS = 14  # logs from before the governor stop at `configuration`


def governed_rows(frames=60, probes=False):
    """Frames at 10 fps of two passes; fit at 10, selections at 12 and 40, a transition after each."""
    rows = []
    for f in range(1, frames + 1):
        configuration = "0:0" if f < 14 else ("2:0" if f < 42 else "2:2")
        decision = {10: "fit", 12: "select", 25: "refit", 40: "select"}.get(f, "transition" if 12 < f < 16 or 40 < f < 44 else "none")
        power = 30 - 5 * (f >= 14) - 3 * (f >= 42) + math.sin(f)
        predicted = f"{power + 0.3:.4f}" if f >= 10 else ""
        budget = "26.0000" if 12 <= f < 40 else ("23.0000" if f >= 40 else "")
        error = f"{0.01 * (f >= 14) + 0.02 * (f >= 42):.6f}" if f >= 12 else ""
        extra = ""
        if probes:
            extra = f",{0.012 + 0.02 * (f >= 42):.6f},1" if f % 10 == 5 else ",,0"
        for p, passname in enumerate(("00000000000000a1", "00000000000000b2")):
            rows.append(f"{f},{1000000000 + f * 100000000},0,{passname},{3 + p},300,{20000 >> p},100,1000,"
                        f"{power:.4f},{power * 0.1:.6f},cpu~estimate,0,{configuration},{predicted},{budget},{error},"
                        f"{decision}{extra}")
    return rows


def selections_text():
    lines = ["frame,configuration,predicted_w,est_error,selected,budget_w,margin_w"]
    for frame, budget, chosen in ((12, 26.0, "2:0"), (40, 23.0, "2:2")):
        for a in range(3):
            for b in range(3):
                c = f"{a}:{b}"
                lines.append(f"{frame},{c},{30 - 2.5 * a - 1.5 * b:.4f},{0.01 * a + 0.01 * b:.6f},{int(c == chosen)},"
                             f"{budget:.4f},0.5000")
    return "\n".join(lines) + "\n"


class Check:
    def __init__(self, glbudget, work):
        self.glbudget, self.work, self.failures = glbudget, work, []

    def write(self, name, text):
        path = os.path.join(self.work, name)
        with open(path, "w") as f:
            f.write(text)
        return path

    def report(self, name, log, *args, env=None):
        """Runs glbudget report on `log` with its PNGs into <work>/<name>.png/; returns
        (status, stderr, PNG names, html path)."""
        png = os.path.join(self.work, name + ".png")
        page = os.path.join(self.work, name + ".html")
        shutil.rmtree(png, ignore_errors=True)
        if os.path.exists(page):
            os.remove(page)
        run = subprocess.run([self.glbudget, "report", log, "--html", page, "--png", png, *args],
                             capture_output=True, text=True, env=env, timeout=120)
        pngs = sorted(os.listdir(png)) if os.path.isdir(png) else []
        print(f"--- {name}: status {run.returncode}, PNGs {pngs}\n{run.stderr}", end="")
        return run.returncode, run.stderr, [os.path.join(png, p) for p in pngs], page

    def expect(self, name, condition, what):
        if not condition:
            self.failures.append(f"{name}: {what}")
            print(f"FAIL {name}: {what}")

    def case(self, name, log, status, messages=(), pngs=(), page=None, args=(), env=None):
        code, err, files, html = self.report(name, log, *args, env=env)
        self.expect(name, code == status, f"exit status {code}, wanted {status}")
        for line in err.splitlines():
            self.expect(name, line.startswith("glbudget: "),
                        f"a stderr line without glbudget: {line!r}")
        for pattern in messages:
            self.expect(name, re.search(pattern, err), f"no message matching {pattern!r}")
        names = [os.path.basename(f) for f in files]
        self.expect(name, names == sorted(pngs), f"PNGs {names}, wanted {sorted(pngs)}")
        for f in files:
            pixels = matplotlib.image.imread(f)
            self.expect(name, pixels.std() > 0, f"{os.path.basename(f)} is blank")
        want_page = page if page is not None else bool(pngs)
        self.expect(name, os.path.exists(html) == want_page, f"page written: {os.path.exists(html)}, wanted {want_page}")
        if want_page and os.path.exists(html):
            with open(html) as f:
                text = f.read()
            self.expect(name, text.count('src="data:image/png;base64,') == len(pngs), "one data URI per plot")
            self.expect(name, "http://" not in text and "https://" not in text, "an external resource")
        return err, html


def main():
    glbudget, work = sys.argv[1], sys.argv[2]
    shutil.rmtree(work, ignore_errors=True)  # no selections file left from an earlier run
    os.makedirs(work)
    check = Check(glbudget, work)
    rows = governed_rows()
    good = check.write("good.csv", HEADER + "\n" + "\n".join(rows) + "\n")
    everything = ["configuration.png", "error.png", "power.png", "scatter.png"]
    timelines = ["configuration.png", "error.png", "power.png"]

    # A whole governed log without, then with, its selections file; then probe columns.
    _, page = check.case("no_selections", good, 0, pngs=timelines)
    with open(page) as f:
        check.expect("no_selections", "No power–error scatter" in f.read(), "the page says why there is no scatter")
    check.write("good.csv.selections.csv", selections_text())
    _, page = check.case("good", good, 0, pngs=everything)
    with open(page) as f:
        text = f.read()
    for words in ("time (s)", "power (W)", "error (1 − SSIM)", "predicted power (W)", "selections</th><td>2",
                  "refits</th><td>1", "switches</th><td>2", "selection of frame 40"):
        check.expect("good", words in text, f"the page lacks {words!r}")
    _, page = check.case("at_nearest", good, 0, [r"no selection at frame 13; showing the nearest, frame 12"],
                         everything, args=["--at", "13", "--names", "scale,shadows"])
    with open(page) as f:
        text = f.read()
    check.expect("at_nearest", "selection of frame 12" in text, "the scatter shows frame 12")
    probed = check.write("probed.csv", HEADER + ",probe_error,probe\n" + "\n".join(governed_rows(probes=True)) + "\n")
    _, page = check.case("probes", probed, 0, pngs=timelines)
    with open(page) as f:
        check.expect("probes", "mean probe error" in f.read(), "the summary has the probe error")

    # Nothing to draw: no file, an empty one, a header alone, not a frame log.
    check.case("missing_file", os.path.join(work, "no_such.csv"), 1, [r"^glbudget: report: cannot read .*no_such.csv"])
    check.case("empty", check.write("empty.csv", ""), 1, [r"empty.csv: empty file"])
    check.case("header_only", check.write("header_only.csv", HEADER + "\n"), 1, [r"header_only.csv: no rows after the header"])
    check.case("not_a_log", check.write("not_a_log.csv", "a,b\n1,2\n"), 1, [r"not a glbudget log: no column frame, time_ns"])
    only_ids = "\n".join(",".join(r.split(",")[:4]) for r in rows)
    check.case("nothing_to_plot", check.write("ids.csv", "frame,time_ns,context,pass\n" + only_ids + "\n"), 1,
               [r"nothing could be plotted"], page=True)

    # Damaged logs: what is left is drawn.
    cut = rows[:50] + [rows[50][:25]] + rows[51:] + [rows[-1][:40]]
    check.case("truncated", check.write("truncated.csv", HEADER + "\n" + "\n".join(cut)), 0,
               [r"skipped 1 row\(s\) whose fields do not match the header's 18 .*line 52",
                r"line 122 has no end \(the log was cut off mid-row\)"], timelines)
    garbled = [r.replace(",cpu~estimate,", ",cpu~estimate,x,") if i == 7 else r for i, r in enumerate(rows)]
    with_cell = lambda line, column, cell: ",".join(cell if k == column else v for k, v in enumerate(line.split(",")))
    garbled = [with_cell(r, 9, "n/a") if i % 9 == 0 else r for i, r in enumerate(garbled)]
    garbled[3] = "three" + garbled[3][1:]
    check.case("not_numbers", check.write("not_numbers.csv", HEADER + "\n" + "\n".join(garbled) + "\n"), 0,
               [r"cell\(s\) of column power_w are not numbers", r"without a frame number or time, first at line 5",
                r"fields do not match"], timelines)
    keep = [i for i, c in enumerate(HEADER.split(",")) if c not in ("power_w", "energy_j", "configuration")]
    drop = lambda line: ",".join(line.split(",")[i] for i in keep)
    check.case("missing_columns", check.write("missing_columns.csv", drop(HEADER) + "\n" + "\n".join(map(drop, rows)) + "\n"),
               0, [r"no column power_w, energy_j, configuration", r"no plot of configuration"], ["error.png", "power.png"])
    old = lambda line: ",".join(line.split(",")[:OLD_COLUMNS])
    check.case("old_log", check.write("old.csv", old(HEADER) + "\n" + "\n".join(map(old, rows)) + "\n"), 0,
               [r"no column predicted_w, budget_w, est_error, decision", r"no plot of error"],
               ["configuration.png", "power.png"])

    # Arguments and the interpreter.
    check.case("bad_at", good, 2, [r"^glbudget: report: argument --at: invalid int value"], args=["--at", "last"],
               page=False)
    no_args = subprocess.run([glbudget, "report"], capture_output=True, text=True)
    check.expect("no_args", no_args.returncode == 2 and no_args.stderr.startswith("glbudget: report: no log given"),
                 f"status {no_args.returncode}, {no_args.stderr!r}")
    env = dict(os.environ, GLBUDGET_PYTHON=os.path.join(work, "no_python3"))
    check.case("no_python", good, 2, [r"^glbudget: report: needs python3 with matplotlib"], env=env, page=False)
    bare = check.write("bare_python3", "#!/bin/sh\nexec /usr/bin/python3 -S -I \"$@\"\n")
    os.chmod(bare, 0o755)
    env = dict(os.environ, GLBUDGET_PYTHON=bare)
    check.case("no_matplotlib", good, 2, [r"^glbudget: report: needs matplotlib"], env=env, page=False)

    if check.failures:
        print(f"{len(check.failures)} failure(s):\n  " + "\n  ".join(check.failures))
        return 1
    print("all report cases passed")
    return 0


if __name__ == "__main__":
    sys.exit(main())
