#!/usr/bin/env python3
"""hertzgear report: figures and one HTML page from the artifacts of a hertzgear run.

    hertzgear_report.py DIR [--out REPORT_DIR]

Reads whatever artifacts DIR holds, flat or in the sub-folders stiffness/, dynamics/, sweep/ and
accuracy/ (stiffness.csv/json, timeseries.csv, poincare.csv, spectrum.csv, force_penetration.csv,
summary.json, sweep.csv, bifurcation.csv, accuracy tables, used_parameters.prm, run.json) and
writes PNG figures and index.html into DIR/report/ (or REPORT_DIR). A figure whose input is absent
is left out with a note on the page. Every file is written atomically (temporary file in the same
folder, then os.replace), so an interrupted report leaves no half-written file behind.

Needs only Python 3, numpy and matplotlib (Debian: python3-numpy, python3-matplotlib); no network.
Exit codes: 0 report written, 2 DIR missing or holding no artifact, 1 anything else.
"""

import argparse
import csv
import html
import json
import math
import os
import re
import sys
import tempfile
import time
import traceback

try:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np
    from matplotlib.patches import Ellipse, Rectangle
except ImportError as missing:
    sys.stderr.write("hertzgear report: error: %s; this interpreter (%s) needs numpy and matplotlib "
                     "(Debian: apt-get install python3-numpy python3-matplotlib), or point "
                     "HERTZGEAR_PYTHON at one that has them\n" % (missing, sys.executable))
    sys.exit(1)

EXIT_BAD_INPUT = 2

# Sub-folders a pipeline may nest its stages in; the run directory itself comes first.
STAGE_FOLDERS = ("", "stiffness", "dynamics", "sweep", "accuracy")

ARTIFACT_NAMES = (
    "stiffness.csv", "stiffness.json", "timeseries.csv", "poincare.csv", "spectrum.csv",
    "force_penetration.csv", "summary.json", "sweep.csv", "bifurcation.csv",
    "used_parameters.prm", "run.json",
)

COLORS = ["#1f5fa8", "#d0591c", "#2e8b57", "#8e44ad", "#b8860b", "#c0392b", "#17a2b8", "#555555"]


class BadInput(Exception):
    """Input the report cannot work with: exit code 2."""


# --------------------------------------------------------------------------------------------
# Atomic output
# --------------------------------------------------------------------------------------------

def _temporary_in(directory, name):
    fd, tmp = tempfile.mkstemp(prefix="." + name + ".hg-partial-", dir=directory)
    os.close(fd)
    return tmp


def write_text_atomically(path, text):
    directory, name = os.path.split(path)
    tmp = _temporary_in(directory, name)
    try:
        with open(tmp, "w", encoding="utf-8") as f:
            f.write(text)
            f.flush()
            os.fsync(f.fileno())
        os.chmod(tmp, 0o644)
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.remove(tmp)
        raise


def save_figure_atomically(fig, path):
    directory, name = os.path.split(path)
    tmp = _temporary_in(directory, name)
    try:
        fig.savefig(tmp, format="png", dpi=110)
        with open(tmp, "rb") as f:
            os.fsync(f.fileno())
        os.chmod(tmp, 0o644)
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.remove(tmp)
        raise
    finally:
        plt.close(fig)


# --------------------------------------------------------------------------------------------
# Reading artifacts
# --------------------------------------------------------------------------------------------

class Table:
    """A CSV table: column name -> numpy array (float where every entry parses, else str)."""

    def __init__(self, path):
        self.path = path
        self.columns = {}
        self.names = []
        with open(path, newline="", encoding="utf-8") as f:
            lines = [line for line in f if line.strip() and not line.lstrip().startswith("#")]
        rows = list(csv.reader(lines))
        if not rows:
            raise BadInput("%s is empty" % path)
        self.names = [n.strip() for n in rows[0]]
        body = [r for r in rows[1:] if len(r) == len(self.names)]
        for i, name in enumerate(self.names):
            raw = [r[i].strip() for r in body]
            try:
                self.columns[name] = np.array([float(v) if v != "" else np.nan for v in raw])
            except ValueError:
                self.columns[name] = np.array(raw, dtype=object)

    @classmethod
    def from_columns(cls, path, columns):
        """A table from equal-length numeric lists (e.g. the samples of stiffness.json)."""
        table = cls.__new__(cls)
        table.path = path
        table.names = list(columns)
        table.columns = {k: np.asarray(v, dtype=float) for k, v in columns.items()}
        return table

    def __len__(self):
        return len(next(iter(self.columns.values()))) if self.columns else 0

    def numeric(self, name):
        return name in self.columns and self.columns[name].dtype != object

    def find(self, *patterns, exclude=()):
        """First column whose lower-case name starts with a pattern (or matches a regex 're:...')."""
        for pattern in patterns:
            for name in self.names:
                low = name.lower()
                if any(e in low for e in exclude):
                    continue
                if pattern.startswith("re:"):
                    if re.search(pattern[3:], low):
                        return name
                elif low.startswith(pattern):
                    return name
        return None

    def __getitem__(self, name):
        return self.columns[name]


def load_json(path):
    with open(path, encoding="utf-8") as f:
        return json.load(f)


def parse_prm(path):
    """deal.II ParameterHandler text -> list of (section path, key, value, help, default)."""
    entries = []
    stack = []
    comment = []
    with open(path, encoding="utf-8") as f:
        for raw in f:
            line = raw.strip()
            if not line:
                comment = []
                continue
            if line.startswith("#"):
                text = line[1:].strip()
                if text and not set(text) <= set("-") and text != "Listing of Parameters":
                    comment.append(text)
                continue
            m = re.match(r"subsection\s+(.+)$", line)
            if m:
                stack.append(m.group(1).strip())
                comment = []
                continue
            if line == "end":
                if stack:
                    stack.pop()
                comment = []
                continue
            m = re.match(r"set\s+(.+?)\s*=\s*(.*)$", line)
            if m:
                value, default = m.group(2), None
                d = re.search(r"#\s*default:\s*(.*)$", value)
                if d:
                    default = d.group(1).strip()
                    value = value[: d.start()]
                value = value.split(" #")[0].strip()
                entries.append(("/".join(stack), m.group(1).strip(), value, " ".join(comment),
                                default))
                comment = []
    return entries


def prm_value(entries, section_suffix, key):
    for section, k, value, _, _ in entries:
        if k == key and section.endswith(section_suffix):
            return value
    return None


def prm_float(entries, section_suffix, key):
    v = prm_value(entries, section_suffix, key)
    try:
        return float(v) if v is not None else None
    except ValueError:
        return None


class Artifacts:
    """Finds each artifact in DIR or its stage sub-folders (the shallowest copy wins)."""

    def __init__(self, run_dir, report_dir):
        self.run_dir = os.path.abspath(run_dir)
        self.report_dir = os.path.abspath(report_dir)
        self.paths = {}
        for name in ARTIFACT_NAMES:
            for folder in STAGE_FOLDERS:
                p = os.path.join(self.run_dir, folder, name)
                if os.path.isfile(p):
                    self.paths[name] = p
                    break
        self.accuracy_tables = self._find_accuracy_tables()
        self.notes = []       # problems met while reading, shown on the page
        self._cache = {}

    def _find_accuracy_tables(self):
        found = []
        for folder in STAGE_FOLDERS:
            d = os.path.join(self.run_dir, folder)
            if not os.path.isdir(d) or os.path.abspath(d) == self.report_dir:
                continue
            for name in sorted(os.listdir(d)):
                low = name.lower()
                if not low.endswith(".csv"):
                    continue
                in_accuracy_folder = folder == "accuracy"
                if in_accuracy_folder or "accuracy" in low or "work_precision" in low:
                    p = os.path.join(d, name)
                    if p not in found:
                        found.append(p)
        return found

    def any(self):
        return bool(self.paths or self.accuracy_tables)

    def has(self, name):
        return name in self.paths

    def rel(self, name):
        return os.path.relpath(self.paths[name], self.run_dir)

    def get(self, name):
        """The parsed artifact, or None when it is absent or unreadable (with a note)."""
        if name not in self.paths:
            return None
        if name in self._cache:
            return self._cache[name]
        path = self.paths[name]
        try:
            if name.endswith(".csv"):
                value = Table(path)
                if len(value) == 0:
                    raise BadInput("no data rows")
            elif name.endswith(".json"):
                value = load_json(path)
            else:
                value = parse_prm(path)
        except Exception as e:  # an unreadable artifact costs its figures, not the report
            self.notes.append("%s could not be read: %s" % (self.rel(name), e))
            value = None
        self._cache[name] = value
        return value


# --------------------------------------------------------------------------------------------
# Units, scene quantities
# --------------------------------------------------------------------------------------------

UNIT_SUFFIXES = [
    ("_n_per_m_pow_n", "N/m$^n$"), ("_n_per_m", "N/m"), ("_m_per_s", "m/s"), ("_n_s_per_m", "N s/m"),
    ("_um", "µm"), ("_mm", "mm"), ("_mpa", "MPa"), ("_hz", "Hz"), ("_rpm", "rpm"), ("_kn", "kN"),
    ("_n", "N"), ("_mj", "mJ"), ("_j", "J"), ("_s", "s"), ("_m", "m"),
]


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


def length_in_um(key, value):
    low = key.lower()
    if low.endswith("_um"):
        return value
    if low.endswith("_mm"):
        return value * 1e3
    if low.endswith("_m"):
        return value * 1e6
    return None


def flatten(obj, prefix=""):
    out = []
    if isinstance(obj, dict):
        for k, v in obj.items():
            out.extend(flatten(v, prefix + "." + k if prefix else k))
    else:
        out.append((prefix, obj))
    return out


