"""Read an ffrf results file (HDF5, one per run) with h5py.

Only reading and reshaping: no solver logic. Layout (see docs/results.md "Results file (HDF5)"):
the Fortran writer stores arrays in Fortran order, so h5py sees them transposed, e.g.
/bodies/<body>/mesh/coordinates as (num_nodes, 3) and /bodies/<body>/modes/shape as
(num_modes, 3*num_nodes). Strings are fixed-length and come back as bytes; `text` decodes.

    with ffrf_results.open_results("crank_rc1.h5") as results:
        body = results.bodies()[0]
        hz = results.frequencies(body)
        u = results.shapes(body)               # (num_modes, num_nodes, 3)
        tris = results.surface_triangles(body)  # (num_triangles, 3), 0-based, outward

Engine (time-integration) runs add /time, /engine, /energy and /joints; `read_engine` reads the
series the charts need, and `cycle_window` / `angle_mean` cut and average whole engine cycles:

    run = ffrf_results.read_engine("engine_rc1.h5")       # allow_incomplete=True for a killed run
    theta_a, theta_b = ffrf_results.cycle_window(run.crank_angle, num_cycles=2)

Any results file (modal, mechanism, engine, one task of a sweep) into numpy at once: `load`
gives status, schema version, the input echo, every body's modes, the time histories, sensors
and peaks, and every dataset of the file by path (docs/results.md "Python package"):

    data = ffrf_results.load("slider_wheel.h5")
    data.time["t"], data.sensors["slider_position"].values, data.datasets["energy/kinetic"]

Every file carries the root attribute schema_version "MAJOR.MINOR" (files written before it
have none and read as "0.x"); this reader reads SCHEMA_VERSION's major and every older one and
refuses a newer major with SchemaError (docs/results.md "Schema version").

Installed with `pip install ./postprocess`, which also gives the console scripts
ffrf-plot-engine, ffrf-plot-modes, ffrf-plot-sensors, ffrf-engine-summary,
ffrf-frequency-table and ffrf-gather (the modules of this package; postprocess/<name>.py are
thin entry points to the same code).
"""
import math
import os
import re
import sys

import h5py
import numpy as np

__all__ = ["ResultsError", "SchemaError", "command_error", "SCHEMA_VERSION",
           "schema_version_of", "Results", "open_results", "text", "exterior_faces", "Sensor", "ResultsData", "load",
           "EngineRun", "read_engine", "unique_labels", "ENGINE_CYCLE", "cycle_window",
           "window_samples", "angle_mean"]

__version__ = "0.1.0"

#: The results schema this reader knows (docs/results.md "Schema version"): it reads files of
#: this major version and of every older one, and refuses a newer major (SchemaError).
SCHEMA_VERSION = "1.0"
#: What a file without the root attribute schema_version is: written before the attribute.
SCHEMA_UNVERSIONED = "0.x"


class ResultsError(Exception):
    """A results file that cannot be used: missing, failed run, missing dataset."""


class SchemaError(ResultsError):
    """A results file of a newer schema major version than this reader's, or with a
    schema_version that is not MAJOR.MINOR."""


def command_error(script, exc):
    """What every console script does with a ResultsError (or SchemaError): one line on
    standard error, exit code 2 (returned)."""
    print(f"{script}: error: {exc}", file=sys.stderr)
    return 2


def schema_version_of(attrs, path="results file"):
    """(version text, major) of a file's root attributes (h5py attrs or a dict): "0.x" and 0
    when schema_version is absent. Raises SchemaError when it is not MAJOR.MINOR (two
    non-negative integers) or its major is newer than SCHEMA_VERSION's."""
    if "schema_version" not in attrs:
        return SCHEMA_UNVERSIONED, 0
    version = text(attrs["schema_version"]).strip()
    match = re.fullmatch(r"(\d+)\.(\d+)", version)
    if not match:
        raise SchemaError(f"{path}: root attribute schema_version is '{version}', not "
                          f"MAJOR.MINOR (e.g. '{SCHEMA_VERSION}'): not a file ffrf wrote, or "
                          f"a damaged one")
    major = int(match.group(1))
    reader_major = int(SCHEMA_VERSION.split(".")[0])
    if major > reader_major:
        raise SchemaError(f"{path}: schema_version {version} is newer than this reader "
                          f"(ffrf_results {__version__} reads schema {reader_major}.x and "
                          f"older): install the reader of the ffrf that wrote the file "
                          f"(pip install ./postprocess in its source tree)")
    return version, major


