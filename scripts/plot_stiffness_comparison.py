#!/usr/bin/env python3
"""Mesh stiffness, loaded STE and load share over one mesh cycle from several stiffness.csv files
(FE and the closed-form sources of `hertzgear stiffness`), drawn on one figure.

usage: plot_stiffness_comparison.py OUT.png "TITLE" LABEL=path/stiffness.csv [LABEL=...]
(run with /usr/bin/python3: it needs matplotlib)
"""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

STYLES = ["o-", "s--", "^-.", "d:", "v-"]


def main(png_path, title, specs):
    fig, axes = plt.subplots(1, 3, figsize=(13, 3.9))
    for i, spec in enumerate(specs):
        label, path = spec.split("=", 1)
        rows = list(csv.DictReader(open(path)))
        phase = [float(r["mesh_phase"]) for r in rows]
        style = STYLES[i % len(STYLES)]
        axes[0].plot(phase, [float(r["k_total_N_per_m"]) / 1e6 for r in rows], style, ms=4, label=label)
        axes[1].plot(phase, [float(r["ste_um"]) for r in rows], style, ms=4, label=label)
        share = [float(r["load_share_1"]) if r["load_share_1"] else float("nan") for r in rows]
        axes[2].plot(phase, share, style, ms=4, label=label)
    axes[0].set_ylabel("k_total [N/µm]")
    axes[1].set_ylabel("loaded STE [µm]")
    axes[2].set_ylabel("load share of pair 1")
    for ax in axes:
        ax.set_xlabel("mesh phase")
        ax.grid(True, alpha=0.3)
    axes[2].legend(fontsize=8, loc="lower right")
    fig.suptitle(title)
    fig.tight_layout()
    fig.savefig(png_path, dpi=110)


if __name__ == "__main__":
    if len(sys.argv) < 4:
        sys.exit(__doc__)
    main(sys.argv[1], sys.argv[2], sys.argv[3:])
