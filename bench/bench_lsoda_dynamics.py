#!/usr/bin/python3
"""SciPy solve_ivp (LSODA) on the equations of `hertzgear dynamics`, against hertzgear's cvode-bdf
and radau-iia.

Two cases (--case):
  paper           data/scenes/paper_crowned_fourier.prm at 150 rpm (dynamic Hertzian layer with
                  Hunt-Crossley damping, backlash, k_h as a 4-harmonic Fourier series, constant k,
                  the scene's initial state), 800 mesh periods by default;
  contact-loss    data/scenes/paper_crowned_table.prm at 16000 rpm (k_h from the shipped FE table
                  data/stiffness/paper_crowned.json, k constant at the table's mean, c from
                  zeta = 0.015): the layer opens, the teeth fly through the backlash and close
                  again once per mesh period; 200 mesh periods by default.
The model's values are checked against those hertzgear resolves (summary.json, "model"). Every
run is measured against hertzgear's converged reference, radau-iia with 7 stages at rtol 1e-13
and atol 1e-17 m (as `hertzgear accuracy dynamics`): relative error of the RMS DTE over the
steady window (the second half of the periods) and the largest error of the Poincare points.
The ratio is reported at equal accuracy: each LSODA run against the cheapest hertzgear run that
is at least as accurate on both measures.

usage: bench/bench_lsoda_dynamics.py HERTZGEAR_EXE [--case paper|contact-loss] [--periods N]
                                      [--rtols 1e-6,1e-8] [--integrators cvode-bdf,radau-iia]
                                      [--repeat 3]

The contenders alternate within each repetition (hertzgear's integrators, then LSODA, for every
tolerance, --repeat times over), so that a slow spell of the shared machine falls on all of them;
wall times are the medians over the repetitions: hertzgear's integration time (summary.json,
integrator.wall_time_s) and the solve_ivp call. The absolute tolerance is rtol * 1e-5 m on the
displacements and that times the mesh frequency on the velocity, for every solver.
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

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
CASES = {
    "paper": {"scene": os.path.join(ROOT, "data", "scenes", "paper_crowned_fourier.prm"),
              "set": [], "rpm": 150.0, "periods": 800},
    "contact-loss": {"scene": os.path.join(ROOT, "data", "scenes", "paper_crowned_table.prm"),
                     "set": ["Operating/speed_rpm=16000"], "rpm": 16000.0, "periods": 200},
}

# Scene values as hertzgear resolves them (checked against summary.json in main).
M_E = 0.1432020538745814       # kg
F0 = 6477.603832462074         # N
B_C = 58.6e-6                  # m
N_EXP = 1.5
ALPHA = 0.26                   # s/m, Hunt-Crossley
Y0 = [58.6059e-6, 5.86e-5, 0.05796e-6]
# Set by use_case: mesh frequency, k, c, k_h = KH_MEAN + sum A_j cos(j theta - phi_j).
OMEGA = C = K = KH_MEAN = MU = 0.0
KH_AMP, KH_PHASE = [], []


def use_case(name):
    """The coefficients of the case; c is checked against hertzgear's in main."""
    global OMEGA, C, K, KH_MEAN, KH_AMP, KH_PHASE, MU
    OMEGA = 2 * math.pi * 23 * CASES[name]["rpm"] / 60
    if name == "paper":
        C, K = 144.33635931367493, 2.79e8
        KH_MEAN, KH_AMP, KH_PHASE = 5.095e10, [2.045e10, 3.769e9, 5.891e9, 3.513e9], [0.0, math.pi, math.pi, 0.0]
    else:
        table = json.load(open(os.path.join(ROOT, "data", "stiffness", "paper_crowned.json")))
        K = table["k_rest_N_per_m"]["mean"]
        kh = table["k_hertz_N_per_m_pow_n"]
        KH_MEAN, KH_AMP, KH_PHASE = kh["mean"], kh["amplitudes"], kh["phases_rad"]
        C = None  # zeta = 0.015 on the linearised stiffness: taken from hertzgear's summary
    MU = 1.5 * ALPHA * KH_MEAN


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


def run_hertzgear(exe, case, rtol, atol, periods, out, integrator="cvode-bdf", stages=0):
    cmd = [exe, "dynamics", CASES[case]["scene"], "--out", out, "--set", f"Dynamics/integrator={integrator}",
           "--set", f"Dynamics/relative_tolerance={rtol}", "--set", f"Dynamics/absolute_tolerance_m={atol}",
           "--set", f"Dynamics/radau_stages={stages}",
           "--set", f"Dynamics/periods={periods}", "--set", f"Dynamics/transient_periods={periods // 2}",
           "--set", "Output/timeseries_periods=0"]
    for kv in CASES[case]["set"]:
        cmd += ["--set", kv]
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    summary = json.load(open(os.path.join(out, "summary.json")))
    poincare = np.loadtxt(os.path.join(out, "poincare.csv"), delimiter=",", skiprows=1)[:, 2] * 1e-6
    return summary, poincare


