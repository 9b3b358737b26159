#!/usr/bin/env python3
"""Synthetic TEST DATA for the hertzgear report: artifacts in the column contract of the
stiffness, dynamics, sweep and accuracy commands, made from closed-form signals (a sinusoidal DTE
with a subharmonic, a cosine stiffness, an elliptical contact pattern that grows with load and
shifts with misalignment), not from any solver. Only the report is tested with it.

    make_report_artifacts.py DIR [--layout flat|nested] [--only dynamics|stiffness]
"""

import argparse
import csv
import json
import math
import os

import numpy as np

F_MESH_HZ = 23 * 150 / 60.0      # 23 pinion teeth at 150 rpm
B_C_UM = 58.6                    # half backlash
F0_N = 6480.0                    # static mesh force


def write_csv(path, header, rows):
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(header)
        for r in rows:
            w.writerow(["%.10g" % v if isinstance(v, float) else v for v in r])


def write_json(path, value):
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "w") as f:
        json.dump(value, f, indent=2)


def stiffness(folder):
    n_pos = 9
    phase = np.arange(n_pos) / n_pos
    theta = 2 * np.pi * phase
    k_total = 3.0e8 + 0.6e8 * np.cos(theta) + 0.1e8 * np.cos(2 * theta - 0.4)
    k_hertz = 9.0e9 + 2.0e9 * np.cos(theta - 0.2)
    k_rest = 2.79e8 + 0.3e8 * np.cos(theta)
    pairs = np.where((phase < 0.35) | (phase > 0.85), 2, 1)
    share1 = np.where(pairs == 2, 0.5 + 0.4 * np.cos(np.pi * phase), 1.0)
    rows = []
    for i in range(n_pos):
        rows.append([i, phase[i], 21.0 / (k_total[i] / 3e8), k_total[i], k_hertz[i], k_rest[i],
                     int(pairs[i]), share1[i], 1 - share1[i], 1.2 + 0.3 * math.sin(theta[i]),
                     0.25 + 0.05 * math.cos(theta[i]), 4.0 + 1.0 * math.sin(theta[i]),
                     1100.0 + 250.0 * (pairs[i] == 1)])
    write_csv(os.path.join(folder, "stiffness.csv"),
              ["position", "mesh_phase", "ste_um", "k_total_N_per_m", "k_hertz", "k_rest_N_per_m",
               "pairs_in_contact", "load_share_1", "load_share_2", "hertz_penetration_um",
               "contact_a_mm", "contact_b_mm", "peak_pressure_MPa"], rows)
    summaries, contact = load_map(folder, rows)
    write_json(os.path.join(folder, "stiffness.json"), {
        "schema": "hertzgear-stiffness-table/1",
        "source": "synthetic test data",
        "hertz_exponent": 1.5,
        "harmonics": 2,
        "k_hertz_N_per_m_pow_n": {"mean": 9.0e9, "amplitudes": [2.0e9, 0.0], "phases_rad": [0.2, 0.0]},
        "k_rest_N_per_m": {"mean": 2.79e8, "amplitudes": [0.3e8, 0.0], "phases_rad": [0.0, 0.0]},
        "k_total_N_per_m": {"mean": 3.0e8, "amplitudes": [0.6e8, 0.1e8], "phases_rad": [0.0, 0.4]},
        "map": summaries,
        "contact": contact,
    })


# The load and design map of a stiffness run (stiffness_map.csv, stiffness.json "map" and
# "contact", contact_pattern.csv): a crowned and an uncrowned variant over torque and misalignment.
FACE_WIDTH_MM = 20.0
ACTIVE_ROLL_MM = (4.7, 18.5)
BASE_PITCH_MM = 8.0
TORQUE_NM = 210.0
MAP_HEADER = ["case", "torque_Nm", "torque_percent", "load_N", "pinion_crowning_um",
              "gear_crowning_um", "mesh_misalignment_um", "pinion_helix_slope_deviation_um",
              "gear_helix_slope_deviation_um", "position", "mesh_phase", "ste_um",
              "k_total_N_per_m", "k_hertz", "k_rest_N_per_m", "pairs_in_contact", "load_share_1",
              "load_share_2", "hertz_penetration_um", "contact_a_mm", "contact_b_mm",
              "peak_pressure_MPa", "k_total_tangent_N_per_m", "contact_centre_z_mm",
              "face_end_contact", "tip_contact"]


