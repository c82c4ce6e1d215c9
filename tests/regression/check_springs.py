#!/usr/bin/env python3
"""The spring-damper (&spring, src/mbs/spring_damper.f90) in two scenes against independent
references (issue 24, item 1).

1. input/spring_oscillator.nml: a 1 kg mass on a prismatic joint, spring k = 100 N/m, damper
   c = 0.4 N s/m, free length 0.5 m, released at rest 0.1 m stretched. Reference: the closed-form
   damped oscillator x(t) = L0 + A exp(-zeta w0 t) (cos wd t + zeta w0 / wd sin wd t). Runs at
   h = 1e-3 s and 5e-4 s (2 s, 3 periods) and asserts
     - the largest position error over all steps <= 5e-5 m at h (generalized-alpha's phase
       error O((w0 h)^2) w0 t A; measured 1.05e-5 m, 2.6e-6 m at h/2),
     - order log2(e(h) / e(h/2)) = 2 +- 0.2,
     - the period of the zero crossings of x - L0 against 2 pi / wd (rtol 1e-4; measured 1e-5)
       and the decay, the logarithmic decrement of the peaks against zeta w0 pi / wd
       (rtol 5e-5; measured 5.6e-6),
     - the spring sensor: its length, rate and tension equal x, x' (velocity sensor) and
       k (x - L0) + c x' to round-off (1e-14: about 100 eps of the 0.6 m length; measured 0;
       the anchor is at the origin on the x axis),
     - the damper's dissipation: T + k (x - L0)^2 / 2 + int c x'^2 dt (trapezoid rule over the
       recorded velocities) stays within 1e-4 of the initial spring energy (both O(h^2)).
2. input/spring_pendulum.nml: the IFToMM A01 pendulum held by an undamped spring from a ground
   point, a nonlinear swing under gravity. Reference: conservation of T + m g y + k (l - L0)^2 / 2
   (T from the energy sensor, y and l from the position sensor). Asserts its largest change
   <= 1e-4 of the initial spring energy at h = 1e-3 s and the order of the drift 2 +- 0.3
   between h and h/2 (generalized-alpha with rho_inf = 0.9 dissipates O(h^2)).
3. check_springs.py flexible: springs at flexible bodies' virtual nodes (the lc 8 mm engine,
   tests/regression/springs.cmake). The spring sensor of the ground - conrod small-end spring
   against the small end's position and velocity sensors (independent: the marker functions
   r_k, L_r v): length |r - anchor| and rate n . v to 1e-14 (m, m/s; round-off, measured
   1.7e-18), tension k (l - L0) + c l' with L0 the starting length (the default free length) to
   1e-14 of k; the pin spring's tension k (l - L0) to 1e-14 of k.
Measured: printed by the script (oscillator errors, order, period; pendulum drifts, order).

    check_springs.py DRIVER OSCILLATOR_CASE PENDULUM_CASE MESH_DIR WORK_DIR
    check_springs.py flexible DRIVER CASE MESH_DIR WORK_DIR
"""
import math
import os
import subprocess
import sys

import h5py
import numpy as np

from oscillator_checks import crossing_period, cumulative_trapezoid, log_decrement

MASS, STIFFNESS, DAMPING, FREE_LENGTH, STRETCH = 1.0, 100.0, 0.4, 0.5, 0.1
PENDULUM_K, PENDULUM_L0, GRAVITY = 20.0, 1.0, 9.81
ANCHOR = np.array([0.0, -1.5, 0.0])

failures = []


def check(ok, what):
    print(("ok     " if ok else "FAILED ") + what)
    if not ok:
        failures.append(what)


def run(driver, case, mesh_dir, work, name, h):
    out = os.path.join(work, name + ".h5")
    proc = subprocess.run([driver, case, "--mesh-dir", mesh_dir, "--output-dir", work,
                           "--output", name + ".h5", "--set", f"integrator.h={h}"],
                          capture_output=True, text=True)
    check(proc.returncode == 0, f"{name}: driver exit {proc.returncode} {proc.stderr.strip()}")
    if proc.returncode != 0:
        sys.exit(1)
    with h5py.File(out, "r") as f:
        return {key: f[path][()] for key, path in
                [("t", "/time/t")] + [(s, "/sensors/" + s) for s in f["/sensors"].keys()]}


def oscillator_reference(t):
    """Closed-form damped oscillator released at rest (module docstring)."""
    w0 = math.sqrt(STIFFNESS / MASS)
    zeta = DAMPING / (2.0 * MASS * w0)
    wd = w0 * math.sqrt(1.0 - zeta**2)
    return FREE_LENGTH + STRETCH * np.exp(-zeta * w0 * t) * (
        np.cos(wd * t) + zeta * w0 / wd * np.sin(wd * t)), wd