class Scene:
    """Quantities the figures need, from summary.json, else used_parameters.prm."""

    def __init__(self, art):
        self.summary = art.get("summary.json") or {}
        self.prm = art.get("used_parameters.prm") or []
        self.flat_summary = dict(flatten(self.summary)) if isinstance(self.summary, dict) else {}
        self.b_c_um, self.b_c_source = self._half_backlash()
        self.f_mesh_hz, self.f_mesh_source = self._mesh_frequency(art)
        self.hertz_exponent = self._hertz_exponent(art)
        self.static_force_n = self._number("static_force_n", "f0_n")
        self.transient_periods = prm_float(self.prm, "Dynamics", "transient_periods")

    def _number(self, *keys):
        for k, v in self.flat_summary.items():
            if k.split(".")[-1].lower() in keys and isinstance(v, (int, float)):
                return float(v)
        return None

    def _half_backlash(self):
        backlash_effect = prm_value(self.prm, "Effects", "backlash")
        if backlash_effect is not None and backlash_effect.lower() in ("off", "false", "0"):
            return None, "the backlash effect is off"
        for k, v in self.flat_summary.items():
            leaf = k.split(".")[-1].lower()
            if not isinstance(v, (int, float)) or isinstance(v, bool):
                continue
            um = length_in_um(leaf, float(v))
            if um is None:
                continue
            if leaf.startswith("b_c") or ("backlash" in leaf and "half" in leaf):
                return um, "summary.json (%s)" % k
            if "backlash" in leaf:
                return um / 2, "summary.json (%s / 2)" % k
        total_mm = prm_float(self.prm, "Operating", "backlash_mm")
        if total_mm is not None and total_mm > 0:
            return total_mm * 1e3 / 2, "used_parameters.prm (Operating/backlash_mm / 2)"
        return None, "no backlash value found"

    def _mesh_frequency(self, art):
        for k, v in self.flat_summary.items():
            leaf = k.split(".")[-1].lower()
            if not isinstance(v, (int, float)) or isinstance(v, bool) or v <= 0:
                continue
            if "mesh_frequency" in leaf and leaf.endswith("_hz"):
                return float(v), "summary.json (%s)" % k
            if "mesh_period" in leaf and leaf.endswith("_s"):
                return 1.0 / float(v), "summary.json (%s)" % k
        rpm = prm_float(self.prm, "Operating", "speed_rpm")
        teeth = prm_float(self.prm, "Gear pair/Pinion", "teeth")
        if rpm and teeth:
            return teeth * rpm / 60.0, "used_parameters.prm (z₁ n₁ / 60)"
        p = art.get("poincare.csv")
        if p is not None:
            t = p.find("time")
            if t and p.numeric(t) and len(p) > 2:
                dt = np.median(np.diff(p[t]))
                if dt > 0:
                    return 1.0 / dt, "poincare.csv (spacing of the section times)"
        return None, "no speed or mesh frequency found"

    def _hertz_exponent(self, art):
        stiffness = art.get("stiffness.json")
        if isinstance(stiffness, dict):
            for k, v in flatten(stiffness):
                if k.split(".")[-1].lower() in ("hertz_exponent", "exponent_n", "n") and \
                        isinstance(v, (int, float)):
                    return float(v)
        return prm_float(self.prm, "Stiffness", "hertz_exponent")


# --------------------------------------------------------------------------------------------
# Figure helpers
# --------------------------------------------------------------------------------------------

def style():
    plt.rcParams.update({
        "figure.dpi": 110, "font.size": 10, "axes.titlesize": 11, "axes.labelsize": 10,
        "axes.grid": True, "grid.alpha": 0.3, "axes.spines.top": False,
        "axes.spines.right": False, "legend.frameon": False, "axes.titlelocation": "left", "legend.fontsize": 9,
        "axes.prop_cycle": matplotlib.cycler(color=COLORS),
        "figure.constrained_layout.use": True,
    })


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


def span_limits(values, min_span):
    """Axis limits that hold the values and span at least min_span (centred on them), or None
    when the values already span more."""
    v = np.asarray(values, dtype=float)
    v = v[np.isfinite(v)]
    if v.size == 0 or not (min_span > 0) or np.ptp(v) >= min_span:
        return None
    centre = 0.5 * (v.min() + v.max())
    return centre - 0.55 * min_span, centre + 0.55 * min_span


def shifted_label(text, unit, ref):
    if not ref:
        return label(text, unit=unit)
    return "%s − %.7g %s (%s)" % (text, ref, unit, unit)


def fourier_value(series, phase_cycles):
    """mean + sum_j A_j cos(j theta - phi_j), theta = 2 pi (mesh phase in cycles)."""
    theta = 2 * np.pi * np.asarray(phase_cycles)
    y = np.full_like(theta, float(series["mean"]), dtype=float)
    for j, (a, phi) in enumerate(zip(series.get("amplitudes", []), series.get("phases_rad", [])),
                                 start=1):
        y += a * np.cos(j * theta - phi)
    return y


def fit_fourier(phase, samples, harmonics):
    """Least-squares fit in the same form as fourier_value."""
    theta = 2 * np.pi * np.asarray(phase)
    cols = [np.ones_like(theta)]
    for j in range(1, harmonics + 1):
        cols += [np.cos(j * theta), np.sin(j * theta)]
    coef, *_ = np.linalg.lstsq(np.column_stack(cols), np.asarray(samples), rcond=None)
    amps = [math.hypot(coef[2 * j - 1], coef[2 * j]) for j in range(1, harmonics + 1)]
    phases = [math.atan2(coef[2 * j], coef[2 * j - 1]) for j in range(1, harmonics + 1)]
    return {"mean": coef[0], "amplitudes": amps, "phases_rad": phases}


def as_series(obj):
    """{mean, amplitudes, phases_rad} from a dict with keys starting mean/amplitude/phase (their
    unit suffixes vary), or None."""
    if not isinstance(obj, dict):
        return None
    pick = {}
    for key, value in obj.items():
        low = key.lower()
        for name in ("mean", "amplitude", "phase"):
            if low.startswith(name) and name not in pick:
                pick[name] = value
    if not isinstance(pick.get("mean"), (int, float)) or "amplitude" not in pick:
        return None
    amplitudes = list(pick.get("amplitude") or [])
    phases = list(pick.get("phase") or [0.0] * len(amplitudes))
    if len(phases) != len(amplitudes):
        return None
    phase_key = next((k for k in obj if k.lower().startswith("phase")), "")
    if phase_key.lower().endswith("_deg"):
        phases = [math.radians(p) for p in phases]
    return {"mean": float(pick["mean"]), "amplitudes": amplitudes, "phases_rad": phases}


def find_series(stiffness_json, *names):
    """A Fourier series in stiffness.json whose key path contains one of the names."""
    if not isinstance(stiffness_json, dict):
        return None, None

    def walk(obj, path):
        if isinstance(obj, dict):
            series = as_series(obj)
            if series is not None:
                yield path, series
            for k, v in obj.items():
                yield from walk(v, path + [k])

    candidates = list(walk(stiffness_json, []))
    for name in names:
        for path, series in candidates:
            if path and any(name in p.lower() for p in path):
                return ".".join(path), series
    return None, None


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


def dominant_frequency(t, y):
    """Frequency (Hz) of the largest spectral line of y(t) (mean removed), or None."""
    if len(t) < 16 or not (t[-1] > t[0]):
        return None
    uniform = np.linspace(t[0], t[-1], len(t))
    yy = np.interp(uniform, t, y)
    spec = np.abs(np.fft.rfft(yy - yy.mean()))
    if len(spec) < 3 or not np.isfinite(spec).all() or spec[1:].max() <= 0:
        return None
    k = 1 + int(np.argmax(spec[1:]))
    return k / (t[-1] - t[0])


def steady_window(t, scene, n_periods, y=None):
    """Index mask of the last n_periods mesh periods of a time series. Without a mesh frequency,
    n_periods cycles of the dominant frequency of y, else the last tenth."""
    frequency = scene.f_mesh_hz or (dominant_frequency(t, y) if y is not None else None)
    if frequency:
        return t >= t[-1] - n_periods / frequency
    return t >= t[-1] - 0.1 * (t[-1] - t[0])


def steady_part(t, scene):
    """Mask of the steady state: after the transient periods when known (a series that starts
    after them is all steady), else the second half."""
    if scene.f_mesh_hz and scene.transient_periods is not None:
        t_steady = scene.transient_periods / scene.f_mesh_hz
        if t[0] >= t_steady - 0.5 / scene.f_mesh_hz:
            return np.ones_like(t, dtype=bool)
        mask = t >= t_steady - 1e-12
        if mask.sum() > 10:
            return mask
    return t >= t[0] + 0.5 * (t[-1] - t[0])


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


def decimate(x, y, n_max=20000):
    """Min/max envelope decimation so long histories plot fast and keep their peaks."""
    n = len(x)
    if n <= n_max:
        return x, y
    bucket = int(math.ceil(n / (n_max / 2)))
    m = n // bucket
    xs = x[: m * bucket].reshape(m, bucket)
    ys = y[: m * bucket].reshape(m, bucket)
    lo, hi = ys.argmin(axis=1), ys.argmax(axis=1)
    idx = np.sort(np.stack([lo, hi], axis=1), axis=1)
    rows = np.repeat(np.arange(m), 2)
    return xs[rows, idx.ravel()], ys[rows, idx.ravel()]


def loop_segments(t, penetration, f_mesh_hz):
    """Index arrays of the force–penetration loops: the runs of contact (δ > 0) between
    separations when the teeth separate, else one loop per mesh period. Returns (loops, kind)."""
    touching = np.asarray(penetration > 0, dtype=int)
    if touching.any() and not touching.all():
        edges = np.flatnonzero(np.diff(np.concatenate([[0], touching, [0]])))
        loops = [np.arange(a, b) for a, b in zip(edges[::2], edges[1::2]) if b - a > 2]
        # A run cut by the start or end of the window is not a whole impact.
        loops = [i for i in loops if i[0] > 0 and i[-1] < len(penetration) - 1]
        return loops, "impact"
    if t is not None and f_mesh_hz:
        k = np.floor((t - t[0]) * f_mesh_hz + 1e-9).astype(int)
        loops = [np.flatnonzero(k == j) for j in np.unique(k)]
        longest = max(len(i) for i in loops)
        return [i for i in loops if len(i) > 2 and len(i) >= 0.9 * longest], "mesh period"
    return [], "loop"