def lsoda(rtol, atol, P, T):
    """One solve_ivp LSODA run: wall time, RHS evaluations, the steady samples and the Poincare
    points (None when it failed)."""
    t_steady = (P // 2) * T + np.arange((P - P // 2) * 100) * T / 100
    t_poincare = (P // 2) * T + np.arange(P - P // 2 + 1) * T
    t_eval = np.union1d(t_steady, t_poincare)
    start = time.perf_counter()
    sol = solve_ivp(rhs, (0.0, P * T), Y0, method="LSODA", rtol=rtol,
                    atol=[atol, atol * OMEGA, atol], t_eval=t_eval)
    wall = time.perf_counter() - start
    if not sol.success:
        return wall, sol.nfev, None, None
    x = dict(zip(np.round(sol.t / T * 100).astype(int), sol.y[0]))
    xs = np.array([x[int(round(t / T * 100))] for t in t_steady])
    xp = np.array([x[int(round(t / T * 100))] for t in t_poincare])
    return wall, sol.nfev, xs, xp


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("hertzgear")
    ap.add_argument("--case", choices=sorted(CASES), default="paper")
    ap.add_argument("--periods", type=int, default=0, help="0: the case's default")
    ap.add_argument("--rtols", default="1e-6,1e-8")
    ap.add_argument("--integrators", default="cvode-bdf,radau-iia",
                    help="hertzgear integrators; radau-iia:S fixes the stage count")
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args()
    use_case(args.case)
    T = 2 * math.pi / OMEGA
    P = args.periods or CASES[args.case]["periods"]
    tmp = tempfile.mkdtemp(prefix="hg_lsoda_")
    global C

    ref, ref_p = run_hertzgear(args.hertzgear, args.case, 1e-13, 1e-17, P, os.path.join(tmp, "ref"),
                               "radau-iia", 7)
    m = ref["model"]
    if C is None:
        C = m["damping_N_s_per_m"]
    for name, ours in [("equivalent_mass_kg", M_E), ("damping_N_s_per_m", C),
                       ("k_rest_mean_N_per_m", K), ("k_hertz_mean_N_per_m_pow_n", KH_MEAN),
                       ("half_backlash_um", B_C * 1e6), ("mesh_frequency_Hz", OMEGA / (2 * math.pi))]:
        assert abs(m[name] - ours) <= 1e-12 * abs(ours), (name, m[name], ours)
    assert abs(ref["static_force_N"] - F0) <= 1e-12 * F0, ref["static_force_N"]
    ref_rms = ref["rms_dte_um"] * 1e-6

    contenders = []
    for spec in args.integrators.split(","):
        name, _, stages = spec.partition(":")
        contenders.append((f"hertzgear {spec}", name, int(stages or 0)))
    rtols = [float(r) for r in args.rtols.split(",")]
    walls = {}
    result = {}
    for _ in range(args.repeat):
        for rtol in rtols:
            atol = 1e-5 * rtol
            for label, name, stages in contenders:
                hg, hg_p = run_hertzgear(args.hertzgear, args.case, rtol, atol, P,
                                         os.path.join(tmp, f"hg{name}{stages}{rtol}"), name, stages)
                walls.setdefault((label, rtol), []).append(hg["integrator"]["wall_time_s"])
                result[(label, rtol)] = (hg["integrator"]["rhs_evals"],
                                         abs(hg["rms_dte_um"] * 1e-6 - ref_rms) / ref_rms,
                                         np.max(np.abs(hg_p - ref_p)))
            wall, nfev, xs, xp = lsoda(rtol, atol, P, T)
            walls.setdefault(("scipy LSODA", rtol), []).append(wall)
            if xs is None:
                result[("scipy LSODA", rtol)] = (nfev, float("nan"), float("nan"))
            else:
                result[("scipy LSODA", rtol)] = (nfev, abs(math.sqrt(np.mean(xs ** 2)) - ref_rms) / ref_rms,
                                                 np.max(np.abs(xp - ref_p)))
    rows = [(label, rtol, float(np.median(walls[(label, rtol)]))) + result[(label, rtol)]
            for rtol in rtols for label in [c[0] for c in contenders] + ["scipy LSODA"]]

    print(f"case {args.case}, {P} mesh periods ({P - P // 2} steady), median wall times of "
          f"{args.repeat} alternating runs; reference hertzgear radau-iia s=7 rtol 1e-13 atol 1e-17 m, "
          f"RMS DTE {ref['rms_dte_um']:.8f} um, {ref['integrator']['wall_time_s']:.3f} s")
    print(f"{'solver':22s} {'rtol':>7s} {'wall [s]':>9s} {'RHS evals':>10s} {'RMS rel err':>12s} {'Poincare err [um]':>18s}")
    for r in rows:
        print(f"{r[0]:22s} {r[1]:7.0e} {r[2]:9.4f} {r[3]:10d} {r[4]:12.2e} {1e6 * r[5]:18.3e}")
    hg_rows = [r for r in rows if r[0].startswith("hertzgear")]
    for r in rows:
        if r[0] != "scipy LSODA" or not math.isfinite(r[5]):
            continue
        for prefix in sorted({h[0].split(":")[0] for h in hg_rows}):
            ok = [h for h in hg_rows if h[0].split(":")[0] == prefix and h[5] <= r[5]
                  and h[4] <= max(r[4], 1e-12)]
            if ok:
                best = min(ok, key=lambda h: h[2])
                print(f"LSODA rtol {r[1]:.0e}: {r[2] / best[2]:.1f}x slower than {best[0]} rtol {best[1]:.0e} "
                      f"at equal or better accuracy")
            else:
                print(f"LSODA rtol {r[1]:.0e}: no {prefix} run in the table is as accurate")


if __name__ == "__main__":
    sys.exit(main())