def map_cases():
    """(crowning µm, torque %, misalignment µm, pinion f_Hβ µm): a tolerance study
    (combination = product), every crowning x f_Hβ x misalignment x torque."""
    return [(c, t, m, f) for c in (0.0, 40.0) for f in (0.0, 20.0) for m in (-30.0, 0.0, 30.0)
            for t in (25.0, 50.0, 100.0, 150.0)]


def contact_band(crowning, percent, misalignment, slope=0.0):
    """(centre z, half length along the face, peak pressure) of the synthetic contact: the
    uncrowned one spans the face, the crowned one grows with load; misalignment and a helix
    slope deviation (the same lead gap) shift it."""
    half = FACE_WIDTH_MM / 2
    tilt = misalignment + slope
    length = half if crowning == 0 else min(half, 3.0 + 2.0 * math.sqrt(percent / 100.0))
    centre = -tilt / 30.0 * (1.5 if crowning else 4.0)
    return centre, length, 1200.0 * math.sqrt(percent / 100.0) * (1 + abs(tilt) / 60.0)


def map_rows(case, variant, stiffness_rows):
    crowning, percent, misalignment, slope = variant
    centre, length, p0 = contact_band(crowning, percent, misalignment, slope)
    scale = percent / 100.0
    edge = int(abs(centre) + length >= FACE_WIDTH_MM / 2 - 1e-9)
    rows = []
    for r in stiffness_rows:
        soft = 1.0 + crowning / 100.0
        rows.append([case, TORQUE_NM * scale, percent, F0_N * scale, crowning, crowning,
                     misalignment, slope, 0.0, r[0], r[1], r[2] * scale * soft, r[3] / soft, r[4], r[5] / soft,
                     r[6], r[7], r[8], r[9] * scale, r[10], length, p0 * (1 + 0.1 * (r[6] == 1)),
                     1.1 * r[3] / soft, centre, edge, int(r[0] == 0)])
    return rows


def map_summary(rows):
    column = {name: np.array([r[i] for r in rows], dtype=float)
              for i, name in enumerate(MAP_HEADER)}
    summary = {k: float(column[k][0]) for k in MAP_HEADER[:9]}
    summary["case"] = int(summary["case"])
    summary.update({
        "ste_peak_to_peak_um": float(np.ptp(column["ste_um"])),
        "mean_ste_um": float(np.mean(column["ste_um"])),
        "mean_k_total_N_per_m": float(np.mean(column["k_total_N_per_m"])),
        "mean_k_rest_N_per_m": float(np.mean(column["k_rest_N_per_m"])),
        "max_peak_pressure_MPa": float(np.max(column["peak_pressure_MPa"])),
        "contact_centre_z_min_mm": float(np.min(column["contact_centre_z_mm"])),
        "contact_centre_z_max_mm": float(np.max(column["contact_centre_z_mm"])),
        "face_end_contact_positions": int(np.sum(column["face_end_contact"])),
        "tip_contact_positions": int(np.sum(column["tip_contact"])),
        "contact_time_s": 0.01})
    return summary


