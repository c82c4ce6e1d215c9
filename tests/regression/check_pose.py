#!/usr/bin/env python3
"""&body orientation, velocity and angular_velocity (issue 24, item 1) on the IFToMM A01 pendulum
(input/iftomm_a01_pendulum.nml: 1 kg on a massless 1 m link, hinged at the origin, gravity
-9.81 m/s^2 along y, released at rest at x = +1 m), against independent references:

1. A rotated scene equals the unrotated one rotated. The whole scene is rotated by a rotation Q
   (the body position, its orientation = Q, the gravity and the hinge axis; the markers are in
   the body frame and the hinge at the origin), so the pendulum swings in a tilted plane that
   is none of xy, yz, zx. Reference: Q times the planar run's mass position at every step.
   Tolerance 1e-12 m: the two runs solve the same equations in rotated coordinates, so they
   differ by round-off only as long as Newton takes the same iterations (its stopping test,
   newton_atol = 1e-10 on residuals of order 1, is met by both alike: a different iteration
   count would show as a difference of up to about 1e-10 m per step). Round-off of about
   1e-16 m per step over 1e4 steps (10 s) is at most 1e-12 m; measured 1.3e-14 m.
2. The initial velocity. The pendulum starts at the phase t1 = 0.4 s of the exact solution
   from rest at phi_0 = pi/2: the mass at the exact position there, the body turned by the
   same angle (orientation), its angular velocity phi_dot = -sqrt(2 m g L (cos phi -
   cos phi_0) / I_p) from the energy and the velocity omega x r of the mass. Reference: the
   exact elliptic solution reference(t + t1) of check_iftomm_pendulum.py (the closed form).
   Tolerance 2.5e-4 m: the from-rest run's largest error at h = 1e-3 s over 10 s is 1.18e-4 m
   (check_iftomm_pendulum.py, the integrator's O(h^2) phase error), twice that for the start
   (an unrotated start has the same error growth); the benchmark allows 1e-3 m.
3. An inconsistent initial velocity: case 2 with a radial velocity of 0.05 m/s added to the
   mass. The projection onto the hinge's velocity constraints removes exactly it (no Euler
   parameter rate moves the mass radially), so the log says "velocity changed 5.00E-02 m/s"
   (relative 1e-3: 3 digits printed) and the run equals case 2's to the tolerance of case 1
   (measured: identical).
4. Cases 1 and 2 together: case 2's start rotated by Q (position, orientation, velocity and
   angular velocity, gravity, hinge axis) equals Q times case 2's run, tolerance of case 1
   (the Euler-parameter rates from a global angular velocity at a rotated pose).
5. A pose the assembly corrects: case 1 with the mass at x = 1.001 m, 1 mm off the link's
   length. The hinge constraint moves the mass back along x only (a turn about z moves the link
   end along y), so the log says "moved 1.00E-03 m" (3 digits printed: 1e-3 relative).
The log line of each run says what the assembly changed (case 1: nothing, "moved 0 m").

`flexible`: tests/data/pose/flexible_pendulum.nml, a flexible conrod (4 modes) hinged at its big
end, started turning at 2 rad/s about z under gravity along -x, and the same scene rotated by
Q = Rz(0.7) (orientation Q, gravity Q g; the hinge axis stays z, the body z axis: joints off it
at a flexible interface are tests/regression/check_frames_pendulum.py's). References: the tip's (small-end virtual node) starting velocity
is omega x r (the modal rates start at zero), 1e-12 m/s (round-off of |v| = 0.3 m/s); the
rotated run's tip is Q times the unrotated one's at every step, 1e-12 m (round-off, as case 1;
the modes are computed in the body frame and equal).

`engine`: input/engine_rigid.nml started at crank_speed = 100 rad/s (10 ms), once as it is and
once with the flywheel's angular_velocity = (0, 0, 100) rad/s given (the projection from a
guess with the crank speed, the rotor path). References: the conrod's frame origin (the crank
pin, r = 0.045 m) starts at omega r = 4.5 m/s (the [assembly] line, 3 digits); the flywheel's
given angular velocity is consistent, so its line says less than 1e-12 rad/s changed; both
runs' crank speed series agree to 1e-12 relative (the velocities agree to round-off at the
start; measured 3.1e-13 over 200 steps: Newton round-off).

    check_pose.py [flexible|engine] DRIVER CASE MESH_DIR WORK_DIR
"""
import math
import os
import re
import subprocess
import sys

import h5py
import numpy as np
from scipy.special import ellipj, ellipk

