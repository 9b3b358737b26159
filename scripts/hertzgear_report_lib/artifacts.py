"""Reading the artifacts of a hertzgear run and writing the report's files.

Finds each artifact in the run directory or its stage sub-folders, parses CSV tables, JSON and the
deal.II parameter file (used_parameters.prm), picks the Fourier coefficients out of stiffness.json,
gathers the scene quantities the figures need (half backlash, mesh frequency, Hertz exponent,
static force) and the load and design map of a stiffness run (per-case summaries, their torque and
misalignment series, the loaded contact-grid cells and the flank's limits). Files are written
atomically: a temporary file in the same folder, then os.replace.
"""

import csv
import itertools
import json
import math
import os
import re
import tempfile
import time

import numpy as np

EXIT_BAD_INPUT = 2

# Sub-folders a pipeline may nest its stages in; the run directory itself comes first.
STAGE_FOLDERS = ("", "stiffness", "dynamics", "sweep", "accuracy")

ARTIFACT_NAMES = (
    "stiffness.csv", "stiffness.json", "stiffness_map.csv", "contact_pattern.csv",
    "timeseries.csv", "poincare.csv", "spectrum.csv", "force_penetration.csv", "summary.json",
    "sweep.csv", "bifurcation.csv", "response.csv", "response.json", "used_parameters.prm",
    "run.json",
)

# In the name of a temporary file, between its leading dot and final name and a random tail.
PARTIAL_MARKER = ".hg-partial-"


class BadInput(Exception):
    """Input the report cannot work with: exit code 2."""


# Column name patterns (Table.find) of the time series and the Poincaré section.
DTE = ("dte_um", "dte")
NOT_A_RATE = ("rate",)
TIME = ("time_s", "time", "t_s")
SPEED = ("speed_rpm", "speed")

# (what, name patterns, excluded names) of the numeric columns each table needs for its figures;
# a table that lacks one is bad input. The figures find their columns by the same patterns.
REQUIRED_COLUMNS = {
    "timeseries.csv": (("time", TIME, ()), ("DTE", DTE, NOT_A_RATE)),
    "poincare.csv": (("DTE", DTE + ("x_um",), NOT_A_RATE),),
    "spectrum.csv": (("frequency", ("frequency", "freq", "f_hz"), ()),
                     ("amplitude", ("amplitude", "amp", "magnitude",
                                    "re:amplitude|magnitude|psd"), ())),
    "force_penetration.csv": (("penetration", ("penetration", "delta", "re:penetration"), ()),
                              ("force", ("mesh_force", "hertz_force", "force", "re:force"), ())),
    "sweep.csv": (("speed", SPEED, ()), ("RMS", ("rms_dte", "rms"), ())),
    "bifurcation.csv": (("speed", SPEED, ()), ("Poincaré DTE", ("poincare_dte", "dte"), ())),
}


# --------------------------------------------------------------------------------------------
# Atomic output
# --------------------------------------------------------------------------------------------

def replace_atomically(path, write):
    """Writes path through write(temporary path), a temporary file in the same folder that is
    synced and then renamed to path; on any failure the temporary file is removed."""
    directory, name = os.path.split(path)
    fd, tmp = tempfile.mkstemp(prefix="." + name + PARTIAL_MARKER, dir=directory)
    os.close(fd)
    try:
        write(tmp)
        with open(tmp, "rb") as f:
            os.fsync(f.fileno())
        os.chmod(tmp, 0o644)
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.remove(tmp)
        raise


def write_text_atomically(path, text):
    def write(tmp):
        with open(tmp, "w", encoding="utf-8") as f:
            f.write(text)

    replace_atomically(path, write)


def remove_stale_temporaries(directory, age_s=600):
    """Temporary files of a report that was killed; young ones may belong to a report running
    now and are left alone."""
    now = time.time()
    for name in os.listdir(directory):
        if name.startswith(".") and PARTIAL_MARKER in name:
            path = os.path.join(directory, name)
            try:
                if now - os.path.getmtime(path) > age_s:
                    os.remove(path)
            except OSError:
                pass


# --------------------------------------------------------------------------------------------
# Tables, JSON, parameter files
# --------------------------------------------------------------------------------------------

