"""Time-series analysis for the dynamics figures: the steady-state window, the dominant frequency,
min/max decimation for plotting, force–penetration loops and their areas, the Poincaré section
(from poincare.csv, or sampled from the time series once per mesh period), the number of distinct
points of a section, and the amplitude spectrum of a signal.
"""

import math

import numpy as np

from .artifacts import DTE, NOT_A_RATE, TIME, BadInput

# Column patterns of the DTE rate (Table.find); those of time and DTE are in artifacts.
RATE = ("dte_rate", "re:rate|velocity")


def time_column(ts):
    """The time values of timeseries.csv; BadInput when it has no time column."""
    t = ts.find(*TIME)
    if not t:
        raise BadInput("timeseries.csv has no time column")
    return ts[t]


def unique_in_order(values):
    seen = []
    for v in values:
        if v not in seen:
            seen.append(v)
    return seen


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


def amplitude_spectrum(t, x):
    """(frequencies, one-sided amplitudes) of x(t), resampled on a uniform grid, mean removed."""
    dt = (t[-1] - t[0]) / (len(t) - 1)
    uniform = np.linspace(t[0], t[-1], len(t))
    xx = np.interp(uniform, t, x)
    spec = np.fft.rfft(xx - xx.mean())
    return np.fft.rfftfreq(len(xx), dt), 2 * np.abs(spec) / len(xx)


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


def overview(table, x, y, n_max=20000):
    """(x, y) of the whole history of columns x, y of a table for one line plot of at most about
    n_max points: the min/max envelope of table.envelope when the table holds only its last rows,
    else decimate()."""
    env = table.envelope
    if env is None:
        return decimate(table[x], table[y], n_max)
    xs = np.repeat(env["first"][x], 2)
    ys = np.stack([env["min"][y], env["max"][y]], axis=1).ravel()
    return xs, ys


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


def distinct_points(xs, rel=1e-3):
    if len(xs) == 0:
        return 0
    span = max(np.ptp(xs), np.max(np.abs(xs)), 1e-300)
    pts = []
    for x in xs:
        if all(abs(x - p) > rel * span for p in pts):
            pts.append(x)
    return len(pts)


def poincare_points(art, scene, ts):
    """(times or None, x, rate or None, x column, rate column, source) of the Poincaré section:
    poincare.csv, else the time series sampled once per mesh period, else None."""
    p = art.get("poincare.csv")
    if p is not None:
        x = p.find(*DTE, "x_um", exclude=NOT_A_RATE)
        if not x:
            return None
        v = p.find(*RATE)
        t = p.find("time")
        return (p[t] if t and p.numeric(t) else None, p[x],
                p[v] if v and p.numeric(v) else None, x, v, "poincare.csv")
    if ts is not None and scene.f_mesh_hz:
        t = time_column(ts)
        x = ts.find(*DTE, exclude=NOT_A_RATE)
        v = ts.find("dte_rate", "re:rate")
        ks = np.arange(math.ceil(t[0] * scene.f_mesh_hz), math.floor(t[-1] * scene.f_mesh_hz) + 1)
        if len(ks) < 3 or not x:
            return None
        tk = ks / scene.f_mesh_hz
        return (tk, np.interp(tk, t, ts[x]), np.interp(tk, t, ts[v]) if v else None, x, v,
                "timeseries.csv sampled here once per mesh period")
    return None
