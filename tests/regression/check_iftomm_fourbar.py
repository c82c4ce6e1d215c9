#!/usr/bin/env python3
"""IFToMM / MBS benchmark A02, the N-four-bar mechanism (input/iftomm_a02_fourbar.nml, N = 1;
input/iftomm_a02_fourbar_n40.nml, the benchmark's N = 40), against the exact solution (issue 24,
item 4).

Reference: the benchmark publishes B0's history as a data file (A02_solution_data.txt, lim.ii.
udc.es/mbsbenchmark), not available here; this check uses the exact solution instead. Every
window stays a parallelogram (the cranks turn by one angle theta, the couplers translate), so
the mechanism is one rotating pendulum: with m = 1 kg, L = 1 m,
    T = I theta'^2 / 2, I = (N + 1) m L^2 / 3 + N m L^2,   V = K sin(theta), K = g m L (3N + 1) / 2
(theta from +x; N + 1 cranks with their centres at L/2, N couplers at L). From theta = pi/2,
theta' = -1 rad/s, with alpha = pi/2 - theta, w^2 = K / I, k^2 = 4 w^2 / (1 + 4 w^2),
s = sqrt(1 + 4 w^2):  alpha'^2 = 1 + 4 w^2 sin^2(alpha / 2), so
    alpha / 2 - pi / 2 = am(s t / 2 - K(k), k),   alpha' = s dn(s t / 2 - K(k), k)
(scipy.special.ellipj, the closed form; the crank turns over the top at every revolution, the
links lie on the ground line at theta = 0 and -pi, the singular configurations).
B0 = L (cos theta, sin theta), its velocity theta' L (-sin theta, cos theta).

Asserts at every recorded step the benchmark's high precision, 1e-3 on B0's x and y (m) and
their rates (m/s), at the finest step run, and with two steps the order of the largest
position error, 2 +- 0.2. Measured (N = 1, 10 s, ten singular passes): position 2.00e-4 m,
velocity 1.39e-3 m/s at h = 1e-3 s, 5.00e-5 m and 3.47e-4 m/s at 5e-4 s (order 2.001); N = 40,
1.3 s at h = 2e-3 s: 1.15e-4 m, 6.89e-4 m/s; see docs/validation.md "Multibody benchmark
problems".

    check_iftomm_fourbar.py DRIVER CASE MESH_DIR WORK_DIR [--t-end T] [--steps H1,H2,...]
"""
import argparse
import math
import os
import re
import sys

import h5py
import numpy as np
from scipy.special import ellipj, ellipk

from iftomm_common import check, check_order, finish, run_driver

GRAVITY = 9.81
HIGH_PRECISION = 1.0e-3  # the benchmark's allowed error, m and m/s

def reference(t, windows):
    """Exact position and velocity of B0 at times t (module docstring), m = 1 kg, L = 1 m."""
    inertia = (windows + 1) / 3.0 + windows
    stiffness = GRAVITY * (3 * windows + 1) / 2.0
    w2 = stiffness / inertia
    m = 4.0 * w2 / (1.0 + 4.0 * w2)
    s = math.sqrt(1.0 + 4.0 * w2)
    _, _, dn, amplitude = ellipj(s * t / 2.0 - ellipk(m), m)
    theta = math.pi / 2.0 - 2.0 * (amplitude + math.pi / 2.0)
    rate = -s * dn
    return (np.cos(theta), np.sin(theta), -np.sin(theta) * rate, np.cos(theta) * rate)


def run(args, windows, name, h):
    sets = [f"integrator.h={h}"]
    if args.t_end:
        sets.append(f"integrator.t_end={args.t_end}")
    out = run_driver(args.driver, args.case, args.mesh_dir, args.work, name, sets)
    with h5py.File(out, "r") as f:
        t = f["/time/t"][()]
        position = f["/sensors/B0"][()]
        velocity = f["/sensors/B0_velocity"][()]
    x, y, vx, vy = reference(t, windows)
    position_error = max(np.max(np.abs(position[:, 0] - x)), np.max(np.abs(position[:, 1] - y)))
    velocity_error = max(np.max(np.abs(velocity[:, 0] - vx)),
                         np.max(np.abs(velocity[:, 1] - vy)))
    print(f"       {name}: N = {windows}, h = {h} s, {len(t)} steps to t = {t[-1]:.6f} s, "
          f"largest error of B0: position {position_error:.3e} m, velocity "
          f"{velocity_error:.3e} m/s")
    return position_error, velocity_error


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("driver")
    parser.add_argument("case")
    parser.add_argument("mesh_dir")
    parser.add_argument("work")
    parser.add_argument("--t-end", type=float, default=None)
    parser.add_argument("--steps", default="1e-3,5e-4")
    args = parser.parse_args()
    os.makedirs(args.work, exist_ok=True)
    with open(args.case, encoding="utf-8") as f:
        windows = len(re.findall(r"name = 'coupler\d+'", f.read()))
    steps = [float(h) for h in args.steps.split(",")]
    errors = [run(args, windows, f"a02_n{windows}_{i}", h) for i, h in enumerate(steps)]
    position_error, velocity_error = errors[-1]
    check(position_error <= HIGH_PRECISION, f"h = {steps[-1]:g} s: B0 position error "
          f"{position_error:.3e} m <= 1e-3 m (the benchmark's high precision)")
    check(velocity_error <= HIGH_PRECISION, f"h = {steps[-1]:g} s: B0 velocity error "
          f"{velocity_error:.3e} m/s <= 1e-3 m/s (the benchmark's high precision)")
    if len(steps) > 1:
        check_order(errors[-2][0], errors[-1][0], "the position error", 0.2,
                    steps[-2] / steps[-1])
    return finish()


if __name__ == "__main__":
    sys.exit(main())