# The most values of one table held in memory: the last million rows of a six-column time series.
# A longer table is read as a stream that keeps its last rows up to this bound at full resolution
# and, of all its rows, the first value, minimum and maximum of each column in ENVELOPE_BUCKETS
# buckets of consecutive rows (Table.envelope: what an overview of the whole file draws). Lines
# are read CHUNK_LINES at a time and none may be longer than MAX_LINE_CHARS, so a table costs
# bounded memory whatever the size of its file (docs/report.md, "Memory").
MAX_TABLE_VALUES = 6_000_000
ENVELOPE_BUCKETS = 10_000
CHUNK_LINES = 50_000
MAX_LINE_CHARS = 1 << 20


def count_newlines(path):
    """The number of newline characters of a file, read in blocks: a bound on its rows."""
    n = 0
    with open(path, "rb") as f:
        for block in iter(lambda: f.read(1 << 22), b""):
            n += block.count(b"\n")
    return n


class Envelope:
    """First value, minimum and maximum of each column over buckets of `bucket` consecutive rows,
    gathered chunk by chunk (non-numeric columns give NaN)."""

    def __init__(self, bucket):
        self.bucket = bucket
        self.carry = None
        self.parts = {"first": [], "min": [], "max": []}

    def add(self, chunk):
        cols = np.column_stack([c if c.dtype != object else np.full(len(c), np.nan)
                                for c in chunk])
        if self.carry is not None:
            cols = np.vstack([self.carry, cols])
        m = len(cols) // self.bucket
        if m:
            self._reduce(cols[: m * self.bucket].reshape(m, self.bucket, cols.shape[1]))
        self.carry = cols[m * self.bucket:]

    def _reduce(self, block):
        self.parts["first"].append(block[:, 0, :].copy())  # not a view that keeps the block
        self.parts["min"].append(np.fmin.reduce(block, axis=1))
        self.parts["max"].append(np.fmax.reduce(block, axis=1))

    def result(self, names):
        if self.carry is not None and len(self.carry):
            self._reduce(self.carry[np.newaxis])
        out = {"rows_per_bucket": self.bucket}
        for key, parts in self.parts.items():
            stacked = np.vstack(parts)
            out[key] = {name: stacked[:, i] for i, name in enumerate(names)}
        return out


