#!/usr/bin/env python3
"""`pip install ./postprocess` into a fresh virtual environment, then its console scripts and
reader on real results files, against the same HDF5 datasets read here with h5py (issue 26
item 3; docs/results.md "Python package" and "Schema version").

    check_package.py --source postprocess --work DIR --modal crank_lc8_rc2.h5
                     --mechanism slider_wheel.h5 [--engine engine_lc8_rc1.h5]

Checks (references: h5py on the same file, so the expected numbers are the file's own bits):
- the venv (--system-site-packages, Debian's numpy/h5py/matplotlib/setuptools) installs the
  package offline (--no-index --no-build-isolation --no-deps) from a copy of pyproject.toml,
  README.md and ffrf_results/ (the source tree stays clean), with six console scripts, and
  `import ffrf_results` there comes from the venv, not from postprocess/;
- modal crank: ffrf-frequency-table's CSV and ffrf-gather's CSV hold the frequencies of
  /bodies/<body>/modes/frequency exactly (CSV cells are round-trip reprs: equality, no
  tolerance), ffrf-plot-modes writes a real PNG; the old entry point
  postprocess/frequency_table.py writes the same CSV bytes (one implementation);
- mechanism: ffrf-plot-sensors' CSV equals /time/t and every /sensors/<name> exactly (its
  %.18e cells carry 19 significant digits: a double's round trip); ffrf-plot-engine and
  ffrf-engine-summary run on the engine file (steps column = len(/time/t));
- ffrf_results.load, run inside the venv, gives status, schema_version, the input echo,
  frequencies, shapes ((num_modes, num_nodes, 3) of /modes/shape), time series and sensors
  equal to h5py's (bitwise);
- schema_version: the files say "1.0"; a copy with "99.0" is refused by ffrf-frequency-table
  and ffrf-plot-sensors (exit 2, one line: the message naming the version and what to
  install) and by load (SchemaError); a copy without the attribute reads as "0.x" with the
  same frequencies (console script and load); "1.7" (a newer minor) reads; "one" is refused
  as not MAJOR.MINOR.
Exit 77 (ctest skip) only when the interpreter has no venv/ensurepip (Debian: python3-venv).
"""
import argparse
import csv
import os
import shutil
import subprocess
import sys
import time

import h5py
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
SCRIPTS = ["ffrf-plot-engine", "ffrf-plot-modes", "ffrf-plot-sensors", "ffrf-engine-summary",
           "ffrf-frequency-table", "ffrf-gather"]
NEWER_MESSAGE = "schema_version 99.0 is newer than this reader"
failures = []


def check(condition, what, detail=""):
    print(("ok   " if condition else "FAIL ") + what + (f" ({detail})" if detail and
                                                         not condition else ""))
    if not condition:
        failures.append(what)


def run(command, cwd, expect_ok=True):
    start = time.perf_counter()
    result = subprocess.run(command, cwd=cwd, capture_output=True, text=True, timeout=120,
                            env=dict(os.environ, MPLBACKEND="Agg"))
    print(f"  [{time.perf_counter() - start:.1f} s] {os.path.basename(command[0])} "
          f"{os.path.basename(command[1]) if len(command) > 1 else ''}")
    if expect_ok and result.returncode != 0:
        print(f"  {' '.join(command)}: exit {result.returncode}\n{result.stdout}{result.stderr}")
    return result


def text(value):
    if isinstance(value, np.ndarray) and value.shape == ():
        value = value[()]
    return bytes(value).rstrip(b"\0").decode() if isinstance(value, (bytes, np.bytes_)) \
        else str(value)


def with_schema(source, target, version):
    """A copy of source with root attribute schema_version set to version (None: removed),
    stored as the Fortran writer stores strings (fixed-length bytes)."""
    shutil.copyfile(source, target)
    with h5py.File(target, "r+") as f:
        if "schema_version" in f.attrs:
            del f.attrs["schema_version"]
        if version is not None:
            f.attrs["schema_version"] = np.bytes_(version)
    return target


