#!/usr/bin/env python3
"""A results file read while its run is going (issue 29 item 3; docs/results.md "Output rate,
peaks, compression, size").

Usage: check_live_read.py FFRF CASE MESH_DIR WORK

Runs CASE (a mechanism) compressed (`&output compression = 4`), decimated (`every_steps = 3`)
and checkpointed every 50 steps, to a t_end it does not reach. While it runs:
  1. the checkpoint copy `<output>.checkpoint` opens with the project's reader
     (ffrf_results.open_results, status 'running') and holds at least two rows;
  2. the file the writer holds, `<output>.part`, opens with h5py in a second process when
     HDF5_USE_FILE_LOCKING=FALSE (docs/results.md says so) and holds at least as many rows.
Then the run is stopped by SIGTERM (exit 5, status 'interrupted: ...') and every series row the
checkpoint held equals the finished file's row, exactly: what was read mid-run was right.
"""
import os
import shutil
import signal
import subprocess
import sys
import time

import h5py
import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..",
                                "postprocess"))
import ffrf_results  # noqa: E402

FAILURES = []


def check(ok, text):
    print(f"{'ok  ' if ok else 'FAIL'} {text}")
    if not ok:
        FAILURES.append(text)


def series(path):
    """Every dataset under /time, /energy and /bodies/*/ that grows with the rows: name -> array
    (rows first, as h5py sees the Fortran layout), and the row count of /time/t."""
    out = {}
    with h5py.File(path, "r") as f:
        rows = f["/time/t"].shape[0]

        def visit(name, obj):
            if (isinstance(obj, h5py.Dataset) and name.split("/")[0] in ("time", "energy",
                                                                         "bodies", "joints")
                    and obj.ndim >= 1 and obj.shape[0] == rows and obj.maxshape[0] is None):
                out[name] = obj[()]
        f.visititems(visit)
    return out, rows


def main():
    if len(sys.argv) != 5:
        raise SystemExit(__doc__)
    ffrf, case, mesh_dir, work = sys.argv[1:]
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    results = os.path.join(work, "live.h5")
    command = [ffrf, case, "--mesh-dir", mesh_dir, "--output-dir", work, "--output", "live.h5",
               "--set", "output.compression=4", "--set", "output.every_steps=3",
               "--set", "integrator.t_end=1000.0", "--set", "integrator.checkpoint_steps=50",
               "--set", "integrator.checkpoint_seconds=0.0", "--set", "mechanism.animation_frames=0"]
    run = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    checkpoint = results + ".checkpoint"
    live_rows = 0
    deadline = time.monotonic() + 120.0
    try:
        while time.monotonic() < deadline and run.poll() is None:
            time.sleep(0.2)
            if not os.path.exists(checkpoint):
                continue
            try:
                with ffrf_results.open_results(checkpoint, require_complete=False) as r:
                    live_status = r.status
                    live_rows = r.file["/time/t"].shape[0]
            except (ffrf_results.ResultsError, OSError, KeyError):
                continue  # being renamed into place: try again
            if live_rows >= 2:
                break
        running = run.poll() is None
        check(running and live_rows >= 2, f"the checkpoint copy read mid-run by ffrf_results: "
              f"{live_rows} rows, run still going: {running}")
        if not running:
            print(run.stderr)
            return
        check(live_status == "running", f"its status while running: '{live_status}'")
        # the checkpoint kept apart: the run replaces it at its next checkpoint
        kept = os.path.join(work, "kept_checkpoint.h5")
        shutil.copyfile(checkpoint, kept)
        kept_series, kept_rows = series(kept)
        probe = subprocess.run(
            [sys.executable, "-c", "import h5py, sys; f = h5py.File(sys.argv[1], 'r'); "
             "print(f['/time/t'].shape[0])", results + ".part"],
            env=dict(os.environ, HDF5_USE_FILE_LOCKING="FALSE"), capture_output=True, text=True)
        part_rows = int(probe.stdout) if probe.returncode == 0 else -1
        check(part_rows >= kept_rows, f"the .part file read mid-run by h5py without HDF5's lock: "
              f"{part_rows} rows (checkpoint {kept_rows}) {probe.stderr.strip()[-200:]}")
    finally:
        if run.poll() is None:
            run.send_signal(signal.SIGTERM)
        _, stderr = run.communicate(timeout=120)
    check(run.returncode == 5, f"SIGTERM ends the run with exit 5: {run.returncode}")
    with ffrf_results.open_results(results, require_complete=False) as r:
        final_status = r.status
    check(final_status.startswith("interrupted"), f"final status '{final_status}'")
    final_series, final_rows = series(results)
    check(final_rows >= kept_rows and len(kept_series) > 5,
          f"{len(kept_series)} series, {kept_rows} rows mid-run, {final_rows} at the end")
    differ = [name for name, rows in kept_series.items()
              if name not in final_series
              or not np.array_equal(rows, final_series[name][:kept_rows], equal_nan=True)]
    check(not differ, f"the rows read mid-run equal the finished file's, exactly: "
          f"{len(kept_series) - len(differ)} of {len(kept_series)} series {differ[:5]}")


if __name__ == "__main__":
    main()
    if FAILURES:
        print(f"{len(FAILURES)} failure(s)")
        sys.exit(1)
    print("all checks passed")
