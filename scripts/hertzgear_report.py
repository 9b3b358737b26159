#!/usr/bin/env python3
"""hertzgear report: figures and one HTML page from the artifacts of a hertzgear run.

    hertzgear_report.py DIR [--out REPORT_DIR]

Reads whatever artifacts DIR holds, flat or in the sub-folders stiffness/, dynamics/, sweep/ and
accuracy/ (stiffness.csv/json, stiffness_map.csv, contact_pattern.csv, timeseries.csv,
poincare.csv, spectrum.csv, force_penetration.csv, summary.json, sweep.csv, bifurcation.csv,
accuracy tables, used_parameters.prm, run.json) and
writes PNG figures and index.html into DIR/report/ (or REPORT_DIR). A figure whose input is absent
is left out with a note on the page. Every file is written atomically (temporary file in the same
folder, then os.replace), so an interrupted report leaves no half-written file behind.

Needs only Python 3, numpy and matplotlib (Debian: python3-numpy, python3-matplotlib); no network.
Exit codes: 0 report written, 2 DIR missing or holding no artifact, 1 anything else.
"""

import argparse
import os
import shutil
import sys

HERE = os.path.dirname(os.path.realpath(__file__))


def load_modules():
    """The report modules, from hertzgear_report_lib/ beside this script (in the source tree and
    when installed); exit 1 with what to install when numpy, matplotlib or the modules are
    missing."""
    if HERE not in sys.path:
        sys.path.insert(0, HERE)
    try:
        from hertzgear_report_lib import artifacts, report
    except ImportError as missing:
        if (missing.name or "").startswith("hertzgear_report_lib"):
            sys.stderr.write("hertzgear report: error: %s; the report modules belong in %s\n"
                             % (missing, os.path.join(HERE, "hertzgear_report_lib")))
        else:
            sys.stderr.write(
                "hertzgear report: error: %s; this interpreter (%s) needs numpy and matplotlib "
                "(Debian: apt-get install python3-numpy python3-matplotlib), or point "
                "HERTZGEAR_PYTHON at one that has them\n" % (missing, sys.executable))
        sys.exit(1)
    return artifacts, report


artifacts, report = load_modules()


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
        return artifacts.EXIT_BAD_INPUT
    out_dir = os.path.abspath(args.out or os.path.join(run_dir, "report"))
    art = artifacts.Artifacts(run_dir, out_dir)
    if not art.any():
        sys.stderr.write(
            "hertzgear report: error: %s holds no hertzgear artifact (looked for %s and accuracy "
            "tables, in the folder and in its sub-folders %s)\n"
            % (run_dir, ", ".join(artifacts.ARTIFACT_NAMES),
               ", ".join(f + "/" for f in artifacts.STAGE_FOLDERS if f)))
        return artifacts.EXIT_BAD_INPUT
    for warning in art.warnings:
        sys.stderr.write("hertzgear report: warning: %s\n" % warning)
    figure_files = write_report_folder(art, out_dir)
    index = os.path.join(out_dir, "index.html")
    sys.stderr.write("hertzgear report: %d figures, %s\n" % (len(figure_files), index))
    return 0


def write_report_folder(art, out_dir):
    """The report is drawn into a hidden folder beside out_dir and swapped in whole when done, so
    an interrupted report leaves the older report or none, never a page mixing the two."""
    parent, name = os.path.split(out_dir)
    os.makedirs(parent, exist_ok=True)
    marker = "." + name + artifacts.PARTIAL_MARKER
    for leftover in os.listdir(parent):
        if leftover.startswith(marker):
            shutil.rmtree(os.path.join(parent, leftover), ignore_errors=True)
    partial = os.path.join(parent, "%snew-%d" % (marker, os.getpid()))
    figure_files, _ = report.write_report(art, partial)
    old = os.path.join(parent, "%sold-%d" % (marker, os.getpid()))
    if os.path.isdir(out_dir):
        os.rename(out_dir, old)
    os.rename(partial, out_dir)
    shutil.rmtree(old, ignore_errors=True)
    return figure_files


if __name__ == "__main__":
    try:
        sys.exit(main())
    except KeyboardInterrupt:
        sys.exit(130)
