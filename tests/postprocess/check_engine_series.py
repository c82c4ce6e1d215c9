#!/usr/bin/python3
"""Read the engine results files that the Fortran writer (src/app/engine/results.f90) left in a
folder, via tests/unit/test_io_engine_results, with postprocess/ffrf_results.read_engine and
engine_summary.py: the writer follows the schema the Python side expects.

Files (written by test_io_engine_results, steps k = 0 .. n-1, t = k * 1e-3 s):
- test_io_engine_results_complete.h5: 1234 steps, status 'complete', stages setup 0.25 s,
  integration 1.5 s, total 1.75 s;
- test_io_engine_results_killed.h5: a byte copy taken after 550 steps with 100 steps per flush,
  what a killed run leaves: 500 steps, status 'running', no /timings.
Checks: t is exact (k * 1e-3 is one IEEE multiplication on both sides); the crank angle and
speed match the analytic functions the test wrote (W0 t + 0.05 sin(2 pi t), W0 + 0.1 pi
cos(2 pi t)) to 1e-12 relative (sin/cos of two libms); units and shapes seen by h5py; label,
timings and wall time (exact); the killed file refused without allow_incomplete (message names
the status and the flag) and read with it (500 steps, labelled incomplete); engine_summary.py
runs on the complete file and reports 1234 steps, status complete, wall time 1.75 s and a mean
speed within the oscillation amplitude 0.1 pi of W0 = 150 rad/s.
"""
import argparse
import csv
import math
import os
import subprocess
import sys
import tempfile

import h5py
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "..", "postprocess"))
import ffrf_results  # noqa: E402

W0 = 150.0
DT = 1.0e-3
PREFIX = "test_io_engine_results"

failures = []


def check(what, condition):
    print(f"{'ok  ' if condition else 'FAIL'} {what}")
    if not condition:
        failures.append(what)


def close(a, b, rtol):
    return np.allclose(a, b, rtol=rtol, atol=0.0)


def check_complete(path):
    run = ffrf_results.read_engine(path)
    n = 1234
    t = np.arange(n) * DT
    check(f"complete: status {run.status!r}", run.status == "complete" and run.complete)
    check(f"complete: {run.num_steps} steps (expected {n})", run.num_steps == n)
    check("complete: t exact", np.array_equal(run.t, t))
    check("complete: crank angle analytic (1e-12)",
          close(run.crank_angle, W0 * t + 0.05 * np.sin(2 * math.pi * t), 1e-12))
    check("complete: crank speed analytic (1e-12)",
          close(run.crank_speed, W0 + 0.1 * math.pi * np.cos(2 * math.pi * t), 1e-12))
    check("complete: pressure present, finite, >= 1e5 Pa",
          run.pressure is not None and np.all(run.pressure >= 1e5))
    check(f"complete: label {run.label!r}", run.label == "RC set 2, RBE3")
    check(f"complete: case {run.case_name!r}, title {run.title!r}",
          run.case_name == "series_test" and run.title == "synthetic engine series")
    check(f"complete: timings {run.timings}",
          run.timings == {"setup": 0.25, "integration": 1.5, "total": 1.75})
    check(f"complete: wall time {run.wall_time}", run.wall_time == 1.75)
    with h5py.File(path, "r") as f:
        units = {name: ffrf_results.text(f[name].attrs["units"]) for name in
                 ["time/t", "time/crank_angle", "time/crank_speed", "time/pressure",
                  "energy/kinetic", "energy/strain", "energy/external_work",
                  "energy/numerical_dissipation"]}
        check(f"complete: units {units}", list(units.values()) ==
              ["s", "rad", "rad/s", "Pa", "J", "J", "J", "J"])
        shapes = {name: f[name].shape for name in
                  ["bodies/crank/modal_coordinates", "bodies/rod/modal_coordinates",
                   "joints/main_bearing/reaction", "joints/piston_pin/reaction"]}
        check(f"complete: h5py shapes {shapes}", list(shapes.values()) ==
              [(n, 3), (n, 2), (n, 12), (n, 12)])
        check("complete: /input/namelist echo", "input/namelist" in f)


def check_killed(path):
    try:
        ffrf_results.read_engine(path)
        check("killed: refused without allow_incomplete", False)
    except ffrf_results.ResultsError as error:
        message = str(error)
        check(f"killed: refused, message names status and flag: {message}",
              "'running'" in message and "--allow-incomplete" in message)
    run = ffrf_results.read_engine(path, allow_incomplete=True)
    check(f"killed: {run.num_steps} steps (expected the 500 flushed)", run.num_steps == 500)
    check("killed: t exact", np.array_equal(run.t, np.arange(500) * DT))
    check(f"killed: status {run.status!r}, label {run.label!r}",
          run.status == "running" and not run.complete and run.label.endswith(
              "(incomplete: running)"))
    check(f"killed: no timings ({run.timings}, {run.wall_time})",
          run.timings == {} and run.wall_time is None)


def check_summary(script, path, killed):
    with tempfile.TemporaryDirectory() as folder:
        table = os.path.join(folder, "summary.csv")
        result = subprocess.run([sys.executable, script, path, "--csv", table],
                                capture_output=True, text=True)
        check(f"engine_summary.py runs on the complete file (rc {result.returncode}) "
              f"{result.stderr.strip()}", result.returncode == 0)
        if result.returncode != 0:
            return
        with open(table, newline="") as stream:
            rows = list(csv.DictReader(stream))
        row = rows[0]
        mean = float(row["mean speed [rad/s]"])
        check(f"summary: {row['steps']} steps, status {row['status']}, wall "
              f"{row['wall time [s]']} s", len(rows) == 1 and int(row["steps"]) == 1234 and
              row["status"] == "complete" and float(row["wall time [s]"]) == 1.75)
        check(f"summary: mean speed {mean} rad/s within 0.1 pi of {W0}",
              abs(mean - W0) <= 0.1 * math.pi)
    result = subprocess.run([sys.executable, script, killed], capture_output=True, text=True)
    check("engine_summary.py refuses the killed file without --allow-incomplete",
          result.returncode != 0 and "allow-incomplete" in result.stderr)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("folder", help="the folder test_io_engine_results wrote to")
    parser.add_argument("--summary-script", required=True, help="postprocess/engine_summary.py")
    args = parser.parse_args()
    complete = os.path.join(args.folder, f"{PREFIX}_complete.h5")
    killed = os.path.join(args.folder, f"{PREFIX}_killed.h5")
    check_complete(complete)
    check_killed(killed)
    check_summary(args.summary_script, complete, killed)
    if failures:
        print(f"{len(failures)} check(s) failed")
        return 1
    print("all checks passed")
    return 0


if __name__ == "__main__":
    sys.exit(main())