def oscillator(driver, case, mesh_dir, work):
    errors = []
    for name, h in [("oscillator_h", 1.0e-3), ("oscillator_h2", 5.0e-4)]:
        data = run(driver, case, mesh_dir, work, name, h)
        t, x = data["t"], data["P"][:, 0]
        x_ref, wd = oscillator_reference(t)
        errors.append(np.max(np.abs(x - x_ref)))
        print(f"       {name}: h = {h} s, {len(t)} steps, largest position error "
              f"{errors[-1]:.3e} m")
        if name == "oscillator_h":
            u = x - FREE_LENGTH
            period, count = crossing_period(t, u)
            print(f"       period from {count} zero crossings {period:.6f} s, "
                  f"closed form {2.0 * math.pi / wd:.6f} s")
            check(abs(period / (2.0 * math.pi / wd) - 1.0) <= 1.0e-4,
                  f"period {period:.6f} s within 1e-4 of 2 pi / wd")
            w0 = math.sqrt(STIFFNESS / MASS)
            zeta = DAMPING / (2.0 * MASS * w0)
            decrement = log_decrement(u)
            expected = zeta * w0 * math.pi / wd
            print(f"       logarithmic decrement per half period {decrement:.6f}, closed form "
                  f"{expected:.6f}")
            check(abs(decrement / expected - 1.0) <= 5.0e-5,
                  f"decay: decrement {decrement:.6f} within 5e-5 of zeta w0 pi / wd "
                  f"(relative difference {abs(decrement / expected - 1.0):.2e})")
            v = data["V"][:, 0]
            power = DAMPING * v**2
            dissipated = cumulative_trapezoid(t, power)
            total = data["energy"][:, 0] + 0.5 * STIFFNESS * u**2 + dissipated
            initial = 0.5 * STIFFNESS * STRETCH**2
            change = np.max(np.abs(total - total[0])) / initial
            print(f"       T + k u^2/2 + int c v^2 dt: largest change {change:.3e} of the "
                  f"initial spring energy {initial:.4f} J (dissipated {dissipated[-1]:.4f} J)")
            check(change <= 1.0e-4, f"damper dissipation: energy change {change:.3e} <= 1e-4")
            sensor = data["spring"]
            tension = STIFFNESS * (x - FREE_LENGTH) + DAMPING * data["V"][:, 0]
            mismatch = max(np.max(np.abs(sensor[:, 0] - x)), np.max(np.abs(sensor[:, 1] -
                           data["V"][:, 0])), np.max(np.abs(sensor[:, 2] - tension)) / STIFFNESS)
            print(f"       spring sensor against x, x' and k (x - L0) + c x': {mismatch:.2e}")
            check(mismatch <= 1.0e-14, f"spring sensor (length, rate, tension) equals x, x', "
                  f"k (x - L0) + c x' to 1e-14 (m, m/s, N / k), got {mismatch:.2e}")
    order = math.log2(errors[0] / errors[1])
    print(f"       order of the position error: {order:.3f}")
    check(errors[0] <= 5.0e-5, f"h = 1e-3 s: position error {errors[0]:.3e} m <= 5e-5 m")
    check(abs(order - 2.0) <= 0.2, f"oscillator: order {order:.3f} = 2 +- 0.2")


def pendulum(driver, case, mesh_dir, work):
    drifts = []
    for name, h in [("pendulum_h", 1.0e-3), ("pendulum_h2", 5.0e-4)]:
        data = run(driver, case, mesh_dir, work, name, h)
        p = data["P1"]
        length = np.linalg.norm(p - ANCHOR, axis=1)
        spring = 0.5 * PENDULUM_K * (length - PENDULUM_L0)**2
        total = data["energy"][:, 0] + MASS * GRAVITY * p[:, 1] + spring
        drifts.append(np.max(np.abs(total - total[0])) / spring[0])
        print(f"       {name}: h = {h} s, mass y {p[:, 1].min():.3f}..{p[:, 1].max():.3f} m, "
              f"spring {length.min():.3f}.."
              f"{length.max():.3f} m, largest energy change {drifts[-1]:.3e} of the "
              f"initial spring energy {spring[0]:.4f} J")
    order = math.log2(drifts[0] / drifts[1])
    print(f"       order of the energy drift: {order:.3f}")
    check(drifts[0] <= 1.0e-4, f"pendulum: energy change {drifts[0]:.3e} <= 1e-4")
    check(abs(order - 2.0) <= 0.3, f"pendulum: drift order {order:.3f} = 2 +- 0.3")


def flexible(driver, case, mesh_dir, work):
    data = run(driver, case, mesh_dir, work, "engine_flexible_springs", 1.0e-4)
    sensor, position, velocity = (data["small_end_spring"], data["small_end_position"],
                                  data["small_end_velocity"])
    anchor = np.array([0.05, 0.25, 0.0])
    d = position - anchor
    length = np.linalg.norm(d, axis=1)
    rate = np.sum(d * velocity, axis=1) / length
    tension = 2.0e4 * (length - length[0]) + 5.0 * rate
    mismatch = [np.max(np.abs(sensor[:, 0] - length)), np.max(np.abs(sensor[:, 1] - rate)),
                np.max(np.abs(sensor[:, 2] - tension)) / 2.0e4]
    pin = data["pin_spring"]
    mismatch.append(np.max(np.abs(pin[:, 2] - 1.0e4 * (pin[:, 0] - 0.1))) / 1.0e4)
    print(f"       small-end spring {length.min():.5f}..{length.max():.5f} m, rate up to "
          f"{np.max(np.abs(rate)):.3f} m/s; differences {', '.join(f'{m:.1e}' for m in mismatch)}")
    check(max(mismatch) <= 1.0e-14, f"flexible: spring sensors against the virtual node's "
          f"position and velocity to 1e-14, got {max(mismatch):.1e}")


def main():
    if sys.argv[1] == "flexible":
        driver, case, mesh_dir, work = sys.argv[2:6]
        os.makedirs(work, exist_ok=True)
        flexible(driver, case, mesh_dir, work)
        print(f"{len(failures)} failure(s)")
        return 1 if failures else 0
    driver, oscillator_case, pendulum_case, mesh_dir, work = sys.argv[1:6]
    os.makedirs(work, exist_ok=True)
    oscillator(driver, oscillator_case, mesh_dir, work)
    pendulum(driver, pendulum_case, mesh_dir, work)
    print(f"{len(failures)} failure(s)")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