def csv_columns(path):
    with open(path, newline="") as stream:
        rows = list(csv.reader(stream))
    return rows[0], rows[1:]


# --------------------------------------------------------------------------- inside the venv

def inside(args):
    """Run by the venv's interpreter: the installed reader against h5py."""
    import ffrf_results
    check(os.path.realpath(ffrf_results.__file__).startswith(os.path.realpath(args.venv)),
          "import ffrf_results comes from the venv", ffrf_results.__file__)
    for path in (args.modal, args.mechanism):
        data = ffrf_results.load(path)
        with h5py.File(path, "r") as f:
            name = os.path.basename(path)
            check(data.status == text(f.attrs["status"]) == "complete", f"{name}: status")
            check(data.schema_version == text(f.attrs["schema_version"]) == "1.0",
                  f"{name}: schema_version 1.0", data.schema_version)
            check(data.input == text(f["input/namelist"][()]) and "&" in data.input,
                  f"{name}: input echo")
            for body, entry in data.bodies.items():
                if f"bodies/{body}/modes/frequency" in f:
                    check(np.array_equal(entry["frequencies"],
                                         f[f"bodies/{body}/modes/frequency"][()]),
                          f"{name}: {body} frequencies bitwise")
                if f"bodies/{body}/modes/shape" in f:
                    raw = f[f"bodies/{body}/modes/shape"][()]
                    check(np.array_equal(entry["shapes"],
                                         raw.reshape(raw.shape[0], -1, 3)),
                          f"{name}: {body} shapes bitwise, {entry['shapes'].shape}")
            for series in f.get("time", {}):
                check(np.array_equal(data.time[series], f[f"time/{series}"][()]),
                      f"{name}: /time/{series} bitwise")
            for sensor in f.get("sensors", {}):
                raw = f[f"sensors/{sensor}"][()]
                check(np.array_equal(data.sensors[sensor].values.reshape(raw.shape), raw),
                      f"{name}: sensor {sensor} bitwise")
            missing = []
            f.visititems(lambda n, o: missing.append(n) if isinstance(o, h5py.Dataset)
                         and n not in data.datasets else None)
            check(not missing, f"{name}: every dataset in load().datasets", str(missing[:3]))
    try:
        ffrf_results.load(args.newer)
        check(False, "load refuses schema 99.0")
    except ffrf_results.SchemaError as exc:
        check(NEWER_MESSAGE in str(exc), "load refuses schema 99.0 (SchemaError)", str(exc))
    old = ffrf_results.load(args.unversioned)
    with h5py.File(args.modal, "r") as f:
        body = sorted(f["bodies"])[0]
        hz = f[f"bodies/{body}/modes/frequency"][()]
    check(old.schema_version == "0.x" and
          np.array_equal(old.bodies[body]["frequencies"], hz),
          "a file without schema_version reads as 0.x, same frequencies", old.schema_version)
    minor = ffrf_results.load(os.path.join(args.work, "minor.h5"))
    check(minor.schema_version == "1.7" and
          np.array_equal(minor.bodies[body]["frequencies"], hz),
          "a file of schema 1.7 (a newer minor) reads, same frequencies", minor.schema_version)
    try:
        ffrf_results.load(os.path.join(args.work, "bad.h5"))
        check(False, "schema_version 'one' refused")
    except ffrf_results.SchemaError as exc:
        check("not MAJOR.MINOR" in str(exc), "schema_version 'one' refused as not MAJOR.MINOR",
              str(exc))
    return 1 if failures else 0


# --------------------------------------------------------------------------- outside