def text(value):
    """A str from what h5py returns for a string dataset or attribute (bytes, numpy bytes,
    str, or a 0-d array of those)."""
    if isinstance(value, np.ndarray) and value.shape == ():
        value = value[()]
    if isinstance(value, (bytes, np.bytes_)):
        return bytes(value).rstrip(b"\0").decode("utf-8", errors="replace")
    return str(value)


def exterior_faces(tets, xyz=None):
    """Exterior triangles of a tetrahedral mesh: the faces that belong to one tetrahedron only.

    tets: (num_tets, nen) 0-based node indices, corners first (Gmsh order, nen 4 or 10; only the
    4 corners are used). xyz: (num_nodes, 3) coordinates; when given, the triangles are ordered
    so that their normals (p1 - p0) x (p2 - p0) point out of the mesh. Returns (num_faces, 3).
    """
    corners = np.asarray(tets)[:, :4].astype(np.int64)
    if xyz is not None:
        p = np.asarray(xyz, dtype=float)[corners]
        volume6 = np.einsum("ij,ij->i", np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]),
                            p[:, 3] - p[:, 0])
        negative = volume6 < 0.0
        corners = corners.copy()
        corners[negative, 1], corners[negative, 2] = corners[negative, 2], corners[negative, 1]
    # outward faces of a positively oriented tetrahedron (a, b, c, d): each face seen from
    # outside is counter-clockwise
    a, b, c, d = corners.T
    faces = np.concatenate([np.stack(f, axis=1) for f in
                            ((a, c, b), (a, b, d), (a, d, c), (b, c, d))])
    keys = np.sort(faces, axis=1)
    _, first, counts = np.unique(keys, axis=0, return_index=True, return_counts=True)
    return faces[np.sort(first[counts == 1])]


