"""The figures of the report, one function per figure. Each draws its PNG into the report folder
and adds it with its caption to a page section, or adds a note saying why it is left out when
its input lacks the columns it needs.

Stiffness: stiffness over the mesh cycle, STE and load sharing, contact per position, contact
pressure map. Load and design map: STE and stiffness against torque, peak pressure and contact
centre against misalignment, contact patterns on the flank at several torques and misalignments (or
over the scene's own cycle). Dynamics: DTE and penetration histories, mesh force, Poincaré map,
phase portrait, force–penetration loops, spectrum. Sweep: RMS versus speed, bifurcation diagram.
Accuracy: work–precision diagram.
"""

import html
import math
import os
import re
from collections import namedtuple

import numpy as np
from matplotlib.cm import ScalarMappable
from matplotlib.collections import PolyCollection
from matplotlib.colors import Normalize
from matplotlib.lines import Line2D
from matplotlib.patches import Ellipse, Patch, Rectangle

from .artifacts import find_series, is_number
from .plotting import (COLORS, fourier_value, force_scale, label, mark_backlash, mark_mesh_periods,
                       plt, reference_of, right_axis, save_figure_atomically, scaled, shade_contact,
                       shifted, shifted_label, span_limits, title_and_legend, unit_of)
from .signals import (DTE, NOT_A_RATE, RATE, TIME, amplitude_spectrum, distinct_points,
                      loop_segments, overview, poincare_points, polygon_area, steady_part,
                      steady_window, time_column, unique_in_order)


def publish(sec, name, fig, caption):
    """Writes the figure into the report folder and adds it to the section."""
    save_figure_atomically(fig, os.path.join(sec.out_dir, name))
    sec.figure(name, caption)


def mesh_phase(table):
    """The mesh phase (cycles) of each row of a stiffness table: its phase column, else
    position / number of positions."""
    column = table.find("mesh_phase", "phase")
    if column:
        return table[column]
    pos = table[table.find("position")]
    return pos / len(pos)


# --------------------------------------------------------------------------------------------
# Stiffness
# --------------------------------------------------------------------------------------------

# (key, panel title, column patterns in stiffness.csv, key names in stiffness.json)
STIFFNESS_PANELS = (
    ("k_total", "total mesh stiffness $k_{total}$", ("k_total",), ("k_total",)),
    ("k_rest", "rest (structural) stiffness $k_{rest}$", ("k_rest",), ("k_rest",)),
    ("k_hertz", "Hertzian stiffness $k_h$ (F = $k_h δ^n$)", ("k_hertz", "k_h_", "k_h"),
     ("k_hertz", "k_h")),
)

Quantity = namedtuple("Quantity", "key title unit samples series note")


def stiffness_quantities(scene, table, js):
    """The stiffness quantities the artifacts give: samples from the table, the Fourier series of
    the coefficients stiffness.json carries (none is fitted here), and a note saying where the
    line comes from or that there is none."""
    n = scene.hertz_exponent
    kh_unit = "N/m" if n in (None, 1.0) else "N/m$^{%g}$" % n
    found = []
    for key, title, patterns, json_names in STIFFNESS_PANELS:
        col = table.find(*patterns, exclude=("total",) if key != "k_total" else ()) \
            if table is not None else None
        samples = table[col] if col and table.numeric(col) else None
        where, series = find_series(js, *json_names)
        if key != "k_total" and where and "total" in where:
            where, series = None, None
        if series is not None:
            note = "%s: Fourier coefficients of stiffness.json (%s)" % (key, where)
        elif samples is not None:
            note = "%s: samples only, %s" % (key, "stiffness.json carries no Fourier coefficients "
                                             "for it" if isinstance(js, dict) else
                                             "no stiffness.json gives its Fourier coefficients")
        else:
            continue
        found.append(Quantity(key, title, kh_unit if key == "k_hertz" else "N/m", samples,
                              series, note))
    return found


def stiffness_panel(ax, q, phase, sample_label):
    fine = np.linspace(0, 1, 400)
    allv = np.concatenate([q.samples[np.isfinite(q.samples)] if q.samples is not None else [],
                           fourier_value(q.series, fine) if q.series is not None else []])
    scale, shown_unit = scaled(allv, q.unit)
    if q.series is not None:
        ax.plot(fine, fourier_value(q.series, fine) / scale, "-", lw=1.6,
                label="Fourier series (%d harmonics)" % len(q.series.get("amplitudes", [])))
        ax.axhline(float(q.series["mean"]) / scale, color="#888888", lw=0.8, ls="--",
                   label="mean")
    if q.samples is not None:
        ax.plot(phase, q.samples / scale, "o", ms=5, color=COLORS[1], label=sample_label)
    ax.set_title(q.title, loc="left")
    ax.set_xlabel("mesh phase (mesh cycles)")
    ax.set_ylabel(label(q.key.replace("_", " "), unit=shown_unit))
    ax.set_xlim(0, 1)


def stiffness_cycle(sec, scene, table, js):
    """k_total, k_rest and k_h over the mesh cycle: samples as dots, the Fourier series of the
    coefficients in stiffness.json as lines."""
    phase = mesh_phase(table) if table is not None else None
    found = stiffness_quantities(scene, table, js)
    if not found:
        sec.note("Neither stiffness samples nor Fourier coefficients were found.")
        return
    sample_label = "samples (%s)" % ("stiffness.csv" if table is not None and
                                     table.path.endswith(".csv") else "stiffness.json")
    width = 10 if len(found) == 3 else 3.4 * len(found) + 0.4
    fig, axes = plt.subplots(1, len(found), figsize=(width, 3.6), squeeze=False)
    for i, (ax, q) in enumerate(zip(axes[0], found)):
        stiffness_panel(ax, q, phase, sample_label)
        if i == 0:
            ax.legend(loc="best", fontsize=8)
    lines = (", lines the Fourier series the dynamics uses"
             if any(q.series is not None for q in found) else "")
    publish(sec, "stiffness_cycle.png", fig,
            "Mesh stiffness over one mesh cycle: the total, its structural (rest) part and "
            "the Hertzian stiffness, as far as the artifacts give them. Dots are the "
            "loaded-TCA positions%s "
            "(1/k<sub>rest</sub> = 1/k<sub>total</sub> − 1/k<sub>h,tangent</sub>). " % lines
            + html.escape("; ".join(q.note for q in found)) + ".")


def ste_load_sharing(sec, table):
    phase = table[table.find("mesh_phase", "phase")]
    ste = table.find("ste_um", "ste")
    shares = [c for c in table.names if c.lower().startswith("load_share")]
    pairs = table.find("pairs_in_contact", "pairs")
    if not ste and not shares:
        sec.note("stiffness.csv has no STE or load-share columns.")
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
    extra = []
    if pairs and table.numeric(pairs):
        ax2 = right_axis(axes[1], "pairs in contact (count)")
        ax2.step(phase[order], table[pairs][order], where="mid", color="#888888", lw=1,
                 ls="--", label="pairs in contact")
        ax2.set_ylim(0, max(3, np.nanmax(table[pairs]) + 0.5))
        extra = [ax2]
    title_and_legend(axes[1], "Load sharing between the tooth pairs", extra, ncol=3)
    axes[1].set_ylabel("load share (–)")
    axes[1].set_ylim(-0.05, 1.05)
    axes[1].set_xlabel("mesh phase (mesh cycles)")
    axes[1].set_xlim(0, 1)
    publish(sec, "ste_load_sharing.png", fig,
            "Loaded static transmission error (top) and the share of the mesh force each "
            "tooth pair carries (bottom). In the single-tooth zone one pair carries all "
            "the load; the STE rises there because the mesh is softer.")


