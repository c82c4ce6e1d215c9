#!/usr/bin/env python3
"""IFToMM / MBS benchmark A05, the stiff flyball governor (input/iftomm_a05_flyball.nml), against
the laws its motion must keep (issue 24, item 4).

Reference: the benchmark publishes the history of the slider position s as a data file
(A05_solution_data.txt, lim.ii.udc.es/mbsbenchmark), not available here. What the physics fixes
exactly, computed from the sensors (positions, velocities, orientations and angular velocities of
the four bodies' centres of mass; the coupler springs' lengths and rates), not from ffrf's energy
accounting:
  - the angular momentum about the shaft axis z, L_z = sum m (r x v)_z + (R I R^T w)_z, is
    constant: gravity is parallel to z, the hinge on the ground carries no moment about z and
    the springs and joints are internal;
  - the energy balance: kinetic + gravity potential + spring energy k (l - L0)^2 / 2 + the work
    dissipated by the dampers, the integral of c l'^2 (trapezoidal rule over the steps), is
    constant.
Runs the driver at h = 1e-3 s (the case) and 5e-4 s, 10 s, and asserts at h = 1e-3 s
  - |L_z - L_z(0)| <= 1e-5 L_z(0) at every step (measured 4.5e-7);
  - energy balance within 1e-5 of the initial energy (measured 7.9e-7 of 238.9 J);
  - the largest change of L_z falls with h at order 1.8 or more (a convergence check; measured
    2.24 from 1e-3 to 5e-4 s and 2.37 from 5e-4 to 2.5e-4 s, 1.8e-8 there);
  - the slider moves: s leaves 0.5 m by more than 0.1 m (measured: up to 0.744 m, 0.620 m at
    10 s; 0.619662 and 0.619633 m at h = 1e-3 and 5e-4 s). Measured at h = 5e-4 s: L_z 9.5e-8,
    energy 2.3e-7 (order 2.24 on L_z).

    check_iftomm_flyball.py DRIVER CASE MESH_DIR WORK_DIR
"""
import sys

import h5py
import numpy as np

from iftomm_common import arguments, check, check_order, finish, run_driver

GRAVITY = 9.81
STIFFNESS, DAMPING, FREE_LENGTH = 8.0e5, 4.0e4, 0.5
ROD = 3000.0 * 1.0 * 0.01 * 0.01          # shaft and rods, kg
BALL = 5.0                                # point mass at a rod's end, kg
ROD_BALL = ROD + BALL
CENTRE = (ROD * 0.5 + BALL * 1.0) / ROD_BALL   # from the hinge, m
ACROSS = ROD * (1.0 + 1.0e-4) / 12.0
ALONG = ROD * 2.0e-4 / 12.0
ROD_ACROSS = ACROSS + ROD * (0.5 - CENTRE) ** 2 + BALL * (1.0 - CENTRE) ** 2
BODIES = {  # mass, inertia about the centre of mass in the body frame
    "shaft": (ROD, np.diag([ACROSS, ACROSS, ALONG])),
    "slider": (3000.0 * 0.1 ** 3, np.diag([0.005, 0.005, 0.005])),
    "rod1": (ROD_BALL, np.diag([ROD_ACROSS, ROD_ACROSS, ALONG])),
    "rod2": (ROD_BALL, np.diag([ROD_ACROSS, ROD_ACROSS, ALONG])),
}
MOMENTUM_TOLERANCE = 1.0e-5  # of L_z(0)
ENERGY_TOLERANCE = 1.0e-5    # of the initial energy

def run(driver, case, mesh_dir, work, name, h):
    out = run_driver(driver, case, mesh_dir, work, name, [f"integrator.h={h}"])
    with h5py.File(out, "r") as f:
        t = f["/time/t"][()]
        momentum = np.zeros(len(t))
        energy = np.zeros(len(t))
        for body, (mass, inertia) in BODIES.items():
            r = f[f"/sensors/{body}_position"][()]
            v = f[f"/sensors/{body}_velocity"][()]
            axes = f[f"/sensors/{body}_orientation"][()]
            w = f[f"/sensors/{body}_angular_velocity"][()]
            rotation = np.stack([axes[:, 0:3], axes[:, 3:6], axes[:, 6:9]], axis=2)
            spin = np.einsum("nij,jk,nlk,nl->ni", rotation, inertia, rotation, w)
            momentum += mass * np.cross(r, v)[:, 2] + spin[:, 2]
            energy += (0.5 * mass * np.sum(v * v, axis=1) + 0.5 * np.sum(w * spin, axis=1)
                       + mass * GRAVITY * r[:, 2])
        for spring in ("coupler1", "coupler2"):
            length, rate = f[f"/sensors/{spring}"][()][:, 0], f[f"/sensors/{spring}"][()][:, 1]
            power = DAMPING * rate ** 2
            energy += 0.5 * STIFFNESS * (length - FREE_LENGTH) ** 2
            energy += np.concatenate([[0.0], np.cumsum(0.5 * (power[1:] + power[:-1])
                                                        * np.diff(t))])
        s = f["/sensors/s"][()][:, 2]
    momentum_change = np.max(np.abs(momentum - momentum[0])) / abs(momentum[0])
    energy_change = np.max(np.abs(energy - energy[0])) / abs(energy[0])
    print(f"       {name}: h = {h} s, {len(t)} steps to t = {t[-1]:.6f} s; L_z(0) = "
          f"{momentum[0]:.6f} kg m^2/s, largest change {momentum_change:.3e} of it; energy "
          f"{energy[0]:.4f} J, largest change of the balance {energy_change:.3e} of it; "
          f"s from {s[0]:.6f} to {s[-1]:.6f} m")
    return momentum_change, energy_change, s


def main():
    driver, case, mesh_dir, work = arguments()
    momentum_h, energy_h, s = run(driver, case, mesh_dir, work, "a05_h", 1.0e-3)
    momentum_h2, _, _ = run(driver, case, mesh_dir, work, "a05_h2", 5.0e-4)
    check(momentum_h <= MOMENTUM_TOLERANCE, f"h = 1e-3 s: angular momentum about z kept to "
          f"{momentum_h:.3e} <= {MOMENTUM_TOLERANCE:g} of L_z(0)")
    check(energy_h <= ENERGY_TOLERANCE, f"h = 1e-3 s: energy balance kept to {energy_h:.3e} "
          f"<= {ENERGY_TOLERANCE:g} of the initial energy")
    check_order(momentum_h, momentum_h2, "the angular-momentum change", 0.2, at_least=True)
    check(np.max(np.abs(s - 0.5)) > 0.1, f"the slider moves: largest |s - 0.5| = "
          f"{np.max(np.abs(s - 0.5)):.4f} m > 0.1 m")
    return finish()


if __name__ == "__main__":
    sys.exit(main())