MASS, LENGTH, GRAVITY, INERTIA_C = 1.0, 1.0, 9.81, 1.0e-8
PHI_0 = math.pi / 2.0
ROTATED_TOLERANCE = 1.0e-12  # m (module docstring, 1.)
EXACT_TOLERANCE = 2.5e-4  # m (module docstring, 2.)
PHASE = 0.4  # s
RADIAL = 0.05  # m/s

failures = []


def check(ok, what):
    print(("ok     " if ok else "FAILED ") + what)
    if not ok:
        failures.append(what)


def reference(t):
    """Exact position of the mass at times t (check_iftomm_pendulum.py)."""
    omega_0 = math.sqrt(MASS * GRAVITY * LENGTH / (MASS * LENGTH**2 + INERTIA_C))
    k = math.sin(PHI_0 / 2.0)
    sn, _, dn, _ = ellipj(ellipk(k * k) - omega_0 * t, k * k)
    return 2.0 * LENGTH * k * sn * dn, -LENGTH * (1.0 - 2.0 * k * k * sn * sn)


def rotation(axis, angle):
    axis = np.asarray(axis, float) / np.linalg.norm(axis)
    k = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    return np.eye(3) + math.sin(angle) * k + (1 - math.cos(angle)) * k @ k


def numbers(values):
    return ", ".join(f"{v:.17g}" for v in np.ravel(values))


def scene(case, name, work, position, orientation, velocity, angular_velocity, gravity, axis):
    """The A01 case with its &body, &mechanism gravity and &joint axis replaced."""
    text = open(case).read()
    body = (f"&body name = 'mass', type = 'rigid', mass = 1.0, inertia = 1.0e-8, 1.0e-8, 1.0e-8, "
            f"0, 0, 0,\n      position = {numbers(position)},\n      orientation = "
            f"{numbers(orientation)},\n      velocity = {numbers(velocity)},\n      "
            f"angular_velocity = {numbers(angular_velocity)} /")
    text, n_body = re.subn(r"&body name = 'mass'.*?/", body, text, flags=re.S)
    text, n_gravity = re.subn(r"gravity = [^,]+, [^,]+, [^,]+,", f"gravity = {numbers(gravity)},",
                              text)
    text, n_joint = re.subn(r"marker2 = 'link_end' /", f"marker2 = 'link_end',\n       axis = "
                            f"{numbers(axis)} /", text)
    assert n_body == n_gravity == n_joint == 1
    path = os.path.join(work, name + ".nml")
    with open(path, "w") as f:
        f.write(text)
    return path


def run(driver, case, mesh_dir, work, name, sensor="P1"):
    out = os.path.join(work, name + ".h5")
    proc = subprocess.run([driver, case, "--mesh-dir", mesh_dir, "--output-dir", work,
                           "--output", name + ".h5"], capture_output=True, text=True)
    check(proc.returncode == 0, f"{name}: driver exit {proc.returncode} {proc.stderr.strip()}")
    if proc.returncode != 0:
        sys.exit(1)
    with h5py.File(out, "r") as f:
        t = f["/time/t"][()]
        position = f["/sensors/" + sensor][()][:, 0:3]
    lines = [line for line in (proc.stdout + proc.stderr).splitlines() if "[assembly]" in line]
    return t, position, lines


def flexible_scene(case, name, work, Q):
    """The flexible pendulum with the body orientation Q and the gravity rotated by Q."""
    text = open(case).read()
    gravity = Q @ np.array([-9.81, 0.0, 0.0])
    text, n_gravity = re.subn(r"gravity = [^,]+, [^,]+, [^,]+,", f"gravity = {numbers(gravity)},",
                              text)
    text, n_body = re.subn(r"angular_velocity = 0.0, 0.0, 2.0 /", "angular_velocity = 0.0, 0.0, "
                           f"2.0,\n      orientation = {numbers(Q)} /", text)
    assert n_gravity == n_body == 1
    path = os.path.join(work, name + ".nml")
    with open(path, "w") as f:
        f.write(text)
    return path