def contact_per_position(sec, table):
    phase = table[table.find("mesh_phase", "phase")]
    a, b = table.find("contact_a_mm"), table.find("contact_b_mm")
    p = table.find("peak_pressure", "pressure")
    pen = table.find("hertz_penetration", "penetration")
    if not (a or b or p):
        sec.note("stiffness.csv has no contact semi-axes or pressure columns.")
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
        ax2 = right_axis(axes[1], label("Hertzian penetration", pen))
        ax2.plot(phase[order], table[pen][order], "s--", ms=3, color=COLORS[2],
                 label="Hertzian penetration")
        title_and_legend(axes[1], "Pressure, penetration", [ax2], ncol=1)
    else:
        title_and_legend(axes[1], "Peak pressure", ncol=1)
    axes[1].set_xlabel("mesh phase (mesh cycles)")
    for ax in axes:
        ax.set_xlim(0, 1)
    publish(sec, "contact_per_position.png", fig,
            "Contact semi-axes (left) and peak contact pressure with the Hertzian "
            "(local) penetration (right) at each mesh position.")


def pressure_panel(ax, a, b, p, grid, line_contact):
    """The Hertz pressure of one mesh position on the shared grid (x, y, half extents); returns
    the image, or None when the position has no contact."""
    xg, yg, amax, bmax, pmax = grid
    if not (a > 0 and b > 0 and np.isfinite(p)):
        ax.text(0, 0, "no contact", ha="center", va="center", fontsize=8)
        return None
    if line_contact:
        # Line contact: the Hertz strip p0 √(1 − x²/a²) along the whole contact line.
        r = np.where(np.abs(yg) <= b, 1 - (xg / a) ** 2, -1.0)
    else:
        r = 1 - (xg / a) ** 2 - (yg / b) ** 2
    pressure = np.where(r > 0, p * np.sqrt(np.clip(r, 0, None)), np.nan)
    image = ax.imshow(pressure, extent=(-amax, amax, -bmax, bmax), origin="lower",
                      aspect="auto", cmap="inferno", vmin=0, vmax=pmax, interpolation="nearest")
    if line_contact:
        ax.add_patch(Rectangle((-a, -b), 2 * a, 2 * b, fill=False, lw=0.8, color="#1f5fa8"))
    else:
        ax.add_patch(Ellipse((0, 0), 2 * a, 2 * b, fill=False, lw=0.8, color="#1f5fa8"))
    return image


def contact_pressure_map(sec, scene, table):
    a, b = table.find("contact_a_mm"), table.find("contact_b_mm")
    p = table.find("peak_pressure", "pressure")
    phase = table[table.find("mesh_phase", "phase")]
    if not (a and b and p):
        sec.note("The contact pressure map needs contact_a_mm, contact_b_mm and "
                 "peak_pressure_MPa.")
        return
    A, B, P = table[a], table[b], table[p]
    n_exp = scene.hertz_exponent
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
        drawn = pressure_panel(ax, A[i], B[i], P[i], (xg, yg, amax, bmax, pmax), line_contact)
        image = drawn if drawn is not None else image
        ax.set_title("phase %.3g" % phase[i], fontsize=9)
    for ax in axes[-1, :]:
        ax.set_xlabel("x, profile (mm)", fontsize=8)
    for ax in axes[:, 0]:
        ax.set_ylabel("y, face width (mm)", fontsize=8)
    if image is not None:
        fig.colorbar(image, ax=axes, shrink=0.9, label="contact pressure (MPa)")
    publish(sec, "contact_pressure_map.png", fig, pressure_map_caption(line_contact, bmax / amax))


def pressure_map_caption(line_contact, stretch):
    if line_contact:
        what = ("Line contact (Hertz exponent n = 1): the Hertz pressure strip p = p<sub>0</sub>"
                "√(1 − x²/a²) of half-width a over the contact length 2b")
    else:
        what = ("Contact ellipse and Hertzian pressure distribution p = p<sub>0</sub>"
                "√(1 − x²/a² − y²/b²)")
    return (what + " at each mesh position, drawn from the semi-axes and peak "
            "pressure of stiffness.csv (the largest-loaded pair); all panels share the "
            "same axes and colour scale. The x axis (profile) is stretched against the "
            "y axis (face width) by about %.0f× so that the narrow contact stays visible."
            % stretch)


# --------------------------------------------------------------------------------------------
# Load and design map
# --------------------------------------------------------------------------------------------

def crowning_label(crowning):
    pinion, gear = crowning
    if pinion == 0 and gear == 0:
        return "uncrowned"
    if pinion == gear:
        return "crowning %g µm" % pinion
    return "crowning %g/%g µm (pinion/gear)" % (pinion, gear)


def fmt_number(v):
    return "%g" % v if v is not None else "?"


def edge_contact(cases):
    return np.array([c.get("face_end_contact_positions", 0) > 0 for c in cases])


def map_line(ax, cases, x_key, y, color, text):
    """y(case) against case[x_key]: a line with filled markers, hollow where the contact reaches
    a face end at some position of the cycle."""
    x = np.array([c[x_key] for c in cases], dtype=float)
    v = np.array([y(c) for c in cases], dtype=float)
    ax.plot(x, v, "-", color=color, lw=1.4, label=text)
    edge = edge_contact(cases)
    ax.plot(x[~edge], v[~edge], "o", ms=5, color=color)
    ax.plot(x[edge], v[edge], "o", ms=7, mfc="white", mec=color, mew=1.6)


def edge_legend(ax, series):
    """The legend of a map panel, with an "edge contact" entry when a hollow marker is drawn."""
    handles, labels = ax.get_legend_handles_labels()
    if any(edge_contact(cases).any() for cases in series.values()):
        handles.append(Line2D([], [], ls="none", marker="o", ms=7, mfc="white", mec="#333333",
                              mew=1.6))
        labels.append("edge contact (face end)")
    ax.legend(handles, labels, loc="best", frameon=True, framealpha=0.9, edgecolor="#dddddd",
              fontsize=8.5)


def lines_over(axes, series, x_key, quantities):
    """One line per crowning variant in each panel: quantities[i] is y(case) of axes[i]."""
    for i, (crowning, cases) in enumerate(series.items()):
        for ax, y in zip(axes, quantities):
            map_line(ax, cases, x_key, y, COLORS[i % len(COLORS)], crowning_label(crowning))


def percent_axis(ax, cases):
    """A top axis with the torque in % of the scene's nominal torque."""
    nominal = cases[0]["torque_Nm"] * 100.0 / cases[0]["torque_percent"]
    top = ax.secondary_xaxis("top", functions=(lambda t: t * 100.0 / nominal,
                                               lambda p: p * nominal / 100.0))
    top.set_xlabel("torque (%% of nominal %.4g N m)" % nominal)
    return nominal


def ste_against_torque(sec, lmap):
    series = {k: v for k, v in lmap.torque_series().items() if len(v) > 1}
    if not series:
        sec.note("The load map has fewer than two torques per crowning variant: the "
                 "STE-against-torque figure is left out.")
        return
    fig, axes = plt.subplots(1, 2, figsize=(10, 4.2))
    lines_over(axes, series, "torque_Nm", (lambda c: c["ste_peak_to_peak_um"],
                                           lambda c: c["mean_k_total_N_per_m"] * 1e-6))
    for ax, title, ylabel in (
            (axes[0], "Peak-to-peak loaded STE", label("STE peak to peak", unit="µm")),
            (axes[1], "Mean mesh stiffness", label("mean k$_{total}$", unit="N/µm"))):
        nominal = percent_axis(ax, next(iter(series.values())))
        ax.set_title(title, loc="left")
        ax.set_xlabel(label("pinion torque", unit="N m"))
        ax.set_ylabel(ylabel)
    edge_legend(axes[0], series)
    publish(sec, "ste_against_torque.png", fig,
            "Loaded static transmission error, peak to peak over the mesh cycle (left), and "
            "the mesh stiffness k<sub>total</sub> averaged over the cycle (right), against the "
            "pinion torque (top axis: %% of the nominal %.4g N m), one line per lead-crowning "
            "variant, at the scene's mesh misalignment (%s µm). A hollow marker means the "
            "contact reaches a face end at one or more positions of the cycle (edge contact)."
            % (nominal, fmt_number(lmap.scene_misalignment_um)))


