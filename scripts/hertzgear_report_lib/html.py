"""The HTML page of the report: sections holding figures and notes, the tables (key–value, scene
effects and parameters, CSV data, stiffness.json, summary.json, the stages of a run), the cards
with the key results, and the self-contained page (inline style, figures beside it).
"""

import html
import os
import re

from .artifacts import ARTIFACT_NAMES, flatten, is_number


class Section:
    """One section of the page: an id for the navigation, a title and HTML blocks."""

    def __init__(self, page, sid, title):
        self.page = page
        self.sid = sid
        self.title = title
        self.blocks = []

    @property
    def out_dir(self):
        return self.page.out_dir

    def add(self, block):
        """An HTML block; an empty one is left out."""
        if block:
            self.blocks.append(block)

    def note(self, text):
        self.blocks.append('<p class="note">%s</p>' % text)

    def figure(self, name, caption):
        """The figure `name` (a PNG already written into the report folder) with its caption."""
        self.page.figures.append(name)
        alt = html.unescape(re.sub("<[^>]+>", "", caption))[:120]
        self.blocks.append('<figure><img src="%s" alt="%s"><figcaption>%s</figcaption></figure>'
                           % (html.escape(name), html.escape(alt), caption))


class Page:
    """The sections of the page, in order, and the figure files written for them."""

    def __init__(self, out_dir):
        self.out_dir = out_dir
        self.sections = []
        self.figures = []

    def section(self, sid, title):
        section = Section(self, sid, title)
        self.sections.append(section)
        return section


# --------------------------------------------------------------------------------------------
# Tables
# --------------------------------------------------------------------------------------------

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


def summary_table(summary):
    """The values of summary.json, lists joined."""
    rows = [(k, ", ".join(map(str, v)) if isinstance(v, list) else v)
            for k, v in flatten(summary)]
    return "<h3>Summary (summary.json)</h3>" + kv_table(rows)


def stiffness_json_table(js):
    """The values of stiffness.json without its long lists (samples), or "" when none is left."""
    rows = []
    for k, v in flatten(js):
        if isinstance(v, list):
            if len(v) > 8 or not all(isinstance(x, (int, float)) for x in v):
                continue
            v = ", ".join("%.6g" % x for x in v)
        rows.append((k, v))
    return "<h3>stiffness.json</h3>" + kv_table(rows[:80]) if rows else ""


# (heading, value of a map case): the columns of the map table.
MAP_COLUMNS = (
    ("case", lambda c: "%d" % c["case"]),
    ("torque (N m)", lambda c: "%.4g" % c["torque_Nm"]),
    ("torque (%)", lambda c: "%g" % c["torque_percent"]),
    ("crowning pinion/gear (µm)",
     lambda c: "%g/%g" % (c["pinion_crowning_um"], c["gear_crowning_um"])),
    ("misalignment f<sub>ma</sub> (µm)", lambda c: "%g" % c["mesh_misalignment_um"]),
    ("f<sub>Hβ</sub> pinion/gear (µm)",
     lambda c: "%g/%g" % (c["pinion_helix_slope_deviation_um"], c["gear_helix_slope_deviation_um"])),
    ("STE p-p (µm)", lambda c: "%.3f" % c["ste_peak_to_peak_um"]),
    ("mean k<sub>total</sub> (N/µm)", lambda c: "%.1f" % (1e-6 * c["mean_k_total_N_per_m"])),
    ("max peak pressure (MPa)", lambda c: "%.0f" % c["max_peak_pressure_MPa"]),
    ("away from the tips (MPa)", lambda c: "%.0f" % c["max_peak_pressure_off_tips_MPa"]),
    ("edge-contact positions", lambda c: "%d" % c["face_end_contact_positions"]),
    ("tip-contact positions", lambda c: "%d" % c["tip_contact_positions"]),
)


def map_cell(case, value):
    try:
        return html.escape(value(case))
    except (KeyError, TypeError, ValueError):
        return "–"