class Table:
    """A CSV table: column name -> numpy array (float where every entry parses, else str).

    Read with bounded memory: a table of more than MAX_TABLE_VALUES values keeps its last rows
    (len(table) of total_rows; the first one kept is row first_row, counted from 0) and the
    envelope of all its rows. BadInput, naming the file, when the table cannot be parsed: no
    header, a row with more or fewer fields than the header, a last line without its line end
    (a file cut short), a line longer than any table has, text that is not UTF-8."""

    def __init__(self, path):
        self.path = path
        self.columns = {}
        self.names = []
        self.total_rows = 0
        self.first_row = 0
        self.envelope = None  # {"first"|"min"|"max": {column: array}, "rows_per_bucket": n}
        try:
            with open(path, newline="", encoding="utf-8") as f:
                self._read(f)
        except UnicodeDecodeError:
            raise BadInput("%s is not UTF-8 text: not a hertzgear table" % path)

    def _lines(self, f):
        """(line number, line) of the lines that are neither blank nor comments."""
        for number, line in enumerate(iter(lambda: f.readline(MAX_LINE_CHARS + 1), ""), 1):
            if len(line) > MAX_LINE_CHARS:
                raise BadInput("%s: line %d is longer than %d characters: not a hertzgear table"
                               % (self.path, number, MAX_LINE_CHARS))
            if not line.endswith("\n"):  # hertzgear ends every line, the last one too
                raise BadInput("%s: line %d stops without a line end: a truncated table"
                               % (self.path, number))
            if line.strip() and not line.lstrip().startswith("#"):
                yield number, line

    def _read(self, f):
        lines = self._lines(f)
        first = next(lines, None)
        if first is None:
            raise BadInput("%s is empty" % self.path)
        self.names = [n.strip() for n in next(csv.reader([first[1]]))]
        n_cols = len(self.names)
        keep = max(1000, MAX_TABLE_VALUES // n_cols)
        envelope = None
        # Every row takes at least two characters a column ("0,"): a smaller file cannot hold
        # more rows than are kept, and is not counted.
        if os.path.getsize(self.path) > 2 * n_cols * keep:
            newlines = count_newlines(self.path)
            if newlines > keep:
                envelope = Envelope(-(-newlines // ENVELOPE_BUCKETS))
        tail, tail_rows = [], 0
        while True:
            block = list(itertools.islice(lines, CHUNK_LINES))
            if not block:
                break
            chunk = self._parse(block, n_cols)
            self.total_rows += len(block)
            if envelope is not None:
                envelope.add(chunk)
            tail.append(chunk)
            tail_rows += len(block)
            while tail_rows - len(tail[0][0]) >= keep:
                tail_rows -= len(tail.pop(0)[0])
        for i, name in enumerate(self.names):
            parts = [c[i] for c in tail]
            if any(p.dtype == object for p in parts):
                parts = [p if p.dtype == object else np.array([repr(float(v)) for v in p],
                                                              dtype=object) for p in parts]
            column = np.concatenate(parts) if parts else np.array([])
            self.columns[name] = column[-keep:]
        self.first_row = self.total_rows - len(self)
        if envelope is not None and self.first_row > 0:
            self.envelope = envelope.result(self.names)

    def _parse(self, block, n_cols):
        """The columns of the numbered lines `block`: float arrays, or arrays of str for a
        column with an entry that is not a number (an empty entry is NaN)."""
        text = [line for _, line in block]
        try:
            values = np.loadtxt(text, delimiter=",", dtype=float, ndmin=2, comments=None)
            if values.shape == (len(text), n_cols):
                return [np.ascontiguousarray(values[:, i]) for i in range(n_cols)]
        except ValueError:
            pass
        rows = list(csv.reader(text))
        for (number, _), r in zip(block, rows):
            if len(r) != n_cols:
                raise BadInput("%s: line %d has %d fields where the header has %d: a truncated "
                               "or garbled table" % (self.path, number, len(r), n_cols))
        if len(rows) != len(block):
            raise BadInput("%s: a quoted field spans lines: not a hertzgear table" % self.path)
        out = []
        for i in range(n_cols):
            raw = [r[i].strip() for r in rows]
            try:
                out.append(np.array([float(v) if v != "" else np.nan for v in raw]))
            except ValueError:
                out.append(np.array(raw, dtype=object))
        return out

    @classmethod
    def from_columns(cls, path, columns):
        """A table from equal-length numeric lists (e.g. the samples of stiffness.json)."""
        table = cls.__new__(cls)
        table.path = path
        table.names = list(columns)
        table.columns = {k: np.asarray(v, dtype=float) for k, v in columns.items()}
        table.total_rows, table.first_row, table.envelope = len(table), 0, None
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


def flatten(obj, prefix=""):
    """Nested dicts as a list of (dotted key path, leaf value)."""
    out = []
    if isinstance(obj, dict):
        for k, v in obj.items():
            out.extend(flatten(v, prefix + "." + k if prefix else k))
    else:
        out.append((prefix, obj))
    return out


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
                value, default = _prm_value_and_default(m.group(2))
                entries.append(("/".join(stack), m.group(1).strip(), value, " ".join(comment),
                                default))
                comment = []
    return entries


def _prm_value_and_default(text):
    """(value, default or None) of the text after 'set key ='."""
    value, default = text, None
    d = re.search(r"#\s*default:\s*(.*)$", value)
    if d:
        default = d.group(1).strip()
        value = value[: d.start()]
    return value.split(" #")[0].strip(), default


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


# --------------------------------------------------------------------------------------------
# The run directory
# --------------------------------------------------------------------------------------------

def fnv1a_64_hex(path):
    """The content hash the cache manifests record (common/hash.h: FNV-1a 64, hex)."""
    h = 0xcbf29ce484222325
    with open(path, "rb") as f:
        for block in iter(lambda: f.read(1 << 20), b""):  # in blocks: bounded memory
            for byte in block:
                h = ((h ^ byte) * 0x100000001b3) & 0xFFFFFFFFFFFFFFFF
    return "%016x" % h


def written_by_run(folder):
    """True when run.json says `hertzgear run` wrote the folder (a folder of single commands,
    `hertzgear stiffness` or `dynamics`, has no cache manifests to check)."""
    try:
        return load_json(os.path.join(folder, "run.json")).get("stage") == "run"
    except Exception:
        return False


def verified_by_manifests(folder):
    """What the cache manifests of a run folder vouch for: (verified, foreign).

    verified: the artifacts (absolute paths) that a manifest lists with their current size and
    hash, and whose manifest records the content hash of the folder's used_parameters.prm (the
    scene the page shows); None for a folder that is not a `hertzgear run` folder.
    foreign: stage -> the artifacts (absolute paths) of the manifests that record another
    used_parameters.prm; they vouch for nothing."""
    cache = os.path.join(folder, ".hertzgear-cache")
    if not os.path.isdir(cache):
        return (set() if written_by_run(folder) else None), {}
    prm = os.path.join(folder, "used_parameters.prm")
    parameters_hash = fnv1a_64_hex(prm) if os.path.isfile(prm) else None
    verified, foreign = set(), {}
    for name in sorted(os.listdir(cache)):
        try:
            manifest = load_json(os.path.join(cache, name))
            listed = {os.path.normpath(os.path.join(folder, a["path"])): a
                      for a in manifest.get("artifacts", [])}
            if manifest.get("used_parameters_hash") != parameters_hash:
                foreign[manifest.get("stage", name)] = set(listed)
                continue
            for p, a in listed.items():
                if (os.path.isfile(p) and os.path.getsize(p) == a["size_bytes"]
                        and fnv1a_64_hex(p) == a["content_hash"]):
                    verified.add(p)
        except Exception:  # an unreadable manifest vouches for nothing
            continue
    return verified, foreign


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
        self.accuracy_data = {}  # path -> Table of each accuracy table, read by check()
        self.untrusted = []   # artifacts the page shows that no verified manifest covers
        self.warnings = []    # why they are untrusted: on the page and on stderr
        self._check_manifests()
        self.notes += self.warnings

    def _check_manifests(self):
        """Names on the page (and on stderr) what in a `hertzgear run` folder no verified
        manifest of this run covers; a folder of single commands has no manifests to check."""
        verified, foreign = verified_by_manifests(self.run_dir)
        if verified is None:
            return
        if not os.path.isdir(os.path.join(self.run_dir, ".hertzgear-cache")):
            self.warnings.append(
                "This folder was written by `hertzgear run` but holds no cache manifest "
                "(.hertzgear-cache/ is missing), so nothing vouches that its artifacts belong to "
                "one run.")
        drawn = {os.path.normpath(p) for p in self.paths.values()}
        foreign_stages = [stage for stage, listed in foreign.items() if listed & drawn]
        if foreign_stages:
            self.untrusted.append("used_parameters.prm")
            self.warnings.append(
                "used_parameters.prm is not the scene of the run that wrote the artifacts of the "
                "stage(s) %s: their cache manifests record another used_parameters.prm (another "
                "run on this folder wrote its parameters after them: one interrupted, or one that "
                "did not run these stages; or the file was replaced), so the scene values on this "
                "page need not be those of the results." % ", ".join(foreign_stages))
        self.untrusted += [os.path.relpath(p, self.run_dir) for name, p in self.paths.items()
                           if os.path.normpath(p) not in verified
                           and name not in ("used_parameters.prm", "run.json")]
        if self.untrusted:
            self.warnings.append(
                "Not covered by a verified cache manifest of this run folder, so they may come "
                "from an interrupted or another run and need not belong with the rest: %s. "
                "Run `hertzgear run` on the folder again to rebuild them."
                % ", ".join(sorted(self.untrusted)))

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

    def read(self, path):
        """The parsed artifact at path: a Table, JSON or the entries of a parameter file;
        BadInput naming the file when it cannot be parsed."""
        try:
            if path.endswith(".csv"):
                return Table(path)
            if path.endswith(".json"):
                try:
                    return load_json(path)
                except ValueError as e:  # json.JSONDecodeError
                    raise BadInput("%s is not valid JSON (%s): a truncated or garbled file"
                                   % (path, e))
            return parse_prm(path)
        except UnicodeDecodeError:
            raise BadInput("%s is not UTF-8 text: not a hertzgear artifact" % path)
        except OSError as e:
            raise BadInput("%s cannot be read: %s" % (path, e.strerror or e))

    def check(self):
        """Reads every artifact before the report writes anything: BadInput naming the first
        that cannot be parsed or lacks a column its figures need. A table with a header and no
        rows costs its figures only (with a note)."""
        for name in self.paths:
            self.get(name)
        for path in self.accuracy_tables:
            if path not in self.accuracy_data:
                self.accuracy_data[path] = self.read(path)

    def get(self, name):
        """The parsed artifact, or None when it is absent or a table without rows (with a note);
        BadInput naming the file when it cannot be parsed or lacks a column its figures need."""
        if name not in self.paths:
            return None
        if name in self._cache:
            return self._cache[name]
        value = self.read(self.paths[name])
        if isinstance(value, Table):
            if len(value) == 0:
                self.notes.append("%s holds no data rows: its figures are left out."
                                  % self.rel(name))
                value = None
            else:
                check_columns(name, value)
                if value.first_row > 0:
                    self.notes.append(
                        "%s has %d rows, more than the report holds in memory: its figures draw "
                        "its last %d rows, and the overview of the whole history the minimum and "
                        "maximum of every %d rows." % (self.rel(name), value.total_rows,
                                                       len(value),
                                                       value.envelope["rows_per_bucket"]))
        self._cache[name] = value
        return value


def check_columns(name, table):
    """BadInput naming the table when it lacks a numeric column its figures need."""
    for what, patterns, exclude in REQUIRED_COLUMNS.get(name, ()):
        column = table.find(*patterns, exclude=exclude)
        if not column:
            raise BadInput("%s has no %s column (looked for a name starting with %s; it has %s)"
                           % (table.path, what, " or ".join(p for p in patterns
                                                            if not p.startswith("re:")),
                              ", ".join(table.names)))
        if not table.numeric(column):
            raise BadInput("%s: column %s holds entries that are not numbers"
                           % (table.path, column))


# --------------------------------------------------------------------------------------------
# stiffness.json
# --------------------------------------------------------------------------------------------

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
    """(key path, series): the Fourier coefficients in stiffness.json whose key path contains one
    of the names, or (None, None)."""
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


def samples_table(stiffness_json):
    """The per-position samples of stiffness.json ("samples": mesh_phase and equal-length numeric
    lists) as a Table, or None."""
    samples = stiffness_json.get("samples") if isinstance(stiffness_json, dict) else None
    if not (isinstance(samples, dict) and samples.get("mesh_phase")):
        return None
    n = len(samples["mesh_phase"])
    return Table.from_columns("stiffness.json samples", {
        k: v for k, v in samples.items()
        if isinstance(v, list) and len(v) == n and all(isinstance(x, (int, float)) for x in v)})


# --------------------------------------------------------------------------------------------
# Scene quantities
# --------------------------------------------------------------------------------------------

def length_in_um(key, value):
    low = key.lower()
    if low.endswith("_um"):
        return value
    if low.endswith("_mm"):
        return value * 1e3
    if low.endswith("_m"):
        return value * 1e6
    return None


def is_number(v):
    """A JSON number (int or float, not a boolean)."""
    return isinstance(v, (int, float)) and not isinstance(v, bool)


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
            if not is_number(v):
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
            if not is_number(v) or v <= 0:
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
# The load and design map of a stiffness run
# --------------------------------------------------------------------------------------------

# The keys that name a map case (stiffness.json "map" and the first columns of stiffness_map.csv).
MAP_CASE_KEYS = ("case", "torque_Nm", "torque_percent", "load_N", "pinion_crowning_um",
                 "gear_crowning_um", "mesh_misalignment_um")

# (summary key, stiffness_map.csv column, reduction over the positions of a case): how a summary
# of stiffness.json "map" follows from the rows of stiffness_map.csv when the JSON lacks it.
MAP_SUMMARY_OF_ROWS = (
    ("ste_peak_to_peak_um", "ste_um", np.ptp), ("mean_ste_um", "ste_um", np.mean),
    ("mean_k_total_N_per_m", "k_total_N_per_m", np.mean),
    ("mean_k_rest_N_per_m", "k_rest_N_per_m", np.mean),
    ("max_peak_pressure_MPa", "peak_pressure_MPa", np.max),
    ("contact_centre_z_min_mm", "contact_centre_z_mm", np.min),
    ("contact_centre_z_max_mm", "contact_centre_z_mm", np.max),
    ("face_end_contact_positions", "face_end_contact", np.sum),
    ("tip_contact_positions", "tip_contact", np.sum),
)


def map_summaries_of_rows(table):
    """The per-case summaries of stiffness_map.csv, in case order, with n_positions."""
    if not table.numeric("case"):
        return []
    summaries = []
    for case in np.unique(table["case"]):
        rows = table["case"] == case
        s = {k: float(table[k][rows][0]) for k in MAP_CASE_KEYS if table.numeric(k)}
        off_tips = rows & (table["tip_contact"] == 0) if table.numeric("tip_contact") else rows
        s["max_peak_pressure_off_tips_MPa"] = (float(np.max(table["peak_pressure_MPa"][off_tips]))
                                               if off_tips.any() else 0.0)
        s.update({key: float(reduce(table[col][rows])) for key, col, reduce in MAP_SUMMARY_OF_ROWS
                  if table.numeric(col)})
        s["n_positions"] = int(rows.sum())
        summaries.append(s)
    return summaries


def map_summaries(stiffness_json, table):
    """The per-case summaries of the map: stiffness.json "map" when it lists them, else derived
    from stiffness_map.csv; [] when the run has no map. A case lacking a torque, a crowning or a
    misalignment is dropped."""
    listed = stiffness_json.get("map") if isinstance(stiffness_json, dict) else None
    if isinstance(listed, list) and listed:
        cases = [c for c in listed if isinstance(c, dict)]
    elif table is not None:
        cases = map_summaries_of_rows(table)
    else:
        return []
    return [c for c in cases if all(is_number(c.get(k)) for k in MAP_CASE_KEYS)]


def same(a, b, tol=1e-6):
    return a is not None and b is not None and abs(a - b) <= tol * max(1.0, abs(a), abs(b))


def crowning_of(case):
    """(pinion, gear) lead crowning of a map case [µm]."""
    return (float(case["pinion_crowning_um"]), float(case["gear_crowning_um"]))


def slope_of(case):
    """The pinion's helix slope deviation f_Hβ of a map case [µm]; 0 for a map without it."""
    v = case.get("pinion_helix_slope_deviation_um")
    return float(v) if is_number(v) else 0.0


def design_of(case):
    """What a map case varies besides the torque: (crowning, f_ma, f_Hβ)."""
    return crowning_of(case) + (float(case["mesh_misalignment_um"]), slope_of(case))


def series_by_crowning(cases, keep, x_key):
    """{crowning: cases sorted by x_key} of the cases `keep` accepts, one case per x value (the
    first in case order)."""
    groups = {}
    for c in cases:
        if keep(c):
            groups.setdefault(crowning_of(c), {}).setdefault(float(c[x_key]), c)
    return {k: [by_x[x] for x in sorted(by_x)] for k, by_x in groups.items()}


class LoadMap:
    """The load and design map of a stiffness run: the per-case summaries, the scene's own
    contact summary (stiffness.json "contact"), the loaded contact-grid cells
    (contact_pattern.csv) and the limits of the pinion flank they lie on."""

    def __init__(self, art, scene):
        js = art.get("stiffness.json")
        js = js if isinstance(js, dict) else {}
        self.cases = map_summaries(js, art.get("stiffness_map.csv"))
        self.contact = js.get("contact") if isinstance(js.get("contact"), dict) else {}
        self.cells = art.get("contact_pattern.csv")
        stiffness = art.get("stiffness.csv")
        self.n_positions = len(stiffness) if stiffness is not None else None
        self.face_width_mm = self._contact_number("face_width_mm") or \
            prm_float(scene.prm, "Gear pair/Pinion", "face_width_mm")
        roll = (self._contact_number("pinion_active_roll_min_mm"),
                self._contact_number("pinion_active_roll_max_mm"))
        self.active_roll_mm = roll if None not in roll else None
        self.scene_crowning_um = prm_float(scene.prm, "Gear pair/Pinion", "crowning_um")
        misalignment = prm_float(scene.prm, "Operating", "mesh_misalignment_um")
        if misalignment is None and self.cases:
            misalignment = float(self.cases[0]["mesh_misalignment_um"])
        self.scene_misalignment_um = misalignment
        self.scene_slope_um = prm_float(scene.prm, "Gear pair/Pinion",
                                        "helix_slope_deviation_um") or 0.0

    def _contact_number(self, key):
        v = self.contact.get(key)
        return float(v) if is_number(v) else None

    def at_scene_slope(self, case):
        return same(slope_of(case), self.scene_slope_um)

    def torque_series(self):
        """{crowning: cases over torque} at the scene's misalignment and helix slope."""
        return series_by_crowning(
            self.cases, lambda c: same(c["mesh_misalignment_um"], self.scene_misalignment_um)
            and self.at_scene_slope(c), "torque_Nm")

    def misalignment_series(self):
        """{crowning: cases over misalignment} at the nominal torque (100 %) and the scene's
        helix slope."""
        return series_by_crowning(
            self.cases, lambda c: same(c["torque_percent"], 100.0) and self.at_scene_slope(c),
            "mesh_misalignment_um")

    def is_scene_design(self, case):
        """Whether a case has the scene's own crowning, misalignment and helix slope."""
        return (same(float(case["pinion_crowning_um"]), self.scene_crowning_um)
                and same(float(case["mesh_misalignment_um"]), self.scene_misalignment_um)
                and self.at_scene_slope(case))

    def designs_by_torque(self):
        """{torque [N m]: the cases at that torque, one per design (crowning, f_ma, f_Hβ)}, in
        increasing torque."""
        groups = {}
        for c in self.cases:
            groups.setdefault(float(c["torque_Nm"]), {}).setdefault(design_of(c), c)
        return {t: list(groups[t].values()) for t in sorted(groups)}

    def pattern_crowning(self, series):
        """The crowning of `series` whose contact patterns to show: the scene's, else the
        first."""
        for crowning in series:
            if same(crowning[0], self.scene_crowning_um):
                return crowning
        return next(iter(series), None)

    def cells_of(self, case, position=None):
        """(z, roll, pressure, roll height) of the loaded cells of `case` (−1: the scene's own
        cycle), of one mesh position when `position` is given, or None when
        contact_pattern.csv has none."""
        t = self.cells
        need = ("case", "position", "pair", "pinion_roll_mm", "z_mm", "pressure_MPa")
        if t is None or not all(t.numeric(k) for k in need):
            return None
        rows = (t["case"] == case) & np.isfinite(t["pressure_MPa"])
        if position is not None:
            rows &= t["position"] == position
        if not rows.any():
            return None
        roll = t["pinion_roll_mm"][rows]
        groups = t["position"][rows] * 1000 + t["pair"][rows]
        return t["z_mm"][rows], roll, t["pressure_MPa"][rows], cell_heights(roll, groups)

    def positions_of(self, case):
        """The mesh positions of `case` that have loaded cells, in order."""
        t = self.cells
        if t is None or not t.numeric("case") or not t.numeric("position"):
            return []
        return [int(p) for p in np.unique(t["position"][t["case"] == case])]

    def cell_width_mm(self):
        """The face-width extent of a contact-grid cell: the spacing of its z values within one
        case (a grid whose face band follows the load, Stiffness/contact_grid_face_extent =
        load, has its own spacing per load), the smallest over the cases."""
        t = self.cells
        z = t["z_mm"] if t is not None else np.array([])
        case = t["case"] if t is not None and t.numeric("case") else np.zeros(np.shape(z))
        widths = []
        for c in np.unique(case):
            steps = np.diff(np.unique(z[case == c]))
            steps = steps[steps > 1e-9]
            if steps.size:
                widths.append(float(np.min(steps)))
        if widths:
            return min(widths)
        return (self.face_width_mm or 1.0) / 16


def cell_heights(roll, groups):
    """The profile (roll-distance) extent of each cell: the distance between the midpoints to its
    neighbours in its line of cells (one position and pair), the median elsewhere for a line of
    one cell."""
    heights = np.full(roll.shape, np.nan)
    for g in np.unique(groups):
        idx = np.flatnonzero(groups == g)
        levels = np.unique(roll[idx])
        if levels.size < 2:
            continue
        edges = np.concatenate([[1.5 * levels[0] - 0.5 * levels[1]],
                                0.5 * (levels[1:] + levels[:-1]),
                                [1.5 * levels[-1] - 0.5 * levels[-2]]])
        k = np.searchsorted(levels, roll[idx])
        heights[idx] = edges[k + 1] - edges[k]
    fallback = np.nanmedian(heights) if np.isfinite(heights).any() else 0.2
    return np.where(np.isfinite(heights), heights, fallback)