def tolerance_study(sec, lmap):
    """The spread of the map's designs at each torque (a tolerance study, Stiffness/Map/
    combination = product): STE peak to peak and peak pressure of every design, their envelope
    and the scene's own design."""
    groups = lmap.designs_by_torque()
    spread = {t: cases for t, cases in groups.items() if len(cases) >= 3}
    if len(spread) < 2:
        sec.note("The map has fewer than two torques with three or more designs each (crowning, "
                 "misalignment, helix slope; Stiffness/Map/combination = product makes them): "
                 "the tolerance-study figure is left out.")
        return
    torques = sorted(spread)
    n_designs = max(len(cases) for cases in spread.values())
    fig, axes = plt.subplots(1, 2, figsize=(10, 4.2))
    quantities = ((lambda c: c["ste_peak_to_peak_um"], "Peak-to-peak loaded STE",
                   label("STE peak to peak", unit="µm")),
                  (off_tips_pressure, "Maximum peak pressure away from the tips",
                   label("peak contact pressure", unit="MPa")))
    for ax, (y, title, ylabel) in zip(axes, quantities):
        lo = [min(y(c) for c in spread[t]) for t in torques]
        hi = [max(y(c) for c in spread[t]) for t in torques]
        ax.fill_between(torques, lo, hi, color=COLORS[0], alpha=0.18, lw=0,
                        label="range over the designs")
        for t in torques:
            cases = spread[t]
            v = np.array([y(c) for c in cases], dtype=float)
            edge = edge_contact(cases)
            ax.plot(np.full(int((~edge).sum()), t), v[~edge], "o", ms=3.5, color="#777777",
                    alpha=0.8)
            ax.plot(np.full(int(edge.sum()), t), v[edge], "o", ms=5, mfc="white", mec="#777777",
                    mew=1.2)
        nominal = [(t, y(c)) for t in torques for c in spread[t] if lmap.is_scene_design(c)]
        if len(nominal) > 1:
            ax.plot(*zip(*nominal), "-o", color="#222222", lw=1.6, ms=4, label="the scene's design")
        t, case = max(((t, c) for t in torques for c in spread[t]), key=lambda p: y(p[1]))
        ax.plot(t, y(case), "o", mfc="none", mec="#c0392b", mew=1.8, ms=11,
                label="worst: %.4g, case %d" % (y(case), int(case["case"])))
        ax.set_title(title, loc="left")
        ax.set_xlabel(label("pinion torque", unit="N m"))
        ax.set_ylabel(ylabel)
        ax.legend(loc="best", fontsize=8.5, frameon=True, framealpha=0.9, edgecolor="#dddddd")
    percent_axis(axes[0], spread[torques[0]])
    percent_axis(axes[1], spread[torques[0]])
    publish(sec, "tolerance_study.png", fig,
            "Tolerance study: at each torque of the map, every design it ran (up to %d: lead "
            "crowning × mesh misalignment f<sub>ma</sub> × helix slope deviation f<sub>Hβ</sub>) "
            "as a grey dot (hollow: the contact reaches a face end somewhere in the cycle), their "
            "range shaded, the scene's own design as a line and the worst case ringed (its case "
            "number in the legend; its values in the map table): the loaded STE peak to peak "
            "over the mesh cycle (left) and the highest peak contact pressure away from the tips "
            "(right)." % n_designs)


def mark_face_ends(ax, half_width):
    if half_width is None:
        return
    for i, v in enumerate((half_width, -half_width)):
        ax.axhline(v, color="#c0392b", lw=1.0, ls="--",
                   label="face ends ±b/2 = ±%g mm" % half_width if i == 0 else None)


def centre_band(ax, series):
    """The range of the contact centre over the cycle, shaded, for each crowning variant."""
    for i, cases in enumerate(series.values()):
        x = [c["mesh_misalignment_um"] for c in cases]
        ax.fill_between(x, [c["contact_centre_z_min_mm"] for c in cases],
                        [c["contact_centre_z_max_mm"] for c in cases],
                        color=COLORS[i % len(COLORS)], alpha=0.18, lw=0)


def centre_legend(ax):
    """Face ends and the meaning of the band; the crowning lines are named in the other panel."""
    handles = [h for h in ax.get_legend_handles_labels()[0] if "face ends" in h.get_label()]
    handles.append(Patch(color="#888888", alpha=0.3, lw=0, label="range over the mesh cycle"))
    ax.legend(handles=handles, loc="best", fontsize=8.5, frameon=True, framealpha=0.9,
              edgecolor="#dddddd")


def mid_centre(case):
    return 0.5 * (case["contact_centre_z_min_mm"] + case["contact_centre_z_max_mm"])


def off_tips_pressure(case):
    """The largest peak pressure away from tip contact (all positions for an older map)."""
    return case.get("max_peak_pressure_off_tips_MPa") or case["max_peak_pressure_MPa"]


def pressure_centre_against_misalignment(sec, lmap):
    series = {k: v for k, v in lmap.misalignment_series().items() if len(v) > 1}
    if not series:
        sec.note("The load map has no misalignment variants (Stiffness/Map/"
                 "mesh_misalignment_um): the pressure and contact-centre figure is left out.")
        return
    fig, axes = plt.subplots(1, 2, figsize=(10, 4.0))
    lines_over(axes, series, "mesh_misalignment_um",
               (off_tips_pressure, mid_centre))
    centre_band(axes[1], series)
    half = 0.5 * lmap.face_width_mm if lmap.face_width_mm else None
    mark_face_ends(axes[1], half)
    if half:
        axes[1].set_ylim(-1.15 * half, 1.15 * half)
    axes[0].set_title("Maximum peak pressure away from the tips", loc="left")
    axes[0].set_ylabel(label("peak contact pressure", unit="MPa"))
    axes[1].set_title("Contact centre along the face", loc="left")
    axes[1].set_ylabel(label("contact centre z", unit="mm"))
    for ax in axes:
        ax.set_xlabel(label("mesh misalignment f$_{ma}$", unit="µm"))
    edge_legend(axes[0], series)
    centre_legend(axes[1])
    publish(sec, "misalignment_pressure_centre.png", fig,
            "Sensitivity to mesh misalignment at the nominal torque, one line per "
            "lead-crowning variant: the highest peak contact pressure of the mesh cycle at the "
            "positions whose contact stays clear of the tips (left; the edge pressure at a tip "
            "without tip relief does not depend on the misalignment and is in the map table) and the position of the contact centre along the face width (right; line: "
            "middle of its range over the cycle, band: its minimum to maximum; z = 0 is the "
            "middle of the face, dashed lines the face ends). A hollow marker means edge "
            "contact at one or more positions of the cycle.")


def draw_cells(ax, lmap, cells, norm):
    """The loaded cells (z, roll, pressure, height) on the flank, coloured by pressure; drawn in
    rising pressure, so where cells of several positions overlap the highest pressure shows (the
    envelope)."""
    if cells is None:
        ax.text(0.5, 0.5, "no loaded cell", transform=ax.transAxes, ha="center", fontsize=8)
        return
    z, roll, pressure, height = cells
    order = np.argsort(pressure)
    w = 0.5 * lmap.cell_width_mm()
    lo, hi = roll - 0.5 * height, roll + 0.5 * height
    boxes = [((z[i] - w, lo[i]), (z[i] + w, lo[i]), (z[i] + w, hi[i]), (z[i] - w, hi[i]))
             for i in order]
    ax.add_collection(PolyCollection(boxes, array=pressure[order], cmap=PATTERN_CMAP, norm=norm,
                                     edgecolors="face", linewidths=0.2))


FACE_END_LINE = dict(color="#1f5fa8", lw=1.0)
ACTIVE_PROFILE_LINE = dict(color="#2e8b57", lw=1.0, ls="--")
PATTERN_CMAP = "YlOrRd"


