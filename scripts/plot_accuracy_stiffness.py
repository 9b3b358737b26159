#!/usr/bin/env python3
"""Refinement plot of `hertzgear accuracy stiffness`: relative error against the Richardson-
extrapolated value, versus DOFs and versus wall time (FE levels), and versus the number of
contact-grid cells across the profile (contact grids). The grid rungs share one set of factorised
FE bodies and cost fractions of a second, and the CSV gives the finer grids one averaged time, so
they are drawn against their cell count, not against time.

usage: plot_accuracy_stiffness.py accuracy_stiffness.csv accuracy_stiffness.png
(run with /usr/bin/python3: it needs matplotlib)
"""
import csv
import math
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

QUANTITIES = [("k_total_relative_error", "mean k_total", "o-"),
              ("ste_pp_relative_error", "STE peak-to-peak", "s-"),
              ("k_mh_relative_error", "k_mh", "^-")]


def points(rows, study, xkey, ekey):
    pts = []
    for r in rows:
        if r["study"] != study:
            continue
        x, e = float(r[xkey]), float(r[ekey])
        if math.isfinite(e) and x > 0:
            pts.append((x, max(e, 1e-8)))
    return sorted(pts)


def main(csv_path, png_path):
    rows = list(csv.DictReader(open(csv_path)))
    fig, axes = plt.subplots(1, 3, figsize=(13, 3.9))
    ax = axes[0]
    for key, label, style in QUANTITIES:
        pts = points(rows, "fe_level", "dofs", key)
        if pts:
            ax.loglog([p[0] for p in pts], [p[1] for p in pts], style, label=label)
    ax.axhline(0.01, color="grey", lw=0.8, ls="--", label="1 %")
    ax.set_xlabel("DOFs (pinion + gear)")
    ax.set_ylabel("relative error vs. extrapolated value")
    ax.set_title("FE refinement levels")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    ax = axes[1]
    for key, label, style in QUANTITIES[:2]:
        pts = points(rows, "fe_level", "wall_time_s", key)
        if pts:
            ax.loglog([p[0] for p in pts], [p[1] for p in pts], style, label=label)
    ax.axhline(0.01, color="grey", lw=0.8, ls="--")
    ax.set_xlabel("wall time of the level [s]")
    ax.set_title("FE levels: error versus time")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    ax = axes[2]
    for key, label, style in QUANTITIES:
        pts = points(rows, "contact_grid", "contact_profile_cells", key)
        if pts:
            ax.loglog([p[0] for p in pts], [p[1] for p in pts], style.replace("-", "--"),
                      label=label)
    ax.axhline(0.01, color="grey", lw=0.8, ls="--")
    ax.set_xlabel("contact-grid cells across the profile")
    ax.set_title("contact grids (scene's FE level)")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(png_path, dpi=90)


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    main(sys.argv[1], sys.argv[2])
