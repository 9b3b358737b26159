"""The report of a run directory: which figures and tables each section of the page gets from the
artifacts at hand (stiffness, dynamics, speed sweep, accuracy, scene), notes for what is left out,
and the page written atomically as index.html beside its figures.
"""

import html
import os
import sys
import traceback

import matplotlib

from . import figures
from .artifacts import (BadInput, LoadMap, Scene, remove_stale_temporaries, samples_table,
                        write_text_atomically)
from .html import (Page, csv_details, dynamics_facts, map_table, render_page, response_tables,
                   scene_tables,
                   stiffness_json_table, summary_table)
from .plotting import close_all, style


class Report:
    def __init__(self, art, out_dir):
        self.art = art
        self.scene = Scene(art)
        self.page = Page(out_dir)

    def attempt(self, sec, what, draw, *args):
        """draw(sec, *args); an unforeseen failure costs that figure only and is shown on the
        page and in one line on stderr (with its traceback when HERTZGEAR_DEBUG is set). Bad
        input (BadInput) ends the report."""
        try:
            draw(sec, *args)
        except BadInput:
            raise
        except Exception as e:
            close_all()
            sys.stderr.write("hertzgear report: warning: the %s could not be drawn: %s: %s\n"
                             % (what, type(e).__name__, e))
            if os.environ.get("HERTZGEAR_DEBUG"):
                traceback.print_exc()
            sec.note("The %s could not be drawn: %s" % (what, html.escape(str(e))))

    def stiffness_section(self):
        sec = self.page.section("stiffness", "Mesh stiffness over the mesh cycle")
        table = self.art.get("stiffness.csv")
        js = self.art.get("stiffness.json")
        if table is None:
            sec.note("No stiffness.csv in this run: the per-position figures (STE, load "
                     "sharing, contact) are left out (the scene may take its stiffness from a "
                     "table or closed forms).")
            if isinstance(js, dict):
                self.attempt(sec, "stiffness figure", figures.stiffness_cycle, self.scene,
                             samples_table(js), js)
                sec.add(stiffness_json_table(js))
            return
        self.attempt(sec, "stiffness figure", figures.stiffness_cycle, self.scene, table, js)
        self.attempt(sec, "STE and load sharing figure", figures.ste_load_sharing, table)
        self.attempt(sec, "contact figure", figures.contact_per_position, table)
        self.attempt(sec, "contact ellipse map", figures.contact_pressure_map, self.scene, table)
        self.attempt(sec, "load and design map", self.load_map)
        if isinstance(js, dict):
            sec.add(stiffness_json_table(js))

    def load_map(self, sec):
        """The figures and table of the load and design map, or the scene's own contact pattern
        when the run has no map."""
        lmap = LoadMap(self.art, self.scene)
        if not lmap.cases:
            sec.note("No load and design map in this run (stiffness_map.csv, written when the "
                     "scene sets Stiffness/Map): the figures over torque and misalignment are "
                     "left out.")
            if lmap.cells is None:
                sec.note("No contact_pattern.csv in this run: the contact pattern on the flank "
                         "is left out.")
            else:
                self.attempt(sec, "contact pattern", figures.contact_pattern_scene, lmap)
                self.attempt(sec, "contact lines over the cycle", figures.contact_lines_over_cycle,
                             lmap)
            return
        self.attempt(sec, "STE-against-torque figure", figures.ste_against_torque, lmap)
        self.attempt(sec, "misalignment figure", figures.pressure_centre_against_misalignment,
                     lmap)
        self.attempt(sec, "tolerance-study figure", figures.tolerance_study, lmap)
        self.attempt(sec, "contact patterns at several torques",
                     figures.contact_patterns_over_torque, lmap)
        self.attempt(sec, "contact patterns at several misalignments",
                     figures.contact_patterns_over_misalignment, lmap)
        self.attempt(sec, "contact lines over the cycle", figures.contact_lines_over_cycle, lmap)
        sec.add(map_table(lmap.cases, lmap.n_positions))

    def dynamics_section(self):
        sec = self.page.section("dynamics", "Gear-pair dynamics")
        ts = self.art.get("timeseries.csv")
        art, scene = self.art, self.scene
        sec.add(dynamics_facts(scene))
        if ts is None:
            sec.note("No timeseries.csv in this run: the time histories, mesh force and "
                     "phase portrait are left out.")
        else:
            self.attempt(sec, "DTE history", figures.dte_penetration, scene, ts)
            self.attempt(sec, "mesh force history", figures.mesh_force, scene, ts)
        self.attempt(sec, "Poincaré map", figures.poincare_map, art, scene, ts)
        self.attempt(sec, "phase portrait", figures.phase_portrait, art, scene, ts)
        self.attempt(sec, "force–penetration loops", figures.force_penetration_loops, art, scene,
                     ts)
        self.attempt(sec, "spectrum", figures.spectrum, art, scene, ts)
        summary = self.art.get("summary.json")
        if isinstance(summary, dict):
            sec.add(summary_table(summary))

    def sweep_section(self):
        sw = self.art.get("sweep.csv")
        bif = self.art.get("bifurcation.csv")
        if sw is None and bif is None:
            return
        sec = self.page.section("sweep", "Speed sweep")
        if sw is not None:
            self.attempt(sec, "sweep figure", figures.sweep_rms, self.scene, sw)
        else:
            sec.note("No sweep.csv: the RMS-versus-speed figure is left out.")
        if bif is not None:
            self.attempt(sec, "bifurcation diagram", figures.bifurcation, self.scene, bif)
        else:
            sec.note("No bifurcation.csv: the bifurcation diagram is left out.")

    def response_section(self):
        resp = self.art.get("response.csv")
        if resp is None:
            return
        sec = self.page.section("response", "Periodic orbits and their stability")
        compared = getattr(self.art, "compared", [])
        labels = [run_label(self.art)] + [run_label(c) for c in compared]
        if len(set(labels)) < len(labels):  # the same model: tell the runs by their folders
            labels = [os.path.basename(os.path.normpath(a.run_dir))
                      for a in [self.art] + list(compared)]
        self.attempt(sec, "response figure", figures.response_curves, self.scene, resp,
                     self.art.get("sweep.csv"), labels[0],
                     [(lab, c.get("response.csv")) for lab, c in zip(labels[1:], compared)])
        js = self.art.get("response.json")
        if isinstance(js, dict):
            sec.add(response_tables(js))

    def accuracy_section(self):
        if not self.art.accuracy_tables:
            return
        sec = self.page.section("accuracy", "Accuracy versus cost")
        for i, path in enumerate(self.art.accuracy_tables):
            rel = os.path.relpath(path, self.art.run_dir)
            table = (self.art.accuracy_data[path] if path in self.art.accuracy_data
                     else self.art.read(path))
            if len(table) == 0:
                sec.note("%s holds no data rows." % html.escape(rel))
                continue
            self.attempt(sec, "accuracy plot of %s" % rel, figures.work_precision, table, rel, i)
            if len(table) <= 60:
                sec.add(csv_details(rel, table))

    def scene_section(self):
        sec = self.page.section("scene", "Scene: values and effects")
        if not self.scene.prm:
            sec.note("No used_parameters.prm in this run: the scene table is left out.")
            return
        for block in scene_tables(self.scene.prm):
            sec.add(block)

    def write(self):
        """Draws every section and writes index.html; returns its path."""
        self.stiffness_section()
        self.dynamics_section()
        self.sweep_section()
        self.response_section()
        self.accuracy_section()
        self.scene_section()
        index = os.path.join(self.page.out_dir, "index.html")
        write_text_atomically(index, render_page(self.page, self.art, self.scene,
                                                 matplotlib.__version__))
        return index


def run_label(art):
    """The mesh force law of a run's response (response.json), or its folder's name."""
    js = art.get("response.json")
    if isinstance(js, dict) and js.get("mesh_force_law"):
        return str(js["mesh_force_law"])
    return os.path.basename(os.path.normpath(art.run_dir))


def write_report(art, out_dir):
    """Writes the report of the artifacts art into out_dir (created if needed); returns the
    figure files and the path of index.html."""
    os.makedirs(out_dir, exist_ok=True)
    remove_stale_temporaries(out_dir)
    style()
    report = Report(art, out_dir)
    index = report.write()
    return report.page.figures, index