def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--source", required=True, help="postprocess/ (pyproject.toml)")
    parser.add_argument("--work", required=True, help="scratch folder (emptied first)")
    parser.add_argument("--modal", required=True, help="results of a modal crank run")
    parser.add_argument("--mechanism", required=True, help="results of a mechanism run "
                        "with sensors")
    parser.add_argument("--engine", help="results of an engine run")
    parser.add_argument("--inside", action="store_true", help=argparse.SUPPRESS)
    parser.add_argument("--venv", help=argparse.SUPPRESS)
    parser.add_argument("--newer", help=argparse.SUPPRESS)
    parser.add_argument("--unversioned", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.inside:
        return inside(args)
    try:
        import ensurepip  # noqa: F401
        import venv  # noqa: F401
    except ImportError:
        print(f"skip: {sys.executable} has no venv/ensurepip (Debian: apt install python3-venv)")
        return 77

    work = os.path.abspath(args.work)
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    venv_dir, src = os.path.join(work, "venv"), os.path.join(work, "src")
    os.makedirs(src)
    for name in ("pyproject.toml", "README.md"):
        shutil.copyfile(os.path.join(args.source, name), os.path.join(src, name))
    shutil.copytree(os.path.join(args.source, "ffrf_results"), os.path.join(src, "ffrf_results"),
                    ignore=shutil.ignore_patterns("__pycache__"))
    result = run([sys.executable, "-m", "venv", "--system-site-packages", venv_dir], work)
    check(result.returncode == 0, "fresh venv (--system-site-packages)", result.stderr[-300:])
    python = os.path.join(venv_dir, "bin", "python")
    result = run([python, "-m", "pip", "install", "--no-index", "--no-build-isolation",
                  "--no-deps", "--disable-pip-version-check", src], work)
    check(result.returncode == 0, "pip install ./postprocess (offline)", result.stderr[-500:])
    bin_dir = os.path.join(venv_dir, "bin")
    check(all(os.access(os.path.join(bin_dir, s), os.X_OK) for s in SCRIPTS),
          "console scripts installed: " + ", ".join(SCRIPTS))
    if failures:
        return 1
    sys.path.insert(0, os.path.join(HERE, "..", "regression"))
    import check_outputs

    def png_ok(path, what):
        try:
            check_outputs.check_png(path)
            check(True, what)
        except SystemExit as exc:
            check(False, what, str(exc))

    def script(name, *arguments, expect_ok=True):
        return run([os.path.join(bin_dir, name)] + [str(a) for a in arguments], work, expect_ok)

    # modal crank
    with h5py.File(args.modal, "r") as f:
        body = sorted(f["bodies"])[0]
        hz = f[f"bodies/{body}/modes/frequency"][()]
    result = script("ffrf-frequency-table", args.modal, "--csv", "table.csv")
    header, rows = csv_columns(os.path.join(work, "table.csv"))
    check(result.returncode == 0 and [float(r[1]) for r in rows] == list(hz),
          f"ffrf-frequency-table: {len(hz)} frequencies equal h5py's exactly")
    old = run([sys.executable, os.path.join(args.source, "frequency_table.py"), args.modal,
               "--csv", "table_old.csv"], work)
    with open(os.path.join(work, "table.csv"), "rb") as a, \
            open(os.path.join(work, "table_old.csv"), "rb") as b:
        check(old.returncode == 0 and a.read() == b.read(),
              "postprocess/frequency_table.py writes the same CSV bytes")
    result = script("ffrf-gather", args.modal, "--modes", len(hz), "--csv", "gather.csv")
    header, rows = csv_columns(os.path.join(work, "gather.csv"))
    got = [float(rows[0][header.index(f"f{k + 1} [Hz]")]) for k in range(len(hz))]
    check(result.returncode == 0 and rows[0][header.index("status")] == "complete" and
          got == list(hz), "ffrf-gather: status complete, frequencies equal h5py's exactly")
    result = script("ffrf-plot-modes", args.modal, "-o", "modes.png", "--modes", "2")
    png_ok(os.path.join(work, "modes.png"), "ffrf-plot-modes: a PNG")

    # mechanism with sensors
    result = script("ffrf-plot-sensors", args.mechanism, "--output", "sensors.png", "--csv",
                    "sensors.csv")
    header, rows = csv_columns(os.path.join(work, "sensors.csv"))
    table = np.array([[float(c) for c in row] for row in rows])
    with h5py.File(args.mechanism, "r") as f:
        t = f["time/t"][()]
        expected = [t] + [np.asarray(f[f"sensors/{n}"][()]).reshape(len(t), -1).T
                          for n in f["sensors"]]
        expected = np.vstack([np.atleast_2d(e) for e in expected]).T
        num_sensors = len(f["sensors"])
    check(result.returncode == 0 and table.shape == expected.shape and
          np.array_equal(table, expected),
          f"ffrf-plot-sensors: CSV of t and {num_sensors} sensors ({table.shape[1] - 1} values, "
          f"{len(t)} samples) equals h5py's exactly")
    png_ok(os.path.join(work, "sensors.png"), "ffrf-plot-sensors: a PNG")

    if args.engine:
        result = script("ffrf-plot-engine", args.engine, "-o", "speed.png")
        png_ok(os.path.join(work, "speed.png"), "ffrf-plot-engine: a PNG")
        result = script("ffrf-engine-summary", args.engine, "--cycles", "1", "--csv",
                        "summary.csv", expect_ok=False)
        with h5py.File(args.engine, "r") as f:
            steps = len(f["time/t"])
        if result.returncode == 0:
            header, rows = csv_columns(os.path.join(work, "summary.csv"))
            column = [h for h in header if "steps" in h]
            check(bool(column) and int(rows[0][header.index(column[0])]) == steps,
                  f"ffrf-engine-summary: {steps} steps, as /time/t")
        else:
            # a short engine run holds no complete cycle: the script says so, in one line
            check("cycle" in result.stderr and result.stderr.count("\n") <= 1,
                  "ffrf-engine-summary: a run without a whole engine cycle refused in one line",
                  result.stderr)

    # schema_version
    newer = with_schema(args.modal, os.path.join(work, "newer.h5"), "99.0")
    unversioned = with_schema(args.modal, os.path.join(work, "unversioned.h5"), None)
    with_schema(args.modal, os.path.join(work, "minor.h5"), "1.7")
    with_schema(args.modal, os.path.join(work, "bad.h5"), "one")
    newer_mechanism = with_schema(args.mechanism, os.path.join(work, "newer_mech.h5"), "99.0")
    for name, arguments in (("ffrf-frequency-table", [newer]),
                            ("ffrf-plot-sensors", [newer_mechanism, "--output", "n.png"])):
        result = script(name, *arguments, expect_ok=False)
        check(result.returncode == 2 and NEWER_MESSAGE in result.stderr and
              "install the reader" in result.stderr and result.stderr.count("\n") == 1,
              f"{name} refuses schema_version 99.0 with the message", result.stderr)
    print("  message:", result.stderr.strip())
    result = script("ffrf-frequency-table", unversioned, "--csv", "v.csv")
    header, rows = csv_columns(os.path.join(work, "v.csv"))
    check(result.returncode == 0 and [float(r[1]) for r in rows] == list(hz),
          "ffrf-frequency-table reads a file without schema_version, same frequencies")

    result = run([python, os.path.abspath(__file__), "--inside", "--source", args.source,
                  "--work", work, "--modal", args.modal, "--mechanism", args.mechanism,
                  "--venv", venv_dir, "--newer", newer, "--unversioned", unversioned], work,
                 expect_ok=False)
    print(result.stdout + result.stderr, end="")
    check(result.returncode == 0, "ffrf_results.load in the venv agrees with h5py")
    if failures:
        print(f"{len(failures)} check(s) failed")
        return 1
    shutil.rmtree(venv_dir)
    print("all checks passed")
    return 0


if __name__ == "__main__":
    sys.exit(main())
