#!/usr/bin/env python3
"""IFToMM / MBS benchmark A01, the simple pendulum (input/iftomm_a01_pendulum.nml), against the
exact solution (issue 24, item 4).

Reference: the physical pendulum released at rest from phi_0 = pi/2 (phi from the downward
vertical), I_p = m L^2 + I_c, omega_0^2 = m g L / I_p, k = sin(phi_0 / 2):
    sin(phi / 2) = k sn(K(k) - omega_0 t, k)
(Jacobi's elliptic function, scipy.special.ellipj; the closed form, not a numerical
integration), so the mass is at x = 2 L k sn dn, y = -L (1 - 2 k^2 sn^2).

Runs the driver at h = 1e-3 s (the case) and 5e-4 s (--set), 10 s, and asserts
  - the benchmark's high-precision criterion: |x - x_ref|, |y - y_ref| <= 1e-3 m at every
    recorded step (the benchmark measures 4000 outputs over 2000 s; this is its first 10 s);
  - second order: log2(e(h) / e(h/2)) = 2 +- 0.2 for the largest position error;
  - the mechanical energy T + m g y from the energy and position sensors: its largest change
    below 1e-4 m g L at h = 1e-3 s (measured 7.5e-6; generalized-alpha with rho_inf = 0.9
    keeps the energy of this slow motion to O(h^2): 1.9e-6 at h/2).
Measured: position errors 1.18e-4 m and 2.94e-5 m, order 2.000.

Further arguments are --set overrides for both runs: regression_iftomm_a01_index2 runs the
stabilized index-2 formulation without numerical damping (integrator.constraints=index2,
integrator.rho_inf=1; docs/theory.md 4.6) under the same assertions. Measured: position errors
8.92e-5 m and 2.23e-5 m, order 2.00; energy change 5.1e-6 m g L (h = 1e-3 s).

    check_iftomm_pendulum.py DRIVER CASE MESH_DIR WORK_DIR [GROUP.KEY=VALUE ...]
"""
import math
import sys

import h5py
import numpy as np
from scipy.special import ellipj, ellipk

from iftomm_common import arguments, check, check_order, finish, run_driver

MASS, LENGTH, GRAVITY, INERTIA_C = 1.0, 1.0, 9.81, 1.0e-8
PHI_0 = math.pi / 2.0
HIGH_PRECISION = 1.0e-3  # m, the benchmark's allowed error

def reference(t):
    """Exact position of the mass at times t (module docstring)."""
    omega_0 = math.sqrt(MASS * GRAVITY * LENGTH / (MASS * LENGTH**2 + INERTIA_C))
    k = math.sin(PHI_0 / 2.0)
    sn, _, dn, _ = ellipj(ellipk(k * k) - omega_0 * t, k * k)
    return 2.0 * LENGTH * k * sn * dn, -LENGTH * (1.0 - 2.0 * k * k * sn * sn)


def run(driver, case, mesh_dir, work, name, h, sets=()):
    out = run_driver(driver, case, mesh_dir, work, name, [f"integrator.h={h}", *sets])
    with h5py.File(out, "r") as f:
        t = f["/time/t"][()]
        position = f["/sensors/P1"][()]
        energy = f["/sensors/energy"][()]
    x_ref, y_ref = reference(t)
    error = max(np.max(np.abs(position[:, 0] - x_ref)), np.max(np.abs(position[:, 1] - y_ref)))
    mechanical = energy[:, 0] + MASS * GRAVITY * position[:, 1]
    drift = np.max(np.abs(mechanical - mechanical[0])) / (MASS * GRAVITY * LENGTH)
    print(f"       {name}: h = {h} s, {len(t)} steps to t = {t[-1]:.6f} s, largest position "
          f"error {error:.3e} m, largest energy change {drift:.3e} m g L")
    return error, drift


def main():
    driver, case, mesh_dir, work = arguments()
    sets = sys.argv[5:]
    error_h, drift_h = run(driver, case, mesh_dir, work, "a01_h", 1.0e-3, sets)
    error_h2, _ = run(driver, case, mesh_dir, work, "a01_h2", 5.0e-4, sets)
    check(error_h <= HIGH_PRECISION, f"h = 1e-3 s: position error {error_h:.3e} m <= 1e-3 m "
          "(the benchmark's high precision)")
    check_order(error_h, error_h2, "the position error", 0.2)
    check(drift_h <= 1.0e-4, f"h = 1e-3 s: energy change {drift_h:.3e} m g L <= 1e-4 m g L")
    return finish()


if __name__ == "__main__":
    sys.exit(main())