def flank_frame(ax, lmap, cells):
    """The pinion flank: face ends (z = ±b/2) and active profile limits, grey behind the cells;
    the axes hold the flank and every cell."""
    half = 0.5 * lmap.face_width_mm if lmap.face_width_mm else None
    roll = lmap.active_roll_mm
    if half and roll:
        ax.add_patch(Rectangle((-half, roll[0]), 2 * half, roll[1] - roll[0], color="#e6e9ee",
                               lw=0, zorder=0))
    for v in (-half, half) if half else ():
        ax.axvline(v, **FACE_END_LINE)
    for v in roll or ():
        ax.axhline(v, **ACTIVE_PROFILE_LINE)
    z_ends = [-half, half] if half else []
    rolls = list(roll or [])
    if cells is not None:
        z, r, _, height = cells
        z_ends += [np.min(z), np.max(z)]
        rolls += [np.min(r - 0.5 * height), np.max(r + 0.5 * height)]
    if z_ends:
        pad = 0.04 * (max(z_ends) - min(z_ends)) + lmap.cell_width_mm()
        ax.set_xlim(min(z_ends) - pad, max(z_ends) + pad)
    if rolls:
        pad = 0.05 * (max(rolls) - min(rolls))
        ax.set_ylim(min(rolls) - pad, max(rolls) + pad)


def pattern_legend(fig):
    """The line styles of the flank limits above the panels."""
    fig.legend([Line2D([], [], **FACE_END_LINE), Line2D([], [], **ACTIVE_PROFILE_LINE)],
               ["face ends z = ±b/2", "active profile limits (root below, tip above)"],
               loc="upper left", bbox_to_anchor=(0.0, 1.0), ncol=2, fontsize=8.5)
    fig.get_layout_engine().set(rect=(0, 0, 1, 1 - 0.32 / fig.get_figheight()))


def pattern_layout(n):
    cols = min(n, 3)
    rows = int(math.ceil(n / cols))
    return plt.subplots(rows, cols, figsize=(max(6.0, 3.1 * cols + 1.3), 2.9 * rows + 0.7),
                        sharex=True, sharey=True, squeeze=False)


def panel_cells(lmap, key):
    """The cells of a panel: key is a case, or (case, position) for one mesh position."""
    return lmap.cells_of(*key) if isinstance(key, tuple) else lmap.cells_of(key)


def pressure_norm(lmap, keys):
    peaks = [np.max(c[2]) for c in (panel_cells(lmap, k) for k in keys) if c is not None]
    return Normalize(0.0, max(peaks) if peaks else 1.0)


def pattern_figure(sec, name, lmap, panels, caption, pattern_caption=None):
    """Contact patterns of `panels` [(case or (case, position), title)] in small multiples with
    one colour bar."""
    fig, axes = pattern_layout(len(panels))
    norm = pressure_norm(lmap, [key for key, _ in panels])
    for ax, (key, title) in zip(axes.ravel(), panels):
        ax.grid(False)
        cells = panel_cells(lmap, key)
        draw_cells(ax, lmap, cells, norm)
        flank_frame(ax, lmap, cells)
        peak = ", max %.0f MPa" % np.max(cells[2]) if cells is not None else ""
        ax.set_title(title + peak, fontsize=9)
    for ax in axes.ravel()[len(panels):]:
        ax.set_visible(False)
    for ax in axes[-1, :]:
        ax.set_xlabel("z, face width (mm)", fontsize=9)
    for ax in axes[:, 0]:
        ax.set_ylabel("pinion roll distance (mm)", fontsize=9)
    fig.colorbar(ScalarMappable(norm=norm, cmap=PATTERN_CMAP), ax=axes, shrink=0.85,
                 label="contact pressure (MPa)")
    pattern_legend(fig)
    publish(sec, name, fig, caption + (PATTERN_CAPTION if pattern_caption is None else pattern_caption))


PATTERN_CAPTION = (
    " Each panel is the pinion flank developed flat: the face width z across (z = 0 in the "
    "middle, solid blue lines at the face ends ±b/2) and the roll distance up, from the root "
    "to the tip (dashed green lines at the start and end of the active profile; grey the "
    "active flank). Coloured "
    "cells are the loaded cells of the FE contact grid (contact_pattern.csv) of every mesh "
    "position and tooth pair, each showing the highest pressure it reaches in the cycle (the "
    "pressure envelope); all panels share the colour scale. Cell pressures are those of the "
    "contact grid and may exceed the Hertzian peak pressure of the other figures.")


def pick(items, n=6):
    """At most n items, evenly spread and keeping the first and the last."""
    if len(items) <= n:
        return items
    return [items[int(round(i))] for i in np.linspace(0, len(items) - 1, n)]


def torque_title(case):
    return "T = %.4g N m (%g %%)" % (case["torque_Nm"], case["torque_percent"])


def contact_patterns_over_torque(sec, lmap):
    series = lmap.torque_series()
    crowning = lmap.pattern_crowning(series)
    if crowning is None or lmap.cells is None:
        sec.note("No contact_pattern.csv or no torque series in the map: the contact patterns "
                 "at several torques are left out.")
        return
    panels = [(int(c["case"]), torque_title(c)) for c in pick(series[crowning])]
    pattern_figure(sec, "contact_pattern_torque.png", lmap, panels,
                   "Contact patterns on the pinion flank at %d torque%s, %s, at the scene's mesh "
                   "misalignment (%s µm)." % (len(panels), "s" if len(panels) > 1 else "",
                                              crowning_label(crowning),
                                              fmt_number(lmap.scene_misalignment_um)))


def contact_patterns_over_misalignment(sec, lmap):
    series = lmap.misalignment_series()
    crowning = lmap.pattern_crowning(series)
    if crowning is None or lmap.cells is None or len(series[crowning]) < 2:
        return
    panels = [(int(c["case"]), "f$_{ma}$ = %g µm" % c["mesh_misalignment_um"])
              for c in pick(series[crowning])]
    pattern_figure(sec, "contact_pattern_misalignment.png", lmap, panels,
                   "Contact patterns on the pinion flank at %d mesh misalignments f<sub>ma</sub>, "
                   "%s, at the nominal torque: how far misalignment moves the pattern along "
                   "the face." % (len(panels), crowning_label(crowning)))


def contact_pattern_scene(sec, lmap):
    if lmap.cells_of(-1) is None:
        sec.note("contact_pattern.csv has no cell of the scene's own cycle (case −1): the "
                 "contact pattern is left out.")
        return
    pattern_figure(sec, "contact_pattern.png", lmap, [(-1, "scene's own mesh cycle")],
                   "Contact pattern on the pinion flank over the scene's own mesh cycle.")


CONTACT_LINES_CAPTION = (
    " Each panel is the pinion flank developed flat at one mesh position: the face width z "
    "across (solid blue lines at the face ends ±b/2) and the roll distance up, from the root to "
    "the tip (dashed green lines at the active profile's limits). Coloured cells are the loaded "
    "cells of the FE contact grid (contact_pattern.csv) at that position, one band per tooth "
    "pair in contact: straight across the face for a spur pair, inclined by the base helix "
    "angle for a helical pair, moving up the flank from root to tip as the pair rolls through "
    "its mesh; all panels share the colour scale.")


def contact_lines_over_cycle(sec, lmap):
    positions = lmap.positions_of(-1)
    if len(positions) < 2:
        return
    panels = [((-1, p), "position %d of %d" % (p + 1, len(positions))) for p in pick(positions)]
    pattern_figure(sec, "contact_lines.png", lmap, panels,
                   "The contact lines on the pinion flank over the scene's own mesh cycle, at "
                   "%d of its %d positions." % (len(panels), len(positions)),
                   CONTACT_LINES_CAPTION)


# --------------------------------------------------------------------------------------------
# Dynamics
# --------------------------------------------------------------------------------------------

def dte_overview(ax, ts, tcol, dte, scene):
    """The whole recorded DTE with both backlash lines in view (unshifted), so that it shows how
    far the motion stays from separation (|x| < b_c) and back-side contact (x < −b_c)."""
    xd, yd = overview(ts, tcol, dte)
    ax.plot(xd, yd, lw=0.6, label="DTE")
    mark_backlash(ax, scene.b_c_um)
    if scene.b_c_um is not None:
        ax.axhspan(-scene.b_c_um, scene.b_c_um, color="#bbbbbb", alpha=0.15, lw=0,
                   label="teeth apart")
    ax.set_ylabel(label("DTE x", dte))
    ax.set_xlabel("time (s)")
    t0, t1 = xd[0], ts[tcol][-1]
    ax.set_xlim(t0, t1)
    span = ("the last %.0f mesh periods of the run" % ((t1 - t0) * scene.f_mesh_hz)
            if scene.f_mesh_hz else "the recorded window")
    title_and_legend(ax, "DTE x = r$_{b1}$θ$_1$ − r$_{b2}$θ$_2$, %s" % span, ncol=3)


