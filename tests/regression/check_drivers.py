#!/usr/bin/env python3
"""Drivers of joints and loads over time from the namelist (&driver, &load law; issue 24, item 1)
on input/driven_crank.nml, against closed forms:

1. the crank: a rigid link (m = 2 kg, L = 0.5 m) on a revolute joint, its speed a smooth step
   0 -> 2 pi rad/s over 0.5 s (quantity = 'rate'), under gravity g = 9.81 m/s^2 along -y.
   - the driver sensor's angle against the spin-up law theta(t) = (W/T)(t^2/2 + (T/(2 pi))^2
     (cos(2 pi t/T) - 1)), then W T/2 + W (t - T), wrapped into (-pi, pi] (1e-9 rad: the
     Newton tolerance; the driven coordinate is the mechanism's only freedom);
   - its rate against theta' (2e-5 of W: index 3 leaves the velocity O(h^2); measured 2.2e-6);
   - its torque against tau = I_O theta'' + m g (L/2) cos(theta), I_O = m L^2/3, over all steps
     (1.5e-4 of max |tau|; measured 1.2e-5 at h = 1e-3 s);
2. the slider: 0.5 kg on a prismatic joint along x pushed by 4 N times a linear table
   (0, 0.2, 0.6, 0.8 s; 0, 1, 1, 0, held): its travel against the closed form of x'' = F/m
   integrated twice piece by piece (2e-6 of the largest travel; measured 1.9e-7);
3. the energy balance: /energy numerical_dissipation (D = W - (T + U - T_0 - U_0), W the work of
   gravity, the load and the driver) within 1e-5 of the gross work sum |dW| (measured
   3.7e-6; without the driver's work D would be of the order of W itself);
4. restart: the run to 0.6 s continued by --restart to 1.2 s equals the uninterrupted run,
   bitwise (driver sensor, travel, energy, time): the driver's law depends on t only.

    check_drivers.py DRIVER CASE MESH_DIR WORK_DIR
"""
import math
import os
import subprocess
import sys

import h5py
import numpy as np

M, L, G = 2.0, 0.5, 9.81
W, T = 2.0 * math.pi, 0.5
SLIDER_MASS, FORCE = 0.5, 4.0
TABLE_T = [0.0, 0.2, 0.6, 0.8]
TABLE_V = [0.0, 1.0, 1.0, 0.0]


def spin_up(t):
    """theta, theta', theta'' of the smooth step of the speed."""
    if t <= T:
        theta = W / T * (0.5 * t * t + (T / (2 * math.pi)) ** 2 * (math.cos(2 * math.pi * t / T) - 1))
        rate = W / T * (t - T / (2 * math.pi) * math.sin(2 * math.pi * t / T))
        accel = W / T * (1 - math.cos(2 * math.pi * t / T))
        return theta, rate, accel
    return W * T / 2 + W * (t - T), W, 0.0


def slider_travel(t):
    """x(t) from x'' = F(t)/m, F piecewise linear (held after the last point), at rest at 0."""
    x, v, t0 = 0.0, 0.0, 0.0
    knots = TABLE_T[1:] + [math.inf]
    values = TABLE_V + [TABLE_V[-1]]
    for k, t1 in enumerate(knots):
        f0 = FORCE * values[k]
        slope = 0.0 if math.isinf(t1) else FORCE * (values[k + 1] - values[k]) / (t1 - t0)
        dt = min(t, t1) - t0
        if dt <= 0:
            break
        x += v * dt + f0 * dt * dt / (2 * SLIDER_MASS) + slope * dt ** 3 / (6 * SLIDER_MASS)
        v += f0 * dt / SLIDER_MASS + slope * dt * dt / (2 * SLIDER_MASS)
        t0 = t1
    return x


def check(what, value, tolerance):
    ok = abs(value) <= tolerance
    print(f"{'ok  ' if ok else 'FAIL'} {what}: {value:.3e} (tolerance {tolerance:.1e})")
    return ok


def main():
    driver, case, mesh_dir, work = sys.argv[1:5]
    os.makedirs(work, exist_ok=True)
    subprocess.run([driver, case, "--mesh-dir", mesh_dir, "--output-dir", work], check=True,
                   stdout=subprocess.DEVNULL)
    name = os.path.splitext(os.path.basename(case))[0]
    with h5py.File(os.path.join(work, name + ".h5"), "r") as f:
        t = f["time/t"][:]
        motor = f["sensors/motor"][:]
        travel = f["sensors/travel"][:, 0]
        units = f["sensors/motor"].attrs["units"]
        dissipation = f["energy/numerical_dissipation"][:]
        work_total = f["energy/external_work"][:]
    ok = units in (b"rad, rad/s, N m", "rad, rad/s, N m")
    print(f"{'ok  ' if ok else 'FAIL'} driver sensor units {units!r}")
    angle_err = rate_err = tau_err = tau_max = travel_err = 0.0
    for k, tk in enumerate(t):
        theta, rate, accel = spin_up(tk)
        wrapped = math.atan2(math.sin(theta), math.cos(theta))
        angle_err = max(angle_err, abs(math.atan2(math.sin(motor[k, 0] - wrapped),
                                                  math.cos(motor[k, 0] - wrapped))))
        rate_err = max(rate_err, abs(motor[k, 1] - rate))
        tau = M * L * L / 3 * accel + M * G * L / 2 * math.cos(theta)
        tau_max = max(tau_max, abs(tau))
        if k > 0:
            tau_err = max(tau_err, abs(motor[k, 2] - tau))
        travel_err = max(travel_err, abs(travel[k] - slider_travel(tk)))
    travel_max = max(abs(slider_travel(tk)) for tk in t)
    gross = float(np.sum(np.abs(np.diff(work_total)))) + 1e-300
    print(f"max |tau| {tau_max:.6f} N m, largest travel {travel_max:.6f} m, gross work {gross:.6f} J")
    ok &= check("crank angle error (rad)", angle_err, 1e-9)
    ok &= check("crank rate error / W", rate_err / W, 2e-5)
    ok &= check("driving torque error / max |tau|", tau_err / tau_max, 1.5e-4)
    ok &= check("slider travel error / largest travel", travel_err / travel_max, 2e-6)
    ok &= check("energy balance max |D| / gross work", float(np.max(np.abs(dissipation))) / gross, 1e-5)
    part = os.path.join(work, "restart")
    os.makedirs(part, exist_ok=True)
    subprocess.run([driver, case, "--mesh-dir", mesh_dir, "--output-dir", part, "--set",
                    "integrator.t_end=0.6"], check=True, stdout=subprocess.DEVNULL)
    results = os.path.join(part, name + ".h5")
    subprocess.run([driver, case, "--mesh-dir", mesh_dir, "--output-dir", part, "--restart",
                    results], check=True, stdout=subprocess.DEVNULL)
    with h5py.File(os.path.join(work, name + ".h5"), "r") as full, h5py.File(results, "r") as cont:
        for key in ("sensors/motor", "sensors/travel", "energy/external_work", "time/t"):
            same = np.array_equal(full[key][()], cont[key][()])
            print(f"{'ok  ' if same else 'FAIL'} restart at 0.6 s: {key} bitwise equal")
            ok &= same
    sys.exit(0 if ok else 1)


if __name__ == "__main__":
    main()
