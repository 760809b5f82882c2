#!/usr/bin/python3
"""Report of a BeamContact study: report.md with one PNG (200 dpi) and one PDF (TrueType fonts, no
Type 3) per figure, from the study directory's cases.csv and study.json (both written by
`beamcontact study`) and the cases' own results (steps.csv, newton.csv, tracked_points.csv).

    /usr/bin/python3 drivers/study_report.py STUDY_DIR

The report says what was varied and against which reference, then gives the table of outputs, the
errors against the study's "Reference Group", the cost per group (Newton iterations, passes, solve
time with its spread) and the figures:
- each plot of the study deck: output Y against varied parameter X, one curve per value of Series.
  With "Relative To Group" Y is the percentage difference against that group's (first complete)
  case, as in the seed paper's Figs. 7-9 and 12-14; with "Error" it is |relative error| on log-log
  axes with the least-squares slope of each curve in its legend. Cases that did not complete are
  dashed vertical lines at their X in their curve's colour (one legend entry says so), as the paper
  marks its non-converging penalty parameters; complete cases without X (another strategy) are
  horizontal lines, or a shaded band from the smallest to the largest value where a group has several;
  the study deck's published values (the paper's) are hollow markers, one legend entry each with its
  label and value, at (Published X, Published Y) or, without X, side by side near the right edge, on
  the same scale;
- load-displacement curves of every tracked-point output, one line per case;
- Newton iterations per step, and the residual history of each case's last converged step.
Every figure is titled with the study's title; every series has a colour, marker and line style of its
own (figure_style.py); a case's legend entry is its group and the values its group varies; every axis
has a unit (the study deck's, a count, seconds, or "(model units)" where the deck states none).
It needs matplotlib (python3-matplotlib): without it, one line naming the package and exit 4
(`study_report.py --check-modules` checks only that, for `beamcontact study` before its cases run).
"""
import csv
import json
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from python_modules import need as need_module  # noqa: E402
import figure_style  # noqa: E402


def need(module):
    return need_module(module, "study report", ", or run the study with --no-report")


matplotlib = need("matplotlib")
matplotlib.use("Agg")
figure_style.setup(matplotlib)
plt = need("matplotlib.pyplot")
Line2D = need("matplotlib.lines").Line2D
MaxNLocator = need("matplotlib.ticker").MaxNLocator


# Columns and contact totals that count things: their axes say "[count]".
COUNTS = {"newton_iterations", "max_newton_per_step", "passes", "steps", "Active Points", "Stick Lines", "Slip Lines"}


def number(text):
    try:
        v = float(text)
        return v if math.isfinite(v) else None
    except (TypeError, ValueError):
        return None


def fmt(text, digits=6):
    v = number(text)
    if v is None:
        return text or ""
    if v == int(v) and abs(v) < 1e6:
        return str(int(v))
    return f"{v:.{digits}g}"


