#!/usr/bin/python3
"""The uniform double helix of the twisting rods (docs/contact.md, "Twisting rods"): the contact line
load between the two wires from their force balance in the Frenet frame,
    P = kappa (N + EI tau^2) - kappa tau M_t,   kappa = R / (R^2 + c^2),  tau = c / (R^2 + c^2),
for a helix of radius R and pitch 2 pi c, wire tension N and twisting moment M_t = GJ Omega.
helix_load() takes R, c, N, M_t measured on a run's middle part; nominal() is the helix a uniform
twist of the whole height would give (theta over H, N from the arc's stretch, Omega = tau), which the
clamped ends' boundary layers shift (the middle's pitch is shorter by about 2 sqrt(EI / N) of height).
Usage: twisting_closed_form.py [--T T]"""
import argparse
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import twisting_deck as d  # noqa: E402

A, I = math.pi * d.R**2, math.pi * d.R**4 / 4
EA, EI, GJ = d.E * A, d.E * I, d.E / (2 * (1 + d.NU)) * 2 * I


def helix_load(R, c, N, Mt):
    """Line load on a wire per current length P, curvature, torsion."""
    kappa, tau = R / (R**2 + c**2), c / (R**2 + c**2)
    return kappa * (N + EI * tau**2) - kappa * tau * Mt, kappa, tau


def nominal(T=1.0):
    H, theta = d.L * (1 + d.STRETCH * T), d.THETA * T
    R, c = d.R, H / theta
    S = math.hypot(H, R * theta)
    N = EA * (S / d.L - 1.0)
    tau = c / (R**2 + c**2)
    P, kappa, tau = helix_load(R, c, N, GJ * tau)
    return dict(R=R, c=c, kappa=kappa, tau=tau, N=N, Mt=GJ * tau, P=P, p0=P * S / d.L, phase=0.5 * theta,
                layer=math.sqrt(EI / N))


if __name__ == "__main__":
    a = argparse.ArgumentParser()
    a.add_argument("--T", type=float, default=1.0)
    o = a.parse_args()
    for k, v in nominal(o.T).items():
        print(f"{k:6s} {v:.12g}")