def flexible(driver, case, mesh_dir, work):
    """The flexible pendulum (module docstring, flexible)."""
    _, tip, lines = run(driver, case, mesh_dir, work, "flexible", "tip")
    with h5py.File(os.path.join(work, "flexible.h5"), "r") as f:
        tip_velocity = f["/sensors/tip_velocity"][()][:, 0:3]
    expected = np.cross([0.0, 0.0, 2.0], tip[0])
    error = np.linalg.norm(tip_velocity[0] - expected)
    print(f"       flexible: tip at the start {tip[0]}, velocity {tip_velocity[0]} (omega x r = "
          f"{expected}); log: {lines}")
    check(error <= 1.0e-12, f"flexible: starting tip velocity = omega x r: {error:.3e} m/s <= "
          f"1e-12 m/s")
    Q = rotation([0.0, 0.0, 1.0], 0.7)
    _, rotated, lines = run(driver, flexible_scene(case, "flexible_rotated", work, Q), mesh_dir,
                            work, "flexible_rotated", "tip")
    difference = np.max(np.linalg.norm(rotated - tip @ Q.T, axis=1))
    print(f"       flexible rotated: {len(rotated)} steps, largest |tip - Q tip_unrotated| = "
          f"{difference:.3e} m; log: {lines}")
    check(len(rotated) == len(tip) and difference <= ROTATED_TOLERANCE,
          f"flexible: rotated scene = Q x scene: {difference:.3e} m <= {ROTATED_TOLERANCE:g} m")


def engine_lines(lines, body):
    """(moved, velocity change, angular velocity change) of a body's [assembly] line."""
    for line in lines:
        match = re.search(rf'body "{body}": moved ([0-9.Ee+-]+) m, velocity changed '
                          r"([0-9.Ee+-]+) m/s, angular velocity changed ([0-9.Ee+-]+) rad/s", line)
        if match:
            return tuple(float(x) for x in match.groups())
    return (float("nan"),) * 3


def engine(driver, case, mesh_dir, work):
    """The rigid engine started at a crank speed, with and without the flywheel's angular
    velocity given (module docstring, engine)."""
    series = []
    for name, extra in (("engine_speed", []),
                        ("engine_flywheel", ["--set", "body[flywheel].angular_velocity=0,0,100"])):
        proc = subprocess.run([driver, case, "--mesh-dir", mesh_dir, "--output-dir", work,
                               "--output", name + ".h5", "--set", "mechanism.crank_speed=100",
                               "--set", "integrator.t_end=0.01"] + extra,
                              capture_output=True, text=True)
        check(proc.returncode == 0, f"{name}: driver exit {proc.returncode} "
              f"{proc.stderr.strip()}")
        if proc.returncode != 0:
            sys.exit(1)
        lines = [line for line in proc.stdout.splitlines() if "[assembly]" in line]
        print(f"       {name}: " + "; ".join(lines))
        with h5py.File(os.path.join(work, name + ".h5"), "r") as f:
            series.append(f["/time/crank_speed"][()])
    conrod = engine_lines(lines, "conrod")
    flywheel = engine_lines(lines, "flywheel")
    check(abs(conrod[1] - 4.5) <= 4.5e-3, f"conrod origin starts at omega r = 4.5 m/s: {conrod}")
    check(flywheel[2] <= 1.0e-12, f"the flywheel's consistent angular velocity is kept: "
          f"{flywheel}")
    difference = np.max(np.abs(series[1] - series[0])) / 100.0
    check(len(series[0]) == len(series[1]) and difference <= 1.0e-12,
          f"crank speed with and without the flywheel's angular velocity: relative "
          f"{difference:.3e} <= 1e-12")


