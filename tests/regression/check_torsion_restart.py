#!/usr/bin/env python3
"""A torsion spring wound whole turns continues bit for bit across --restart (issue 24: the
torsion springs' unwrapping references in the restart state, docs/restart.md "Unwrapped angles").

The multi-turn case of check_torsion_springs.py (input/torsion_pendulum.nml without damping and
free angle, started at 150 rad/s: phi(t) = (150 / w0) sin(w0 t), w0 = 10 rad/s, amplitude
15 rad = 2.4 turns) at h = 5e-4 s:
  A  straight to t_end = 0.3 s;
  B  to t_end = 0.1 s (its restart state: the step before 0.1 s, the spring wound
     15 sin(1) = 12.6 rad = 2.0 turns), then --restart to t_end = 0.3 s.
The energy watch is off in all runs: its windows start again at a restart (docs/restart.md),
so its warnings on this fast rotation (3e-4 of the energy scale) fall at other times.
Asserts
  - B's restart state holds /checkpoint/torsion_reference, wound past 1.5 turns (> 3 pi rad);
  - every entry of A's and B's results files bitwise equal (bitwise.py's digests: every dataset
    and attribute, wall-clock figures left out; /restart_origin, B's only, excepted): the
    torsion_spring sensor's unwrapped angle, every history, the energy and the final state.
    The reference is the uninterrupted run, run against run on this machine. Without the
    references in the restart state, B continues from the starting pose's reference and its
    angle falls back by 2 turns (4 pi rad) at the restart;
  - A's unwrapped angle within 1e-2 rad of (150 / w0) sin(w0 t) (a second, closed-form check
    that the runs compared are the wound ones; check_torsion_springs.py measured 2.6e-2 over 1 s
    at this h, the error grows with t);
  - a restart state without /checkpoint/torsion_reference (written before issue 24; the dataset
    deleted from a copy of B's) is refused: exit 2, one line naming the dataset and the fix.
About 2 s.

    check_torsion_restart.py DRIVER CASE MESH_DIR WORK_DIR
"""
import math
import os
import shutil
import subprocess
import sys

import h5py
import numpy as np

from bitwise import digest_h5
from check_torsion_springs import SPIN, STIFFNESS, INERTIA, check, failures, write_spin_case

H, T_STOP, T_END = 5.0e-4, 0.1, 0.3
NAME = "torsion_spin"


def run(driver, case, mesh_dir, out, t_end, extra=()):
    os.makedirs(out, exist_ok=True)
    return subprocess.run([driver, case, "--mesh-dir", mesh_dir, "--output-dir", out,
                           "--output", NAME + ".h5", "--set", f"integrator.h={H}",
                           "--set", f"integrator.t_end={t_end}",
                           "--set", "integrator.energy_watch=off", *extra],
                          capture_output=True, text=True)


def main():
    driver, case, mesh_dir, work = sys.argv[1:5]
    os.makedirs(work, exist_ok=True)
    spin_case = write_spin_case(case, work)
    if spin_case is None:
        check(False, "the case could not be edited (its text changed)")
        return 1
    straight, part = os.path.join(work, "straight"), os.path.join(work, "restart")
    for out in (straight, part):
        shutil.rmtree(out, ignore_errors=True)
    a_file, b_file = os.path.join(straight, NAME + ".h5"), os.path.join(part, NAME + ".h5")
    proc = run(driver, spin_case, mesh_dir, straight, T_END)
    check(proc.returncode == 0, f"run A to {T_END} s: exit {proc.returncode} "
          f"{proc.stderr.strip()}")
    proc = run(driver, spin_case, mesh_dir, part, T_STOP)
    check(proc.returncode == 0, f"run B to {T_STOP} s: exit {proc.returncode} "
          f"{proc.stderr.strip()}")
    if failures:
        return 1
    with h5py.File(b_file, "r") as f:
        has = "/checkpoint/torsion_reference" in f
        reference = f["/checkpoint/torsion_reference"][()] if has else np.zeros(1)
    print(f"       B's restart state: torsion_reference {reference} rad "
          f"({reference[0] / (2.0 * math.pi):.3f} turns)")
    check(has and abs(reference[0]) > 3.0 * math.pi,
          "B's restart state holds the torsion reference, wound past 1.5 turns")
    old = os.path.join(work, "old_checkpoint.h5")
    shutil.copyfile(b_file, old)
    proc = run(driver, spin_case, mesh_dir, part, T_END, ["--restart", b_file])
    check(proc.returncode == 0, f"run B --restart to {T_END} s: exit {proc.returncode} "
          f"{proc.stderr.strip()}")
    if proc.returncode != 0:
        return 1
    a, b = digest_h5(a_file), digest_h5(b_file)
    differ = sorted(key for key in set(a) | set(b)
                    if not key.startswith("restart_origin")
                    and a.get(key, {}).get("sha256") != b.get(key, {}).get("sha256"))
    for key in differ[:20]:
        print(f"       differs: {key}")
    with h5py.File(a_file, "r") as fa, h5py.File(b_file, "r") as fb:
        t, phi = fa["/time/t"][()], fa["/sensors/torsion"][:, 0]
        phi_b = fb["/sensors/torsion"][:, 0]
        jump = np.max(np.abs(phi_b - phi)) if phi_b.shape == phi.shape else math.inf
    print(f"       {len(a)} entries compared; A's angle {phi.min():.3f}..{phi.max():.3f} rad; "
          f"largest |phi_B - phi_A| {jump:.3e} rad")
    check(not differ, f"B (restarted at {T_STOP} s) equals A bitwise in every entry "
          f"({len(differ)} differ)")
    w0 = math.sqrt(STIFFNESS / INERTIA)
    error = np.max(np.abs(phi - SPIN / w0 * np.sin(w0 * t)))
    check(error <= 1.0e-2, f"A's unwrapped angle within 1e-2 rad of (w/w0) sin(w0 t), got "
          f"{error:.3e}")
    with h5py.File(old, "a") as f:
        if "/checkpoint/torsion_reference" in f:
            del f["/checkpoint/torsion_reference"]
    proc = run(driver, spin_case, mesh_dir, os.path.join(work, "refused"), T_END,
               ["--restart", old])
    message = proc.stderr.strip()
    print(f"       restart state without the references: exit {proc.returncode}: {message}")
    check(proc.returncode == 2 and "torsion_reference" in message and
          "run the case from t = 0" in message and len(message.splitlines()) == 1,
          "a restart state without torsion references is refused (exit 2, one line)")
    print(f"{len(failures)} failure(s)")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
