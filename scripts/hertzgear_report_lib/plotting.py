"""Matplotlib set-up (Agg backend, one style for every figure) and the drawing helpers the figures
share: axis labels with units, scaling and shifting of values for readable ticks, legends beside
the title, markers for mesh periods and the backlash, contact shading, the Fourier series of a set
of coefficients, and atomic PNG output.
"""

import math

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402 (after the backend is chosen)
import numpy as np  # noqa: E402

from .artifacts import replace_atomically  # noqa: E402

COLORS = ["#1f5fa8", "#d0591c", "#2e8b57", "#8e44ad", "#b8860b", "#c0392b", "#17a2b8", "#555555"]

UNIT_SUFFIXES = [
    ("_n_per_m_pow_n", "N/m$^n$"), ("_n_per_m", "N/m"), ("_m_per_s", "m/s"), ("_n_s_per_m", "N s/m"),
    ("_um", "µm"), ("_mm", "mm"), ("_mpa", "MPa"), ("_hz", "Hz"), ("_rpm", "rpm"), ("_kn", "kN"),
    ("_n", "N"), ("_mj", "mJ"), ("_j", "J"), ("_s", "s"), ("_m", "m"),
]


def style():
    plt.rcParams.update({
        "figure.dpi": 110, "font.size": 10, "axes.titlesize": 11, "axes.labelsize": 10,
        "axes.grid": True, "grid.alpha": 0.3, "axes.spines.top": False,
        "axes.spines.right": False, "legend.frameon": False, "axes.titlelocation": "left", "legend.fontsize": 9,
        "axes.prop_cycle": matplotlib.cycler(color=COLORS),
        "figure.constrained_layout.use": True,
    })


def save_figure_atomically(fig, path):
    try:
        replace_atomically(path, lambda tmp: fig.savefig(tmp, format="png", dpi=110))
    finally:
        plt.close(fig)


def close_all():
    plt.close("all")


# --------------------------------------------------------------------------------------------
# Units and labels
# --------------------------------------------------------------------------------------------

def unit_of(column):
    """The unit a column name carries as a suffix (dte_um) or, for multi-letter units, inside
    (dte_um_at_section)."""
    low = column.lower()
    for suffix, unit in UNIT_SUFFIXES:
        if low.endswith(suffix):
            return unit
    for suffix, unit in UNIT_SUFFIXES:
        if len(suffix) > 3 and suffix + "_" in low:
            return unit
    return None


def label(text, column=None, unit=None):
    unit = unit or (unit_of(column) if column else None)
    return "%s (%s)" % (text, unit) if unit else "%s (–)" % text


def shifted_label(text, unit, ref):
    if not ref:
        return label(text, unit=unit)
    return "%s − %.7g %s (%s)" % (text, ref, unit, unit)


def scaled(values, unit):
    """Values divided by a power of ten that keeps tick labels short, and the label unit."""
    finite = np.asarray(values, dtype=float)
    finite = finite[np.isfinite(finite)]
    peak = np.max(np.abs(finite)) if finite.size else 0.0
    if peak == 0 or 1e-2 <= peak < 1e4:
        return 1.0, unit
    exponent = int(math.floor(math.log10(peak)))
    return 10.0 ** exponent, "10$^{%d}$ %s" % (exponent, unit)


def reference_of(values, rel=1e-4):
    """A value to subtract before plotting when the variation is tiny against the level (ticks
    would otherwise need more than four significant digits), else 0."""
    v = np.asarray(values, dtype=float)
    v = v[np.isfinite(v)]
    if v.size < 2:
        return 0.0
    mean = float(np.mean(v))
    if mean == 0 or np.ptp(v) >= rel * abs(mean):
        return 0.0
    return float("%.7g" % mean)


def force_scale(ref):
    """(divisor, unit) of a force axis: N when a reference is subtracted, else kN."""
    return (1.0, "N") if ref else (1e3, "kN")


def span_limits(values, min_span):
    """Axis limits that hold the values and span at least min_span (centred on them), or None
    when the values already span more."""
    v = np.asarray(values, dtype=float)
    v = v[np.isfinite(v)]
    if v.size == 0 or not (min_span > 0) or np.ptp(v) >= min_span:
        return None
    centre = 0.5 * (v.min() + v.max())
    return centre - 0.55 * min_span, centre + 0.55 * min_span