def polygon_area(x, y):
    return 0.5 * float(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)))


# --------------------------------------------------------------------------------------------
# The report
# --------------------------------------------------------------------------------------------

class Report:
    def __init__(self, art, out_dir):
        self.art = art
        self.out = out_dir
        self.scene = Scene(art)
        self.sections = []   # (id, title, [html blocks])
        self.figures = []    # file names written

    # -- page building ------------------------------------------------------------------------
    def section(self, sid, title):
        blocks = []
        self.sections.append((sid, title, blocks))
        return blocks

    def figure(self, blocks, name, fig, caption):
        save_figure_atomically(fig, os.path.join(self.out, name))
        self.figures.append(name)
        blocks.append('<figure><img src="%s" alt="%s"><figcaption>%s</figcaption></figure>'
                      % (html.escape(name), html.escape(html.unescape(re.sub("<[^>]+>", "", caption))[:120]),
                         caption))

    @staticmethod
    def note(blocks, text):
        blocks.append('<p class="note">%s</p>' % text)

    def attempt(self, blocks, what, draw):
        """Draw one figure; a failure costs that figure only and is shown on the page."""
        try:
            draw(blocks)
        except Exception as e:
            plt.close("all")
            sys.stderr.write("hertzgear report: %s failed: %s\n%s" % (what, e, traceback.format_exc()))
            self.note(blocks, "The %s could not be drawn: %s" % (what, html.escape(str(e))))

    # -- stiffness -----------------------------------------------------------------------------
    def stiffness_section(self):
        blocks = self.section("stiffness", "Mesh stiffness over the mesh cycle")
        table = self.art.get("stiffness.csv")
        js = self.art.get("stiffness.json")
        if table is None:
            self.note(blocks, "No stiffness.csv in this run: the per-position figures (STE, load "
                      "sharing, contact) are left out (the scene may take its stiffness from a "
                      "table or closed forms).")
            if isinstance(js, dict):
                samples = js.get("samples")
                if isinstance(samples, dict) and samples.get("mesh_phase"):
                    n = len(samples["mesh_phase"])
                    table = Table.from_columns("stiffness.json samples", {
                        k: v for k, v in samples.items()
                        if isinstance(v, list) and len(v) == n and
                        all(isinstance(x, (int, float)) for x in v)})
                self.attempt(blocks, "stiffness fit", lambda b: self.fig_stiffness(b, table, js))
                self.stiffness_json_table(blocks, js)
            return
        self.attempt(blocks, "stiffness figure", lambda b: self.fig_stiffness(b, table, js))
        self.attempt(blocks, "STE and load sharing figure", lambda b: self.fig_ste(b, table))
        self.attempt(blocks, "contact figure", lambda b: self.fig_contact(b, table))
        self.attempt(blocks, "contact ellipse map", lambda b: self.fig_ellipses(b, table))
        if isinstance(js, dict):
            self.stiffness_json_table(blocks, js)

    def fig_stiffness(self, blocks, table, js):
        n = self.scene.hertz_exponent
        kh_unit = "N/m" if n in (None, 1.0) else "N/m$^{%g}$" % n
        phase = None
        if table is not None:
            phase_col = table.find("mesh_phase", "phase")
            if phase_col:
                phase = table[phase_col]
            else:
                pos = table[table.find("position")]
                phase = pos / len(pos)
        fine = np.linspace(0, 1, 400)
        panels = [
            ("k_total", "total mesh stiffness $k_{total}$", ("k_total",), "N/m", ("k_total",)),
            ("k_rest", "rest (structural) stiffness $k_{rest}$", ("k_rest",), "N/m", ("k_rest",)),
            ("k_hertz", "Hertzian stiffness $k_h$ (F = $k_h δ^n$)", ("k_hertz", "k_h_", "k_h"),
             kh_unit, ("k_hertz", "k_h")),
        ]
        harmonics = prm_float(self.scene.prm, "Stiffness", "harmonics")
        sample_label = "samples (%s)" % ("stiffness.csv" if table is not None and
                                         table.path.endswith(".csv") else "stiffness.json")
        found = []
        for key, title, patterns, unit, json_names in panels:
            col = table.find(*patterns, exclude=("total",) if key != "k_total" else ()) \
                if table is not None else None
            samples = table[col] if col and table.numeric(col) else None
            where, series = find_series(js, *json_names)
            if key != "k_total" and where and "total" in where:
                where, series = None, None
            fit_note = None
            if series is None and samples is not None and np.isfinite(samples).sum() >= 3:
                ok = np.isfinite(samples)
                h = int(harmonics) if harmonics else 4
                h = max(1, min(h, (int(ok.sum()) - 1) // 2))
                series = fit_fourier(phase[ok], samples[ok], h)
                fit_note = "%s: least-squares fit of %d harmonics made here" % (key, h)
            elif series is not None:
                fit_note = "%s: Fourier coefficients of stiffness.json (%s)" % (key, where)
            if samples is not None or series is not None:
                found.append((key, title, unit, samples, series, fit_note))
        if not found:
            self.note(blocks, "Neither stiffness samples nor Fourier coefficients were found.")
            return
        width = 10 if len(found) == 3 else 3.4 * len(found) + 0.4
        fig, axes = plt.subplots(1, len(found), figsize=(width, 3.6), squeeze=False)
        for i, (ax, (key, title, unit, samples, series, _)) in enumerate(zip(axes[0], found)):
            allv = np.concatenate([samples[np.isfinite(samples)] if samples is not None else [],
                                   fourier_value(series, fine) if series else []])
            scale, shown_unit = scaled(allv, unit)
            if series is not None:
                ax.plot(fine, fourier_value(series, fine) / scale, "-", lw=1.6,
                        label="Fourier series (%d harmonics)" % len(series.get("amplitudes", [])))
                ax.axhline(float(series["mean"]) / scale, color="#888888", lw=0.8, ls="--",
                           label="mean")
            if samples is not None:
                ax.plot(phase, samples / scale, "o", ms=5, color=COLORS[1], label=sample_label)
            ax.set_title(title, loc="left")
            ax.set_xlabel("mesh phase (mesh cycles)")
            ax.set_ylabel(label(key.replace("_", " "), unit=shown_unit))
            ax.set_xlim(0, 1)
            if i == 0:
                ax.legend(loc="best", fontsize=8)
        fit_sources = [f[5] for f in found if f[5]]
        self.figure(blocks, "stiffness_cycle.png", fig,
                    "Mesh stiffness over one mesh cycle: the total, its structural (rest) part and "
                    "the Hertzian stiffness, as far as the artifacts give them. Dots are the "
                    "loaded-TCA positions, lines the Fourier series the dynamics uses "
                    "(1/k<sub>rest</sub> = 1/k<sub>total</sub> − 1/k<sub>h,tangent</sub>). "
                    + html.escape("; ".join(fit_sources)) + ".")

    def fig_ste(self, blocks, table):
        phase = table[table.find("mesh_phase", "phase")]
        ste = table.find("ste_um", "ste")
        shares = [c for c in table.names if c.lower().startswith("load_share")]
        pairs = table.find("pairs_in_contact", "pairs")
        if not ste and not shares:
            self.note(blocks, "stiffness.csv has no STE or load-share columns.")
            return
        fig, axes = plt.subplots(2, 1, figsize=(10, 5.4), sharex=True)
        order = np.argsort(phase)
        if ste:
            axes[0].plot(phase[order], table[ste][order], "o-", ms=4)
            axes[0].set_ylabel(label("loaded STE", ste))
            axes[0].set_title("Loaded static transmission error along the line of action",
                              loc="left")
        for i, c in enumerate(shares):
            axes[1].plot(phase[order], table[c][order], "o-", ms=4, color=COLORS[i + 1],
                         label=c.replace("load_share_", "tooth pair "))
        if pairs and table.numeric(pairs):
            ax2 = axes[1].twinx()
            ax2.step(phase[order], table[pairs][order], where="mid", color="#888888", lw=1,
                     ls="--", label="pairs in contact")
            ax2.set_ylabel("pairs in contact (count)")
            ax2.set_ylim(0, max(3, np.nanmax(table[pairs]) + 0.5))
            ax2.spines["right"].set_visible(True)
            ax2.grid(False)
            title_and_legend(axes[1], "Load sharing between the tooth pairs", [ax2], ncol=3)
        else:
            title_and_legend(axes[1], "Load sharing between the tooth pairs", ncol=3)
        axes[1].set_ylabel("load share (–)")
        axes[1].set_ylim(-0.05, 1.05)
        axes[1].set_xlabel("mesh phase (mesh cycles)")
        axes[1].set_xlim(0, 1)
        self.figure(blocks, "ste_load_sharing.png", fig,
                    "Loaded static transmission error (top) and the share of the mesh force each "
                    "tooth pair carries (bottom). In the single-tooth zone one pair carries all "
                    "the load; the STE rises there because the mesh is softer.")

    def fig_contact(self, blocks, table):
        phase = table[table.find("mesh_phase", "phase")]
        a, b = table.find("contact_a_mm"), table.find("contact_b_mm")
        p = table.find("peak_pressure", "pressure")
        pen = table.find("hertz_penetration", "penetration")
        if not (a or b or p):
            self.note(blocks, "stiffness.csv has no contact semi-axes or pressure columns.")
            return
        order = np.argsort(phase)
        fig, axes = plt.subplots(1, 2, figsize=(10, 3.6))
        for i, c in enumerate([x for x in (a, b) if x]):
            axes[0].plot(phase[order], table[c][order], "o-", ms=4, color=COLORS[i],
                         label="semi-axis " + ("a (profile)" if c == a else "b (face width)"))
        axes[0].set_ylabel("contact semi-axis (mm)")
        axes[0].set_xlabel("mesh phase (mesh cycles)")
        title_and_legend(axes[0], "Contact semi-axes", ncol=1)
        if p:
            axes[1].plot(phase[order], table[p][order], "o-", ms=4, color=COLORS[5],
                         label="peak pressure")
            axes[1].set_ylabel(label("peak contact pressure", p))
        if pen and table.numeric(pen):
            ax2 = axes[1].twinx()
            ax2.plot(phase[order], table[pen][order], "s--", ms=3, color=COLORS[2],
                     label="Hertzian penetration")
            ax2.set_ylabel(label("Hertzian penetration", pen))
            ax2.spines["right"].set_visible(True)
            ax2.grid(False)
            title_and_legend(axes[1], "Pressure, penetration", [ax2], ncol=1)
        else:
            title_and_legend(axes[1], "Peak pressure", ncol=1)
        axes[1].set_xlabel("mesh phase (mesh cycles)")
        for ax in axes:
            ax.set_xlim(0, 1)
        self.figure(blocks, "contact_per_position.png", fig,
                    "Contact semi-axes (left) and peak contact pressure with the Hertzian "
                    "(local) penetration (right) at each mesh position.")

    def fig_ellipses(self, blocks, table):
        a, b = table.find("contact_a_mm"), table.find("contact_b_mm")
        p = table.find("peak_pressure", "pressure")
        phase = table[table.find("mesh_phase", "phase")]
        if not (a and b and p):
            self.note(blocks, "The contact pressure map needs contact_a_mm, contact_b_mm and "
                      "peak_pressure_MPa.")
            return
        A, B, P = table[a], table[b], table[p]
        n_exp = self.scene.hertz_exponent
        line_contact = n_exp is not None and abs(n_exp - 1.0) < 1e-9
        order = np.argsort(phase)
        n = len(order)
        cols = min(n, 6)
        rows = int(math.ceil(n / cols))
        amax = np.nanmax(A) * 1.15 if np.nanmax(A) > 0 else 1.0
        bmax = np.nanmax(B) * 1.15 if np.nanmax(B) > 0 else 1.0
        pmax = np.nanmax(P) if np.nanmax(P) > 0 else 1.0
        fig, axes = plt.subplots(rows, cols, figsize=(min(10, 1.55 * cols + 1.0), 1.8 * rows + 0.5),
                                 sharex=True, sharey=True, squeeze=False)
        xg, yg = np.meshgrid(np.linspace(-amax, amax, 121), np.linspace(-bmax, bmax, 121))
        image = None
        for k, ax in enumerate(axes.ravel()):
            if k >= n:
                ax.set_visible(False)
                continue
            i = order[k]
            ax.grid(False)
            if A[i] > 0 and B[i] > 0 and np.isfinite(P[i]):
                if line_contact:
                    # Line contact: the Hertz strip p0 √(1 − x²/a²) along the whole contact line.
                    r = np.where(np.abs(yg) <= B[i], 1 - (xg / A[i]) ** 2, -1.0)
                else:
                    r = 1 - (xg / A[i]) ** 2 - (yg / B[i]) ** 2
                pressure = np.where(r > 0, P[i] * np.sqrt(np.clip(r, 0, None)), np.nan)
                image = ax.imshow(pressure, extent=(-amax, amax, -bmax, bmax), origin="lower",
                                  aspect="auto", cmap="inferno", vmin=0, vmax=pmax,
                                  interpolation="nearest")
                if line_contact:
                    ax.add_patch(Rectangle((-A[i], -B[i]), 2 * A[i], 2 * B[i], fill=False,
                                           lw=0.8, color="#1f5fa8"))
                else:
                    ax.add_patch(Ellipse((0, 0), 2 * A[i], 2 * B[i], fill=False, lw=0.8,
                                         color="#1f5fa8"))
            else:
                ax.text(0, 0, "no contact", ha="center", va="center", fontsize=8)
            ax.set_title("phase %.3g" % phase[i], fontsize=9)
        for ax in axes[-1, :]:
            ax.set_xlabel("x, profile (mm)", fontsize=8)
        for ax in axes[:, 0]:
            ax.set_ylabel("y, face width (mm)", fontsize=8)
        if image is not None:
            fig.colorbar(image, ax=axes, shrink=0.9, label="contact pressure (MPa)")
        if line_contact:
            what = ("Line contact (Hertz exponent n = 1): the Hertz pressure strip p = p<sub>0</sub>"
                    "√(1 − x²/a²) of half-width a over the contact length 2b")
        else:
            what = ("Contact ellipse and Hertzian pressure distribution p = p<sub>0</sub>"
                    "√(1 − x²/a² − y²/b²)")
        self.figure(blocks, "contact_pressure_map.png", fig,
                    what + " at each mesh position, drawn from the semi-axes and peak "
                    "pressure of stiffness.csv (the largest-loaded pair); all panels share the "
                    "same axes and colour scale. The x axis (profile) is stretched against the "
                    "y axis (face width) by about %.0f× so that the narrow contact stays visible."
                    % (bmax / amax))

    def stiffness_json_table(self, blocks, js):
        rows = []
        for k, v in flatten(js):
            if isinstance(v, list):
                if len(v) > 8 or not all(isinstance(x, (int, float)) for x in v):
                    continue
                v = ", ".join("%.6g" % x for x in v)
            rows.append((k, v))
        if rows:
            blocks.append("<h3>stiffness.json</h3>" + kv_table(rows[:80]))

    # -- dynamics ------------------------------------------------------------------------------
    def dynamics_section(self):
        blocks = self.section("dynamics", "Gear-pair dynamics")
        ts = self.art.get("timeseries.csv")
        s = self.scene
        facts = []
        if s.f_mesh_hz:
            facts.append("mesh frequency f<sub>m</sub> = %.6g Hz (T<sub>m</sub> = %.6g s), from %s"
                         % (s.f_mesh_hz, 1 / s.f_mesh_hz, html.escape(s.f_mesh_source)))
        else:
            facts.append("mesh frequency unknown (%s): no mesh-period markers"
                         % html.escape(s.f_mesh_source))
        if s.b_c_um is not None:
            facts.append("half backlash b<sub>c</sub> = %.6g µm, from %s"
                         % (s.b_c_um, html.escape(s.b_c_source)))
        else:
            facts.append("no backlash lines: %s" % html.escape(s.b_c_source))
        blocks.append("<ul class=\"facts\">%s</ul>" % "".join("<li>%s</li>" % f for f in facts))
        if ts is None:
            self.note(blocks, "No timeseries.csv in this run: the time histories, mesh force and "
                      "phase portrait are left out.")
        else:
            self.attempt(blocks, "DTE history", lambda b: self.fig_dte(b, ts))
            self.attempt(blocks, "mesh force history", lambda b: self.fig_force(b, ts))
        self.attempt(blocks, "Poincaré map", lambda b: self.fig_poincare(b, ts))
        self.attempt(blocks, "phase portrait", lambda b: self.fig_phase(b, ts))
        self.attempt(blocks, "force–penetration loops", lambda b: self.fig_loops(b, ts))
        self.attempt(blocks, "spectrum", lambda b: self.fig_spectrum(b, ts))
        summary = self.art.get("summary.json")
        if isinstance(summary, dict):
            rows = [(k, ", ".join(map(str, v)) if isinstance(v, list) else v)
                    for k, v in flatten(summary)]
            blocks.append("<h3>Summary (summary.json)</h3>" + kv_table(rows))

    def _time(self, ts):
        t = ts.find("time_s", "time", "t_s")
        if not t:
            raise BadInput("timeseries.csv has no time column")
        return ts[t]

    def fig_dte(self, blocks, ts):
        t = self._time(ts)
        dte = ts.find("dte_um", "dte", exclude=("rate",))
        pen = ts.find("penetration_um", "penetration")
        contact = ts.find("contact")
        if not dte:
            self.note(blocks, "timeseries.csv has no DTE column.")
            return
        s = self.scene
        period = 1 / s.f_mesh_hz if s.f_mesh_hz else None
        n_zoom = 6
        zoom = steady_window(t, s, n_zoom, ts[dte])
        cvals = ts[contact] if contact and ts.numeric(contact) else None
        n_panels = 3 if pen else 2
        fig, axes = plt.subplots(n_panels, 1, figsize=(10, 2.7 * n_panels + 0.4))
        ref = reference_of(ts[dte])
        b_c = s.b_c_um - ref if s.b_c_um is not None and ref else s.b_c_um
        # The overview keeps both backlash lines in view (unshifted), so that it shows how far
        # the motion stays from separation (|x| < b_c) and back-side contact (x < −b_c).
        x, y = decimate(t, ts[dte])
        axes[0].plot(x, y, lw=0.6, label="DTE")
        mark_backlash(axes[0], s.b_c_um)
        if s.b_c_um is not None:
            axes[0].axhspan(-s.b_c_um, s.b_c_um, color="#bbbbbb", alpha=0.15, lw=0,
                            label="teeth apart")
        axes[0].set_ylabel(label("DTE x", dte))
        axes[0].set_xlabel("time (s)")
        axes[0].set_xlim(t[0], t[-1])
        span = ("the last %.0f mesh periods of the run" % ((t[-1] - t[0]) * s.f_mesh_hz)
                if s.f_mesh_hz else "the recorded window")
        title_and_legend(axes[0], "DTE x = r$_{b1}$θ$_1$ − r$_{b2}$θ$_2$, %s" % span, ncol=3)
        ax = axes[1]
        tz = t[zoom]
        shade_contact(ax, tz, cvals[zoom] if cvals is not None else None)
        ax.plot(tz, ts[dte][zoom] - ref, lw=1.2, label="DTE")
        mark_backlash(ax, b_c, near_data=True)
        mark_mesh_periods(ax, tz[0], tz[-1], period)
        ax.set_xlim(tz[0], tz[-1])
        ax.set_ylabel(shifted_label("DTE x", unit_of(dte), ref))
        ax.set_xlabel("time (s)")
        title_and_legend(ax, "DTE, last %d %s" % (n_zoom, "mesh periods" if period else
                                                    "cycles of its main frequency"))
        if pen:
            ax = axes[2]
            shade_contact(ax, tz, cvals[zoom] if cvals is not None else None)
            ax.plot(tz, ts[pen][zoom], lw=1.2, color=COLORS[2], label="Hertzian penetration δ")
            mark_mesh_periods(ax, tz[0], tz[-1], period)
            ax.set_xlim(tz[0], tz[-1])
            ax.set_ylabel(label("penetration δ", pen))
            ax.set_xlabel("time (s)")
            title_and_legend(ax, "Hertzian penetration δ, same periods")
        self.figure(blocks, "dte_penetration.png", fig,
                    "Dynamic transmission error over the recorded time series "
                    "(top, Output/timeseries_periods), over the last mesh periods (middle), with "
                    "the Hertzian penetration δ (bottom). Dashed red lines are ±b<sub>c</sub>: "
                    "for |x| &lt; b<sub>c</sub> the teeth are apart (grey), below "
                    "−b<sub>c</sub> they hit on the back side (red bands). Dotted lines mark "
                    "mesh periods; the zoomed panels keep their own scale and say when "
                    "±b<sub>c</sub> lies off it.")

    def fig_force(self, blocks, ts):
        t = self._time(ts)
        force = ts.find("mesh_force_n", "mesh_force", "force", exclude=("hertz",))
        hertz = ts.find("hertz_force", "hertzian_force")
        if not force and not hertz:
            self.note(blocks, "timeseries.csv has no force column: the mesh-force figure is left out.")
            return
        s = self.scene
        period = 1 / s.f_mesh_hz if s.f_mesh_hz else None
        zoom = steady_window(t, s, 6, ts[force or hertz])
        tz = t[zoom]
        contact = ts.find("contact")
        fig, axes = plt.subplots(1, 2, figsize=(10, 3.6), gridspec_kw={"width_ratios": [2, 1]})
        ax = axes[0]
        if contact and ts.numeric(contact):
            shade_contact(ax, tz, ts[contact][zoom])
        main = force or hertz
        steady = steady_part(t, s)
        ref = reference_of(ts[main][steady])
        scale, unit = (1.0, "N") if ref else (1e3, "kN")
        ax.plot(tz, (ts[main][zoom] - ref) / scale, lw=1.2, label="mesh force F")
        if hertz and hertz != main:
            ax.plot(tz, (ts[hertz][zoom] - ref) / scale, lw=1.0, ls="--", label="Hertzian force")
        if s.static_force_n:
            ax.axhline((s.static_force_n - ref) / scale, color="#2e8b57", lw=1, ls="--",
                       label="static force F$_0$")
        mark_mesh_periods(ax, tz[0], tz[-1], period)
        ax.set_xlim(tz[0], tz[-1])
        ax.set_xlabel("time (s)")
        ax.set_ylabel(shifted_label("mesh force", unit, ref))
        title_and_legend(ax, "Mesh (Hertzian) force, last %s" % ("mesh periods" if period else
                                                                   "cycles"), ncol=2)
        ax = axes[1]
        values = (ts[main][steady] - ref) / scale
        ax.hist(values[np.isfinite(values)], bins=60, color=COLORS[0], alpha=0.8)
        if s.static_force_n:
            ax.axvline((s.static_force_n - ref) / scale, color="#2e8b57", lw=1, ls="--",
                       label="F$_0$")
        ax.axvline(np.nanmean(values), color=COLORS[1], lw=1, label="mean")
        ax.set_xlabel(shifted_label("mesh force", unit, ref))
        ax.set_ylabel("samples (count)")
        title_and_legend(ax, "Steady-state distribution", ncol=2)
        mean = np.nanmean(ts[main][steady])
        extra = ""
        if s.static_force_n:
            extra = (" The steady mean force is %.5g N against F<sub>0</sub> = %.5g N "
                     "(a periodic steady state has mean F = F<sub>0</sub>)." % (mean, s.static_force_n))
        self.figure(blocks, "mesh_force.png", fig,
                    "Force through the mesh, equal to the force of the Hertzian layer "
                    "k<sub>h</sub>G(δ) + μH(δ)δ̇; zero while the teeth are apart." + extra)

    def poincare_points(self, ts):
        """(times or None, x, rate or None, x column, rate column, source) of the Poincaré section."""
        p = self.art.get("poincare.csv")
        s = self.scene
        if p is not None:
            x = p.find("dte_um", "dte", "x_um", exclude=("rate",))
            if not x:
                return None
            v = p.find("dte_rate", "re:rate|velocity")
            t = p.find("time")
            return (p[t] if t and p.numeric(t) else None, p[x],
                    p[v] if v and p.numeric(v) else None, x, v, "poincare.csv")
        if ts is not None and s.f_mesh_hz:
            t = self._time(ts)
            x = ts.find("dte_um", "dte", exclude=("rate",))
            v = ts.find("dte_rate", "re:rate")
            ks = np.arange(math.ceil(t[0] * s.f_mesh_hz), math.floor(t[-1] * s.f_mesh_hz) + 1)
            if len(ks) < 3 or not x:
                return None
            tk = ks / s.f_mesh_hz
            return (tk, np.interp(tk, t, ts[x]), np.interp(tk, t, ts[v]) if v else None, x, v,
                    "timeseries.csv sampled here once per mesh period")
        return None

    def fig_poincare(self, blocks, ts):
        section = self.poincare_points(ts)
        if section is None:
            self.note(blocks, "No poincare.csv (with a DTE column) in this run, and no time series "
                      "to sample one from: the Poincaré map is left out.")
            return
        _, xs, vs, xcol, vcol, source = section
        ok = np.isfinite(xs) & (np.isfinite(vs) if vs is not None else True)
        xs, vs = xs[ok], (vs[ok] if vs is not None else None)
        xunit = unit_of(xcol) if xcol else None
        n_last = min(16, len(xs))
        period_k = self.scene.flat_summary.get("period_multiplicity")
        if isinstance(period_k, (int, float)) and not isinstance(period_k, bool):
            motion = "aperiodic" if period_k == 0 else "period-%d" % period_k
            where = "summary.json"
        else:
            motion = "%d distinct points" % distinct_points(xs[-n_last:])
            where = "last %d sections" % n_last
        # The smallest span drawn: a tenth of the steady orbit (the phase portrait), so that the
        # scatter of a period-1 point at the integrator's tolerance (1e-7 µm) shows as the one
        # point it is rather than as a cloud blown up to fill the axes.
        x_span, v_span = 1e-4 * max(1.0, float(np.nanmax(np.abs(xs)))), 0.0
        if ts is not None and ts.find("time_s", "time", "t_s"):
            steady = steady_part(self._time(ts), self.scene)
            xc = ts.find("dte_um", "dte", exclude=("rate",))
            vc = ts.find("dte_rate", "re:rate|velocity")
            if xc:
                x_span = max(x_span, 0.1 * float(np.ptp(ts[xc][steady])))
            if vc:
                v_span = 0.1 * float(np.ptp(ts[vc][steady]))
        if vs is not None and not v_span > 0:
            v_span = 1e-4 * max(1e-12, float(np.nanmax(np.abs(vs))))
        xlim = span_limits(xs, x_span)
        vlim = span_limits(vs, v_span) if vs is not None else None
        xref = reference_of(np.array(xlim) if xlim else xs)
        xs = xs - xref
        fig, ax = plt.subplots(figsize=(7.4, 4.8))
        if vs is not None:
            sc = ax.scatter(xs, vs, c=np.arange(len(xs)), cmap="viridis", s=12, zorder=3,
                            label="all sections")
            ax.scatter(xs[-n_last:], vs[-n_last:], s=70, facecolors="none",
                       edgecolors="#c0392b", lw=1.4, zorder=4, label="last %d sections" % n_last)
            fig.colorbar(sc, ax=ax, label="section number (mesh periods)")
            if xlim:
                ax.set_xlim(xlim[0] - xref, xlim[1] - xref)
            if vlim:
                ax.set_ylim(*vlim)
            b_c = self.scene.b_c_um - xref if self.scene.b_c_um is not None else None
            mark_backlash(ax, b_c, horizontal=False, near_data=True)
            ax.set_xlabel(shifted_label("DTE x at the section", xunit, xref))
            ax.set_ylabel(label("DTE rate ẋ at the section", vcol))
        else:
            ax.scatter(xs[:-1], xs[1:], c=np.arange(len(xs) - 1), cmap="viridis", s=12, zorder=3)
            if xlim:
                ax.set_xlim(xlim[0] - xref, xlim[1] - xref)
                ax.set_ylim(xlim[0] - xref, xlim[1] - xref)
            ax.set_xlabel(shifted_label("x$_k$", xunit, xref))
            ax.set_ylabel(shifted_label("x$_{k+1}$", xunit, xref))
        ax.ticklabel_format(axis="both", style="plain", useOffset=False)
        spread = ""
        if xlim or vlim:
            spread = (" Here the sections spread over %.2g %s%s only, the integrator's tolerance "
                      "rather than motion: the axes are widened to a tenth of the steady orbit so "
                      "that they show as the one point they are."
                      % (np.ptp(xs), html.escape(xunit or ""),
                         (" and %.2g %s" % (np.ptp(vs), html.escape(unit_of(vcol) or "")))
                         if vs is not None else ""))
        title_and_legend(ax, "Poincaré map: %s (%s)" % (motion, where), ncol=3)
        self.figure(blocks, "poincare.png", fig,
                    "Poincaré section: the state sampled once per mesh period (%s). One point is "
                    "period-1 motion, k points period-k, a closed curve quasi-periodic motion, and "
                    "a scattered cloud with structure chaos. Colour runs from the first to the "
                    "last section, so a transient shows as a trail into the final points (circled)."
                    "%s" % (html.escape(source), spread))

    def fig_phase(self, blocks, ts):
        if ts is None:
            return
        t = self._time(ts)
        x = ts.find("dte_um", "dte", exclude=("rate",))
        v = ts.find("dte_rate", "re:rate|velocity")
        if not (x and v):
            self.note(blocks, "timeseries.csv lacks DTE or its rate: the phase portrait is left out.")
            return
        s = self.scene
        steady = steady_part(t, s)
        fig, ax = plt.subplots(figsize=(7.4, 4.8))
        xref = reference_of(ts[x][steady])
        xx, vv = ts[x][steady] - xref, ts[v][steady]
        ax.plot(xx, vv, lw=0.6, color=COLORS[0], label="steady-state trajectory")
        section = self.poincare_points(ts)
        if section is not None and section[2] is not None:
            tk, xk, vk = section[0], section[1], section[2]
            keep = tk >= t[steady][0] if tk is not None else slice(-16, None)
            ax.plot(xk[keep] - xref, vk[keep], "o", ms=5, color=COLORS[1],
                    label="Poincaré points", zorder=4)
        mark_backlash(ax, s.b_c_um - xref if s.b_c_um is not None else None, horizontal=False,
                      near_data=True)
        ax.set_xlabel(shifted_label("DTE x", unit_of(x), xref))
        ax.set_ylabel(label("DTE rate ẋ", v))
        title_and_legend(ax, "Phase portrait, steady state", ncol=3)
        self.figure(blocks, "phase_portrait.png", fig,
                    "Phase portrait (x, ẋ) after the transient. Between the dashed lines "
                    "(|x| &lt; b<sub>c</sub>) the teeth fly free and the trajectory is straight in "
                    "time; a period-k orbit closes after k loops.")

    def fig_loops(self, blocks, ts):
        fp = self.art.get("force_penetration.csv")
        s = self.scene
        if fp is not None:
            data, source = fp, "force_penetration.csv"
            window = np.ones(len(fp), dtype=bool)
        elif ts is not None:
            data, source = ts, "timeseries.csv, last mesh periods"
        else:
            self.note(blocks, "No force_penetration.csv in this run: the loops are left out.")
            return
        pen = data.find("penetration", "delta", "re:penetration")
        force = data.find("mesh_force", "hertz_force", "force", "re:force")
        if not (pen and force and data.numeric(pen) and data.numeric(force)):
            self.note(blocks, "%s lacks a penetration or force column: the loops are left out."
                      % html.escape(source))
            return
        tcol = data.find("time_s", "time")
        t = data[tcol] if tcol and data.numeric(tcol) else None
        if fp is None:
            window = steady_window(t, s, 4, ts[force])
        P, F = data[pen][window], data[force][window]
        t = t[window] if t is not None else None
        group = data.find("impact", "loop", "cycle", "event")
        if group and data.numeric(group):
            ids = data[group][window]
            loops = [np.flatnonzero(ids == g) for g in unique_in_order(ids[np.isfinite(ids)])]
            kind = "impact"
        else:
            loops, kind = loop_segments(t, P, s.f_mesh_hz)
        fig, ax = plt.subplots(figsize=(7.4, 4.8))
        energies = [abs(polygon_area(P[i] * 1e-6, F[i])) for i in loops
                    if len(i) > 2 and unit_of(pen) == "µm"]
        pref = reference_of(P)
        fref = reference_of(F)
        fscale, funit = (1.0, "N") if fref else (1e3, "kN")
        if loops:
            shown = loops[-12:]
            # Light to dark blue: the last loop, drawn on top, is the darkest, so a steady state
            # whose loops coincide shows as one dark, readable curve.
            cmap = plt.get_cmap("Blues")
            first = len(loops) - len(shown) + 1
            for j, idx in enumerate(shown):
                closed = np.append(idx, idx[0])
                ax.plot(P[closed] - pref, (F[closed] - fref) / fscale, lw=1.2,
                        color=cmap(0.35 + 0.65 * j / max(1, len(shown) - 1)),
                        label=("%s %d" % (kind, first + j))
                        if len(shown) <= 6 else None)
            if len(shown) > 6:
                ax.text(0.02, 0.96, "%ss %d–%d of the window, later ones darker"
                        % (kind, first, len(loops)), transform=ax.transAxes, ha="left",
                        va="top", fontsize=8.5)
        else:
            ax.plot(P - pref, (F - fref) / fscale, lw=1.0)
        ax.set_xlabel(shifted_label("Hertzian penetration δ", unit_of(pen), pref))
        ax.set_ylabel(shifted_label("mesh force F", funit, fref))
        title_and_legend(ax, "Force–penetration loops", ncol=3)
        energy_text = ""
        if energies:
            energy_text = (" Mean enclosed area ∮F dδ over the last %d %ss: %.4g mJ."
                           % (len(energies), kind, 1e3 * np.mean(energies)))
            ax.text(0.98, 0.04, "mean loop area %.3g mJ" % (1e3 * np.mean(energies)),
                    transform=ax.transAxes, ha="right", va="bottom")
        reported = s.flat_summary.get("mean_energy_dissipated_per_impact_J")
        if isinstance(reported, (int, float)) and not isinstance(reported, bool):
            energy_text += " summary.json gives %.4g mJ dissipated per impact." % (1e3 * reported)
        self.figure(blocks, "force_penetration.png", fig,
                    "Mesh force against Hertzian penetration (%s), one colour per %s, later ones "
                    "darker. Loading runs along the upper branch and unloading along the lower "
                    "one; the area enclosed by a loop is the energy the contact damping dissipates "
                    "in that %s, and an upward-bending branch is the hardening of "
                    "F = k<sub>h</sub>δ<sup>n</sup> with n &gt; 1.%s"
                    % (html.escape(source), kind, kind, energy_text))

    def fig_spectrum(self, blocks, ts):
        sp = self.art.get("spectrum.csv")
        s = self.scene
        if sp is not None:
            fcol = sp.find("frequency", "freq", "f_hz")
            acol = sp.find("amplitude", "amp", "magnitude", "re:amplitude|magnitude|psd")
            if not (fcol and acol):
                self.note(blocks, "spectrum.csv lacks a frequency or amplitude column.")
                return
            f, a = sp[fcol], sp[acol]
            source = "spectrum.csv"
            a_label = label("amplitude", acol)
        elif ts is not None:
            t = self._time(ts)
            x = ts.find("dte_um", "dte", exclude=("rate",))
            steady = steady_part(t, s)
            tt, xx = t[steady], ts[x][steady]
            if len(tt) < 16:
                self.note(blocks, "No spectrum.csv and too short a time series for one.")
                return
            dt = (tt[-1] - tt[0]) / (len(tt) - 1)
            uniform = np.linspace(tt[0], tt[-1], len(tt))
            xx = np.interp(uniform, tt, xx)
            spec = np.fft.rfft(xx - xx.mean())
            f = np.fft.rfftfreq(len(xx), dt)
            a = 2 * np.abs(spec) / len(xx)
            source = "FFT of the steady part of timeseries.csv, computed here"
            a_label = label("amplitude of DTE", x)
        else:
            self.note(blocks, "No spectrum.csv in this run: the spectrum is left out.")
            return
        ok = np.isfinite(a) & (f > 0) & (a > 0)
        fig, ax = plt.subplots(figsize=(10, 3.8))
        ax.semilogy(f[ok], a[ok], lw=1.0)
        if s.f_mesh_hz and ok.any():
            fmax = f[ok].max()
            ax.grid(False, axis="x")
            for k in range(1, int(fmax / s.f_mesh_hz) + 1):
                if k > 8:
                    break
                ax.axvline(k * s.f_mesh_hz, color="#c0392b", lw=0.7, ls="--", zorder=0)
                ax.text(k * s.f_mesh_hz, 1.0, "%df$_m$" % k if k > 1 else "f$_m$",
                        transform=ax.get_xaxis_transform(), ha="center", va="bottom",
                        fontsize=8, color="#c0392b")
            ax.axvline(0.5 * s.f_mesh_hz, color="#8e44ad", lw=0.6, ls=":", zorder=0)
            ax.text(0.5 * s.f_mesh_hz, 1.0, "f$_m$/2", transform=ax.get_xaxis_transform(),
                    ha="center", va="bottom", fontsize=8, color="#8e44ad")
            ax.set_xlim(0, min(fmax, 8.5 * s.f_mesh_hz))
        ax.set_xlabel(label("frequency", unit="Hz"))
        ax.set_ylabel(a_label)
        ax.set_title("Spectrum of the steady-state DTE", pad=14)
        self.figure(blocks, "spectrum.png", fig,
                    "Amplitude spectrum of the steady dynamic transmission error (%s), log scale. "
                    "Dashed lines mark the mesh frequency f<sub>m</sub> and its harmonics; a line "
                    "at f<sub>m</sub>/2 and its odd multiples means period-2 motion, and a broad "
                    "floor between the harmonics means aperiodic motion." % html.escape(source))

    # -- sweep ---------------------------------------------------------------------------------
    def sweep_section(self):
        sw = self.art.get("sweep.csv")
        bif = self.art.get("bifurcation.csv")
        if sw is None and bif is None:
            return
        blocks = self.section("sweep", "Speed sweep")
        if sw is not None:
            self.attempt(blocks, "sweep figure", lambda b: self.fig_sweep(b, sw))
        else:
            self.note(blocks, "No sweep.csv: the RMS-versus-speed figure is left out.")
        if bif is not None:
            self.attempt(blocks, "bifurcation diagram", lambda b: self.fig_bifurcation(b, bif))
        else:
            self.note(blocks, "No bifurcation.csv: the bifurcation diagram is left out.")

    def fig_sweep(self, blocks, sw):
        speed = sw.find("speed_rpm", "speed")
        rms = sw.find("rms_dte", "rms")
        if not (speed and rms):
            self.note(blocks, "sweep.csv lacks speed or RMS columns.")
            return
        direction = sw.find("direction")
        dirs = sw[direction] if direction else np.array(["sweep"] * len(sw), dtype=object)
        lo, hi = sw.find("min_dte"), sw.find("max_dte")
        df, loss = sw.find("dynamic_factor"), sw.find("contact_loss")
        s = self.scene
        fig, axes = plt.subplots(2, 1, figsize=(10, 6.4), sharex=True)
        markers = {"up": "^", "down": "v"}
        for i, d in enumerate(unique_in_order(dirs)):
            m = dirs == d
            order = np.argsort(sw[speed][m])
            sp = sw[speed][m][order]
            color = COLORS[i % len(COLORS)]
            mk = markers.get(str(d).lower(), "o")
            axes[0].plot(sp, sw[rms][m][order], "-", marker=mk, ms=4, color=color,
                         label="RMS DTE, %s" % d)
            if lo and hi:
                axes[0].fill_between(sp, sw[lo][m][order], sw[hi][m][order], color=color,
                                     alpha=0.12, lw=0, label="min…max DTE, %s" % d)
            if df:
                axes[1].plot(sp, sw[df][m][order], "-", marker=mk, ms=4, color=color,
                             label="dynamic factor, %s" % d)
            if loss:
                axes[1].plot(sp, sw[loss][m][order], ":", marker=mk, ms=3, color=color,
                             alpha=0.7, label="contact-loss fraction, %s" % d)
        mark_backlash(axes[0], s.b_c_um, near_data=True)
        axes[0].set_ylabel(label("DTE", rms))
        title_and_legend(axes[0], "RMS and range of the DTE", ncol=3)
        axes[1].set_ylabel("dynamic factor, loss fraction (–)")
        axes[1].set_xlabel(label("pinion speed", speed))
        title_and_legend(axes[1], "Dynamic factor F$_{max}$/F$_0$, contact-loss fraction", ncol=2)
        self.figure(blocks, "sweep_rms.png", fig,
                    "Frequency response from the speed sweep: RMS of the DTE with its min…max band "
                    "(top), dynamic factor and contact-loss fraction (bottom), for the up and down "
                    "sweeps. Where the two directions disagree the response has two stable "
                    "branches (a jump, typical of the softening backlash nonlinearity).")

    def fig_bifurcation(self, blocks, bif):
        speed = bif.find("speed_rpm", "speed")
        x = bif.find("poincare_dte", "dte")
        if not (speed and x):
            self.note(blocks, "bifurcation.csv lacks speed or Poincaré DTE columns.")
            return
        fig, ax = plt.subplots(figsize=(10, 4.2))
        ref = reference_of(bif[x])
        ax.plot(bif[speed], bif[x] - ref, ".", ms=2.5, color="#222222", alpha=0.7)
        mark_backlash(ax, self.scene.b_c_um - ref if self.scene.b_c_um is not None else None,
                      near_data=True)
        ax.set_xlabel(label("pinion speed", speed))
        ax.set_ylabel(shifted_label("DTE at the Poincaré section", unit_of(x), ref))
        title_and_legend(ax, "Bifurcation diagram", ncol=1)
        self.figure(blocks, "bifurcation.png", fig,
                    "Bifurcation diagram: the Poincaré points of the steady state at each speed. "
                    "One point per speed is period-1 motion, two period-2 (a period-doubling "
                    "bifurcation where the branch splits), a vertical smear aperiodic or chaotic "
                    "motion.")

    # -- accuracy ------------------------------------------------------------------------------
    def accuracy_section(self):
        if not self.art.accuracy_tables:
            return
        blocks = self.section("accuracy", "Accuracy versus cost")
        for i, path in enumerate(self.art.accuracy_tables):
            rel = os.path.relpath(path, self.art.run_dir)
            try:
                table = Table(path)
            except Exception as e:
                self.note(blocks, "%s could not be read: %s" % (html.escape(rel), html.escape(str(e))))
                continue
            self.attempt(blocks, "accuracy plot of %s" % rel,
                         lambda b, t=table, r=rel, k=i: self.fig_accuracy(b, t, r, k))
            if len(table) <= 60:
                blocks.append("<details><summary>%s (%d rows)</summary>%s</details>"
                              % (html.escape(rel), len(table), csv_table(table)))

    def fig_accuracy(self, blocks, table, rel, index):
        time = table.find("wall_time", "re:time_s$", "re:time", "re:seconds")
        errors = [c for c in table.names if re.search("err", c.lower()) and table.numeric(c)]
        if not time or not table.numeric(time) or not errors:
            self.note(blocks, "%s has no wall-time and error columns to plot." % html.escape(rel))
            return
        group = None
        for c in table.names:
            if not table.numeric(c):
                group = c
                break
        groups = table[group] if group else np.array(["all"] * len(table), dtype=object)
        errors = errors[:3]
        fig, axes = plt.subplots(1, len(errors), figsize=(4.6 * len(errors) + 0.8, 3.9),
                                 squeeze=False)
        for ax, err in zip(axes[0], errors):
            for j, g in enumerate(unique_in_order(groups)):
                m = (groups == g) & (table[time] > 0) & (np.abs(table[err]) > 0)
                if not m.any():
                    continue
                # Joined in the table's order (its tolerance or step ladder), not by wall time:
                # timings of cheap runs scatter, and sorting by them would zigzag the line.
                order = np.arange(int(m.sum()))
                ax.loglog(table[time][m][order], np.abs(table[err][m][order]), "o-", ms=4,
                          color=COLORS[j % len(COLORS)], label=str(g))
            name = re.sub(r"_(um|mm|m|s|n)$", "", err).replace("_", " ")
            name = name.replace("poincare", "Poincaré").replace("rms dte", "RMS DTE")
            ax.set_xlabel(label("wall time", time))
            ax.set_ylabel(label(name, err))
            ax.set_title(name[:1].upper() + name[1:])
            if ax.get_legend_handles_labels()[0]:
                ax.legend(loc="best")
        name = "accuracy_%d.png" % (index + 1)
        self.figure(blocks, name, fig,
                    "Work–precision diagram from %s: error against wall time, log–log, each method's "
                    "points joined in the order of its tolerance (or step) ladder. Lower left "
                    "is better; at a given error, the leftmost method is the cheapest."
                    % html.escape(rel))

    # -- scene ---------------------------------------------------------------------------------
    def scene_section(self):
        blocks = self.section("scene", "Scene: values and effects")
        prm = self.scene.prm
        if not prm:
            self.note(blocks, "No used_parameters.prm in this run: the scene table is left out.")
            return
        effects = [(k, v, h) for sec, k, v, h, _ in prm if sec.split("/")[0] == "Effects"]
        if effects:
            blocks.append("<h3>Effects</h3><p>The model contains only the terms of the effects "
                          "that are on.</p>" + effect_table(effects))
        by_section = {}
        for sec, k, v, h, default in prm:
            by_section.setdefault(sec.split("/")[0], []).append((sec, k, v, h, default))
        for top, rows in by_section.items():
            if top == "Effects":
                continue
            body = "".join(
                "<tr><td>%s</td><td class=\"key\">%s</td><td class=\"val\">%s%s</td><td>%s</td></tr>"
                % (html.escape("/".join(sec.split("/")[1:])), html.escape(k), html.escape(v),
                   ' <span class="changed" title="default: %s">≠ default</span>'
                   % html.escape(d) if d is not None else "", html.escape(h))
                for sec, k, v, h, d in rows)
            opened = " open" if top in ("Operating", "Dynamics") else ""
            blocks.append("<details%s><summary>%s (%d values)</summary><table class=\"prm params\">"
                          "<colgroup><col class=\"c1\"><col class=\"c2\"><col class=\"c3\"><col>"
                          "</colgroup><thead><tr><th>subsection</th><th>key</th><th>value</th>"
                          "<th>meaning</th></tr></thead><tbody>%s</tbody></table></details>"
                          % (opened, html.escape(top), len(rows), body))

    # -- page ----------------------------------------------------------------------------------
    def write(self):
        self.stiffness_section()
        self.dynamics_section()
        self.sweep_section()
        self.accuracy_section()
        self.scene_section()
        page = render_page(self)
        write_text_atomically(os.path.join(self.out, "index.html"), page)
        return os.path.join(self.out, "index.html")


def unique_in_order(values):
    seen = []
    for v in values:
        if v not in seen:
            seen.append(v)
    return seen


def distinct_points(xs, rel=1e-3):
    if len(xs) == 0:
        return 0
    span = max(np.ptp(xs), np.max(np.abs(xs)), 1e-300)
    pts = []
    for x in xs:
        if all(abs(x - p) > rel * span for p in pts):
            pts.append(x)
    return len(pts)


def fmt(v):
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, float):
        return "%.6g" % v
    if v is None:
        return "–"
    return str(v)


def kv_table(rows):
    body = "".join("<tr><td class=\"key\">%s</td><td class=\"val\">%s</td></tr>"
                   % (html.escape(str(k)), html.escape(fmt(v))) for k, v in rows)
    return "<table class=\"kv\"><tbody>%s</tbody></table>" % body


def effect_table(effects):
    body = ""
    for k, v, h in effects:
        off = v.lower() in ("off", "false", "constant", "none")
        body += ("<tr><td class=\"key\">%s</td><td><span class=\"badge %s\">%s</span></td>"
                 "<td>%s</td></tr>" % (html.escape(k), "off" if off else "on", html.escape(v),
                                       html.escape(h)))
    return ("<table class=\"prm effects\"><colgroup><col class=\"c1\"><col class=\"c2\"><col>"
            "</colgroup><thead><tr><th>effect</th><th>choice</th><th>meaning</th></tr>"
            "</thead><tbody>%s</tbody></table>" % body)


def csv_table(table):
    head = "".join("<th>%s</th>" % html.escape(n) for n in table.names)
    rows = ""
    for i in range(len(table)):
        rows += "<tr>%s</tr>" % "".join("<td>%s</td>" % html.escape(fmt(table[n][i].item()
                                                                          if table.numeric(n)
                                                                          else table[n][i]))
                                        for n in table.names)
    return "<table class=\"data\"><thead><tr>%s</tr></thead><tbody>%s</tbody></table>" % (head, rows)


CSS = """
:root { --ink:#1d2430; --muted:#5b6575; --line:#dde2ea; --accent:#1f5fa8; --bg:#f6f7f9; }
* { box-sizing: border-box; }
body { margin:0; font:15px/1.5 -apple-system, "Segoe UI", "DejaVu Sans", Helvetica, Arial, sans-serif;
       color:var(--ink); background:var(--bg); }
header { background:#18324f; color:#fff; padding:22px 32px 18px; }
header h1 { margin:0 0 4px; font-size:24px; font-weight:600; letter-spacing:.2px; }
header .meta { color:#c8d5e6; font-size:13px; }
header .meta code { color:#fff; }
nav { position:sticky; top:0; z-index:2; background:#fff; border-bottom:1px solid var(--line);
      padding:8px 32px; font-size:14px; }
nav a { color:var(--accent); text-decoration:none; margin-right:18px; }
nav a:hover { text-decoration:underline; }
main { max-width:1120px; margin:0 auto; padding:8px 32px 48px; }
section { background:#fff; border:1px solid var(--line); border-radius:8px; margin:22px 0;
          padding:8px 24px 18px; }
h2 { font-size:20px; margin:14px 0 10px; padding-bottom:6px; border-bottom:2px solid var(--accent); }
h3 { font-size:16px; margin:20px 0 8px; }
figure { margin:18px 0 26px; }
figure img { display:block; max-width:100%; height:auto; margin:0 auto; border:1px solid var(--line);
             border-radius:4px; background:#fff; }
figcaption { color:var(--muted); font-size:13.5px; margin:8px 4px 0; }
p.note { background:#fff8e5; border-left:4px solid #e0a800; padding:8px 12px; margin:12px 0;
         font-size:14px; }
ul.facts { font-size:14px; color:var(--muted); }
table { border-collapse:collapse; font-size:13.5px; margin:6px 0 14px; width:100%; }
th, td { border-bottom:1px solid var(--line); padding:4px 8px; text-align:left; vertical-align:top; }
th { background:#eef2f7; font-weight:600; }
table.kv { width:auto; min-width:50%; }
td.key { font-family:"DejaVu Sans Mono", Menlo, Consolas, monospace; font-size:12.5px; white-space:nowrap; }
td.val { font-family:"DejaVu Sans Mono", Menlo, Consolas, monospace; font-size:12.5px; }
table.data td { font-family:"DejaVu Sans Mono", Menlo, Consolas, monospace; font-size:12px; }
.badge { display:inline-block; white-space:nowrap; padding:1px 8px; border-radius:10px; font-size:12px; font-weight:600; }
.badge.on { background:#dff3e4; color:#1e6b34; }
.badge.off { background:#eceff3; color:#5b6575; }
.changed { color:#b35c00; font-size:11px; font-family:sans-serif; white-space:nowrap; }
table.prm { table-layout:fixed; }
table.prm.params col.c1 { width:13%; } table.prm.params col.c2 { width:25%; }
table.prm.params col.c3 { width:16%; }
table.prm.effects col.c1 { width:25%; } table.prm.effects col.c2 { width:16%; }
table.prm td.val { overflow-wrap:anywhere; }
details { margin:8px 0; }
summary { cursor:pointer; font-weight:600; padding:4px 0; }
.cards { display:flex; flex-wrap:wrap; gap:12px; margin:14px 0 4px; }
.card { flex:1 1 150px; background:#fff; border:1px solid var(--line); border-radius:8px;
        padding:10px 14px; border-top:3px solid var(--accent); }
.card .num { font-size:20px; font-weight:600; }
.card .lbl { color:var(--muted); font-size:12.5px; }
footer { text-align:center; color:var(--muted); font-size:12px; padding:0 0 24px; }
"""


KEY_RESULTS = (
    ("rms_dte_um", "RMS DTE", "µm"), ("dynamic_factor", "dynamic factor", ""),
    ("mean_mesh_force_n", "mean mesh force", "N"), ("max_penetration_um", "max penetration", "µm"),
    ("contact_loss_fraction", "contact-loss fraction", ""),
    ("period_multiplicity", "period", ""),
)


def key_results(report):
    """A row of cards with the headline numbers of summary.json."""
    flat = {k.split(".")[-1].lower(): v for k, v in report.scene.flat_summary.items()}
    cards = []
    for key, text, unit in KEY_RESULTS:
        v = flat.get(key)
        if not isinstance(v, (int, float)) or isinstance(v, bool):
            continue
        if key == "period_multiplicity":
            shown = "aperiodic" if v == 0 else "period-%d" % v
        else:
            number = "%.3f" % v if key == "dynamic_factor" else "%.4g" % v
            shown = number + (" " + unit if unit else "")
        cards.append('<div class="card"><div class="num">%s</div><div class="lbl">%s</div></div>'
                     % (html.escape(shown), html.escape(text)))
    return '<div class="cards">%s</div>' % "".join(cards) if cards else ""


def pipeline_table(run):
    """The stages of `hertzgear run` (run.json "pipeline"): whether each ran, and why."""
    stages = run.get("pipeline") if isinstance(run, dict) else None
    if not isinstance(stages, list) or not stages:
        return ""
    rows = []
    for st in stages:
        if not isinstance(st, dict):
            continue
        wall = st.get("wall_time_s")
        rows.append("<tr><td class=\"key\">%s</td><td>%s</td><td>%s</td>"
                    "<td class=\"val\">%s</td></tr>"
                    % (html.escape(str(st.get("stage", ""))),
                       "ran" if st.get("ran") else "reused",
                       html.escape(str(st.get("reason", ""))),
                       html.escape("%.3g s" % wall) if isinstance(wall, (int, float)) else ""))
    if not rows:
        return ""
    return ("<details class=\"pipeline\" open><summary>Stages of this run (the "
            "<code>hertzgear run</code> that wrote this page): which ran, and why</summary>"
            "<table class=\"prm\"><thead><tr><th>stage</th><th>ran?</th><th>why</th>"
            "<th>wall time</th></tr></thead><tbody>%s</tbody></table></details>"
            % "".join(rows))


def render_page(report):
    art = report.art
    run = art.get("run.json") or {}
    title = "hertzgear report"
    scene_file = run.get("scene_file") if isinstance(run, dict) else None
    if scene_file:
        title += " — " + os.path.basename(scene_file)
    meta = []
    if isinstance(run, dict):
        for key, text in (("scene_file", "scene"), ("scene_hash", "scene hash"),
                          ("hertzgear_version", "version"), ("git_revision", "git"),
                          ("finished_utc", "finished")):
            if run.get(key):
                meta.append("%s <code>%s</code>" % (text, html.escape(str(run[key]))))
    meta.append("run directory <code>%s</code>" % html.escape(art.run_dir))
    found = ", ".join(html.escape(art.rel(n)) for n in ARTIFACT_NAMES if art.has(n))
    found += "".join(", " + html.escape(os.path.relpath(p, art.run_dir))
                     for p in art.accuracy_tables)
    nav = "".join('<a href="#%s">%s</a>' % (sid, html.escape(t)) for sid, t, _ in report.sections)
    body = ""
    for sid, t, blocks in report.sections:
        body += '<section id="%s"><h2>%s</h2>%s</section>\n' % (sid, html.escape(t), "\n".join(blocks))
    notes = ""
    if art.notes:
        notes = "".join('<p class="note">%s</p>' % html.escape(n) for n in art.notes)
    return """<!DOCTYPE html>
<html lang="en">
<head>
<meta charset="utf-8">
<meta name="viewport" content="width=device-width, initial-scale=1">
<title>%s</title>
<style>%s</style>
</head>
<body>
<header><h1>%s</h1><div class="meta">%s</div></header>
<nav>%s</nav>
<main>
<p class="facts">Artifacts read: %s.</p>
%s
%s
%s
%s
</main>
<footer>Written by hertzgear report. Figures: matplotlib %s.</footer>
</body>
</html>
""" % (html.escape(title), CSS, html.escape(title), " · ".join(meta), nav, found,
       key_results(report), pipeline_table(run), notes, body, matplotlib.__version__)


def remove_stale_temporaries(directory, age_s=600):
    """Temporary files of a report that was killed; young ones may belong to a report running
    now and are left alone."""
    now = time.time()
    for name in os.listdir(directory):
        if name.startswith(".") and ".hg-partial-" in name:
            path = os.path.join(directory, name)
            try:
                if now - os.path.getmtime(path) > age_s:
                    os.remove(path)
            except OSError:
                pass


def main(argv=None):
    parser = argparse.ArgumentParser(
        description="Figures and an HTML page from the artifacts of a hertzgear run.")
    parser.add_argument("run_dir", help="run directory holding CSV/JSON artifacts")
    parser.add_argument("--out", help="report folder (default: RUN_DIR/report)")
    args = parser.parse_args(argv)
    run_dir = args.run_dir
    if not os.path.isdir(run_dir):
        sys.stderr.write("hertzgear report: error: the run directory %s does not exist or is not "
                         "a directory\n" % run_dir)
        return EXIT_BAD_INPUT
    out_dir = os.path.abspath(args.out or os.path.join(run_dir, "report"))
    art = Artifacts(run_dir, out_dir)
    if not art.any():
        sys.stderr.write(
            "hertzgear report: error: %s holds no hertzgear artifact (looked for %s and accuracy "
            "tables, in the folder and in its sub-folders %s)\n"
            % (run_dir, ", ".join(ARTIFACT_NAMES), ", ".join(f + "/" for f in STAGE_FOLDERS if f)))
        return EXIT_BAD_INPUT
    os.makedirs(out_dir, exist_ok=True)
    remove_stale_temporaries(out_dir)
    style()
    report = Report(art, out_dir)
    index = report.write()
    sys.stderr.write("hertzgear report: %d figures, %s\n" % (len(report.figures), index))
    return 0


if __name__ == "__main__":
    try:
        sys.exit(main())
    except KeyboardInterrupt:
        sys.exit(130)