def median(values):
    v = sorted(values)
    n = len(v)
    return None if n == 0 else (v[n // 2] if n % 2 else 0.5 * (v[n // 2 - 1] + v[n // 2]))


def slope(points):
    """Least-squares slope of log10(y) against log10(x) (None with fewer than two distinct x)."""
    pts = [(math.log10(x), math.log10(y)) for x, y in points if x > 0 and y > 0]
    if len({p[0] for p in pts}) < 2:
        return None
    mx = sum(p[0] for p in pts) / len(pts)
    my = sum(p[1] for p in pts) / len(pts)
    sxx = sum((p[0] - mx) ** 2 for p in pts)
    return sum((p[0] - mx) * (p[1] - my) for p in pts) / sxx


class Study:
    def __init__(self, directory):
        self.dir = directory
        with open(os.path.join(directory, "study.json")) as f:
            self.meta = json.load(f)
        with open(os.path.join(directory, "cases.csv")) as f:
            self.rows = list(csv.DictReader(f))
        self.units = self.meta.get("units", {})
        self.columns = self.meta["columns"]
        self.stems = set()  # the figures' file stems written (lower case), see save

    def label(self, name):
        unit = self.units.get(name)
        return f"{name} [{unit}]" if unit else name

    def axis_label(self, name):
        """`name` with its unit for an axis: the study deck's (or its default), a count, seconds, or
        "(model units)" where the deck states none."""
        unit = self.units.get(name)
        if unit:
            return f"{name} [{unit}]"
        if name in COUNTS or self.meta.get("output_sources", {}).get(name, {}).get("contact") in COUNTS:
            return f"{name} [count]"
        if name.startswith("solve_seconds"):
            return f"{name} [s]"
        return f"{name} (model units)"

    def case_label(self, r):
        """A case in a legend: its group's name and the values of the parameters that the group varies
        (those with more than one value in it), not those it sets once."""
        group = next((g for g in self.meta.get("groups", []) if g["name"] == r["group"]), None)
        varied = [v["name"] for v in group["variables"] if len(v["values"]) > 1] if group else self.columns
        return " ".join([r["group"]] + [f"{c}={fmt(r[c])}" for c in varied if r.get(c)])

    def case_dir(self, r):
        return os.path.join(self.dir, "cases", f"{int(r['case']):03d}")

    def save(self, fig, title):
        """Writes the figure as PNG (200 dpi) and PDF (TrueType fonts) under the study's title."""
        stem = "".join(c if c.isalnum() or c in "-_" else "_" for c in title)
        # Titles that differ only in characters a file name does not keep ("a/b", "a_b"; a plot named
        # like an automatic curve) get numbered files: no figure replaces another.
        base, n = stem, 1
        while stem.lower() in self.stems:
            n += 1
            stem = f"{base}_{n}"
        self.stems.add(stem.lower())
        fig.suptitle(self.meta["title"], fontsize=10)
        fig.tight_layout()
        fig.savefig(os.path.join(self.dir, stem + ".png"), dpi=figure_style.DPI)
        fig.savefig(os.path.join(self.dir, stem + ".pdf"))
        plt.close(fig)
        return stem


def read_csv(path):
    try:
        with open(path) as f:
            return list(csv.DictReader(f))
    except OSError:
        return []


def plot_one(study, plot):
    rows = study.rows
    x, y, series, ref_group, error = plot["x"], plot["y"], plot["series"], plot["relative_to"], plot.get("error")
    reference = None
    if ref_group:
        for r in rows:
            if r["group"] == ref_group and r["status"] == "complete" and number(r[y]) is not None:
                reference = number(r[y])
                break
        if reference is None or reference == 0.0:
            return None, f"no complete case of group \"{ref_group}\" with a non-zero {y}"

    def scaled(v):
        """A value of Y as the plot draws it: itself, its % difference or its |relative error|."""
        if reference is None:
            return v
        relative = (v - reference) / abs(reference)
        return abs(relative) if error else 100.0 * relative

    def value(r):
        v = number(r[y])
        return None if v is None else scaled(v)

    fig, ax = plt.subplots(figsize=(7.5, 4.8))
    keys = []
    for r in rows:
        if number(r.get(x)) is None:
            continue
        k = r.get(series, "") if series else ""
        if k not in keys:
            keys.append(k)
    keys.sort(key=lambda k: (number(k) is None, number(k) or 0.0, k))
    failed_any = False
    for i, k in enumerate(keys):
        style = figure_style.series_style(i)
        members = [r for r in rows if number(r.get(x)) is not None and (not series or r.get(series, "") == k)]
        ok = sorted((number(r[x]), value(r)) for r in members if r["status"] == "complete" and value(r) is not None)
        if error:
            ok = [p for p in ok if p[1] > 0.0]
        label = f"{series} = {fmt(k)}" if series else y
        if error and ok:
            s = slope(ok)
            if s is not None:
                label += f" (slope {s:.2f})"
        if ok:
            ax.plot([p[0] for p in ok], [p[1] for p in ok], label=label, markersize=5, **style)
        for r in members:
            if r["status"] != "complete":
                ax.axvline(number(r[x]), color=style["color"], linestyle="--", linewidth=1)
                failed_any = True
    # Complete cases without X, per group: one case is a horizontal line, several a band from their
    # smallest to their largest value; each labelled with its group at the left.
    others = {}
    for r in rows:
        if number(r.get(x)) is None and r["status"] == "complete" and r["group"] != ref_group \
                and value(r) is not None and not (error and value(r) <= 0.0):
            others.setdefault(r["group"], []).append(value(r))
    for n, (group, values) in enumerate(others.items()):
        lo, hi = min(values), max(values)
        if len(values) == 1:
            ax.axhline(lo, color="0.3", linestyle=":", linewidth=1.2)
            text = group
        else:
            ax.axhspan(lo, hi, color="0.5", alpha=0.12)
            text = f"{group} ({len(values)} cases)"
        ax.annotate(text, (0.01 + 0.3 * (n % 3), hi), xycoords=("axes fraction", "data"), fontsize=7, color="0.3",
                    va="bottom")
    for r in rows:
        if number(r.get(x)) is None and r["status"] != "complete" and r["group"] != ref_group:
            failed_any = True  # another strategy that did not complete: in the table's causes
    # Published values, on the same scale as the cases (relative to the reference where the plot is):
    # one hollow marker and one legend entry each, its label and value ("paper: Lagrange: A uz =
    # -9.89"); at (Published X, Y), or without X side by side in a strip at the right (the X axis is
    # widened for it below) at their Y. Their styles go on from the cases' so that none repeats.
    published_y = plot.get("published_y", [])
    published_x = plot.get("published_x", [])
    published_labels = plot.get("published_labels", []) or ["published"] * len(published_y)
    for k, py in enumerate(published_y):
        v = scaled(py)
        if error and v <= 0.0:
            continue
        style = figure_style.series_style(len(keys) + k)
        label = f"{published_labels[k]}: {y} = {fmt(py)}"
        marker = {"marker": style["marker"], "color": style["color"], "linestyle": "none", "markersize": 9,
                  "markerfacecolor": "none", "markeredgewidth": 2, "label": label}
        if published_x:
            ax.plot([published_x[k]], [v], **marker)
        else:
            at = STRIP + 0.02 + (0.96 - STRIP) * (k + 0.5) / len(published_y)
            ax.plot([at], [v], transform=ax.get_yaxis_transform(), clip_on=False, **marker)
    if plot["log_x"] or error:
        ax.set_xscale("log")
    if error:
        ax.set_yscale("log")
    if published_y and not published_x and keys:  # the strip for published values without X
        lo, hi = ax.get_xlim()
        ticks = [ax.get_xticks(), ax.get_xticks(minor=True)]
        if ax.get_xscale() == "log":
            ax.set_xlim(lo, lo * (hi / lo) ** (1.0 / STRIP))
        else:
            ax.set_xlim(lo, lo + (hi - lo) / STRIP)
        # No X ticks over the strip (its markers have no X); a thin line and a word set it apart.
        for minor, t in enumerate(ticks):
            ax.set_xticks([v for v in t if lo <= v <= hi], minor=bool(minor))
        ax.plot([STRIP, STRIP], [0.0, 1.0], transform=ax.transAxes, color="0.5", linewidth=0.8)
        ax.text(0.5 * (1.0 + STRIP), 0.01, "published", transform=ax.transAxes, fontsize=7, color="0.3",
                ha="center", va="bottom")
    ax.set_xlabel(study.axis_label(x))
    if error:
        ax.set_ylabel(f"|{y} - {y} of {ref_group}| / |{y} of {ref_group}| [-]")
    elif ref_group:
        ax.set_ylabel(f"{y}: difference vs {ref_group} [%]")
        ax.axhline(0.0, color="k", linewidth=0.6)
    else:
        ax.set_ylabel(study.axis_label(y))
    ax.set_title(plot["name"])
    ax.grid(True, alpha=0.3, which="both" if error else "major")
    handles, labels = ax.get_legend_handles_labels()
    if failed_any:
        handles.append(Line2D([], [], color="0.4", linestyle="--", linewidth=1))
        labels.append("did not complete (at its X)")
    if handles:
        legend(fig, ax, len(handles), handles, labels)
    return study.save(fig, plot["name"]), None


# The share of a plot's width for its cases when published values without X sit in a strip at the right.
STRIP = 0.88


def legend(fig, ax, entries, handles=None, labels=None, beside=False):
    """A legend inside the axes for a few entries; beside them (or always with `beside`), in columns of
    at most 30, for more; the figure is widened by 3.2 inches for each column after the first."""
    if entries <= 6 and not beside:
        options = {"fontsize": 8}
    else:
        options = {"fontsize": 7, "loc": "center left", "bbox_to_anchor": (1.01, 0.5), "ncol": 1 + (entries - 1) // 30}
        fig.set_size_inches(fig.get_figwidth() + 3.2 * (options["ncol"] - 1), fig.get_figheight())
    if handles is None:
        ax.legend(**options)
    else:
        ax.legend(handles, labels, **options)


def curves(study):
    """Load-displacement curves of the tracked-point outputs, Newton iterations per step and the
    residual history of each case's last converged step; returns (title, file stem) pairs."""
    figures = []
    rows = [r for r in study.rows if os.path.isdir(study.case_dir(r))]
    if not rows:
        return figures

    def style(i, points):
        """Case i's colour, marker and line style, with a marker on about eight of its points (staggered
        from case to case, so that curves on top of each other still show their markers)."""
        every = max(1, points // 8)
        return dict(figure_style.series_style(i), markersize=3, markevery=(i % every, every))

    sources = study.meta.get("output_sources", {})
    for name, src in sources.items():
        if not src.get("tracked_point"):
            continue
        column = f"{src['tracked_point']}_{src['component']}"
        fig, ax = plt.subplots(figsize=(9, 4.8))
        drawn = 0
        for i, r in enumerate(rows):
            rows_t = read_csv(os.path.join(study.case_dir(r), "tracked_points.csv"))
            data = [(number(t["T"]), number(t.get(column))) for t in rows_t]
            data = [d for d in data if d[0] is not None and d[1] is not None]
            if data:
                label = study.case_label(r) + ("" if r["status"] == "complete" else f" ({r['status']})")
                ax.plot([d[0] for d in data], [d[1] for d in data], label=label, linewidth=1.2, **style(i, len(data)))
                drawn += 1
        if drawn:
            ax.set_xlabel("load factor T [-]")
            ax.set_ylabel(study.axis_label(name))
            ax.set_title(f"{name} against the load factor")
            ax.grid(True, alpha=0.3)
            legend(fig, ax, drawn, beside=True)
            figures.append((f"{name} against the load factor", study.save(fig, f"curve {name}")))
        else:
            plt.close(fig)
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(12, 4.8))
    for i, r in enumerate(rows):
        steps = read_csv(os.path.join(study.case_dir(r), "steps.csv"))
        pts = [(number(s["T"]), number(s["newton_iterations"])) for s in steps]
        pts = [p for p in pts if p[0] is not None and p[1] is not None]
        if pts:
            a1.plot([p[0] for p in pts], [p[1] for p in pts], label=study.case_label(r), linewidth=1.0,
                    **style(i, len(pts)))
        history = read_csv(os.path.join(study.case_dir(r), "newton.csv"))
        if history:
            last = history[-1]["step"]
            res = [number(h["residual_norm"]) for h in history if h["step"] == last]
            res = [v for v in res if v is not None and v > 0.0]
            if res:
                a2.semilogy(range(len(res)), res, label=study.case_label(r), linewidth=0.8, **style(i, 8))
    a1.set_xlabel("load factor T [-]")
    a1.set_ylabel("Newton iterations in the step (all passes) [count]")
    a1.set_title("Newton iterations per step")
    a1.grid(True, alpha=0.3)
    a2.set_xlabel("iteration (all passes) [count]")
    a2.xaxis.set_major_locator(MaxNLocator(integer=True))
    a2.set_ylabel("||r|| [force]")
    a2.set_title("Residual history of the last converged step")
    a2.grid(True, alpha=0.3, which="both")
    legend(fig, a2, len(a2.get_lines()), beside=True)
    figures.append(("Newton iterations per step and residual histories", study.save(fig, "newton_per_step")))
    return figures


def provenance(meta, rows):
    """The report's last section: what wrote it (study.json's provenance), and the cases that another
    version or commit ran (cases kept from an earlier study run; cases.csv's version and commit)."""
    p = meta.get("provenance", {})
    if not p:
        return []
    lines = ["## Provenance", "",
             f"BeamContact {p.get('version')}, commit {p.get('commit')} ({p.get('build_type')} build; Trilinos "
             f"{p.get('trilinos')}; {p.get('mpi')}; {p.get('compiler')}), on {p.get('host')} at {p.get('date')}: "
             f"`{p.get('command')}`.", ""]
    other = [r["case"] for r in rows if (r.get("version"), r.get("commit")) != (p.get("version"), p.get("commit"))
             and r.get("commit")]
    if other:
        lines += [f"Cases run by another version or commit (see cases.csv): {', '.join(other)}.", ""]
    return lines


def main(directory):
    study = Study(directory)
    meta, rows, columns, outputs = study.meta, study.rows, study.columns, study.meta["outputs"]
    complete = sum(r["status"] == "complete" for r in rows)
    ref = meta.get("reference_group", "")
    timing = int(meta.get("timing_runs", 0) or 0)
    base = meta.get("base", {})
    lines = [f"# {meta['title']}", ""]
    facts = [f"base deck `{meta['base_deck']}`"]
    if base.get("strategy"):
        facts.append(f"its strategy {base['strategy']}")
    if base.get("beams"):
        facts.append(f"{base['beams']} beams")
    if base.get("increments"):
        facts.append(f"{base['increments']} increments")
    lines += ["; ".join(facts).capitalize() + f". Outputs at T = {meta['at_T']}; {len(rows)} cases, {complete} "
              f"complete, {len(rows) - complete} not" + (f"; reference: group \"{ref}\"" if ref else "") + ".", ""]
    if timing:
        lines += [f"Timings: each case ran {timing} times, one case at a time, without VTK output; the solve time "
                  "is the median of those runs with its range (`study --timing`).", ""]
    else:
        lines += [f"Timings are indicative: cases ran {meta.get('parallel', 'several')} at a time with the base "
                  "deck's output settings. For method timings run `beamcontact study --timing`.", ""]
    lines += ["## What was varied", ""]
    for g in meta.get("groups", []):
        parts = [f"{v['name']} (`{v['path']}`) = {', '.join(v['values'])}" for v in g["variables"]]
        lines.append(f"- **{g['name']}**: " + ("; ".join(parts) if parts else "the base deck"))
    lines.append("")
    head = ["case", "group"] + columns + ["status"] + [study.label(o) for o in outputs] + \
        ["Newton", "max/step", "passes", "solve [s]"]
    lines += ["## Results", "", "| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for r in rows:
        cells = [r["case"], r["group"]] + [fmt(r[c]) for c in columns] + [r["status"]]
        cells += [fmt(r[o]) for o in outputs]
        seconds = r.get("solve_seconds_median") if timing else r["solve_seconds"]
        cells += [r["newton_iterations"], r["max_newton_per_step"], r["passes"], fmt(seconds, 3)]
        lines.append("| " + " | ".join(cells) + " |")
    if ref:
        lines += ["", f"## Relative error against \"{ref}\"", "",
                  f"`(y - y_ref) / |y_ref|` for each output; the absolute errors are in cases.csv (`<output> error`).",
                  "", "| case | group | " + " | ".join(columns + outputs) + " |",
                  "|" + "---|" * (2 + len(columns) + len(outputs))]
        for r in rows:
            cells = [r["case"], r["group"]] + [fmt(r[c]) for c in columns]
            cells += [f"{number(r.get(o + ' relative error')):.2e}" if number(r.get(o + " relative error")) is not None
                      else "" for o in outputs]
            lines.append("| " + " | ".join(cells) + " |")
    causes = [r for r in rows if r["status"] != "complete"]
    if causes:
        lines += ["", "## Cases that did not complete", ""]
        for r in causes:
            lines.append(f"- case {r['case']} ({r['group']}): {r['status']} at T = {fmt(r['last_T'])}: {r['cause']}")
    lines += ["", "## Cost per group (complete cases)", "",
              "| group | cases | complete | median Newton | median passes | median solve [s] | solve range [s] |",
              "|---|---|---|---|---|---|---|"]
    for g in dict.fromkeys(r["group"] for r in rows):
        members = [r for r in rows if r["group"] == g]
        ok = [r for r in members if r["status"] == "complete"]

        def values(key):
            return [number(r.get(key)) for r in ok if number(r.get(key)) is not None]
        mn, mp = median(values("newton_iterations")), median(values("passes"))
        times = values("solve_seconds_median" if timing else "solve_seconds")
        # The range: over every timing run of the group's cases, or over its cases.
        lows, highs = (values("solve_seconds_min"), values("solve_seconds_max")) if timing else (times, times)
        lo, hi = (min(lows), max(highs)) if lows and highs else (None, None)
        lines.append(f"| {g} | {len(members)} | {len(ok)} | {fmt(mn) if mn is not None else ''} | "
                     f"{fmt(mp) if mp is not None else ''} | {fmt(median(times), 3) if times else ''} | "
                     f"{'' if lo is None else f'{lo:.3g} - {hi:.3g}'} |")
    if timing:
        lines += ["", "With --timing the range is over every run of the group's cases; without it, over its cases."]
    if meta["plots"]:
        lines += ["", "## Plots", ""]
    for plot in meta["plots"]:
        name, problem = plot_one(study, plot)
        if name:
            lines += [f"### {plot['name']}", "", f"![{plot['name']}]({name}.png) ([PDF]({name}.pdf))", ""]
        else:
            lines += [f"### {plot['name']}", "", f"Not drawn: {problem}.", ""]
    figures = curves(study)
    if figures:
        lines += ["## Curves", ""]
        for title, stem in figures:
            lines += [f"### {title}", "", f"![{title}]({stem}.png) ([PDF]({stem}.pdf))", ""]
    lines += provenance(meta, rows)
    with open(os.path.join(directory, "report.md"), "w") as f:
        f.write("\n".join(lines) + "\n")
    if not QUIET:
        print(f"report: {os.path.join(directory, 'report.md')}")


QUIET = False  # --quiet (beamcontact study --quiet): nothing on stdout

if __name__ == "__main__":
    if sys.argv[1:] == ["--check-modules"]:  # beamcontact study, before its cases: the imports above ran
        sys.exit(0)
    args = sys.argv[1:]
    if args[:1] == ["--quiet"]:
        QUIET = True
        args = args[1:]
    if len(args) != 1:
        sys.exit("usage: study_report.py [--quiet] STUDY_DIR")
    try:
        main(args[0])
    except SystemExit:
        raise
    except Exception as e:  # noqa: BLE001 - reported as one line, not a traceback
        print(f"beamcontact: study report: {type(e).__name__}: {e}", file=sys.stderr)
        sys.exit(3)