def map_table(cases, n_positions):
    """The per-case summaries of the load and design map, one row per case, or "" without."""
    if not cases:
        return ""
    head = "".join("<th>%s</th>" % h for h, _ in MAP_COLUMNS)
    rows = "".join("<tr>%s</tr>" % "".join("<td>%s</td>" % map_cell(c, v) for _, v in MAP_COLUMNS)
                   for c in cases)
    positions = "of %d per cycle" % n_positions if n_positions else "per cycle"
    return ("<details open><summary>Load and design map: %d cases</summary><p>Per case: the "
            "loaded STE peak to peak and the mean mesh stiffness over the mesh cycle, the highest "
            "Hertzian peak pressure, and at how many mesh positions (%s) the contact reaches a "
            "face end or the tip. In the case order of the map (Stiffness/Map/combination): "
            "separate lists the torque cases first (each crowning variant at every torque), then "
            "the misalignment and the helix slope cases (each crowning variant at every value, "
            "nominal torque); product lists every combination, the torque innermost.</p><table class=\"data\"><thead><tr>%s</tr></thead>"
            "<tbody>%s</tbody></table></details>" % (len(cases), positions, head, rows))


def response_tables(js):
    """The bifurcations and the branches of response.json."""
    param = html.escape(str(js.get("parameter", "parameter")))
    rows = "".join("<tr><td>%s</td><td>%s</td><td>%s</td><td>%s</td><td>%s</td></tr>" % (
        html.escape(str(b.get("type"))), fmt(b.get(js.get("parameter"))), b.get("branch"),
        fmt(b.get("rms_dte_um")), html.escape(str(b.get("multipliers"))))
        for b in js.get("bifurcations", []))
    out = ("<h3>Bifurcations (response.json)</h3><table class=\"data\"><thead><tr><th>type</th>"
           "<th>%s</th><th>branch</th><th>RMS DTE (µm)</th><th>Floquet multipliers</th></tr>"
           "</thead><tbody>%s</tbody></table>" % (param, rows or
                                                   "<tr><td colspan=5>none found</td></tr>"))
    rows = "".join("<tr><td>%s</td><td>%s</td><td>%s</td><td>%s</td><td>%s</td><td>%s</td></tr>" % (
        b.get("id"), b.get("period_multiple"), fmt(b.get("start")), b.get("points"),
        b.get("stable_points"), html.escape(str(b.get("end_reason"))))
        for b in js.get("branches", []))
    out += ("<h3>Branches</h3><table class=\"data\"><thead><tr><th>branch</th><th>period</th>"
            "<th>starts at %s</th><th>orbits</th><th>stable</th><th>ends</th></tr></thead>"
            "<tbody>%s</tbody></table>" % (param, rows))
    return out


def csv_table(table):
    head = "".join("<th>%s</th>" % html.escape(n) for n in table.names)
    rows = ""
    for i in range(len(table)):
        rows += "<tr>%s</tr>" % "".join("<td>%s</td>" % html.escape(fmt(table[n][i].item()
                                                                          if table.numeric(n)
                                                                          else table[n][i]))
                                        for n in table.names)
    return "<table class=\"data\"><thead><tr>%s</tr></thead><tbody>%s</tbody></table>" % (head, rows)


def csv_details(rel, table):
    """A CSV table folded under its path."""
    return ("<details><summary>%s (%d rows)</summary>%s</details>"
            % (html.escape(rel), len(table), csv_table(table)))


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


def parameter_table(top, rows):
    """The values of one top-level subsection of the parameter file, folded; Operating and
    Dynamics open."""
    body = "".join(
        "<tr><td>%s</td><td class=\"key\">%s</td><td class=\"val\">%s%s</td><td>%s</td></tr>"
        % (html.escape("/".join(sec.split("/")[1:])), html.escape(k), html.escape(v),
           ' <span class="changed" title="default: %s">≠ default</span>'
           % html.escape(d) if d is not None else "", html.escape(h))
        for sec, k, v, h, d in rows)
    opened = " open" if top in ("Operating", "Dynamics") else ""
    return ("<details%s><summary>%s (%d values)</summary><table class=\"prm params\">"
            "<colgroup><col class=\"c1\"><col class=\"c2\"><col class=\"c3\"><col>"
            "</colgroup><thead><tr><th>subsection</th><th>key</th><th>value</th>"
            "<th>meaning</th></tr></thead><tbody>%s</tbody></table></details>"
            % (opened, html.escape(top), len(rows), body))


def scene_tables(prm):
    """The blocks of the scene section from used_parameters.prm entries: the effects, then one
    table per top-level subsection."""
    blocks = []
    effects = [(k, v, h) for sec, k, v, h, _ in prm if sec.split("/")[0] == "Effects"]
    if effects:
        blocks.append("<h3>Effects</h3><p>The model contains only the terms of the effects "
                      "that are on.</p>" + effect_table(effects))
    by_section = {}
    for sec, k, v, h, default in prm:
        by_section.setdefault(sec.split("/")[0], []).append((sec, k, v, h, default))
    blocks += [parameter_table(top, rows) for top, rows in by_section.items() if top != "Effects"]
    return blocks


