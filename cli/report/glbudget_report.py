#!/usr/bin/env python3
"""glbudget report: draws a governed run from the shim's frame log (GLBUDGET_LOG).

Usage: glbudget_report.py LOG.csv [--html OUT.html] [--png DIR] [--names a,b,c] [--at FRAME]

The page (one self-contained HTML file, images embedded as data URIs) holds, as the paper's
Fig. 12: power over time (measured, predicted, the budget, transitions shaded), the
configuration's levels per pass over time, the estimated (and measured probe) error over time,
the power-error scatter of every configuration at one selection (from LOG.selections.csv when
the shim wrote one) and a summary table.

Problems with the log (missing columns, rows cut off, cells that are not numbers) are named
on stderr, one `glbudget: report:` line each, and whatever can still be drawn is drawn.
Exit status: 0 when at least one plot was drawn, 1 when none could be, 2 for bad arguments
or no matplotlib. Run by `glbudget report`, which finds an interpreter that has matplotlib.
"""
import argparse
import base64
import bisect
import html
import importlib.util
import io
import math
import os
import sys

NO_MATPLOTLIB = 3  # told to `glbudget report`, which then tries another python3
if importlib.util.find_spec("matplotlib") is None:
    if os.environ.get("GLBUDGET_REPORT_LAUNCHER"):
        sys.exit(NO_MATPLOTLIB)
    sys.stderr.write("glbudget: report: needs matplotlib (Debian: apt-get install python3-matplotlib)\n")
    sys.exit(2)


def load_matplotlib():
    """Imported only once there is something to draw: the import takes half a second."""
    global plt, BoundaryNorm, ListedColormap
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.colors import BoundaryNorm, ListedColormap


# The columns today's shim writes (interpose/observe/frame_log.hpp); the last four are empty
# when it does not govern, and logs from before the governor stop at `configuration`.
# probe_error and probe (quality probes) are drawn when present.
LOG_COLUMNS = ["frame", "time_ns", "context", "pass", "batches", "vertices", "fragments", "primitives",
               "gpu_ns", "power_w", "energy_j", "sensor", "sensor_dropped", "configuration",
               "predicted_w", "budget_w", "est_error", "decision"]
GOVERNOR_COLUMNS = ["predicted_w", "budget_w", "est_error", "decision"]
NAN = float("nan")


def say(message):
    sys.stderr.write(f"glbudget: report: {message}\n")


def finite(x):
    return x is not None and math.isfinite(x)


# --- reading ---------------------------------------------------------------------------------

class Table:
    """A CSV file's header and rows, with what was wrong with it counted, not raised."""

    def __init__(self, path, label):
        self.path, self.label = path, label
        self.header, self.rows = [], []  # rows: (line number, fields)
        self.columns = {}                # name -> index in header
        self.bad_numbers = {}            # column -> (count, first line)

    def index(self, column):
        return self.columns.get(column, -1)

    def text(self, fields, column):
        i = self.index(column)
        return fields[i].strip() if i >= 0 else ""

    def number(self, line, fields, column):
        """NaN when the column is absent or the cell empty; a cell that is not a number is
        counted (one message per column later) and read as NaN."""
        cell = self.text(fields, column)
        if not cell:
            return NAN
        try:
            return float(cell)
        except ValueError:
            count, first = self.bad_numbers.get(column, (0, line))
            self.bad_numbers[column] = (count + 1, first)
            return NAN

    def report_bad_numbers(self):
        for column, (count, first) in sorted(self.bad_numbers.items(), key=lambda item: item[1][1]):
            say(f"{self.label}: {count} cell(s) of column {column} are not numbers (first at line {first}); "
                "read as missing")