def finish_zoom(ax, tz, period):
    """Mesh-period lines, the time range and the time label of a panel of the last periods."""
    mark_mesh_periods(ax, tz[0], tz[-1], period)
    ax.set_xlim(tz[0], tz[-1])
    ax.set_xlabel("time (s)")


def dte_penetration(sec, scene, ts):
    t = time_column(ts)
    dte = ts.find(*DTE, exclude=NOT_A_RATE)
    pen = ts.find("penetration_um", "penetration")
    contact = ts.find("contact")
    if not dte:
        sec.note("timeseries.csv has no DTE column.")
        return
    period = 1 / scene.f_mesh_hz if scene.f_mesh_hz else None
    n_zoom = 6
    zoom = steady_window(t, scene, n_zoom, ts[dte])
    cvals = ts[contact][zoom] if contact and ts.numeric(contact) else None
    n_panels = 3 if pen else 2
    fig, axes = plt.subplots(n_panels, 1, figsize=(10, 2.7 * n_panels + 0.4))
    ref = reference_of(ts[dte])
    dte_overview(axes[0], ts, ts.find(*TIME), dte, scene)
    tz = t[zoom]
    shade_contact(axes[1], tz, cvals)
    axes[1].plot(tz, ts[dte][zoom] - ref, lw=1.2, label="DTE")
    mark_backlash(axes[1], shifted(scene.b_c_um, ref), near_data=True)
    finish_zoom(axes[1], tz, period)
    axes[1].set_ylabel(shifted_label("DTE x", unit_of(dte), ref))
    title_and_legend(axes[1], "DTE, last %d %s" % (n_zoom, "mesh periods" if period else
                                                     "cycles of its main frequency"))
    if pen:
        shade_contact(axes[2], tz, cvals)
        axes[2].plot(tz, ts[pen][zoom], lw=1.2, color=COLORS[2], label="Hertzian penetration δ")
        finish_zoom(axes[2], tz, period)
        axes[2].set_ylabel(label("penetration δ", pen))
        title_and_legend(axes[2], "Hertzian penetration δ, same periods")
    publish(sec, "dte_penetration.png", fig,
            "Dynamic transmission error over the recorded time series "
            "(top, Output/timeseries_periods), over the last mesh periods (middle), with "
            "the Hertzian penetration δ (bottom). Dashed red lines are ±b<sub>c</sub>: "
            "for |x| &lt; b<sub>c</sub> the teeth are apart (grey), below "
            "−b<sub>c</sub> they hit on the back side (red bands). Dotted lines mark "
            "mesh periods; the zoomed panels keep their own scale and say when "
            "±b<sub>c</sub> lies off it.")


def force_histogram(ax, values, static, ref, scale):
    """Steady-state distribution of the mesh force, with F_0 and the mean."""
    ax.hist(values[np.isfinite(values)], bins=60, color=COLORS[0], alpha=0.8)
    if static:
        ax.axvline((static - ref) / scale, color="#2e8b57", lw=1, ls="--", label="F$_0$")
    ax.axvline(np.nanmean(values), color=COLORS[1], lw=1, label="mean")
    ax.set_ylabel("samples (count)")
    title_and_legend(ax, "Steady-state distribution", ncol=2)


def mesh_force(sec, scene, ts):
    t = time_column(ts)
    force = ts.find("mesh_force_n", "mesh_force", "force", exclude=("hertz",))
    hertz = ts.find("hertz_force", "hertzian_force")
    if not force and not hertz:
        sec.note("timeseries.csv has no force column: the mesh-force figure is left out.")
        return
    period = 1 / scene.f_mesh_hz if scene.f_mesh_hz else None
    main = force or hertz
    zoom = steady_window(t, scene, 6, ts[main])
    tz = t[zoom]
    contact = ts.find("contact")
    fig, axes = plt.subplots(1, 2, figsize=(10, 3.6), gridspec_kw={"width_ratios": [2, 1]})
    ax = axes[0]
    if contact and ts.numeric(contact):
        shade_contact(ax, tz, ts[contact][zoom])
    steady = steady_part(t, scene)
    ref = reference_of(ts[main][steady])
    scale, unit = force_scale(ref)
    ax.plot(tz, (ts[main][zoom] - ref) / scale, lw=1.2, label="mesh force F")
    if hertz and hertz != main:
        ax.plot(tz, (ts[hertz][zoom] - ref) / scale, lw=1.0, ls="--", label="Hertzian force")
    if scene.static_force_n:
        ax.axhline((scene.static_force_n - ref) / scale, color="#2e8b57", lw=1, ls="--",
                   label="static force F$_0$")
    finish_zoom(ax, tz, period)
    ax.set_ylabel(shifted_label("mesh force", unit, ref))
    title_and_legend(ax, "Mesh (Hertzian) force, last %s" % ("mesh periods" if period else
                                                               "cycles"), ncol=2)
    axes[1].set_xlabel(shifted_label("mesh force", unit, ref))
    force_histogram(axes[1], (ts[main][steady] - ref) / scale, scene.static_force_n, ref, scale)
    extra = ""
    if scene.static_force_n:
        extra = (" The steady mean force is %.5g N against F<sub>0</sub> = %.5g N "
                 "(a periodic steady state has mean F = F<sub>0</sub>)."
                 % (np.nanmean(ts[main][steady]), scene.static_force_n))
    publish(sec, "mesh_force.png", fig,
            "Force through the mesh, equal to the force of the Hertzian layer "
            "k<sub>h</sub>G(δ) + μH(δ)δ̇; zero while the teeth are apart." + extra)


def motion_of_section(scene, xs, n_last):
    """(kind of motion, where it comes from): period-k from summary.json, else the number of
    distinct points of the last sections."""
    period_k = scene.flat_summary.get("period_multiplicity")
    if is_number(period_k):
        return ("aperiodic" if period_k == 0 else "period-%d" % period_k), "summary.json"
    return "%d distinct points" % distinct_points(xs[-n_last:]), "last %d sections" % n_last


def section_spans(scene, ts, xs, vs):
    """The smallest spans of x and ẋ a Poincaré map is drawn with: a tenth of the steady orbit
    (the phase portrait), so that the scatter of a period-1 point at the integrator's tolerance
    (1e-7 µm) shows as the one point it is rather than as a cloud blown up to fill the axes."""
    x_span, v_span = 1e-4 * max(1.0, float(np.nanmax(np.abs(xs)))), 0.0
    if ts is not None and ts.find(*TIME):
        steady = steady_part(time_column(ts), scene)
        xc = ts.find(*DTE, exclude=NOT_A_RATE)
        vc = ts.find(*RATE)
        if xc:
            x_span = max(x_span, 0.1 * float(np.ptp(ts[xc][steady])))
        if vc:
            v_span = 0.1 * float(np.ptp(ts[vc][steady]))
    if vs is not None and not v_span > 0:
        v_span = 1e-4 * max(1e-12, float(np.nanmax(np.abs(vs))))
    return x_span, v_span


def poincare_scatter(fig, ax, xs, vs, n_last, limits, b_c, xlabel, vlabel):
    """The sections in the (x, ẋ) plane, coloured by number, the last ones circled."""
    xlim, vlim = limits
    sc = ax.scatter(xs, vs, c=np.arange(len(xs)), cmap="viridis", s=12, zorder=3,
                    label="all sections")
    ax.scatter(xs[-n_last:], vs[-n_last:], s=70, facecolors="none",
               edgecolors="#c0392b", lw=1.4, zorder=4, label="last %d sections" % n_last)
    fig.colorbar(sc, ax=ax, label="section number (mesh periods)")
    if xlim:
        ax.set_xlim(*xlim)
    if vlim:
        ax.set_ylim(*vlim)
    mark_backlash(ax, b_c, horizontal=False, near_data=True)
    ax.set_xlabel(xlabel)
    ax.set_ylabel(vlabel)


