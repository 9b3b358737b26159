#!/usr/bin/env python3
"""Work-precision plot of `hertzgear accuracy dynamics`: error against wall time per integrator.

usage: plot_accuracy_dynamics.py accuracy_dynamics.csv accuracy_dynamics.png
"""
import csv
import math
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main(csv_path, png_path):
    rows = list(csv.DictReader(open(csv_path)))
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2))
    panels = [("rms_dte_relative_error", "relative error of RMS DTE"),
              ("poincare_max_error_um", "max Poincare error [um]")]
    for ax, (key, label) in zip(axes, panels):
        def series(r):
            # radau-iia once per stage count.
            return r["integrator"] + (f" s={r['stages']}" if r.get("stages") else "")

        for name in sorted({series(r) for r in rows}):
            pts = []
            for r in rows:
                if series(r) != name or r["status"] != "ok":
                    continue
                err, t = float(r[key]), float(r["wall_time_s"])
                if math.isfinite(err) and t > 0:
                    pts.append((t, max(err, 1e-16), r["relative_tolerance"] or r["steps_per_period"]))
            if not pts:
                continue
            # In table order (tightening tolerance, or more steps), so each line reads as a ladder.
            ax.loglog([p[0] for p in pts], [p[1] for p in pts], "o-", label=name)
            for t, e, tag in pts:
                ax.annotate(tag, (t, e), fontsize=6, textcoords="offset points", xytext=(3, 3))
        ax.set_xlabel("wall time [s]")
        ax.set_ylabel(label)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8)
    fig.suptitle("hertzgear dynamics: work-precision (converged reference)")
    fig.tight_layout()
    fig.savefig(png_path, dpi=120)


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    main(sys.argv[1], sys.argv[2])