def read_table(path, label, required):
    """The file as a Table, or None (with a message) when it cannot be read or lacks a
    required column. Rows cut off mid-row (fewer or more fields than the header, or a last
    line with no end) are skipped with one message."""
    try:
        with open(path, encoding="utf-8", errors="replace", newline="") as f:
            text = f.read()
    except OSError as e:
        say(f"cannot read {label}: {e.strerror or e}")
        return None
    table = Table(path, label)
    if not text.strip():
        say(f"{label}: empty file, not a frame log")
        return None
    lines = text.split("\n")
    cut_last = not text.endswith("\n") and len(lines) > 1
    table.header = [name.strip() for name in lines[0].rstrip("\r").split(",")]
    table.columns = {name: i for i, name in reversed(list(enumerate(table.header)))}
    missing = [c for c in required if c not in table.header]
    if missing:
        say(f"{label}: not a glbudget log: no column {', '.join(missing)} (header: {lines[0][:80]})")
        return None
    wrong_width, first_wrong = 0, 0
    for number, line in enumerate(lines[1:], start=2):
        line = line.rstrip("\r")
        if not line:
            continue
        fields = line.split(",")
        if number == len(lines) and cut_last:
            say(f"{label}: line {number} has no end (the log was cut off mid-row); skipped")
            continue
        if len(fields) != len(table.header):
            wrong_width += 1
            first_wrong = first_wrong or number
            continue
        table.rows.append((number, fields))
    if wrong_width:
        say(f"{label}: skipped {wrong_width} row(s) whose fields do not match the header's "
            f"{len(table.header)} (cut off mid-row?), first at line {first_wrong}")
    return table


class Frame:
    __slots__ = ("frame", "time_s", "power_w", "energy_j", "sensor", "configuration", "predicted_w",
                 "budget_w", "est_error", "decision", "probe_error", "probe")


def parse_configuration(text):
    """'1:0:2' -> [1, 0, 2]; a level that is not a number is None."""
    if not text:
        return []
    levels = []
    for part in text.split(":"):
        try:
            levels.append(int(part))
        except ValueError:
            levels.append(None)
    return levels


def read_frames(path, label):
    """The frames of the log's busiest context, in time order; None when there are none."""
    table = read_table(path, label, ["frame", "time_ns"])
    if table is None:
        return None
    absent = [c for c in LOG_COLUMNS if c not in table.header]
    governor_absent = [c for c in GOVERNOR_COLUMNS if c in absent]
    if governor_absent:
        say(f"{label}: no column {', '.join(governor_absent)} (a log without a budget, or from before the "
            "governor): predicted power, budget, error and decisions are left out")
    other_absent = [c for c in absent if c not in GOVERNOR_COLUMNS]
    if other_absent:
        say(f"{label}: no column {', '.join(other_absent)}")
    if not table.rows:
        say(f"{label}: no rows after the header: nothing to draw")
        return None

    frames, contexts, skipped, first_skipped = {}, {}, 0, 0
    for line, fields in table.rows:
        number = table.number(line, fields, "frame")
        time_ns = table.number(line, fields, "time_ns")
        if not (finite(number) and finite(time_ns)):
            skipped += 1
            first_skipped = first_skipped or line
            continue
        context = table.text(fields, "context")
        key = (context, int(number))
        f = frames.get(key)
        if f is None:
            f = frames[key] = Frame()
            contexts[context] = contexts.get(context, 0) + 1
            f.frame, f.time_s = int(number), time_ns * 1e-9
            f.power_w = f.energy_j = f.predicted_w = f.budget_w = f.est_error = f.probe_error = NAN
            f.sensor = f.configuration = f.decision = ""
            f.probe = False
        # Per-frame figures repeat on every pass row: take the first row that has each.
        for name in ("power_w", "energy_j", "predicted_w", "budget_w", "est_error", "probe_error"):
            if not finite(getattr(f, name)):
                setattr(f, name, table.number(line, fields, name))
        for name in ("sensor", "configuration", "decision"):
            if not getattr(f, name):
                setattr(f, name, table.text(fields, name))
        f.probe = f.probe or table.text(fields, "probe") in ("1", "true", "yes")
    table.report_bad_numbers()
    if skipped:
        say(f"{label}: skipped {skipped} row(s) without a frame number or time, first at line {first_skipped}")
    if not frames:
        say(f"{label}: no row with a frame number and a time: nothing to draw")
        return None
    busiest = max(contexts, key=contexts.get)
    if len(contexts) > 1:
        say(f"{label}: {len(contexts)} contexts; drawing context {busiest or '(none)'}, the one with the most frames")
    chosen = sorted((f for (c, _), f in frames.items() if c == busiest), key=lambda f: (f.time_s, f.frame))
    start = chosen[0].time_s
    for f in chosen:
        f.time_s -= start
    return chosen


