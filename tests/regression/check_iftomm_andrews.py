#!/usr/bin/env python3
"""IFToMM / MBS benchmark A03, Andrews' squeezing mechanism (input/iftomm_a03_andrews.nml),
against the published reference solution at t = 0.03 s (issue 24, item 4).

Reference: the IVP test set of Mazzia & Magherini (Universita di Bari, release 2.4, problem
"Andrews' squeezing mechanism", andrews.f, subroutine SOLN; the DAE of Hairer & Wanner, Solving
ODEs II, sec. VII.7): the seven angles (beta, Theta, gamma, Phi, delta, Omega, epsilon) and their
rates at t = 0.03 s, computed by the test set's authors with RADAU5 at tight tolerances and
given to 16 digits (below). The test set's consistent initial angles are those of the case.

The angles come from the bodies' orientation sensors (each body frame is parallel to the global
axes at the start, so a body's rotation about z, unwrapped over the steps, is its absolute angle
less the starting one) and the rates from the angular-velocity sensors:
  beta = crank, Theta = rod_FE - crank, gamma = triangle_BDE, delta = rod_AG,
  Phi = rod_GE - rod_AG, epsilon = rod_AH, Omega = rod_HE - rod_AH (absolute angles).

Runs the driver at h = 2e-5 s (--set) and 1e-5 s (the case) to t = 0.03 s and asserts at
h = 1e-5 s
  - every angle within 5e-4 rad of the reference (the crank turns 15.9 rad in 0.03 s);
  - every rate within 1e-2 max(1, |rate|) of the reference (the crank reaches 1140 rad/s);
  - second order: log2(e(2h) / e(h)) = 2 +- 0.1 for the largest angle error.
The benchmark's own allowed error for A03 (lim.ii.udc.es/mbsbenchmark) was not found in the
sources available; these tolerances are ffrf's (docs/validation.md "Multibody benchmark
problems"). Measured: largest angle error 1.78e-4 rad (Theta; beta 1.42e-4) at h = 1e-5 s,
7.11e-4 at 2e-5 s (order 2.00), 4.44e-5 at 5e-6 s; largest relative rate error 3.7e-3.

    check_iftomm_andrews.py DRIVER CASE MESH_DIR WORK_DIR
"""
import sys

import h5py
import numpy as np

from iftomm_common import arguments, check, check_order, finish, run_driver

# The test set's consistent initial angles (andrews.f, subroutine INITIAL)
START = {"beta": -0.0617138900142764496358948458001, "Theta": 0.0,
         "gamma": 0.455279819163070380255912382449, "Phi": 0.222668390165885884674473185609,
         "delta": 0.487364979543842550225598953530, "Omega": -0.222668390165885884674473185609,
         "epsilon": 1.23054744454982119249735015568}
NAMES = ("beta", "Theta", "gamma", "Phi", "delta", "Omega", "epsilon")
# The reference solution at t = 0.03 s (andrews.f, subroutine SOLN, y(1..14))
ANGLES = (0.1581077119629904e+2, -0.1575637105984298e+2, 0.4082224013073101e-1,
          -0.5347301163226948e+0, 0.5244099658805304e+0, 0.5347301163226948e+0,
          0.1048080741042263e+1)
RATES = (0.1139920302151208e+4, -0.1424379294994111e+4, 0.1103291221937134e+2,
         0.1929337464421385e+2, 0.5735699284790808e+0, -0.1929337464421385e+2,
         0.3231791658026955e+0)
T_END = 0.03
ANGLE_TOLERANCE = 5.0e-4  # rad
RATE_TOLERANCE = 1.0e-2   # of max(1, |rate|)

def rotation(f, body):
    """Rotation of a body about z since the start, unwrapped over the recorded steps."""
    axes = f["/sensors/" + body][()]
    return np.unwrap(np.arctan2(axes[:, 1], axes[:, 0]))


def spin(f, body):
    return f["/sensors/w_" + body][()][:, 2]


def run(driver, case, mesh_dir, work, name, h):
    out = run_driver(driver, case, mesh_dir, work, name, [f"integrator.h={h}"])
    with h5py.File(out, "r") as f:
        t = f["/time/t"][()]
        s = START
        beta = s["beta"] + rotation(f, "crank")
        delta = s["delta"] + rotation(f, "rod_AG")
        epsilon = s["epsilon"] + rotation(f, "rod_AH")
        angles = (beta, s["beta"] + s["Theta"] + rotation(f, "rod_FE") - beta,
                  s["gamma"] + rotation(f, "triangle_BDE"),
                  s["Phi"] + s["delta"] + rotation(f, "rod_GE") - delta, delta,
                  s["Omega"] + s["epsilon"] + rotation(f, "rod_HE") - epsilon, epsilon)
        rates = (spin(f, "crank"), spin(f, "rod_FE") - spin(f, "crank"),
                 spin(f, "triangle_BDE"), spin(f, "rod_GE") - spin(f, "rod_AG"),
                 spin(f, "rod_AG"), spin(f, "rod_HE") - spin(f, "rod_AH"), spin(f, "rod_AH"))
    check(abs(t[-1] - T_END) <= 1.0e-12, f"{name}: run ends at t = {t[-1]:.9f} s")
    angle_errors = [abs(a[-1] - r) for a, r in zip(angles, ANGLES)]
    rate_errors = [abs(w[-1] - r) / max(1.0, abs(r)) for w, r in zip(rates, RATES)]
    print(f"       {name}: h = {h} s, {len(t)} steps; at t = {T_END} s")
    for n, a, r, ea, er in zip(NAMES, angles, rates, angle_errors, rate_errors):
        print(f"         {n:8s} {a[-1]: .10f} rad (error {ea:.2e}), rate {r[-1]: .6f} rad/s "
              f"(relative error {er:.2e})")
    return max(angle_errors), max(rate_errors)


def main():
    driver, case, mesh_dir, work = arguments()
    angle_2h, _ = run(driver, case, mesh_dir, work, "a03_2h", 2.0e-5)
    angle_h, rate_h = run(driver, case, mesh_dir, work, "a03_h", 1.0e-5)
    check(angle_h <= ANGLE_TOLERANCE, f"h = 1e-5 s: largest angle error {angle_h:.3e} rad "
          f"<= {ANGLE_TOLERANCE:g} rad")
    check(rate_h <= RATE_TOLERANCE, f"h = 1e-5 s: largest rate error {rate_h:.3e} of "
          f"max(1, |rate|) <= {RATE_TOLERANCE:g}")
    check_order(angle_2h, angle_h, "the largest angle error", 0.1)
    return finish()


if __name__ == "__main__":
    sys.exit(main())
