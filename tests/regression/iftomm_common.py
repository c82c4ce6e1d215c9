"""Shared by the IFToMM benchmark checks (tests/regression/check_iftomm_*.py): the pass/fail
record and one driver run."""
import math
import os
import subprocess
import sys

failures = []


def check(ok, what):
    """Print and record one assertion."""
    print(("ok     " if ok else "FAILED ") + what)
    if not ok:
        failures.append(what)


def run_driver(driver, case, mesh_dir, work, name, sets=()):
    """Run the driver on CASE with --set overrides into WORK/NAME.h5; its path. A failed run is
    recorded and ends the check (exit 1)."""
    command = [driver, case, "--mesh-dir", mesh_dir, "--output-dir", work,
               "--output", name + ".h5"]
    for value in sets:
        command += ["--set", value]
    proc = subprocess.run(command, capture_output=True, text=True)
    check(proc.returncode == 0, f"{name}: driver exit {proc.returncode} {proc.stderr.strip()}")
    if proc.returncode != 0:
        sys.exit(1)
    return os.path.join(work, name + ".h5")


def finish():
    """Print the number of failures; the exit code."""
    print(f"{len(failures)} failure(s)")
    return 1 if failures else 0


def arguments():
    """DRIVER CASE MESH_DIR WORK_DIR from the command line; WORK_DIR is created."""
    driver, case, mesh_dir, work = sys.argv[1:5]
    os.makedirs(work, exist_ok=True)
    return driver, case, mesh_dir, work


def check_order(coarse, fine, what, tolerance, ratio=2.0, at_least=False):
    """Order of convergence from the errors at step ratio * h and h, asserted 2 +- tolerance
    (at_least: asserted >= 2 - tolerance, for a drift that may fall faster)."""
    order = math.log(coarse / fine) / math.log(ratio)
    print(f"       order of {what}: {order:.3f}")
    if at_least:
        check(order >= 2.0 - tolerance, f"order {order:.3f} >= {2.0 - tolerance:g}")
    else:
        check(abs(order - 2.0) <= tolerance, f"second order: {order:.3f} = 2 +- {tolerance:g}")
    return order