def pattern_cells(case, variant, n_pos):
    """Loaded contact-grid cells on the pinion flank: three cells across the profile around each
    pair's contact line, sixteen across the face."""
    centre, length, p0 = contact_band(*variant)
    cells = []
    for position in range(n_pos):
        for pair in (0, 1):
            line = ACTIVE_ROLL_MM[0] + 0.2 + (position / n_pos + pair) * BASE_PITCH_MM
            if line > ACTIVE_ROLL_MM[1] - 0.2:
                continue
            for dr in (-0.2, 0.0, 0.2):
                for z in (np.arange(16) + 0.5) * FACE_WIDTH_MM / 16 - FACE_WIDTH_MM / 2:
                    u = 1 - ((z - centre) / length) ** 2
                    if u > 0:
                        cells.append([case, position, pair, line + dr, z,
                                      p0 * math.sqrt(u) * (1 - 2 * dr * dr / 0.09)])
    return cells


def load_map(folder, stiffness_rows):
    """stiffness_map.csv and contact_pattern.csv; returns stiffness.json's "map" and "contact"."""
    rows, summaries, cells = [], [], []
    for case, variant in enumerate(map_cases()):
        case_rows = map_rows(case, variant, stiffness_rows)
        rows += case_rows
        summaries.append(map_summary(case_rows))
        cells += pattern_cells(case, variant, len(stiffness_rows))
    scene = (40.0, 100.0, 0.0, 0.0)
    contact = {k: v for k, v in map_summary(map_rows(-1, scene, stiffness_rows)).items()
               if k not in MAP_HEADER[:9]}
    contact.update({"pinion_active_roll_min_mm": ACTIVE_ROLL_MM[0],
                    "pinion_active_roll_max_mm": ACTIVE_ROLL_MM[1],
                    "face_width_mm": FACE_WIDTH_MM})
    write_csv(os.path.join(folder, "stiffness_map.csv"), MAP_HEADER, rows)
    write_csv(os.path.join(folder, "contact_pattern.csv"),
              ["case", "position", "pair", "pinion_roll_mm", "z_mm", "pressure_MPa"],
              pattern_cells(-1, scene, len(stiffness_rows)) + cells)
    return summaries, contact


def dte(t):
    """Period-2 motion that dips below b_c (contact loss) after a decaying transient (µm)."""
    w = 2 * np.pi * F_MESH_HZ
    return (B_C_UM + 14.0 + 22.0 * np.sin(w * t) + 6.0 * np.sin(0.5 * w * t + 0.3)
            + 30.0 * np.exp(-t * F_MESH_HZ / 4.0) * np.cos(1.3 * w * t))


def dynamics(folder):
    periods, per = 40, 100
    t = np.arange(periods * per + 1) / (per * F_MESH_HZ)
    x = dte(t)
    rate = np.gradient(x * 1e-6, t)
    excess = np.clip(x - B_C_UM, 0.0, None)
    contact = np.where(x >= B_C_UM, 1, np.where(x <= -B_C_UM, -1, 0))
    penetration = 0.12 * excess ** (2 / 3)
    force = F0_N * excess / 14.0
    write_csv(os.path.join(folder, "timeseries.csv"),
              ["time_s", "dte_um", "dte_rate_m_per_s", "penetration_um", "mesh_force_N", "contact"],
              [[t[i], x[i], rate[i], penetration[i], force[i], int(contact[i])] for i in range(len(t))])
    tk = np.arange(0, periods + 1) / F_MESH_HZ
    xk = dte(tk)
    vk = np.interp(tk, t, rate)
    write_csv(os.path.join(folder, "poincare.csv"), ["time_s", "dte_um", "dte_rate_m_per_s"],
              [[tk[i], xk[i], vk[i]] for i in range(len(tk))])
    steady = t >= t[-1] / 2
    xs = x[steady] - x[steady].mean()
    spec = 2 * np.abs(np.fft.rfft(xs)) / len(xs) + 1e-6
    freq = np.fft.rfftfreq(len(xs), t[1] - t[0])
    write_csv(os.path.join(folder, "spectrum.csv"), ["frequency_Hz", "amplitude_um"],
              [[freq[i], spec[i]] for i in range(len(freq))])
    rows = []
    for impact in range(1, 6):
        d_max = 1.0 + 0.1 * impact
        for s in np.linspace(0, np.pi, 60):
            d = d_max * math.sin(s)
            d_rate = math.cos(s)
            f = 6.0e3 * d ** 1.5 * (1 + 0.4 * d_rate)
            rows.append([impact, d, max(f, 0.0)])
    write_csv(os.path.join(folder, "force_penetration.csv"),
              ["impact", "penetration_um", "mesh_force_N"], rows)
    write_json(os.path.join(folder, "summary.json"), {
        "rms_dte_um": float(np.sqrt(np.mean(x[steady] ** 2))), "mean_mesh_force_N": 6470.0,
        "static_force_N": F0_N, "max_mesh_force_N": float(force.max()),
        "dynamic_factor": float(force.max() / F0_N), "contact_loss_fraction": 0.18,
        "contact_losses_per_period": 0.5, "backside_impacts": 0, "period_multiplicity": 2,
        "max_penetration_um": float(penetration.max()), "state_dimension": 3,
        "effects": {"backlash": "on", "hertzian_layer": "dynamic"},
        "equivalent_mass_kg": 0.51, "half_backlash_um": B_C_UM,
        "mesh_frequency_Hz": F_MESH_HZ,
        "integrator": {"name": "cvode-bdf", "steps": 12345, "rejected_steps": 12,
                       "rhs_evals": 23456, "events": 80},
        "wall_time_s": 0.05,
    })


