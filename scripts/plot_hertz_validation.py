#!/usr/bin/python3
"""Figures of `hertzgear validate hertz --out DIR`.

    /usr/bin/python3 scripts/plot_hertz_validation.py DIR [FIGURE_DIR [PREFIX]]

Reads DIR/hertz_validation.csv and DIR/pressure_profiles.csv and writes to FIGURE_DIR (default
DIR): PREFIXerror_vs_dofs.png, PREFIXerror_vs_time.png (|relative error| of the semi-axes,
half-width and peak pressure per case against the number of DOFs and against the cumulative wall
time of the adaptive run) and PREFIXpressure_profiles.png (FE nodal pressure against Hertz's
p0 sqrt(1 - x^2/a^2 - y^2/b^2) along both axes, finest level). PREFIX defaults to "hertz_"; the
figures of docs/validation-hertz.md are made with FIGURE_DIR = docs/figures and
PREFIX = validation_hertz_. The finite-length line contacts, where Hertz's infinite line is not
the exact answer (end effects), are drawn dashed. Needs matplotlib (Debian's /usr/bin/python3 has
it).
"""
import csv
import os
import sys
from collections import defaultdict

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

QUANTITIES = ["semi_axis_x", "semi_axis_y", "half_width", "peak_pressure"]
MARKERS = {"semi_axis_x": "o", "semi_axis_y": "s", "half_width": "^", "peak_pressure": "D"}
# Cases whose closed form is not the exact answer of the modelled problem (finite line contacts).
NOT_EXACT = ("finite_cylinder",)


def read_rows(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def error_figure(rows, x_key, x_label, out):
    series = defaultdict(list)
    for r in rows:
        if r["quantity"] in QUANTITIES:
            series[(r["case"], r["quantity"])].append(
                (float(r[x_key]), abs(float(r["relative_error"]))))
    cases = sorted({c for c, _ in series})
    colours = {c: plt.cm.tab10(i % 10) for i, c in enumerate(cases)}
    fig, ax = plt.subplots(figsize=(8, 5.5))
    for (case, q), pts in sorted(series.items()):
        pts.sort()
        dashed = case.startswith(NOT_EXACT)
        ax.loglog([p[0] for p in pts], [max(p[1], 1e-6) for p in pts], marker=MARKERS[q],
                  color=colours[case], ls="--" if dashed else "-", alpha=0.6 if dashed else 1.0,
                  label=f"{case}: {q}")
    ax.axhline(0.02, color="k", ls="--", lw=0.8)
    ax.text(ax.get_xlim()[0], 0.021, " 2 % acceptance", fontsize=8, va="bottom")
    ax.set_xlabel(x_label)
    ax.set_ylabel("|relative error| against the Hertz closed form")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7, ncol=2)
    fig.tight_layout()
    fig.savefig(out, dpi=90)
    plt.close(fig)


def profile_figure(rows, out):
    by_case = defaultdict(lambda: defaultdict(list))
    for r in rows:
        by_case[r["case"]][r["axis"]].append(
            (float(r["coordinate_mm"]), float(r["fe_pressure_MPa"]), float(r["hertz_pressure_MPa"])))
    cases = sorted(by_case)
    ncols = 2
    nrows = (len(cases) + ncols - 1) // ncols
    fig, axes = plt.subplots(nrows, ncols, figsize=(11, 2.7 * nrows), squeeze=False)
    for ax in axes.flat[len(cases):]:
        ax.set_visible(False)
    for ax, case in zip(axes.flat, cases):
        for axis, style in (("x", "C0"), ("y", "C1")):
            pts = sorted(by_case[case].get(axis, []))
            if not pts:
                continue
            ax.plot([p[0] for p in pts], [p[2] for p in pts], "-", color=style, lw=1,
                    label=f"Hertz along {axis}")
            ax.plot([p[0] for p in pts], [p[1] for p in pts], ".", color=style, ms=3,
                    label=f"FE along {axis}")
        ax.set_title(case, fontsize=9)
        ax.set_ylabel("p [MPa]")
        ax.set_xlabel("distance from the contact centre [mm]", fontsize=8)
        ax.legend(fontsize=7)
        ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(out, dpi=80)
    plt.close(fig)


def main():
    if len(sys.argv) not in (2, 3, 4):
        sys.exit(__doc__)
    run_dir = sys.argv[1]
    fig_dir = sys.argv[2] if len(sys.argv) >= 3 else run_dir
    prefix = sys.argv[3] if len(sys.argv) == 4 else "hertz_"
    os.makedirs(fig_dir, exist_ok=True)
    rows = read_rows(os.path.join(run_dir, "hertz_validation.csv"))
    error_figure(rows, "dofs", "degrees of freedom (modelled half/quarter)",
                 os.path.join(fig_dir, prefix + "error_vs_dofs.png"))
    error_figure(rows, "wall_time_s", "cumulative wall time of the adaptive run [s]",
                 os.path.join(fig_dir, prefix + "error_vs_time.png"))
    profile_figure(read_rows(os.path.join(run_dir, "pressure_profiles.csv")),
                   os.path.join(fig_dir, prefix + "pressure_profiles.png"))


if __name__ == "__main__":
    main()