def return_map(ax, xs, xlim, xunit, xref):
    """x_{k+1} against x_k, for a section without the rate."""
    ax.scatter(xs[:-1], xs[1:], c=np.arange(len(xs) - 1), cmap="viridis", s=12, zorder=3)
    if xlim:
        ax.set_xlim(*xlim)
        ax.set_ylim(*xlim)
    ax.set_xlabel(shifted_label("x$_k$", xunit, xref))
    ax.set_ylabel(shifted_label("x$_{k+1}$", xunit, xref))


def poincare_map(sec, art, scene, ts):
    section = poincare_points(art, scene, ts)
    if section is None:
        sec.note("No poincare.csv (with a DTE column) in this run, and no time series "
                 "to sample one from: the Poincaré map is left out.")
        return
    _, xs, vs, xcol, vcol, source = section
    ok = np.isfinite(xs) & (np.isfinite(vs) if vs is not None else True)
    xs, vs = xs[ok], (vs[ok] if vs is not None else None)
    xunit = unit_of(xcol) if xcol else None
    n_last = min(16, len(xs))
    motion, where = motion_of_section(scene, xs, n_last)
    x_span, v_span = section_spans(scene, ts, xs, vs)
    xlim = span_limits(xs, x_span)
    vlim = span_limits(vs, v_span) if vs is not None else None
    xref = reference_of(np.array(xlim) if xlim else xs)
    xs = xs - xref
    shown_xlim = (xlim[0] - xref, xlim[1] - xref) if xlim else None
    fig, ax = plt.subplots(figsize=(7.4, 4.8))
    if vs is not None:
        poincare_scatter(fig, ax, xs, vs, n_last, (shown_xlim, vlim),
                         shifted(scene.b_c_um, xref),
                         shifted_label("DTE x at the section", xunit, xref),
                         label("DTE rate ẋ at the section", vcol))
    else:
        return_map(ax, xs, shown_xlim, xunit, xref)
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
    publish(sec, "poincare.png", fig,
            "Poincaré section: the state sampled once per mesh period (%s). One point is "
            "period-1 motion, k points period-k, a closed curve quasi-periodic motion, and "
            "a scattered cloud with structure chaos. Colour runs from the first to the "
            "last section, so a transient shows as a trail into the final points (circled)."
            "%s" % (html.escape(source), spread))


# The most samples of the steady state the phase portrait draws (1 000 mesh periods of 100).
PHASE_PORTRAIT_SAMPLES = 100_000


def phase_portrait(sec, art, scene, ts):
    if ts is None:
        return
    t = time_column(ts)
    x = ts.find(*DTE, exclude=NOT_A_RATE)
    v = ts.find(*RATE)
    if not (x and v):
        sec.note("timeseries.csv lacks DTE or its rate: the phase portrait is left out.")
        return
    steady = steady_part(t, scene)
    # The last PHASE_PORTRAIT_SAMPLES of the steady state: a longer trajectory only retraces the
    # orbit, while the memory and time of drawing it grow with its length (Agg, 1.5 GB for a
    # million samples).
    drawn = np.flatnonzero(steady)[-PHASE_PORTRAIT_SAMPLES:]
    fig, ax = plt.subplots(figsize=(7.4, 4.8))
    xref = reference_of(ts[x][steady])
    xx, vv = ts[x][drawn] - xref, ts[v][drawn]
    ax.plot(xx, vv, lw=0.6, color=COLORS[0], label="steady-state trajectory")
    section = poincare_points(art, scene, ts)
    if section is not None and section[2] is not None:
        tk, xk, vk = section[0], section[1], section[2]
        keep = tk >= t[drawn][0] if tk is not None else slice(-16, None)
        ax.plot(xk[keep] - xref, vk[keep], "o", ms=5, color=COLORS[1],
                label="Poincaré points", zorder=4)
    mark_backlash(ax, shifted(scene.b_c_um, xref), horizontal=False, near_data=True)
    ax.set_xlabel(shifted_label("DTE x", unit_of(x), xref))
    ax.set_ylabel(label("DTE rate ẋ", v))
    title_and_legend(ax, "Phase portrait, steady state", ncol=3)
    publish(sec, "phase_portrait.png", fig,
            "Phase portrait (x, ẋ) after the transient. Between the dashed lines "
            "(|x| &lt; b<sub>c</sub>) the teeth fly free and the trajectory is straight in "
            "time; a period-k orbit closes after k loops." + drawn_part(t, steady, drawn, scene))


def drawn_part(t, steady, drawn, scene):
    """What the caption of the phase portrait says when it draws only the last samples of the
    steady state."""
    n_steady = int(np.count_nonzero(steady))
    if len(drawn) == n_steady:
        return ""
    periods = ("%.0f mesh periods, " % ((t[drawn][-1] - t[drawn][0]) * scene.f_mesh_hz)
               if scene.f_mesh_hz else "")
    return (" Drawn: the last %d samples of the steady state (%sof %d)."
            % (len(drawn), periods, n_steady))


def loop_data(sec, art, scene, ts):
    """(penetration, force, loops, kind, penetration column, source) of the force–penetration
    loops: force_penetration.csv, else the last mesh periods of the time series; None with a
    note when neither has the columns."""
    fp = art.get("force_penetration.csv")
    if fp is not None:
        data, source = fp, "force_penetration.csv"
    elif ts is not None:
        data, source = ts, "timeseries.csv, last mesh periods"
    else:
        sec.note("No force_penetration.csv in this run: the loops are left out.")
        return None
    pen = data.find("penetration", "delta", "re:penetration")
    force = data.find("mesh_force", "hertz_force", "force", "re:force")
    if not (pen and force and data.numeric(pen) and data.numeric(force)):
        sec.note("%s lacks a penetration or force column: the loops are left out."
                 % html.escape(source))
        return None
    tcol = data.find("time_s", "time")
    t = data[tcol] if tcol and data.numeric(tcol) else None
    window = np.ones(len(fp), dtype=bool) if fp is not None else \
        steady_window(t, scene, 4, ts[force])
    P, F = data[pen][window], data[force][window]
    t = t[window] if t is not None else None
    group = data.find("impact", "loop", "cycle", "event")
    if group and data.numeric(group):
        ids = data[group][window]
        loops = [np.flatnonzero(ids == g) for g in unique_in_order(ids[np.isfinite(ids)])]
        kind = "impact"
    else:
        loops, kind = loop_segments(t, P, scene.f_mesh_hz)
    return P, F, loops, kind, pen, source


def draw_loops(ax, P, F, loops, kind, shift):
    """The last twelve loops, light to dark blue: the last loop, drawn on top, is the darkest, so
    a steady state whose loops coincide shows as one dark, readable curve."""
    pref, fref, fscale = shift
    if not loops:
        ax.plot(P - pref, (F - fref) / fscale, lw=1.0)
        return
    shown = loops[-12:]
    cmap = plt.get_cmap("Blues")
    first = len(loops) - len(shown) + 1
    for j, idx in enumerate(shown):
        closed = np.append(idx, idx[0])
        ax.plot(P[closed] - pref, (F[closed] - fref) / fscale, lw=1.2,
                color=cmap(0.35 + 0.65 * j / max(1, len(shown) - 1)),
                label=("%s %d" % (kind, first + j)) if len(shown) <= 6 else None)
    if len(shown) > 6:
        ax.text(0.02, 0.96, "%ss %d–%d of the window, later ones darker"
                % (kind, first, len(loops)), transform=ax.transAxes, ha="left",
                va="top", fontsize=8.5)


