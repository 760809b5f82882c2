#!/usr/bin/python3
"""Report of a BeamContact study: report.md and one PNG per plot, from the study directory's
cases.csv and study.json (both written by `beamcontact study`).

    /usr/bin/python3 drivers/study_report.py STUDY_DIR

A plot draws output Y against varied parameter X, one curve per value of Series. With "Relative To
Group" Y is the percentage difference against that group's (first complete) case, as in the seed
paper's Figs. 7-9 and 12-14. Cases that did not complete are drawn as dashed vertical lines at
their X in their curve's colour, as the paper marks its non-converging penalty parameters; cases
without X (another strategy) are drawn as horizontal lines.
"""
import csv
import json
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


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


def plot_one(plot, rows, directory):
    x, y, series, ref_group = plot["x"], plot["y"], plot["series"], plot["relative_to"]
    reference = None
    if ref_group:
        for r in rows:
            if r["group"] == ref_group and r["status"] == "complete" and number(r[y]) is not None:
                reference = number(r[y])
                break
        if reference is None or reference == 0.0:
            return None, f"no complete case of group \"{ref_group}\" with a non-zero {y}"

    def value(r):
        v = number(r[y])
        if v is None:
            return None
        return 100.0 * (v - reference) / abs(reference) if reference is not None else v

    fig, ax = plt.subplots(figsize=(7, 4.5))
    keys = []
    for r in rows:
        if number(r.get(x)) is None:
            continue
        k = r.get(series, "") if series else ""
        if k not in keys:
            keys.append(k)
    keys.sort(key=lambda k: (number(k) is None, number(k) or 0.0, k))
    colours = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    for i, k in enumerate(keys):
        colour = colours[i % len(colours)]
        members = [r for r in rows if number(r.get(x)) is not None and (not series or r.get(series, "") == k)]
        ok = sorted((number(r[x]), value(r)) for r in members if r["status"] == "complete" and value(r) is not None)
        label = f"{series} = {fmt(k)}" if series else y
        if ok:
            ax.plot([p[0] for p in ok], [p[1] for p in ok], "o-", color=colour, label=label)
        for r in members:
            if r["status"] != "complete":
                ax.axvline(number(r[x]), color=colour, linestyle="--", linewidth=1)
    for r in rows:
        if number(r.get(x)) is None and r["status"] == "complete" and r["group"] != ref_group and value(r) is not None:
            ax.axhline(value(r), color="0.3", linestyle=":", linewidth=1.2)
            ax.annotate(r["group"], (0.01, value(r)), xycoords=("axes fraction", "data"), fontsize=8, color="0.3")
    if plot["log_x"]:
        ax.set_xscale("log")
    ax.set_xlabel(x)
    ax.set_ylabel(f"{y}: % difference vs {ref_group}" if ref_group else y)
    if ref_group:
        ax.axhline(0.0, color="k", linewidth=0.6)
    ax.set_title(plot["name"])
    ax.grid(True, alpha=0.3)
    if keys:
        ax.legend(fontsize=8)
    fig.tight_layout()
    name = "".join(c if c.isalnum() or c in "-_" else "_" for c in plot["name"]) + ".png"
    fig.savefig(os.path.join(directory, name), dpi=110)
    plt.close(fig)
    return name, None


def median(values):
    v = sorted(values)
    n = len(v)
    return None if n == 0 else (v[n // 2] if n % 2 else 0.5 * (v[n // 2 - 1] + v[n // 2]))


def main(directory):
    with open(os.path.join(directory, "study.json")) as f:
        study = json.load(f)
    with open(os.path.join(directory, "cases.csv")) as f:
        rows = list(csv.DictReader(f))
    columns, outputs = study["columns"], study["outputs"]
    complete = sum(r["status"] == "complete" for r in rows)
    lines = [f"# {study['title']}", "",
             f"Base deck `{study['base_deck']}`; outputs at T = {study['at_T']}; "
             f"{len(rows)} cases, {complete} complete, {len(rows) - complete} not. "
             "Newton iterations count the converged steps (all passes); solve time is the wall time of the "
             "load stepping, without start-up and deck reading.", ""]
    head = ["case", "group"] + columns + ["status"] + outputs + ["Newton", "max/step", "passes", "solve [s]"]
    lines.append("| " + " | ".join(head) + " |")
    lines.append("|" + "---|" * len(head))
    for r in rows:
        cells = [r["case"], r["group"]] + [fmt(r[c]) for c in columns] + [r["status"]]
        cells += [fmt(r[o]) for o in outputs]
        cells += [r["newton_iterations"], r["max_newton_per_step"], r["passes"], fmt(r["solve_seconds"], 3)]
        lines.append("| " + " | ".join(cells) + " |")
    causes = [r for r in rows if r["status"] != "complete"]
    if causes:
        lines += ["", "## Cases that did not complete", ""]
        for r in causes:
            lines.append(f"- case {r['case']} ({r['group']}): {r['status']} at T = {fmt(r['last_T'])}: {r['cause']}")
    lines += ["", "## Per group (complete cases)", "", "| group | cases | median Newton | median solve [s] |",
              "|---|---|---|---|"]
    for g in dict.fromkeys(r["group"] for r in rows):
        ok = [r for r in rows if r["group"] == g and r["status"] == "complete"]
        mn = median([number(r["newton_iterations"]) for r in ok if number(r["newton_iterations"]) is not None])
        ms = median([number(r["solve_seconds"]) for r in ok if number(r["solve_seconds"]) is not None])
        lines.append(f"| {g} | {len(ok)} | {fmt(mn) if mn is not None else ''} | "
                     f"{fmt(ms, 3) if ms is not None else ''} |")
    if study["plots"]:
        lines += ["", "## Plots", ""]
    for plot in study["plots"]:
        name, problem = plot_one(plot, rows, directory)
        if name:
            lines += [f"### {plot['name']}", "", f"![{plot['name']}]({name})", ""]
        else:
            lines += [f"### {plot['name']}", "", f"Not drawn: {problem}.", ""]
    with open(os.path.join(directory, "report.md"), "w") as f:
        f.write("\n".join(lines) + "\n")
    print(f"report: {os.path.join(directory, 'report.md')}")


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit("usage: study_report.py STUDY_DIR")
    try:
        main(sys.argv[1])
    except SystemExit:
        raise
    except Exception as e:  # noqa: BLE001 - reported as one line, not a traceback
        print(f"beamcontact: study report: {type(e).__name__}: {e}", file=sys.stderr)
        sys.exit(3)