def main():
    if sys.argv[1] in ("flexible", "engine"):
        driver, case, mesh_dir, work = sys.argv[2:6]
        os.makedirs(work, exist_ok=True)
        (flexible if sys.argv[1] == "flexible" else engine)(driver, case, mesh_dir, work)
        if failures:
            print(f"{len(failures)} check(s) failed")
            sys.exit(1)
        return
    driver, case, mesh_dir, work = sys.argv[1:5]
    os.makedirs(work, exist_ok=True)
    g = np.array([0.0, -GRAVITY, 0.0])
    e_z = np.array([0.0, 0.0, 1.0])

    # 1. the rotated scene
    Q = rotation([0.3, -0.5, 0.8], 1.1)
    t, planar, _ = run(driver, scene(case, "planar", work, [1, 0, 0], np.eye(3), [0, 0, 0],
                                     [0, 0, 0], g, e_z), mesh_dir, work, "planar")
    t_r, rotated, lines = run(driver, scene(case, "rotated", work, Q @ [1, 0, 0], Q, [0, 0, 0],
                                            [0, 0, 0], Q @ g, Q @ e_z), mesh_dir, work, "rotated")
    difference = np.max(np.linalg.norm(rotated - planar @ Q.T, axis=1))
    print(f"       rotated scene: {len(t_r)} steps, largest |p_rotated - Q p_planar| = "
          f"{difference:.3e} m; log: {lines}")
    check(len(t_r) == len(t) and difference <= ROTATED_TOLERANCE,
          f"rotated scene = Q x planar scene: {difference:.3e} m <= {ROTATED_TOLERANCE:g} m")
    check(len(lines) == 1 and "moved 0 m, velocity changed 0 m/s" in lines[0],
          f"the log states what the assembly changed on the body (a consistent pose: nothing): "
          f"{lines}")

    # 2. started at the phase t1 with the exact angular velocity
    x1, y1 = reference(np.array([PHASE]))
    x1, y1 = float(x1[0]), float(y1[0])
    phi = math.atan2(x1, -y1)
    inertia_p = MASS * LENGTH**2 + INERTIA_C
    phi_dot = -math.sqrt(2.0 * MASS * GRAVITY * LENGTH * (math.cos(phi) - math.cos(PHI_0))
                         / inertia_p)
    turned = rotation(e_z, phi - PHI_0)
    r = np.array([x1, y1, 0.0])
    velocity = phi_dot * np.cross(e_z, r)
    t_v, moving, lines = run(driver, scene(case, "phase", work, r, turned, velocity,
                                           phi_dot * e_z, g, e_z), mesh_dir, work, "phase")
    x_ref, y_ref = reference(t_v + PHASE)
    error = max(np.max(np.abs(moving[:, 0] - x_ref)), np.max(np.abs(moving[:, 1] - y_ref)))
    print(f"       phase start: phi = {phi:.6f} rad, phi_dot = {phi_dot:.6f} rad/s, largest "
          f"position error against the exact solution {error:.3e} m; log: {lines}")
    check(error <= EXACT_TOLERANCE,
          f"started at t1 = {PHASE} s: position error {error:.3e} m <= {EXACT_TOLERANCE:g} m")

    # 3. an inconsistent (radial) velocity is projected out
    radial = velocity + RADIAL * r / np.linalg.norm(r)
    _, projected, lines = run(driver, scene(case, "radial", work, r, turned, radial,
                                            phi_dot * e_z, g, e_z), mesh_dir, work, "radial")
    match = re.search(r"moved ([0-9.Ee+-]+) m, velocity changed ([0-9.Ee+-]+) m/s, angular velocity changed "
                      r"([0-9.Ee+-]+) rad/s", lines[0]) if len(lines) == 1 else None
    moved = float(match.group(1)) if match else float("nan")
    changed = float(match.group(2)) if match else float("nan")
    turned_rate = float(match.group(3)) if match else float("nan")
    check(moved == 0.0 and abs(changed - RADIAL) <= 1.0e-3 * RADIAL and
          turned_rate <= 1.0e-12 * abs(phi_dot),
          f"radial velocity projected out, log: {lines}")
    difference = np.max(np.linalg.norm(projected - moving, axis=1))
    check(difference <= ROTATED_TOLERANCE,
          f"projected run = consistent run: {difference:.3e} m <= {ROTATED_TOLERANCE:g} m")

    # 4. the phase start of case 2 in the rotated scene of case 1
    _, rotated_moving, lines = run(driver, scene(case, "phase_rotated", work, Q @ r, Q @ turned,
                                                 Q @ velocity, phi_dot * (Q @ e_z), Q @ g,
                                                 Q @ e_z), mesh_dir, work, "phase_rotated")
    difference = np.max(np.linalg.norm(rotated_moving - moving @ Q.T, axis=1))
    print(f"       rotated phase start: largest |p - Q p_phase| = {difference:.3e} m; log: "
          f"{lines}")
    check(difference <= ROTATED_TOLERANCE,
          f"rotated phase start = Q x phase start: {difference:.3e} m <= "
          f"{ROTATED_TOLERANCE:g} m")

    # 5. a start 1 mm off, moved by the assembly
    _, _, lines = run(driver, scene(case, "off", work, [1.001, 0, 0], np.eye(3), [0, 0, 0],
                                    [0, 0, 0], g, e_z), mesh_dir, work, "off")
    match = re.search(r"moved ([0-9.Ee+-]+) m", lines[0]) if len(lines) == 1 else None
    moved = float(match.group(1)) if match else float("nan")
    check(abs(moved - 1.0e-3) <= 1.0e-6, f"a start 1 mm off is moved back 1 mm: {lines}")

    if failures:
        print(f"{len(failures)} check(s) failed")
        sys.exit(1)


if __name__ == "__main__":
    main()
