#!/usr/bin/env python3
"""`glbudget report` end to end: a governed run of the demo (as README "Keeping a budget"),
its report, and the page opened in headless Chromium.

Checks: the report exits 0 with its four plots (three without a selections file); the page
loads in Chromium with every image decoded from a data URI (a harness page beside it reads the
report's DOM), its text names the axes' units (W, s) and the PNGs' metadata do too; nothing
external is referenced; the screenshot and each PNG are not blank (and the screenshot shows
the plots' colours, not only text).

Usage: report_demo_test.py GLBUDGET DEMO SOURCE_DIR WORK_DIR
Exit 77 (skipped) without chromium.
"""
import html
import json
import os
import re
import shutil
import subprocess
import sys

import matplotlib.image
import numpy
from PIL import Image

SKIPPED = 77
PASSES = "resolution,base,reflections,shadows,metals,antialiasing"

# Loads the report in an iframe (file:// pages may read each other with
# --allow-file-access-from-files) and writes what it found into the DOM that --dump-dom prints.
HARNESS = """<!DOCTYPE html><html><body><pre id="result">pending</pre>
<iframe id="report" src="%s" width="1400" height="3000"></iframe>
<script>
window.addEventListener("load", () => {
  const out = document.getElementById("result");
  try {
    const d = document.getElementById("report").contentDocument;
    const external = [...d.querySelectorAll("[src],[href]")]
      .map(e => e.getAttribute("src") || e.getAttribute("href")).filter(u => !u.startsWith("data:"));
    out.textContent = JSON.stringify({
      title: d.title,
      images: [...d.images].map(i => ({complete: i.complete, width: i.naturalWidth, height: i.naturalHeight,
                                       alt: i.alt, data: i.getAttribute("src").startsWith("data:image/png;base64,")})),
      captions: [...d.querySelectorAll("figcaption")].map(c => c.textContent),
      text: d.body.innerText, external: external});
  } catch (e) { out.textContent = JSON.stringify({error: String(e)}); }
});
</script></body></html>
"""


class Failures(list):
    def expect(self, condition, what):
        if not condition:
            self.append(what)
            print(f"FAIL {what}")


def run(command, **kwargs):
    print("$ " + " ".join(command))
    return subprocess.run(command, capture_output=True, text=True, timeout=180, **kwargs)


def chromium(browser, *args):
    return run([browser, "--headless", "--no-sandbox", "--disable-gpu", "--enable-logging=stderr", "--v=0",
                "--hide-scrollbars", *args])


def main():
    glbudget, demo, source, work = sys.argv[1:5]
    browser = shutil.which("chromium") or shutil.which("chromium-browser")
    if not browser:
        print("SKIPPED: no chromium (Debian: apt-get install chromium)")
        return SKIPPED
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    failures = Failures()

    # A governed run: selections every 20 frames after the fit, 1-s transitions.
    log = os.path.join(work, "run.csv")
    env = dict(os.environ, GLBUDGET_SELECT_FRAMES="20", GLBUDGET_TRANSITION_S="1")
    governed = run([glbudget, "run", "--power", "40%", "--fps", "10",
                    "--profile", os.path.join(source, "tests/data/logs/demo_cpu.profile.json"),
                    "--config", os.path.join(source, "testapps/demo/glbudget.toml"), "--log", log, "--",
                    demo, "--frames", "80", "--width", "320", "--height", "180", "--detail", "0.2"], env=env)
    print(governed.stderr, end="")
    if governed.returncode != 0:
        print(f"FAIL the governed demo run exited with {governed.returncode}")
        return 1
    with_selections = os.path.exists(log + ".selections.csv")

    page = os.path.join(work, "run.html")
    png = os.path.join(work, "png")
    report = run([glbudget, "report", log, "--png", png, "--names", PASSES])
    print(report.stdout + report.stderr, end="")
    failures.expect(report.returncode == 0, f"glbudget report exited with {report.returncode}")
    failures.expect(os.path.exists(page), "no run.html beside the log (the default)")
    wanted = ["configuration.png", "error.png", "power.png"] + (["scatter.png"] if with_selections else [])
    pngs = sorted(os.listdir(png)) if os.path.isdir(png) else []
    failures.expect(pngs == wanted, f"PNGs {pngs}, wanted {wanted}")
    for name in pngs:
        path = os.path.join(png, name)
        failures.expect(matplotlib.image.imread(path).std() > 0, f"{name} is blank")
        description = Image.open(path).text.get("Description", "")
        failures.expect(re.search(r"time \(s\)|power \(W\)", description), f"{name}: no axes with units in its metadata")
    if failures:
        return 1

    # The page in Chromium: what it loaded, then what it shows.
    harness = os.path.join(work, "harness.html")
    with open(harness, "w") as f:
        f.write(HARNESS % "run.html")
    dom = chromium(browser, "--allow-file-access-from-files", "--virtual-time-budget=10000", "--dump-dom",
                   "file://" + harness)
    found = re.search(r'<pre id="result">(.*?)</pre>', dom.stdout, re.S)
    failures.expect(dom.returncode == 0 and found, f"chromium --dump-dom: status {dom.returncode}, no result")
    console_errors = [l for l in dom.stderr.splitlines() if "CONSOLE" in l or "Failed to load" in l]
    failures.expect(not console_errors, f"console messages: {console_errors}")
    if found:
        result = json.loads(html.unescape(found.group(1)))
        failures.expect("error" not in result, f"the harness could not read the page: {result.get('error')}")
        images = result.get("images", [])
        print(f"page: {len(images)} images: " + "; ".join(f"{i['width']}x{i['height']} {i['alt']}" for i in images))
        failures.expect(len(images) == len(wanted), f"{len(images)} images on the page, wanted {len(wanted)}")
        for i in images:
            failures.expect(i["complete"] and i["width"] > 0 and i["height"] > 0 and i["data"],
                            f"image not decoded from a data URI: {i}")
            failures.expect(re.search(r"\((W|s)\)", i["alt"]), f"image without axes in its alt text: {i['alt']}")
        failures.expect(len(result.get("captions", [])) == len(wanted), "a caption per plot")
        text = result.get("text", "")
        for words in ("time (s)", "power (W)", "mean power", "energy", "selections", "switches"):
            failures.expect(words in text, f"the page's text lacks {words!r}")
        failures.expect(with_selections or "No power–error scatter" in text, "no word on the missing scatter")
        failures.expect(not result.get("external"), f"external resources: {result.get('external')}")

    shot = os.path.join(work, "screenshot.png")
    capture = chromium(browser, f"--screenshot={shot}", "--window-size=1400,3000", "file://" + page)
    failures.expect(capture.returncode == 0 and os.path.exists(shot), f"chromium --screenshot: status {capture.returncode}")
    if os.path.exists(shot):
        pixels = numpy.asarray(Image.open(shot).convert("RGB")).astype(int)
        colourful = int(((pixels.max(axis=2) - pixels.min(axis=2)) > 80).sum())
        print(f"screenshot: {pixels.shape[1]}x{pixels.shape[0]}, std {pixels.std():.1f}, {colourful} coloured pixels")
        failures.expect(pixels.std() > 0, "the screenshot is blank")
        failures.expect(colourful > 2000, "the screenshot shows no plots (too few coloured pixels)")

    if failures:
        print(f"{len(failures)} failure(s):\n  " + "\n  ".join(failures))
        return 1
    print("report opened in chromium with all its plots")
    return 0


if __name__ == "__main__":
    sys.exit(main())