def read_selections(path, label):
    """{frame: [(levels text, predicted_w, est_error, selected, budget_w, margin_w, weighed_w)]}, or None.
    margin_w (optional): what the governor kept under the budget at that selection; weighed_w
    (optional): the power as the selection weighed it, the margin kept below it."""
    if not os.path.exists(path):
        return None
    table = read_table(path, label, ["frame", "predicted_w", "est_error"])
    if table is None:
        return None
    selections = {}
    for line, fields in table.rows:
        frame = table.number(line, fields, "frame")
        power = table.number(line, fields, "predicted_w")
        error = table.number(line, fields, "est_error")
        if not (finite(frame) and finite(power) and finite(error)):
            continue
        selected = table.text(fields, "selected") in ("1", "true", "yes")
        selections.setdefault(int(frame), []).append(
            (table.text(fields, "configuration"), power, error, selected, table.number(line, fields, "budget_w"),
             table.number(line, fields, "margin_w"), table.number(line, fields, "weighed_w")))
    table.report_bad_numbers()
    if not selections:
        say(f"{label}: no usable rows: the scatter is left out")
        return None
    return selections


# --- figures ---------------------------------------------------------------------------------

class Figure:
    """One plot of the page: its PNG bytes, a file name, a caption and the axes it shows."""

    def __init__(self, name, title, caption, axes, png):
        self.name, self.title, self.caption, self.axes, self.png = name, title, caption, axes, png


def render(fig, name, title, caption, axes):
    buffer = io.BytesIO()
    fig.savefig(buffer, format="png", dpi=100,
                metadata={"Title": title, "Description": f"{caption} Axes: {axes}.", "Software": "glbudget report"})
    plt.close(fig)
    return Figure(name, title, caption, axes, buffer.getvalue())


def time_axes(height_in, legend_row=True):
    """A figure 10 in wide whose plot area spans the same width in every time plot, so that
    the plots line up one above the other on the page; room on the right for a colour bar
    and above for a row of legend."""
    fig = plt.figure(figsize=(10, height_in))
    bottom, top = 0.55 / height_in, 1 - (0.45 if legend_row else 0.2) / height_in
    ax = fig.add_axes([0.11, bottom, 0.77, top - bottom])
    return fig, ax


def legend_above(ax):
    ax.legend(loc="lower left", bbox_to_anchor=(0, 1.01), ncol=6, fontsize=8, frameon=False,
              borderaxespad=0, handlelength=1.8)


def spans(frames, decision):
    """[(start s, end s)] of the runs of frames whose decision is `decision`."""
    out, start = [], None
    for i, f in enumerate(frames):
        if f.decision == decision and start is None:
            start = f.time_s
        if start is not None and (f.decision != decision or i == len(frames) - 1):
            out.append((start, f.time_s))
            start = None
    return out


def shade_transitions(ax, frames):
    for k, (a, b) in enumerate(spans(frames, "transition")):
        ax.axvspan(a, max(b, a + 1e-3), color="tab:orange", alpha=0.15, lw=0,
                   label="transition" if k == 0 else None)


def windows(times, start, width=1.0):
    """[(window start, first index, end index)] of the whole `width`-second windows of the
    sorted `times` from `start` on."""
    out, k = [], 0
    while times and start + (k + 1) * width <= times[-1] + 1e-9:
        lo = start + k * width
        out.append((lo, bisect.bisect_left(times, lo), bisect.bisect_left(times, lo + width)))
        k += 1
    return out


def mean_of_finite(values):
    kept = [v for v in values if finite(v)]
    return sum(kept) / len(kept) if kept else NAN


def window_means(times, values, width=1.0):
    """Mean of the finite values in each whole `width`-second window from times[0]:
    [(start, end, mean)]."""
    out = []
    for lo, i, j in windows(times, times[0] if times else 0.0, width):
        mean = mean_of_finite(values[i:j])
        if finite(mean):
            out.append((lo, lo + width, mean))
    return out