class Results:
    """One open results file. Raises ResultsError unless the run's status is 'complete'
    (pass require_complete=False to look at a failed run)."""

    def __init__(self, path, require_complete=True):
        self.path = str(path)
        try:
            self.file = h5py.File(self.path, "r")
        except OSError as exc:
            raise ResultsError(f"{self.path}: cannot open as HDF5 ({exc})") from exc
        try:
            self.schema_version, self.schema_major = schema_version_of(self.file.attrs,
                                                                       self.path)
        except SchemaError:
            self.file.close()
            raise
        self.status = text(self.file.attrs.get("status", b"(no status attribute)"))
        if require_complete and self.status != "complete":
            self.file.close()
            raise ResultsError(f"{self.path}: the run did not complete, status is "
                               f"'{self.status}'; rerun it or look at its log")

    def close(self):
        self.file.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def _dataset(self, path):
        if path not in self.file:
            raise ResultsError(f"{self.path}: no dataset {path}")
        return self.file[path][()]

    def attribute(self, name, path="/", default=None):
        """A string or number attribute of `path` (strings decoded)."""
        if path not in self.file:
            return default
        value = self.file[path].attrs.get(name, default)
        if isinstance(value, (bytes, np.bytes_, str)):
            return text(value)
        return value

    @property
    def case_name(self):
        return self.attribute("case_name", default="")

    def bodies(self):
        """Names of the bodies in the file, in stored (alphabetical) order."""
        if "bodies" not in self.file:
            return []
        return list(self.file["bodies"].keys())

    def body(self, name=None):
        """`name` if the file has it, else the first body; ResultsError if none or unknown."""
        names = self.bodies()
        if not names:
            raise ResultsError(f"{self.path}: no bodies in the file")
        if name is None:
            return names[0]
        if name not in names:
            raise ResultsError(f"{self.path}: no body '{name}'; bodies: {', '.join(names)}")
        return name

    def history(self, path):
        """A time series (a step per row), e.g. 'joints/crank_pin/reaction' (num_samples, 12):
        full rate, decimated (&output) or compressed alike."""
        return np.asarray(self._dataset(f"/{path.strip('/')}"), dtype=float)

    def peaks(self, path):
        """The extremes of a decimated series over each output interval (docs/results.md
        "Output rate, peaks, compression, size"): a dict min, max, t_min, t_max of arrays shaped
        as the series, or None when the file has none (full rate, or peaks = .false.)."""
        group = f"/peaks/{path.strip('/')}"
        if group not in self.file:
            return None
        return {name: np.asarray(self.file[f"{group}/{name}"][()], dtype=float)
                for name in ("min", "max", "t_min", "t_max")}

    @property
    def decimated(self):
        """True when the series hold samples at a reduced rate (/peaks written, or an
        &output every_steps/every_seconds in the input echo)."""
        if "peaks" in self.file:
            return True
        if "input/namelist" not in self.file:
            return False
        echo = text(self.file["input/namelist"][()])
        for line in echo.splitlines():
            if line.lstrip().startswith("&output"):
                steps = re.search(r"every_steps\s*=\s*(\d+)", line)
                seconds = re.search(r"every_seconds\s*=\s*([0-9.EeDd+-]+)", line)
                return bool((steps and int(steps.group(1)) > 1) or
                            (seconds and float(seconds.group(1).replace("D", "E")
                                               .replace("d", "e")) > 0))
        return False

    def frequencies(self, body):
        """Natural frequencies, Hz, (num_modes,)."""
        return np.atleast_1d(self._dataset(f"/bodies/{body}/modes/frequency")).astype(float)

    def shapes(self, body):
        """Mass-normalised mode shapes as (num_modes, num_nodes, 3)."""
        shape = np.atleast_2d(self._dataset(f"/bodies/{body}/modes/shape")).astype(float)
        return shape.reshape(shape.shape[0], -1, 3)

    def coordinates(self, body):
        """Node coordinates, m, (num_nodes, 3)."""
        return self._dataset(f"/bodies/{body}/mesh/coordinates").astype(float)

    def tets(self, body):
        """Tetrahedra as 0-based node indices, (num_tets, 4 or 10)."""
        return self._dataset(f"/bodies/{body}/mesh/tets").astype(np.int64) - 1

    def surface_triangles(self, body):
        """Exterior triangles (corner nodes, 0-based, outward normals), (num_triangles, 3)."""
        return exterior_faces(self.tets(body), self.coordinates(body))

    def modes_info(self, body):
        """The modes group's attributes: rc_set, mpc, formulation (strings, '' if absent)."""
        path = f"/bodies/{body}/modes"
        return {key: self.attribute(key, path, default="")
                for key in ("rc_set", "mpc", "formulation")}

    def label(self, body):
        """'RC set 1, RBE3' from the modes attributes (the file name if they are absent)."""
        info = self.modes_info(body)
        parts = [p for p in (info["rc_set"], info["mpc"]) if p]
        return ", ".join(parts) if parts else self.path

    def timings(self):
        """{stage: wall seconds} from /timings ({} if the file has none yet)."""
        if "timings/stage" not in self.file or "timings/seconds" not in self.file:
            return {}
        stages = [text(s) for s in np.atleast_1d(self.file["timings/stage"][()])]
        seconds = np.atleast_1d(self.file["timings/seconds"][()]).astype(float)
        return dict(zip(stages, seconds[:len(stages)]))


def open_results(path, require_complete=True):
    """Open a results file (context manager); see Results."""
    return Results(path, require_complete=require_complete)