def force_penetration_loops(sec, art, scene, ts):
    data = loop_data(sec, art, scene, ts)
    if data is None:
        return
    P, F, loops, kind, pen, source = data
    fig, ax = plt.subplots(figsize=(7.4, 4.8))
    energies = [abs(polygon_area(P[i] * 1e-6, F[i])) for i in loops
                if len(i) > 2 and unit_of(pen) == "µm"]
    pref = reference_of(P)
    fref = reference_of(F)
    fscale, funit = force_scale(fref)
    draw_loops(ax, P, F, loops, kind, (pref, fref, fscale))
    ax.set_xlabel(shifted_label("Hertzian penetration δ", unit_of(pen), pref))
    ax.set_ylabel(shifted_label("mesh force F", funit, fref))
    title_and_legend(ax, "Force–penetration loops", ncol=3)
    energy_text = ""
    if energies:
        energy_text = (" Mean enclosed area ∮F dδ over the last %d %ss: %.4g mJ."
                       % (len(energies), kind, 1e3 * np.mean(energies)))
        ax.text(0.98, 0.04, "mean loop area %.3g mJ" % (1e3 * np.mean(energies)),
                transform=ax.transAxes, ha="right", va="bottom")
    reported = scene.flat_summary.get("mean_loop_work_per_impact_J")
    if is_number(reported):
        energy_text += (" summary.json gives a mean loop work ∮F dδ of %.4g mJ per impact."
                        % (1e3 * reported))
    publish(sec, "force_penetration.png", fig,
            "Mesh force against Hertzian penetration (%s), one colour per %s, later ones "
            "darker. Loading runs along the upper branch and unloading along the lower "
            "one when the contact damping dominates. The loop integral ∮F dδ is the energy the "
            "contact damping dissipates in that %s when k<sub>h</sub> is constant under load; "
            "when k<sub>h</sub>(t) varies while the teeth are loaded it also holds the work of "
            "the stiffness variation, and unloading can run above loading (a negative ∮F dδ). "
            "An upward-bending branch is the hardening of "
            "F = k<sub>h</sub>δ<sup>n</sup> with n &gt; 1.%s"
            % (html.escape(source), kind, kind, energy_text))


def spectrum_data(sec, art, scene, ts):
    """(frequencies, amplitudes, source, amplitude label): spectrum.csv, else the FFT of the
    steady DTE of the time series; None with a note when there is neither."""
    sp = art.get("spectrum.csv")
    if sp is not None:
        fcol = sp.find("frequency", "freq", "f_hz")
        acol = sp.find("amplitude", "amp", "magnitude", "re:amplitude|magnitude|psd")
        if not (fcol and acol):
            sec.note("spectrum.csv lacks a frequency or amplitude column.")
            return None
        return sp[fcol], sp[acol], "spectrum.csv", label("amplitude", acol)
    if ts is None:
        sec.note("No spectrum.csv in this run: the spectrum is left out.")
        return None
    t = time_column(ts)
    x = ts.find(*DTE, exclude=NOT_A_RATE)
    steady = steady_part(t, scene)
    tt, xx = t[steady], ts[x][steady]
    if len(tt) < 16:
        sec.note("No spectrum.csv and too short a time series for one.")
        return None
    f, a = amplitude_spectrum(tt, xx)
    return (f, a, "FFT of the steady part of timeseries.csv, computed here",
            label("amplitude of DTE", x))


def mark_mesh_harmonics(ax, f_mesh, fmax):
    """Dashed lines at f_m and its harmonics (up to 8), dotted at f_m/2; x up to 8.5 f_m."""
    ax.grid(False, axis="x")
    for k in range(1, int(fmax / f_mesh) + 1):
        if k > 8:
            break
        ax.axvline(k * f_mesh, color="#c0392b", lw=0.7, ls="--", zorder=0)
        ax.text(k * f_mesh, 1.0, "%df$_m$" % k if k > 1 else "f$_m$",
                transform=ax.get_xaxis_transform(), ha="center", va="bottom",
                fontsize=8, color="#c0392b")
    ax.axvline(0.5 * f_mesh, color="#8e44ad", lw=0.6, ls=":", zorder=0)
    ax.text(0.5 * f_mesh, 1.0, "f$_m$/2", transform=ax.get_xaxis_transform(),
            ha="center", va="bottom", fontsize=8, color="#8e44ad")
    ax.set_xlim(0, min(fmax, 8.5 * f_mesh))


def spectrum(sec, art, scene, ts):
    data = spectrum_data(sec, art, scene, ts)
    if data is None:
        return
    f, a, source, a_label = data
    ok = np.isfinite(a) & (f > 0) & (a > 0)
    fig, ax = plt.subplots(figsize=(10, 3.8))
    ax.semilogy(f[ok], a[ok], lw=1.0)
    if scene.f_mesh_hz and ok.any():
        mark_mesh_harmonics(ax, scene.f_mesh_hz, f[ok].max())
    ax.set_xlabel(label("frequency", unit="Hz"))
    ax.set_ylabel(a_label)
    ax.set_title("Spectrum of the steady-state DTE", pad=14)
    publish(sec, "spectrum.png", fig,
            "Amplitude spectrum of the steady dynamic transmission error (%s), log scale. "
            "Dashed lines mark the mesh frequency f<sub>m</sub> and its harmonics; a line "
            "at f<sub>m</sub>/2 and its odd multiples means period-2 motion, and a broad "
            "floor between the harmonics means aperiodic motion." % html.escape(source))


# --------------------------------------------------------------------------------------------
# Sweep
# --------------------------------------------------------------------------------------------

def sweep_direction(axes, sw, columns, m, d, i):
    """The curves of one sweep direction (rows m): RMS with its min…max band on top, dynamic
    factor and contact-loss fraction below."""
    speed, rms, lo, hi, df, loss = columns
    order = np.argsort(sw[speed][m])
    sp = sw[speed][m][order]
    color = COLORS[i % len(COLORS)]
    mk = {"up": "^", "down": "v"}.get(str(d).lower(), "o")
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


def speed_and(sec, table, name, what, *patterns):
    """The speed column and the column of `patterns` of `table`, or None after a note that the
    file `name` lacks them."""
    speed, column = table.find("speed_rpm", "speed"), table.find(*patterns)
    if not (speed and column):
        sec.note("%s lacks speed or %s columns." % (name, what))
        return None
    return speed, column


def sweep_rms(sec, scene, sw):
    columns = speed_and(sec, sw, "sweep.csv", "RMS", "rms_dte", "rms")
    if not columns:
        return
    speed, rms = columns
    direction = sw.find("direction")
    dirs = sw[direction] if direction else np.array(["sweep"] * len(sw), dtype=object)
    columns = (speed, rms, sw.find("min_dte"), sw.find("max_dte"), sw.find("dynamic_factor"),
               sw.find("contact_loss"))
    fig, axes = plt.subplots(2, 1, figsize=(10, 6.4), sharex=True)
    for i, d in enumerate(unique_in_order(dirs)):
        sweep_direction(axes, sw, columns, dirs == d, d, i)
    mark_backlash(axes[0], scene.b_c_um, near_data=True)
    axes[0].set_ylabel(label("DTE", rms))
    title_and_legend(axes[0], "RMS and range of the DTE", ncol=3)
    axes[1].set_ylabel("dynamic factor, loss fraction (–)")
    axes[1].set_xlabel(label("pinion speed", speed))
    title_and_legend(axes[1], "Dynamic factor F$_{max}$/F$_0$, contact-loss fraction", ncol=2)
    publish(sec, "sweep_rms.png", fig,
            "Frequency response from the speed sweep: RMS of the DTE with its min…max band "
            "(top), dynamic factor and contact-loss fraction (bottom), for the up and down "
            "sweeps. Where the two directions disagree the response has two stable "
            "branches (a jump, typical of the softening backlash nonlinearity).")


# --------------------------------------------------------------------------------------------
# Periodic orbits by shooting and continuation
# --------------------------------------------------------------------------------------------

BIFURCATION_MARKERS = {"fold": ("s", "fold"), "period-doubling": ("D", "period doubling"),
                       "neimark-sacker": ("o", "Neimark–Sacker"),
                       "corner-turn": ("^", "corner turn (non-smooth)")}


