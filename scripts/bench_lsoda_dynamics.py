#!/usr/bin/python3
"""SciPy solve_ivp (LSODA) on the equations of `hertzgear dynamics`, against hertzgear's cvode-bdf
and radau-iia.

The same model and coefficients as data/scenes/paper_crowned_fourier.prm (dynamic Hertzian layer
with Hunt-Crossley damping, backlash, k_h as a 4-harmonic Fourier series, constant k, the scene's
initial state), checked against the values hertzgear resolves (summary.json, "model"). Both are
measured against hertzgear's reference run at rtol 1e-12: relative error of the RMS DTE over the
steady window and the largest error of the Poincare points. The ratio is reported at equal
accuracy: each LSODA run against the cheapest hertzgear run that is at least as accurate.

usage: scripts/bench_lsoda_dynamics.py HERTZGEAR_EXE [--periods N] [--rtols 1e-6,1e-8]
                                      [--integrators cvode-bdf,radau-iia] [--repeat 3]

Wall times are medians over --repeat runs (the machines are shared and noisy).
"""
import argparse
import json
import math
import os
import subprocess
import sys
import tempfile
import time

import numpy as np
from scipy.integrate import solve_ivp

SCENE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "data", "scenes",
                     "paper_crowned_fourier.prm")

# Scene values as hertzgear resolves them (checked against summary.json below).
M_E = 0.1432020538745814       # kg
F0 = 6477.603832462074         # N
B_C = 58.6e-6                  # m
C = 144.33635931367493         # N s/m
K = 2.79e8                     # N/m
N_EXP = 1.5
KH_MEAN = 5.095e10
KH_AMP = [2.045e10, 3.769e9, 5.891e9, 3.513e9]
KH_PHASE = [0.0, math.pi, math.pi, 0.0]
MU = 1.5 * 0.26 * KH_MEAN
OMEGA = 2 * math.pi * 57.5     # rad/s, 23 teeth at 150 rpm
Y0 = [58.6059e-6, 5.86e-5, 0.05796e-6]


def k_hertz(t):
    th = OMEGA * t
    return KH_MEAN + sum(a * math.cos((j + 1) * th - p) for j, (a, p) in enumerate(zip(KH_AMP, KH_PHASE)))


def rhs(t, y):
    """GearPairModel::rhs for the dynamic layer (docs/dynamics.md)."""
    x, v, d = y
    zone = 1 if x >= B_C else (-1 if x <= -B_C else 0)
    f = x - zone * B_C if zone else 0.0
    fd = v if zone else 0.0
    if zone and d * zone > 0:
        h = abs(d) ** N_EXP
        g = math.copysign(h, d)
        kh = k_hertz(t)
        dd = (K * (f - d) + C * fd - kh * g) / (C + MU * h)
        force = kh * g + MU * h * dd
    else:
        dd = fd + K * (f - d) / C
        force = 0.0
    return [v, (F0 - force) / M_E, dd]