def _value(dataset):
    """A dataset as numpy: strings decoded (str, or a list of str), numbers as arrays."""
    value = dataset[()]
    if dataset.dtype.kind in "SOU":
        if np.ndim(value) == 0:
            return text(value)
        return [text(v) for v in np.asarray(value).ravel()]
    return np.asarray(value)


class Sensor:
    """One sensor of /sensors (docs/sensors.md): values (num_samples, k) and its attributes
    (type, units, body, marker, joint, ... as str)."""

    def __init__(self, values, attrs):
        self.values = values
        self.attrs = attrs


class ResultsData:
    """Everything of one results file in memory (see load). Attributes:

    path, status, complete (status == 'complete'), schema_version ('0.x' for a file without
    it), case_name, title, attributes ({root attribute: value}), input (the resolved input
    echo, /input/namelist, '' if absent); bodies ({body: {'frequencies' (Hz), 'shapes'
    (num_modes, num_nodes, 3), 'coordinates', 'tets' (0-based), 'modal_coordinates'
    (num_samples, num_modes)}}, each key only when the file has it); time ({name: (num_samples,)},
    /time); sensors ({name: Sensor}); peaks ({series path: {min, max, t_min, t_max}});
    datasets ({path without the leading '/': numpy array, or str / list of str for strings}:
    every dataset of the file).
    """

    def __init__(self, **fields):
        self.__dict__.update(fields)

    @property
    def complete(self):
        return self.status == "complete"


def load(path, require_complete=False):
    """Read a whole results file into a ResultsData (numpy arrays, strings decoded). A run
    that did not complete is read as far as it got, unless require_complete (then
    ResultsError). SchemaError for a newer schema major."""
    with Results(path, require_complete=require_complete) as results:
        datasets = {}

        def visit(name, item):
            if isinstance(item, h5py.Dataset):
                datasets[name] = _value(item)

        results.file.visititems(visit)
        attributes = {key: (text(value) if isinstance(value, (bytes, np.bytes_, str))
                            else value) for key, value in results.file.attrs.items()}
        bodies = {}
        for body in results.bodies():
            entry = {}
            prefix = f"bodies/{body}/"
            for key, name in (("frequencies", "modes/frequency"), ("shapes", "modes/shape"),
                              ("coordinates", "mesh/coordinates"), ("tets", "mesh/tets"),
                              ("modal_coordinates", "modal_coordinates")):
                if prefix + name in datasets:
                    entry[key] = datasets[prefix + name]
            if "frequencies" in entry:
                entry["frequencies"] = np.atleast_1d(entry["frequencies"]).astype(float)
            if "shapes" in entry:
                entry["shapes"] = results.shapes(body)
            if "tets" in entry:
                entry["tets"] = results.tets(body)
            bodies[body] = entry
        time = {name[len("time/"):]: value for name, value in datasets.items()
                if name.startswith("time/")}
        sensors = {}
        if "sensors" in results.file:
            for name, item in results.file["sensors"].items():
                values = np.asarray(item[()])
                sensors[name] = Sensor(values[:, None] if values.ndim == 1 else values,
                                       {k: text(v) for k, v in item.attrs.items()})
        peaks = {}
        for name in datasets:
            if name.startswith("peaks/") and name.endswith("/min"):
                series = name[len("peaks/"):-len("/min")]
                peaks[series] = results.peaks(series)
        return ResultsData(path=results.path, status=results.status,
                           schema_version=results.schema_version,
                           case_name=results.case_name,
                           title=results.attribute("title", default=""),
                           attributes=attributes, input=datasets.get("input/namelist", ""),
                           bodies=bodies, time=time, sensors=sensors, peaks=peaks,
                           datasets=datasets)


# ---------------------------------------------------------------------------------------------
# Engine runs

#: One four-stroke engine cycle in crank angle, rad (two revolutions).
ENGINE_CYCLE = 4.0 * math.pi