def power_figure(frames, xlim):
    t = [f.time_s for f in frames]
    measured = [f.power_w for f in frames]
    predicted = [f.predicted_w for f in frames]
    budget = [f.budget_w for f in frames]
    if not any(finite(v) for v in measured + predicted + budget):
        return None
    fig, ax = time_axes(3.6)
    shade_transitions(ax, frames)
    if any(finite(v) for v in measured):
        ax.plot(t, measured, color="tab:blue", lw=0.7, alpha=0.45, label="measured (per frame)")
        means = window_means(t, measured)
        if means:
            ax.hlines([v for _, _, v in means], [a for a, _, _ in means], [b for _, b, _ in means],
                      color="tab:blue", lw=2.5, label="measured (1-s mean)")
    if any(finite(v) for v in predicted):
        ax.plot(t, predicted, color="tab:green", lw=1.2, label="predicted")
    if any(finite(v) for v in budget):
        ax.step(t, budget, where="post", color="tab:red", lw=1.5, ls="--", label="budget")
    selections = [f.time_s for f in frames if f.decision in ("select", "explore")]
    if selections:  # one collection: a long run has thousands; the power's range stays the y axis
        watts = ax.get_ylim()
        ax.vlines(selections, 0, 1, transform=ax.get_xaxis_transform(), color="0.4", lw=0.8, ls=":",
                  alpha=1.0 if len(selections) <= 50 else 0.3, label="selection")
        ax.set_ylim(watts)
    ax.set_xlim(*xlim)
    ax.set_xlabel("time (s)")
    ax.set_ylabel("power (W)")
    ax.grid(alpha=0.3)
    legend_above(ax)
    return render(fig, "power.png", "Power over time",
                  "Measured power per frame and its 1-s means, the model's prediction and the budget; "
                  "transitions of the temporal filter shaded, selections dotted.",
                  "time (s), power (W)")


def configuration_figure(frames, names, xlim):
    levels = [parse_configuration(f.configuration) for f in frames]
    passes = max((len(l) for l in levels), default=0)
    if passes == 0:
        return None
    if names and len(names) != passes:
        say(f"--names gives {len(names)} name(s) for {passes} pass(es); the others are numbered")
    labels = [(names[i] if i < len(names) else f"pass {i + 1}") for i in range(passes)]
    grid = [[(l[i] if i < len(l) and l[i] is not None else NAN) for l in levels] for i in range(passes)]
    top = int(max((v for row in grid for v in row if finite(v)), default=0))
    t = [f.time_s for f in frames]
    step = (t[-1] - t[-2]) if len(t) > 1 else 1.0
    edges = t + [t[-1] + max(step, 1e-3)]
    fig, ax = time_axes(0.45 * passes + 1.0, legend_row=False)
    # The same colour for a level whatever the run reached (three levels span the scale).
    colours = ListedColormap(plt.get_cmap("YlOrRd")([0.08 + 0.84 * min(k / max(top, 2), 1) for k in range(top + 1)]))
    mesh = ax.pcolormesh(edges, list(range(passes + 1)), grid, cmap=colours,
                         norm=BoundaryNorm([k - 0.5 for k in range(top + 2)], top + 1), shading="flat")
    box = ax.get_position()
    bar = fig.colorbar(mesh, cax=fig.add_axes([0.895, box.y0, 0.015, box.height]), ticks=list(range(top + 1)))
    bar.set_label("level (0 = best)")
    ax.set_yticks([i + 0.5 for i in range(passes)])
    ax.set_yticklabels(labels)
    ax.invert_yaxis()
    ax.set_xlim(*xlim)
    ax.set_xlabel("time (s)")
    return render(fig, "configuration.png", "Configuration over time",
                  f"The level each of the {passes} manifest passes drew at (0 = best, the app's own), "
                  "one row per pass.", "time (s), pass, level")