def run_hertzgear(exe, rtol, atol, periods, out, integrator="cvode-bdf"):
    cmd = [exe, "dynamics", SCENE, "--out", out, "--set", f"Dynamics/integrator={integrator}",
           "--set", f"Dynamics/relative_tolerance={rtol}", "--set", f"Dynamics/absolute_tolerance_m={atol}",
           "--set", f"Dynamics/periods={periods}", "--set", f"Dynamics/transient_periods={periods // 2}",
           "--set", "Output/timeseries_periods=0"]
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    summary = json.load(open(os.path.join(out, "summary.json")))
    poincare = np.loadtxt(os.path.join(out, "poincare.csv"), delimiter=",", skiprows=1)[:, 2] * 1e-6
    return summary, poincare


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("hertzgear")
    ap.add_argument("--periods", type=int, default=800)
    ap.add_argument("--rtols", default="1e-6,1e-8")
    ap.add_argument("--integrators", default="cvode-bdf,radau-iia")
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args()
    T = 2 * math.pi / OMEGA
    P = args.periods
    tmp = tempfile.mkdtemp(prefix="hg_lsoda_")

    ref, ref_p = run_hertzgear(args.hertzgear, 1e-12, 1e-17, P, os.path.join(tmp, "ref"))
    m = ref["model"]
    for name, ours in [("equivalent_mass_kg", M_E), ("damping_N_s_per_m", C),
                       ("k_rest_mean_N_per_m", K), ("k_hertz_mean_N_per_m_pow_n", KH_MEAN)]:
        assert abs(m[name] - ours) <= 1e-12 * abs(ours), (name, m[name], ours)
    ref_rms = ref["rms_dte_um"] * 1e-6

    # Steady window: the last P/2 periods, 100 samples per period (as hertzgear).
    t_steady = (P // 2) * T + np.arange((P - P // 2) * 100) * T / 100
    t_poincare = (P // 2) * T + np.arange(P - P // 2 + 1) * T

    rows = []
    for rtol in [float(r) for r in args.rtols.split(",")]:
        atol = 1e-13 * rtol / 1e-8
        for integrator in args.integrators.split(","):
            walls = []
            for _ in range(args.repeat):
                hg, hg_p = run_hertzgear(args.hertzgear, rtol, atol, P,
                                         os.path.join(tmp, f"hg{integrator}{rtol}"), integrator)
                walls.append(hg["integrator"]["wall_time_s"])
            rows.append((f"hertzgear {integrator}", rtol, float(np.median(walls)),
                         hg["integrator"]["rhs_evals"], abs(hg["rms_dte_um"] * 1e-6 - ref_rms) / ref_rms,
                         np.max(np.abs(hg_p - ref_p))))

        t_eval = np.union1d(t_steady, t_poincare)
        walls = []
        for _ in range(args.repeat):
            start = time.perf_counter()
            sol = solve_ivp(rhs, (0.0, P * T), Y0, method="LSODA", rtol=rtol,
                            atol=[atol, atol * OMEGA, atol], t_eval=t_eval)
            walls.append(time.perf_counter() - start)
        wall = float(np.median(walls))
        if not sol.success:
            rows.append(("scipy LSODA", rtol, wall, sol.nfev, float("nan"), float("nan")))
            continue
        x = dict(zip(np.round(sol.t / T * 100).astype(int), sol.y[0]))
        xs = np.array([x[int(round(t / T * 100))] for t in t_steady])
        xp = np.array([x[int(round(t / T * 100))] for t in t_poincare])
        rms = math.sqrt(np.mean(xs ** 2))
        rows.append(("scipy LSODA", rtol, wall, sol.nfev, abs(rms - ref_rms) / ref_rms,
                     np.max(np.abs(xp - ref_p))))

    print(f"paper crowned pair, {P} mesh periods, median wall times of {args.repeat} runs; "
          f"reference hertzgear cvode-bdf rtol 1e-12, "
          f"RMS DTE {ref['rms_dte_um']:.6f} um")
    print(f"{'solver':22s} {'rtol':>7s} {'wall [s]':>9s} {'RHS evals':>10s} {'RMS rel err':>12s} {'Poincare err [um]':>18s}")
    for r in rows:
        print(f"{r[0]:22s} {r[1]:7.0e} {r[2]:9.3f} {r[3]:10d} {r[4]:12.2e} {1e6 * r[5]:18.3e}")
    hg_rows = [r for r in rows if r[0].startswith("hertzgear")]
    for r in rows:
        if r[0] != "scipy LSODA" or not math.isfinite(r[5]):
            continue
        ok = [h for h in hg_rows if h[5] <= r[5] and h[4] <= max(r[4], 1e-12)]
        if ok:
            best = min(ok, key=lambda h: h[2])
            print(f"LSODA rtol {r[1]:.0e}: {r[2] / best[2]:.1f}x slower than {best[0]} rtol {best[1]:.0e} "
                  f"at equal or better accuracy")
        else:
            print(f"LSODA rtol {r[1]:.0e}: no hertzgear run in the table is as accurate")


if __name__ == "__main__":
    sys.exit(main())