def sweep(folder):
    speeds = np.arange(50.0, 601.0, 10.0)
    rows, bif = [], []
    for direction in ("up", "down"):
        for n in speeds:
            shift = 20.0 if direction == "down" else 0.0
            rms = 70.0 + 40.0 / (1 + ((n - 300.0 - shift) / 40.0) ** 2)
            period = 2 if 250 <= n <= 330 else 1
            rows.append([n, direction, rms, rms - 50.0, rms + 50.0, 1.0 + (rms - 70.0) / 40.0,
                         0.3 * (rms > 90.0), period])
    for n in speeds:
        branches = (2 if 250 <= n <= 330 else 1)
        for b in range(branches):
            bif.append([n, 70.0 + 20.0 * (b - 0.5 * (branches - 1)) * (n - 240.0) / 90.0])
    write_csv(os.path.join(folder, "sweep.csv"),
              ["speed_rpm", "direction", "rms_dte_um", "min_dte_um", "max_dte_um", "dynamic_factor",
               "contact_loss_fraction", "period_multiplicity"], rows)
    write_csv(os.path.join(folder, "bifurcation.csv"), ["speed_rpm", "poincare_dte_um"], bif)


def accuracy(path):
    rows = []
    for integrator, cost, order in (("rk4", 0.4, 4), ("arkode-erk", 0.08, 5), ("cvode-bdf", 0.02, 3)):
        for k, tol in enumerate((1e-4, 1e-6, 1e-8, 1e-10)):
            rows.append([integrator, tol, cost * (1 + k) ** 1.6, int(1e4 * (1 + k) ** 1.6),
                         tol * 3.0, tol * 50.0])
    write_csv(path, ["integrator", "tolerance", "wall_time_s", "rhs_evals", "rms_dte_rel_error",
                     "poincare_error_um"], rows)


def main():
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("dir")
    parser.add_argument("--layout", choices=("flat", "nested"), default="nested")
    parser.add_argument("--only", choices=("dynamics", "stiffness"))
    args = parser.parse_args()
    nested = args.layout == "nested"
    sub = (lambda name: os.path.join(args.dir, name)) if nested else (lambda name: args.dir)
    os.makedirs(args.dir, exist_ok=True)
    if args.only in (None, "stiffness"):
        stiffness(sub("stiffness"))
    if args.only in (None, "dynamics"):
        dynamics(sub("dynamics"))
    if args.only is None:
        sweep(sub("sweep"))
        accuracy(os.path.join(args.dir, "accuracy", "work_precision.csv") if nested
                 else os.path.join(args.dir, "accuracy_dynamics.csv"))


if __name__ == "__main__":
    main()