def dynamics_facts(scene):
    """The mesh frequency and half backlash the dynamics figures use, and where they come from."""
    facts = []
    if scene.f_mesh_hz:
        facts.append("mesh frequency f<sub>m</sub> = %.6g Hz (T<sub>m</sub> = %.6g s), from %s"
                     % (scene.f_mesh_hz, 1 / scene.f_mesh_hz, html.escape(scene.f_mesh_source)))
    else:
        facts.append("mesh frequency unknown (%s): no mesh-period markers"
                     % html.escape(scene.f_mesh_source))
    if scene.b_c_um is not None:
        facts.append("half backlash b<sub>c</sub> = %.6g µm, from %s"
                     % (scene.b_c_um, html.escape(scene.b_c_source)))
    else:
        facts.append("no backlash lines: %s" % html.escape(scene.b_c_source))
    return "<ul class=\"facts\">%s</ul>" % "".join("<li>%s</li>" % f for f in facts)


KEY_RESULTS = (
    ("rms_dte_um", "RMS DTE", "µm"), ("dynamic_factor", "dynamic factor", ""),
    ("mean_mesh_force_n", "mean mesh force", "N"), ("max_penetration_um", "max penetration", "µm"),
    ("contact_loss_fraction", "contact-loss fraction", ""),
    ("period_multiplicity", "period", ""),
)


def key_results(flat_summary):
    """A row of cards with the headline numbers of summary.json."""
    flat = {k.split(".")[-1].lower(): v for k, v in flat_summary.items()}
    cards = []
    for key, text, unit in KEY_RESULTS:
        v = flat.get(key)
        if not is_number(v):
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


# --------------------------------------------------------------------------------------------
# The page
# --------------------------------------------------------------------------------------------

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

TEMPLATE = """<!DOCTYPE html>
<html lang="en">
<head>
<meta charset="utf-8">
<meta name="viewport" content="width=device-width, initial-scale=1">
<title>%(title)s</title>
<style>%(css)s</style>
</head>
<body>
<header><h1>%(title)s</h1><div class="meta">%(meta)s</div></header>
<nav>%(nav)s</nav>
<main>
<p class="facts">Artifacts read: %(found)s.</p>
%(cards)s
%(stages)s
%(notes)s
%(body)s
</main>
<footer>Written by hertzgear report. Figures: matplotlib %(matplotlib)s.</footer>
</body>
</html>
"""


def run_facts(run):
    """The header line items of run.json: scene, its hash, version, git revision, finish time."""
    meta = []
    if isinstance(run, dict):
        for key, text in (("scene_file", "scene"), ("scene_hash", "scene hash"),
                          ("hertzgear_version", "version"), ("git_revision", "git"),
                          ("finished_utc", "finished")):
            if run.get(key):
                meta.append("%s <code>%s</code>" % (text, html.escape(str(run[key]))))
    return meta


def artifacts_read(art):
    found = ", ".join(html.escape(art.rel(n)) for n in ARTIFACT_NAMES if art.has(n))
    return found + "".join(", " + html.escape(os.path.relpath(p, art.run_dir))
                           for p in art.accuracy_tables)


def render_page(page, art, scene, matplotlib_version):
    """The whole HTML page: header from run.json, the key results, the stages of the run, the
    notes met while reading, and the sections."""
    run = art.get("run.json") or {}
    title = "hertzgear report"
    scene_file = run.get("scene_file") if isinstance(run, dict) else None
    if scene_file:
        title += " — " + os.path.basename(scene_file)
    meta = run_facts(run) + ["run directory <code>%s</code>" % html.escape(art.run_dir)]
    nav = "".join('<a href="#%s">%s</a>' % (s.sid, html.escape(s.title)) for s in page.sections)
    body = "".join('<section id="%s"><h2>%s</h2>%s</section>\n'
                   % (s.sid, html.escape(s.title), "\n".join(s.blocks)) for s in page.sections)
    notes = "".join('<p class="note">%s</p>' % html.escape(n) for n in art.notes)
    return TEMPLATE % {
        "title": html.escape(title), "css": CSS, "meta": " · ".join(meta), "nav": nav,
        "found": artifacts_read(art), "cards": key_results(scene.flat_summary),
        "stages": pipeline_table(run), "notes": notes, "body": body,
        "matplotlib": matplotlib_version}
