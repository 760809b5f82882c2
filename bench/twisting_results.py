#!/usr/bin/python3
"""Reads a twisting-rods run's results directory (bench/twisting_deck.py) and compares its last step
with the helix closed form (bench/twisting_closed_form.py) on the middle quarter of rod 1 (between
its tracked nodes L/8 below and above the middle): mid-node phase against theta T / 2 (exact by the
problem's symmetry), the line load of the Gauss points there (their lengths' weighted mean) against
the helix's P for the measured radius, pitch, wire tension (from the stretch of that quarter) and
twisting moment (the top clamp's reaction about z), and their gap against -P / eps_N (Penalty) or 0.
Usage: twisting_results.py DIR [--eps EPS_N]"""
import argparse
import csv
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import twisting_closed_form as cf  # noqa: E402
import twisting_deck as td  # noqa: E402


def node(t, name):
    x = float(t[name + "_ux"]) + td.R
    y = float(t[name + "_uy"])
    return x, y, float(t[name + "_uz"])


def read(out, eps_n=None):
    status = open(os.path.join(out, "status.txt")).read().strip()
    steps = list(csv.DictReader(open(os.path.join(out, "steps.csv"))))
    res = dict(status=status.split(":")[0], T=float(steps[-1]["T"]) if steps else 0.0,
               newton=sum(int(s["newton_iterations"]) for s in steps), steps=len(steps))
    if not steps:
        return res
    T = res["T"]
    t = list(csv.DictReader(open(os.path.join(out, "tracked_points.csv"))))[-1]
    x, y, _ = node(t, "rod1 middle")
    res["phase_err"] = math.atan2(y, x) - 0.5 * td.THETA * T
    b, a = node(t, "rod1 below"), node(t, "rod1 above")
    zb, za = b[2] + td.L * 3 / 8, a[2] + td.L * 5 / 8
    dphi = math.atan2(a[1], a[0]) - math.atan2(b[1], b[0])
    R = math.hypot(x, y)
    c = (za - zb) / dphi
    stretch = math.hypot(za - zb, R * dphi) / (td.L / 4)
    N = cf.EA * (stretch - 1.0)
    rx = list(csv.DictReader(open(os.path.join(out, "reactions.csv"))))[-1]
    Mt = float(rx["rod1 top z_Mz"])
    P, kappa, tau = cf.helix_load(R, c, N, Mt)
    p0 = P * stretch
    rows = [r for r in csv.DictReader(open(os.path.join(out, "contact_points.csv"))) if r["step"] == steps[-1]["step"]]
    mid = [r for r in rows if zb <= float(r["z"]) <= za and float(r["line_traction"]) != 0.0]
    w = [float(r["normal_force"]) / float(r["line_traction"]) for r in mid]
    load = sum(float(r["normal_force"]) for r in mid) / sum(w)
    res["load"] = load
    res["load_err"] = load / p0 - 1.0
    res["gap"] = sum(float(r["gap"]) * wi for r, wi in zip(mid, w)) / sum(w)
    res["gap_ref"] = -p0 / eps_n if eps_n else 0.0
    res["gap_min"] = min(float(r["gap"]) for r in rows)
    nom = cf.nominal(T)
    res["pitch_ratio"] = nom["c"] / c
    res["layer"] = 0.5 * (td.L * (1 + td.STRETCH * T) - td.THETA * T * c)
    res["layer_ref"] = math.sqrt(cf.EI / N)
    return res


if __name__ == "__main__":
    a = argparse.ArgumentParser()
    a.add_argument("dir")
    a.add_argument("--eps", type=float, default=None)
    o = a.parse_args()
    for k, v in read(o.dir, o.eps).items():
        print(k, v)