def error_figure(frames, xlim):
    t = [f.time_s for f in frames]
    estimated = [f.est_error for f in frames]
    probes = [(f.time_s, f.probe_error) for f in frames if finite(f.probe_error)]
    if not any(finite(v) for v in estimated) and not probes:
        return None
    fig, ax = time_axes(3.0)
    shade_transitions(ax, frames)
    if any(finite(v) for v in estimated):
        ax.step(t, estimated, where="post", color="tab:purple", lw=1.5, label="estimated")
    if probes:
        ax.plot([p for p, _ in probes], [e for _, e in probes], ls="none", marker="x", color="black",
                label="measured on probe frames")
    probe_times = [f.time_s for f in frames if f.probe]
    if probe_times and not probes:
        ax.plot(probe_times, [0] * len(probe_times), ls="none", marker="|", color="black", label="probe frames")
    ax.set_xlim(*xlim)
    ax.set_ylim(bottom=0)
    ax.set_xlabel("time (s)")
    ax.set_ylabel("error (1 − SSIM)")
    ax.grid(alpha=0.3)
    legend_above(ax)
    return render(fig, "error.png", "Error over time",
                  "The estimated error (1 − SSIM against the best configuration) of the configuration chosen"
                  + (", and the error measured on probe frames." if probes else "."),
                  "time (s), error (1 − SSIM)")


def pick_selection(selections, at):
    frames = sorted(selections)
    if at is None:
        return frames[-1]
    if at in selections:
        return at
    nearest = min(frames, key=lambda f: (abs(f - at), f))
    say(f"no selection at frame {at}; showing the nearest, frame {nearest}")
    return nearest


def scatter_figure(selections, at):
    frame = pick_selection(selections, at)
    rows = selections[frame]
    # The power as the selection weighed it where the log has it (unmeasured configurations
    # raised by the guard), so that the margin's line divides what it admitted from the rest.
    weighed = all(finite(r[6]) for r in rows)
    power = [r[6] if weighed else r[1] for r in rows]
    fig, ax = plt.subplots(figsize=(7, 4.6))
    ax.scatter(power, [r[2] for r in rows], s=10, color="tab:blue", alpha=0.5,
               label=f"configurations ({len(rows)})")
    for p, r in zip(power, rows):
        if r[3]:
            ax.scatter([p], [r[2]], s=160, marker="*", color="tab:red", edgecolor="black", zorder=3,
                       label=f"selected {r[0]}")
    budgets = [r[4] for r in rows if finite(r[4])]
    lines = []
    if budgets:
        lines.append(budgets[0])
        ax.axvline(budgets[0], color="tab:red", ls="--", lw=1.5, label=f"budget {budgets[0]:.1f} W")
        margins = [r[5] for r in rows if finite(r[5]) and r[5] > 0]
        if margins:
            lines.append(budgets[0] - margins[0])
            ax.axvline(lines[-1], color="tab:red", ls=":", lw=1.2, label=f"budget − margin {lines[-1]:.1f} W")
    xs = power + lines  # the budget's lines in view, as the points are
    pad = 0.05 * ((max(xs) - min(xs)) or 1.0)
    ax.set_xlim(min(xs) - pad, max(xs) + pad)
    power_label = "power (W) as the selection weighed it" if weighed else "predicted power (W)"
    ax.set_xlabel(power_label)
    ax.set_ylabel("estimated error (1 − SSIM)")
    ax.set_title(f"Every configuration at the selection of frame {frame}")
    ax.grid(alpha=0.3)
    ax.legend(loc="upper right", fontsize=8)
    fig.tight_layout()
    return render(fig, "scatter.png", f"Power and error at the selection of frame {frame}",
                  "Every configuration's " + ("power as the selection weighed it (its corrected prediction, "
                  "raised by the guard where the run never measured it)" if weighed else "predicted power")
                  + " and estimated error when the governor selected; "
                  "the selected one is the star, the budget the dashed line (budget less the governor's "
                  "margin dotted, where it kept one): the lowest error left of the line, wherever the "
                  "budget falls, not a point of a Pareto frontier fixed in advance.",
                  power_label + ", estimated error (1 − SSIM)")


# --- summary ---------------------------------------------------------------------------------

