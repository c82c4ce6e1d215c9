#!/usr/bin/env python3
"""The 6-dof bushing (&bushing, src/mbs/bushing.f90) against independent references (issue 24,
item 1).

input/bushing_mass.nml: a rigid block (m = 2 kg, principal inertia J = (0.01, 0.02, 0.03)
kg m^2 at its centre) held only by an undamped bushing at its centre, K = (200, 800, 1800) N/m
and K_r = (2.25, 12.5, 36.75) N m/rad, started at rest position with v = omega = 0.01 in every
direction: six uncoupled oscillators to first order in the amplitude (<= 1e-3 m, 6.7e-4 rad).
Reference: x_i(t) = (v0 / w_i) sin(w_i t), w_i = sqrt(k_i / m) = 10, 20, 30 rad/s and
sqrt(k_r,i / J_i) = 15, 25, 35 rad/s. Asserts, at h = 5e-4 s over 1 s:
  - the period of each of the six deflections (zero crossings) within 1e-4 of 2 pi / w_i
    (generalized-alpha's period error ~ (w h)^2: measured 2e-6 .. 3.2e-5),
  - each amplitude within 1e-3 of v0 / w_i (measured <= 2.8e-4: the rotations' second-order
    coupling and the scheme's amplitude error),
  - T + e^T K e / 2 conserved to 1e-5 (measured 5.6e-7; no damping), and the results file's
    external work W (/energy/external_work) equal to -(U - U_0) to 1e-4 of E_0 (trapezoid
    quadrature; measured 2.6e-5): the bushing is conservative,
  - the sensor's forces and moments equal -K e to 1e-12 of max |K e| (no damping).
A damped bushing's C = -dQ/dv and every tangent are compared with central differences in
tests/unit/test_mbs_tangents.f90.

    check_bushings.py DRIVER CASE MESH_DIR WORK_DIR
"""
import math
import os
import subprocess
import sys

import h5py
import numpy as np

from oscillator_checks import crossing_period

STIFFNESS = np.array([200.0, 800.0, 1800.0, 2.25, 12.5, 36.75])
INERTIA = np.array([2.0, 2.0, 2.0, 0.01, 0.02, 0.03])
START = 0.01

failures = []


def check(ok, what):
    print(("ok     " if ok else "FAILED ") + what)
    if not ok:
        failures.append(what)


def main():
    driver, case, mesh_dir, work = sys.argv[1:5]
    os.makedirs(work, exist_ok=True)
    proc = subprocess.run([driver, case, "--mesh-dir", mesh_dir, "--output-dir", work,
                           "--output", "bushing.h5"], capture_output=True, text=True)
    check(proc.returncode == 0, f"driver exit {proc.returncode} {proc.stderr.strip()}")
    if proc.returncode != 0:
        return 1
    with h5py.File(os.path.join(work, "bushing.h5"), "r") as f:
        t = f["/time/t"][()]
        sensor = f["/sensors/mount"][()]
        kinetic = f["/sensors/energy"][()][:, 0]
        work_done = f["/energy/external_work"][()]
    omega = np.sqrt(STIFFNESS / INERTIA)
    names = ["x", "y", "z", "rx", "ry", "rz"]
    for i in range(6):
        u = sensor[:, i]
        period, count = crossing_period(t, u, skip_first=True)
        expected = 2.0 * math.pi / omega[i]
        amplitude = np.max(np.abs(u))
        print(f"       {names[i]}: period {period:.7f} s, closed form {expected:.7f} s "
              f"({count} crossings); amplitude {amplitude:.6e}, v0/w {START / omega[i]:.6e}")
        check(abs(period / expected - 1.0) <= 1.0e-4,
              f"{names[i]}: period within 1e-4 of 2 pi / w = {expected:.6f} s "
              f"(relative difference {period / expected - 1.0:.2e})")
        check(abs(amplitude * omega[i] / START - 1.0) <= 1.0e-3,
              f"{names[i]}: amplitude within 1e-3 of v0 / w "
              f"(relative difference {amplitude * omega[i] / START - 1.0:.2e})")
    potential = 0.5 * np.sum(STIFFNESS * sensor[:, :6]**2, axis=1)
    total = kinetic + potential
    change = np.max(np.abs(total - total[0])) / total[0]
    print(f"       T + e^T K e / 2: largest change {change:.3e} of E_0 = {total[0]:.6e} J")
    check(change <= 1.0e-5, f"energy conserved to 1e-5, got {change:.3e}")
    mismatch = np.max(np.abs(work_done + (potential - potential[0]))) / total[0]
    print(f"       /energy/external_work against -(U - U_0): {mismatch:.3e} of E_0")
    check(mismatch <= 1.0e-4, f"external work is the bushing's work to 1e-4 of E_0, got "
          f"{mismatch:.3e}")
    elastic = STIFFNESS * sensor[:, :6]
    force_error = np.max(np.abs(sensor[:, 6:] + elastic)) / np.max(np.abs(elastic))
    print(f"       sensor forces against -K e: {force_error:.2e}")
    check(force_error <= 1.0e-12, f"sensor forces equal -K e to 1e-12, got {force_error:.2e}")
    print(f"{len(failures)} failure(s)")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
