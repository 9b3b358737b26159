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

Every artifact is read and checked before the first write: a table or JSON file that cannot be
parsed, a table without a column its figures need, or a report folder that is a file or cannot be
written ends the report with one line naming the file and exit code 2. Tables are read with
bounded memory (at most the last million rows of a time series are held, see
hertzgear_report_lib/artifacts.py).

Needs only Python 3, numpy and matplotlib (Debian: python3-numpy, python3-matplotlib); no network.
Exit codes: 0 report written; 2 bad input (DIR missing or holding no artifact, an artifact that
cannot be parsed, a report folder that cannot be written); 1 anything else, in one line
"report script failed: ...", with the traceback when the environment variable HERTZGEAR_DEBUG is
set.
"""

import argparse
import errno
import os
import shutil
import sys
import traceback

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
    parser.add_argument("--compare", action="append", default=[], metavar="OTHER_RUN_DIR",
                        help="another run's folder whose periodic orbits (response.csv) are drawn "
                             "on the response figure beside this run's, e.g. the other mesh force "
                             "law (repeatable)")
    args = parser.parse_args(argv)
    run_dir = args.run_dir
    if not os.path.isdir(run_dir):
        sys.stderr.write("hertzgear report: error: the run directory %s does not exist or is not "
                         "a directory\n" % run_dir)
        return artifacts.EXIT_BAD_INPUT
    out_dir = os.path.abspath(args.out or os.path.join(run_dir, "report"))
    check_report_folder(out_dir)
    art = artifacts.Artifacts(run_dir, out_dir)
    if not art.any():
        sys.stderr.write(
            "hertzgear report: error: %s holds no hertzgear artifact (looked for %s and accuracy "
            "tables, in the folder and in its sub-folders %s)\n"
            % (run_dir, ", ".join(artifacts.ARTIFACT_NAMES),
               ", ".join(f + "/" for f in artifacts.STAGE_FOLDERS if f)))
        return artifacts.EXIT_BAD_INPUT
    art.check()  # every artifact parsed before the first write
    art.compared = []
    for other in args.compare:
        if not os.path.isdir(other):
            raise artifacts.BadInput("--compare %s: the run directory does not exist or is not a "
                                     "directory" % other)
        c = artifacts.Artifacts(other, out_dir)
        if not c.has("response.csv") or not art.has("response.csv"):
            raise artifacts.BadInput(
                "--compare %s: the response figure compares periodic orbits, and %s holds no "
                "response.csv (run `hertzgear response` into it)"
                % (other, other if not c.has("response.csv") else run_dir))
        c.check()
        if c.get("response.csv") is None:
            raise artifacts.BadInput("--compare %s: its response.csv holds no orbits" % other)
        art.compared.append(c)
    for warning in art.warnings:
        sys.stderr.write("hertzgear report: warning: %s\n" % warning)
    figure_files = write_report_folder(art, out_dir)
    index = os.path.join(out_dir, "index.html")
    sys.stderr.write("hertzgear report: %d figures, %s\n" % (len(figure_files), index))
    return 0


def check_report_folder(out_dir):
    """BadInput unless out_dir is a folder or can be made, in a folder this process can write
    into (the report is drawn beside it and renamed into place)."""
    if os.path.lexists(out_dir) and not os.path.isdir(out_dir):
        raise artifacts.BadInput("the report folder %s is a file, not a folder: remove it or "
                                 "give another folder with --out" % out_dir)
    parent = os.path.dirname(out_dir)
    ancestor = parent
    while not os.path.lexists(ancestor):
        ancestor = os.path.dirname(ancestor)
    if not os.path.isdir(ancestor):
        raise artifacts.BadInput("the report folder %s cannot be made: %s is a file, not a "
                                 "folder" % (out_dir, ancestor))
    if not os.access(ancestor, os.W_OK | os.X_OK):
        raise artifacts.BadInput("the report folder %s cannot be written: no write permission "
                                 "in %s" % (out_dir, ancestor))


def write_report_folder(art, out_dir):
    """The report is drawn into a hidden folder beside out_dir and swapped in whole when done, so
    an interrupted or failed report leaves the older report or none, never a page mixing the
    two."""
    parent, name = os.path.split(out_dir)
    os.makedirs(parent, exist_ok=True)
    marker = "." + name + artifacts.PARTIAL_MARKER
    for leftover in os.listdir(parent):
        if leftover.startswith(marker):
            shutil.rmtree(os.path.join(parent, leftover), ignore_errors=True)
    partial = os.path.join(parent, "%snew-%d" % (marker, os.getpid()))
    old = os.path.join(parent, "%sold-%d" % (marker, os.getpid()))
    try:
        figure_files, _ = report.write_report(art, partial)
        if os.path.isdir(out_dir):
            os.rename(out_dir, old)
        try:
            os.rename(partial, out_dir)
        except BaseException:
            if os.path.isdir(old):  # the older report back in its place
                os.rename(old, out_dir)
            raise
    except BaseException:
        shutil.rmtree(partial, ignore_errors=True)
        raise
    shutil.rmtree(old, ignore_errors=True)
    return figure_files


def run():
    """main(), its failures turned into one line on stderr and an exit code: 2 for bad input
    (and a report folder that cannot be written), 1 for anything unforeseen (its traceback
    follows when HERTZGEAR_DEBUG is set), 130 when interrupted."""
    try:
        return main()
    except KeyboardInterrupt:
        return 130
    except artifacts.BadInput as e:
        sys.stderr.write("hertzgear report: error: %s\n" % e)
        return artifacts.EXIT_BAD_INPUT
    except OSError as e:
        if e.errno in (errno.EACCES, errno.EPERM, errno.EROFS, errno.ENOTDIR, errno.EISDIR):
            sys.stderr.write("hertzgear report: error: %s%s\n"
                             % (e.strerror or e, ": " + e.filename if e.filename else ""))
            return artifacts.EXIT_BAD_INPUT
        return failed(e)
    except Exception as e:
        return failed(e)


def failed(e):
    """One line for an unforeseen failure (the traceback after it with HERTZGEAR_DEBUG set)."""
    debug = os.environ.get("HERTZGEAR_DEBUG")
    sys.stderr.write("hertzgear report: error: report script failed: %s: %s%s\n"
                     % (type(e).__name__, e, "" if debug else " (HERTZGEAR_DEBUG=1 shows where)"))
    if debug:
        traceback.print_exc()
    return 1


if __name__ == "__main__":
    sys.exit(run())