def intervals(frames):
    """Each frame's duration: the time since the previous frame (the first: NaN)."""
    return [NAN] + [b.time_s - a.time_s for a, b in zip(frames, frames[1:])]


def weighted_mean(values, weights):
    pairs = [(v, w) for v, w in zip(values, weights) if finite(v) and finite(w) and w > 0]
    total = sum(w for _, w in pairs)
    return sum(v * w for v, w in pairs) / total if total > 0 else NAN


def summary(frames):
    dt = intervals(frames)
    power = [f.power_w for f in frames]
    rows = [("frames", f"{len(frames)}"), ("duration", f"{frames[-1].time_s:.2f} s")]
    sensors = sorted({f.sensor for f in frames if f.sensor})
    if sensors:
        rows.append(("sensor", ", ".join(sensors)))
    mean_power = weighted_mean(power, dt)
    rows.append(("mean power", f"{mean_power:.2f} W" if finite(mean_power) else "not measured"))
    energies = [f.energy_j for f in frames if finite(f.energy_j)]
    if energies:
        rows.append(("energy", f"{sum(energies):.1f} J"))
    elif finite(mean_power):
        rows.append(("energy", f"{mean_power * frames[-1].time_s:.1f} J (mean power × duration)"))
    else:
        rows.append(("energy", "not measured"))

    governed = [(p, f.budget_w, d) for p, f, d in zip(power, frames, dt)
                if finite(p) and finite(f.budget_w) and finite(d) and d > 0]
    if governed:
        under = sum(d for p, b, d in governed if p <= b) / sum(d for _, _, d in governed)
        rows.append(("time under budget", f"{under:.0%} (of the time with a budget and a measurement)"))
        windows = budget_windows(frames)
        if windows:
            rows.append(("1-s windows under budget",
                         f"{sum(windows) / len(windows):.0%} ({sum(windows)} of {len(windows)} from the first selection)"))
    else:
        rows.append(("time under budget", "no budget in the log"))
    error = weighted_mean([f.est_error for f in frames], dt)
    rows.append(("mean estimated error", f"{error:.4f}" if finite(error) else "not in the log"))
    probes = [f.probe_error for f in frames if finite(f.probe_error)]
    if probes:
        rows.append(("mean probe error", f"{sum(probes) / len(probes):.4f} ({len(probes)} probe frames)"))
    switches = sum(1 for a, b in zip(frames, frames[1:]) if a.configuration != b.configuration)
    rows.append(("switches", f"{switches} (configuration changes from one frame to the next)"))
    if any(f.decision for f in frames):
        count = lambda name: sum(1 for f in frames if f.decision == name)
        rows.append(("selections", f"{count('select')}"))
        rows.append(("refits", f"{count('refit')}"))
        rows.append(("transition frames", f"{count('transition')}"))
        if count("hold"):
            rows.append(("held frames", f"{count('hold')}"))
    last = frames[-1].configuration
    if last:
        rows.append(("final configuration", last))
    return rows


def budget_windows(frames):
    """One bool per whole 1-s window from the first selection: its mean measured power is at
    or under its mean budget (windows without either are left out)."""
    selected = [f.time_s for f in frames if f.decision in ("select", "explore")]
    if not selected:
        return []
    times = [f.time_s for f in frames]
    out = []
    for _, i, j in windows(times, selected[0]):
        power = mean_of_finite([f.power_w for f in frames[i:j]])
        budget = mean_of_finite([f.budget_w for f in frames[i:j]])
        if finite(power) and finite(budget):
            out.append(power <= budget)
    return out


# --- the page --------------------------------------------------------------------------------

PAGE_STYLE = """
body { font-family: sans-serif; margin: 1.5em auto; max-width: 1060px; color: #222; }
h1 { font-size: 1.4em; } h2 { font-size: 1.1em; margin-top: 1.6em; }
table { border-collapse: collapse; } td, th { padding: 0.2em 0.8em; border-bottom: 1px solid #ddd; text-align: left; }
figure { margin: 1em 0; } figure img { max-width: 100%; border: 1px solid #eee; }
figcaption { font-size: 0.9em; color: #444; } .note { color: #8a4b00; } code { background: #f4f4f4; }
"""