class EngineRun:
    """The time series of one engine run (see read_engine). Attributes:

    path, status, complete (status == 'complete'), case_name, title, rc_set, mpc, label;
    t (s), crank_angle (rad, unwrapped), crank_speed (rad/s): (num_steps,) arrays;
    pressure (Pa, (num_steps,)) or None if the file has no /time/pressure;
    timings ({stage: s}), wall_time (s: the stage 'total' if present, else the sum of the
    stages; None if /timings is absent, as in a killed run), num_steps = len(t).
    """

    def __init__(self, **fields):
        self.__dict__.update(fields)

    @property
    def num_steps(self):
        return len(self.t)


def _engine_label(rc_set, mpc, fallback):
    """'RC set 1, RBE3'; 'rigid crank' (no 'rigid' MPC repeated); the fallback if both are
    empty."""
    parts = [rc_set] if rc_set else []
    if mpc and not (mpc.lower() == "rigid" and "rigid" in rc_set.lower()):
        parts.append(mpc)
    return ", ".join(parts) if parts else fallback


def read_engine(path, allow_incomplete=False):
    """Read the time series of an engine run into an EngineRun.

    Raises ResultsError when the file cannot be opened, has no /time group (a modal results
    file, say), lacks t, crank_angle or crank_speed, holds no step, has non-finite values, or
    a crank angle that jumps by more than pi in one step (wrapped, not unwrapped), and, unless
    allow_incomplete, when its status is not 'complete'. A run killed mid-way keeps status
    'running' and the steps flushed so far; its series may differ in length by the last chunk,
    so an incomplete run is cut to the shortest series (a complete one must agree exactly).
    The label says when the run is incomplete.
    """
    with Results(path, require_complete=False) as results:
        status = results.status
        complete = status == "complete"
        if not complete and not allow_incomplete:
            raise ResultsError(f"{results.path}: the run is not complete, status is "
                               f"'{status}' (a killed run keeps 'running'); rerun it, or pass "
                               f"--allow-incomplete (allow_incomplete=True) to use the steps "
                               f"it saved")
        if "time" not in results.file:
            raise ResultsError(f"{results.path}: no /time group, so not the results of a time "
                               f"integration (a modal run?); an engine run has /time/t, "
                               f"/time/crank_angle and /time/crank_speed")
        names = ["t", "crank_angle", "crank_speed"]
        if "pressure" in results.file["time"]:
            names.append("pressure")
        series = {}
        for name in names:
            series[name] = np.atleast_1d(results._dataset(f"/time/{name}")).astype(float)
        lengths = {name: len(values) for name, values in series.items()}
        num_steps = min(lengths.values())
        if len(set(lengths.values())) > 1:
            if complete:
                raise ResultsError(f"{results.path}: /time series of different lengths "
                                   f"{lengths} in a complete run")
            series = {name: values[:num_steps] for name, values in series.items()}
        if num_steps == 0:
            raise ResultsError(f"{results.path}: no time step saved yet (status '{status}')")
        for name, values in series.items():
            bad = np.flatnonzero(~np.isfinite(values))
            if bad.size:
                raise ResultsError(f"{results.path}: /time/{name} is {values[bad[0]]} at step "
                                   f"{bad[0]} (t = {series['t'][bad[0]]} s)")
        # samples at a reduced rate may lie more than pi apart: no wrap check then
        jumps = np.flatnonzero(np.abs(np.diff(series["crank_angle"])) > math.pi)
        if jumps.size and not results.decimated:
            k = jumps[0]
            raise ResultsError(f"{results.path}: /time/crank_angle jumps from "
                               f"{series['crank_angle'][k]} to {series['crank_angle'][k + 1]} "
                               f"rad at step {k}: it must be unwrapped (continuous over "
                               f"revolutions)")
        rc_set = results.attribute("rc_set", "/engine", default="") or ""
        mpc = results.attribute("mpc", "/engine", default="") or ""
        case_name = results.case_name
        label = _engine_label(str(rc_set), str(mpc), case_name or results.path)
        if not complete:
            label += f" (incomplete: {status})"
        timings = results.timings()
        if "total" in timings:
            wall_time = float(timings["total"])
        elif timings:
            wall_time = float(sum(timings.values()))
        else:
            wall_time = None
        return EngineRun(path=results.path, status=status, complete=complete,
                         case_name=case_name, title=results.attribute("title", default=""),
                         rc_set=str(rc_set), mpc=str(mpc), label=label,
                         t=series["t"], crank_angle=series["crank_angle"],
                         crank_speed=series["crank_speed"], pressure=series.get("pressure"),
                         timings=timings, wall_time=wall_time)