def fourier_value(series, phase_cycles):
    """mean + sum_j A_j cos(j theta - phi_j), theta = 2 pi (mesh phase in cycles)."""
    theta = 2 * np.pi * np.asarray(phase_cycles)
    y = np.full_like(theta, float(series["mean"]), dtype=float)
    for j, (a, phi) in enumerate(zip(series.get("amplitudes", []), series.get("phases_rad", [])),
                                 start=1):
        y += a * np.cos(j * theta - phi)
    return y


# --------------------------------------------------------------------------------------------
# Decoration
# --------------------------------------------------------------------------------------------

def title_and_legend(ax, title, extra_axes=(), ncol=4):
    """Title on the left above the axes, legend on the right on the same line, off the data."""
    ax.set_title(title, loc="left")
    handles, labels = ax.get_legend_handles_labels()
    for other in extra_axes:
        h, l = other.get_legend_handles_labels()
        handles, labels = handles + h, labels + l
    if not handles:
        return
    fig = ax.get_figure()
    width_in = ax.get_position().width * fig.get_figwidth()
    text_in = sum(len(l) for l in labels) * 0.075 + 0.5 * len(labels) + 0.09 * len(title)
    if text_in > width_in or len(labels) > 2 * ncol:
        # No room beside the title: inside the axes, on a white box, where the data leave space.
        ax.legend(handles, labels, loc="best", ncol=1, frameon=True, framealpha=0.9,
                  edgecolor="#dddddd", fontsize=8.5)
    else:
        ax.legend(handles, labels, loc="lower right", bbox_to_anchor=(1.0, 1.0), ncol=ncol,
                  borderaxespad=0.2, handlelength=1.6, columnspacing=1.2)


def right_axis(ax, ylabel):
    """A twin axis on the right for a second quantity, with its spine and without a grid."""
    ax2 = ax.twinx()
    ax2.set_ylabel(ylabel)
    ax2.spines["right"].set_visible(True)
    ax2.grid(False)
    return ax2


def mark_mesh_periods(ax, t0, t1, period, label_first=True):
    """Vertical lines at multiples of the mesh period (the x grid is turned off to keep them apart)."""
    if not period or period <= 0:
        return
    k0, k1 = math.ceil(t0 / period - 1e-9), math.floor(t1 / period + 1e-9)
    if k1 - k0 > 60:
        return
    ax.grid(False, axis="x")
    for i, k in enumerate(range(k0, k1 + 1)):
        ax.axvline(k * period, color="#5b6575", lw=0.8, ls=(0, (2, 3)), zorder=1,
                   label="mesh period $T_m$" if (i == 0 and label_first) else None)


def mark_backlash(ax, b_c_um, horizontal=True, near_data=False):
    """Dashed lines at ±b_c; with near_data only those within the data range (plus a margin), so
    a plot of one side of the backlash keeps its scale."""
    if b_c_um is None:
        return
    line = ax.axhline if horizontal else ax.axvline
    values = [b_c_um, -b_c_um]
    if near_data:
        ax.autoscale_view()
        lo, hi = ax.get_ylim() if horizontal else ax.get_xlim()
        margin = 0.25 * (hi - lo)
        values = [v for v in values if lo - margin <= v <= hi + margin]
        if not values:
            ax.text(0.995, 0.02, "±b$_c$ off scale", transform=ax.transAxes, ha="right",
                    va="bottom", fontsize=8, color="#c0392b", zorder=5,
                    bbox=dict(facecolor="white", edgecolor="none", alpha=0.8, pad=1.5))
    for i, v in enumerate(values):
        line(v, color="#c0392b", lw=1.0, ls="--",
             label=("±$b_c$ = ±%.4g µm" % b_c_um) if i == 0 else None)


def shifted(value, ref):
    """value − ref, or None when there is no value (a backlash line that does not exist)."""
    return value - ref if value is not None else None


def shade_contact(ax, t, contact):
    """Grey bands where the teeth are separated (contact 0), red where they hit back (contact −1)."""
    if contact is None:
        return
    labelled = set()
    for value, color, text in ((0, "#bbbbbb", "separated"), (-1, "#f5b7b1", "back-side contact")):
        on = np.asarray(np.round(contact) == value, dtype=int)
        if not on.any():
            continue
        edges = np.flatnonzero(np.diff(np.concatenate([[0], on, [0]])))
        for a, b in zip(edges[::2], edges[1::2]):
            ax.axvspan(t[a], t[min(b, len(t) - 1)], color=color, alpha=0.5, lw=0,
                       label=text if value not in labelled else None)
            labelled.add(value)