def branch_runs(stable):
    """Index ranges [a, b] of equal stability along a branch; neighbouring runs share their
    boundary point so that the curve stays connected."""
    runs, a = [], 0
    for i in range(1, len(stable) + 1):
        if i == len(stable) or stable[i] != stable[a]:
            runs.append((a, min(i, len(stable) - 1), bool(stable[a])))
            a = i
    return runs


def response_curves(sec, scene, resp, sw=None, label_of_run=None, compared=()):
    """The frequency (or torque, or damping) response of the periodic orbits as engineers read
    it: the dynamic factor F_max/F_0 and the fluctuation of the DTE (peak-to-peak over the
    orbit) per branch, stable solid and unstable dashed, bifurcations marked; below, the largest
    Floquet multiplier modulus. `compared` holds (label, table) of other runs' response.csv
    (`hertzgear report --compare`, e.g. the other mesh force law), drawn on the same axes, one
    colour per run. Time-marched sweep points, when there are any, as dots."""
    runs = [(label_of_run, resp)] + list(compared)
    x_col = resp.names[0]
    for name, table in runs:
        needed = ("dynamic_factor", "min_dte", "max_dte", "branch", "stable", "max_multiplier")
        missing = [c for c in needed if not table.find(c)]
        if missing or table.names[0] != x_col:
            sec.note("response.csv%s lacks the columns %s or is over another parameter (%s)."
                     % (" of " + name if name else "", ", ".join(missing) or "-",
                        table.names[0]))
            return
    fig, axes = plt.subplots(3, 1, figsize=(10, 8.6), sharex=True,
                             gridspec_kw={"height_ratios": [2.0, 1.5, 1]})
    labelled = set()
    many = len(runs) > 1
    for r, (name, t) in enumerate(runs):
        x = t[x_col]
        df, mu = t[t.find("dynamic_factor")], t[t.find("max_multiplier")]
        fluct = t[t.find("max_dte")] - t[t.find("min_dte")]
        branch, stable = t[t.find("branch")], t[t.find("stable")]
        bif, period = t.find("bifurcation"), t.find("period")
        for i, b in enumerate(unique_in_order(branch)):
            m = np.where(branch == b)[0]
            color = COLORS[(r if many else i) % len(COLORS)]
            k = int(t[period][m[0]]) if period else 1
            base = name if many else "branch %d (period %d)" % (int(b), k)
            for a, e, st in branch_runs(stable[m] > 0.5):
                idx = m[a:e + 1]
                text = base + (", stable" if st else ", unstable")
                style = dict(ls="-" if st else "--", color=color, lw=1.6 if st else 1.1)
                axes[0].plot(x[idx], df[idx], label=None if text in labelled else text, **style)
                labelled.add(text)
                axes[1].plot(x[idx], fluct[idx], **style)
                axes[2].plot(x[idx], mu[idx], ls=style["ls"], color=color, lw=1.2)
        if bif and t[bif].dtype == object:
            for kind, (marker, text) in BIFURCATION_MARKERS.items():
                m = t[bif] == kind
                if m.any():
                    for ax, y in ((axes[0], df), (axes[1], fluct), (axes[2], mu)):
                        ax.plot(x[m], y[m], marker, ms=7 if ax is axes[0] else 6, mfc="none",
                                mec="k", mew=1.2, ls="none",
                                label=text if ax is axes[0] and text not in labelled else None)
                    labelled.add(text)
    if sw is not None and x_col.startswith("speed"):
        sp, sdf = sw.find("speed_rpm", "speed"), sw.find("dynamic_factor")
        lo, hi = sw.find("min_dte"), sw.find("max_dte")
        if sp and sdf:
            axes[0].plot(sw[sp], sw[sdf], ".", color="#777777", ms=4,
                         label="time marching (sweep.csv)")
        if sp and lo and hi:
            axes[1].plot(sw[sp], sw[hi] - sw[lo], ".", color="#777777", ms=4)
    axes[0].axhline(1.0, color="k", lw=0.6, ls=":")
    axes[2].axhline(1.0, color="k", lw=0.8, ls=":")
    axes[0].set_ylabel("dynamic factor F$_{max}$/F$_0$ (–)")
    title_and_legend(axes[0], "Periodic orbits: dynamic factor", ncol=2 if many else 3)
    axes[1].set_ylabel("DTE peak-to-peak (µm)")
    axes[1].set_title("Fluctuation of the DTE over the orbit (max − min)", loc="left")
    axes[2].set_ylabel("largest |μ| (–)")
    axes[2].set_xlabel(label(x_col.replace("_", " ").split(" ")[0], x_col))
    axes[2].set_title("Largest Floquet multiplier modulus (stable below 1)", loc="left")
    runs_text = (" Curves of %d runs, one colour each: %s." % (len(runs), ", ".join(
        "%s (%s)" % (n, "this run" if i == 0 else "compared") for i, (n, _) in enumerate(runs)))
        if many else "")
    publish(sec, "response.png", fig,
            "Periodic orbits found by shooting and followed by pseudo-arclength continuation "
            "(response.csv): the dynamic factor (largest mesh force over the static load) and "
            "the peak-to-peak fluctuation of the DTE over the orbit, solid where the orbit is "
            "stable (every Floquet multiplier inside the unit circle), dashed where it is "
            "unstable; squares mark folds (a multiplier through +1: the jumps of a sweep), "
            "diamonds period doublings (−1), circles Neimark–Sacker points (a complex pair), "
            "triangles corner turns (the branch turns back at a grazing contact, where the "
            "period map has a kink and no multiplier is 1). "
            "Below: the largest multiplier modulus. Grey dots, when present, are the "
            "time-marched sweep points (sweep.csv), which only ever land on stable branches."
            + runs_text)


def bifurcation(sec, scene, bif):
    columns = speed_and(sec, bif, "bifurcation.csv", "Poincaré DTE", "poincare_dte", "dte")
    if not columns:
        return
    speed, x = columns
    fig, ax = plt.subplots(figsize=(10, 4.2))
    ref = reference_of(bif[x])
    ax.plot(bif[speed], bif[x] - ref, ".", ms=2.5, color="#222222", alpha=0.7)
    mark_backlash(ax, shifted(scene.b_c_um, ref), near_data=True)
    ax.set_xlabel(label("pinion speed", speed))
    ax.set_ylabel(shifted_label("DTE at the Poincaré section", unit_of(x), ref))
    title_and_legend(ax, "Bifurcation diagram", ncol=1)
    publish(sec, "bifurcation.png", fig,
            "Bifurcation diagram: the Poincaré points of the steady state at each speed. "
            "One point per speed is period-1 motion, two period-2 (a period-doubling "
            "bifurcation where the branch splits), a vertical smear aperiodic or chaotic "
            "motion.")


# --------------------------------------------------------------------------------------------
# Accuracy
# --------------------------------------------------------------------------------------------

def error_panel(ax, table, time, err, groups):
    """One error column against wall time, log–log, one line per method."""
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


def work_precision(sec, table, rel, index):
    time = table.find("wall_time", "re:time_s$", "re:time", "re:seconds")
    errors = [c for c in table.names if re.search("err", c.lower()) and table.numeric(c)]
    if not time or not table.numeric(time) or not errors:
        sec.note("%s has no wall-time and error columns to plot." % html.escape(rel))
        return
    group = next((c for c in table.names if not table.numeric(c)), None)
    groups = table[group] if group else np.array(["all"] * len(table), dtype=object)
    errors = errors[:3]
    fig, axes = plt.subplots(1, len(errors), figsize=(4.6 * len(errors) + 0.8, 3.9),
                             squeeze=False)
    for ax, err in zip(axes[0], errors):
        error_panel(ax, table, time, err, groups)
    publish(sec, "accuracy_%d.png" % (index + 1), fig,
            "Work–precision diagram from %s: error against wall time, log–log, each method's "
            "points joined in the order of its tolerance (or step) ladder. Lower left "
            "is better; at a given error, the leftmost method is the cheapest."
            % html.escape(rel))