def page(log, rows, figures, notes):
    e = html.escape
    parts = ["<!DOCTYPE html>", '<html lang="en"><head><meta charset="utf-8">',
             f"<title>glbudget report: {e(os.path.basename(log))}</title>",
             f"<style>{PAGE_STYLE}</style></head><body>",
             f"<h1>glbudget report: <code>{e(log)}</code></h1>", "<h2>Summary</h2>", "<table>"]
    parts += [f"<tr><th>{e(k)}</th><td>{e(v)}</td></tr>" for k, v in rows]
    parts.append("</table>")
    for note in notes:
        parts.append(f'<p class="note">{e(note)}</p>')
    for fig in figures:
        data = base64.b64encode(fig.png).decode("ascii")
        parts += [f'<h2>{e(fig.title)}</h2>', f'<figure id="{e(fig.name[:-4])}">',
                  f'<img src="data:image/png;base64,{data}" alt="{e(fig.title)}: {e(fig.axes)}">',
                  f"<figcaption>{e(fig.caption)} Axes: {e(fig.axes)}.</figcaption></figure>"]
    parts.append("</body></html>\n")
    return "\n".join(parts)


class Arguments(argparse.ArgumentParser):
    def error(self, message):
        say(f"{message}; usage: glbudget report LOG.csv [--html OUT.html] [--png DIR] [--names a,b,c] [--at FRAME]")
        sys.exit(2)


def parse_arguments(argv):
    parser = Arguments(prog="glbudget report", description="Draw a governed run from its frame log.")
    parser.add_argument("log", help="the shim's frame log (GLBUDGET_LOG, glbudget run --log)")
    parser.add_argument("--html", help="the page to write (default: the log's name with .html)")
    parser.add_argument("--png", metavar="DIR", help="also write each plot as a PNG into DIR")
    parser.add_argument("--names", help="names of the manifest's passes, in order: a,b,c")
    parser.add_argument("--at", type=int, metavar="FRAME", help="the selection the scatter shows (default: the last)")
    return parser.parse_args(argv)


def main(argv):
    a = parse_arguments(argv)
    out = a.html or os.path.splitext(a.log)[0] + ".html"
    names = [n.strip() for n in a.names.split(",")] if a.names else []
    frames = read_frames(a.log, a.log)
    if not frames:
        return 1
    load_matplotlib()
    xlim = (0.0, max(frames[-1].time_s, 1e-3))
    notes, figures = [], []
    for draw, what in ((lambda: power_figure(frames, xlim), "power (no power_w, predicted_w or budget_w values)"),
                       (lambda: configuration_figure(frames, names, xlim), "configuration (no configuration values)"),
                       (lambda: error_figure(frames, xlim), "error (no est_error or probe_error values)")):
        fig = draw()
        if fig:
            figures.append(fig)
        else:
            say(f"{a.log}: no plot of {what}")
            notes.append(f"No plot of {what}.")
    selections_path = a.log + ".selections.csv"
    selections = read_selections(selections_path, selections_path)
    if selections:
            figures.append(scatter_figure(selections, a.at))
    else:
        notes.append(f"No power–error scatter: it needs the configurations of a selection, which the shim "
                     f"writes beside the log ({os.path.basename(selections_path)}); there is none.")
    if a.png:
        try:
            os.makedirs(a.png, exist_ok=True)
            for fig in figures:
                with open(os.path.join(a.png, fig.name), "wb") as f:
                    f.write(fig.png)
        except OSError as e:
            say(f"cannot write the PNGs into {a.png}: {e.strerror or e}")
    try:
        with open(out, "w", encoding="utf-8") as f:
            f.write(page(a.log, summary(frames), figures, notes))
    except OSError as e:
        say(f"cannot write {out}: {e.strerror or e}")
        return 1
    print(f"glbudget report: {len(figures)} plot(s) in {out}" + (f" and {a.png}" if a.png and figures else ""))
    if not figures:
        say(f"{a.log}: nothing could be plotted (the page has the summary only)")
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