def unique_labels(runs):
    """Set each EngineRun's label unique by appending its file name where two coincide."""
    labels = [run.label for run in runs]
    for run in runs:
        if labels.count(run.label) > 1:
            run.label = f"{run.label} ({os.path.basename(run.path)})"
    return runs


def cycle_window(crank_angle, num_cycles=1):
    """(theta_a, theta_b), rad: the last num_cycles complete engine cycles of a run.

    Cycles are counted from crank angle 0 (TDC at the start of intake, scene.md), so cycle k
    is [4 pi k, 4 pi (k + 1)] and keeps the phase of the four-stroke cycle; complete means the
    run covers all of it. Raises ResultsError if the run holds fewer complete cycles.
    """
    if num_cycles < 1:
        raise ResultsError(f"number of engine cycles {num_cycles}: must be at least 1")
    first, last = float(np.min(crank_angle)), float(crank_angle[-1])
    end_cycle = math.floor(last / ENGINE_CYCLE)
    start_cycle = end_cycle - num_cycles
    available = end_cycle - math.ceil(first / ENGINE_CYCLE)
    if start_cycle * ENGINE_CYCLE < first:
        raise ResultsError(f"the run covers {max(available, 0)} complete engine cycle(s) "
                           f"(crank angle {first:.6g} .. {last:.6g} rad, a cycle is 4 pi), "
                           f"{num_cycles} needed: run longer or ask for fewer cycles")
    return start_cycle * ENGINE_CYCLE, end_cycle * ENGINE_CYCLE


def window_samples(crank_angle, values, theta_a, theta_b):
    """The samples of `values` (one per step, or (num_steps, n)) over the crank-angle window
    [theta_a, theta_b], with linearly interpolated samples added at both ends.

    The window starts at the last upward crossing of theta_a (an early rocking of the crank
    before it settles is skipped) and ends at the first crossing of theta_b after that.
    Returns (theta, values) of the window, theta[0] = theta_a and theta[-1] = theta_b.
    """
    theta = np.asarray(crank_angle, dtype=float)
    values = np.asarray(values, dtype=float)
    below = np.flatnonzero(theta < theta_a)
    i = below[-1] if below.size else 0
    after = np.flatnonzero(theta[i + 1:] >= theta_b)
    if theta[i] > theta_a or not after.size:
        raise ResultsError(f"crank angle window [{theta_a:.6g}, {theta_b:.6g}] rad is not "
                           f"covered by the run ({theta.min():.6g} .. {theta[-1]:.6g} rad)")
    j = i + 1 + after[0]

    def at(k, target):
        w = (target - theta[k]) / (theta[k + 1] - theta[k])
        return values[k] + w * (values[k + 1] - values[k])

    inner = slice(i + 1, j)
    window_theta = np.concatenate([[theta_a], theta[inner], [theta_b]])
    window_values = np.concatenate([np.asarray(at(i, theta_a))[None], values[inner],
                                    np.asarray(at(j - 1, theta_b))[None]])
    return window_theta, window_values


def angle_mean(theta, values):
    """Mean of values over crank angle, (1 / (theta_b - theta_a)) int values d theta, by the
    trapezoidal rule on the samples (theta from window_samples)."""
    theta = np.asarray(theta, dtype=float)
    values = np.asarray(values, dtype=float)
    integral = np.sum(0.5 * (values[1:] + values[:-1]) * np.diff(theta))
    return float(integral / (theta[-1] - theta[0]))
