#!/usr/bin/env python3
"""Sensors against independent references (tests/regression/sensors.cmake).

    check_sensors.py slider DRIVER CASE MESH_DIR OUT_DIR
        runs the crank-less slider-crank of tests/data/sensors/slider_wheel.nml and checks:
        - the log and the results file say nothing of a crank (no /time/crank_*, no
          /final_state/crank_angle, no "crank" in the progress lines);
        - every sensor is a (num_steps x k) dataset under /sensors with its attributes;
        - slider position = the closed form r cos(phi) + sqrt(l^2 - r^2 sin(phi)^2) of the wheel
          angle phi = 30 deg + the bearing's joint coordinate (to the constraint tolerance);
        - the bearing's joint coordinate = the wheel's rotation about z from its orientation
          sensor (an identity of two computations, to round-off);
        - the guide's travel = slider x - its start (prismatic joint coordinate);
        - a marker's velocity = the central difference of its position, its acceleration the
          central difference of its velocity, to O(h^2) (bound below);
        - the wheel's angular velocity about z = the central difference of its angle;
        - the bearing reaction sensor = /joints/bearing/reaction, bitwise (the same multipliers);
        - energy: strain 0 for a rigid body, kinetic >= 0, and = J_O omega^2 / 2 for the wheel
          turning about its fixed axis (J_O about the axis through O: inertia + m |c|^2);
        - a ground marker's position is constant;
        - --restart of this crank-less run to a later t_end gives the sensors of an
          uninterrupted run, bitwise (its restart state holds no crank reference).
    check_sensors.py engine RESULTS.h5
        the engine's crank sensors equal /time/crank_angle and /time/crank_speed bitwise.
    check_sensors.py flexible DRIVER CASE MESH_DIR OUT_DIR
        runs the lc 8 mm engine with a flexible conrod (10 RC normal modes) and sensors on its
        small-end virtual node and on the conrod's energy, and checks against the body's own
        series: position = R + A(theta) (x_V + Psi_V zeta) (theory.md 3.1; the virtual-node rows
        /modes/virtual_node_shape), to round-off; velocity = the central difference of position
        to O(h^2); the elastic part is seen (the sensor differs from the rigid motion of x_V);
        strain energy = 1/2 sum (2 pi f_i)^2 zeta_i^2 (mass-normalised modes), kinetic >= 0;
        a mesh node (tag 100 of conrod_lc8.msh): displacement = its rows of /modes/shape times
        zeta, position = R + A (x_n + u) with x_n read from the mesh file.
"""
import math
import os
import subprocess
import sys

import h5py
import numpy as np

R, L, PHI0 = 0.05, 0.2, math.radians(30.0)


def fail(message):
    print("check_sensors: FAIL: " + message)
    sys.exit(1)


def check(condition, message):
    if not condition:
        fail(message)
    print("check_sensors: ok: " + message)


def central(x, h):
    """Central difference of the rows of x (steps x k), interior steps."""
    return (x[2:] - x[:-2]) / (2.0 * h)


def o_h2_bound(x, h):
    """|x'(t) - central difference| <= h^2/6 max|x'''|; max|x'''| from the third differences
    (times 3: the estimate's own error, and generalized-alpha's velocities differ from the
    positions' central difference at O(h^2) as well), plus round-off of the quotient."""
    third = np.abs(np.diff(x, n=3, axis=0)).max() / h**3 if len(x) > 3 else 0.0
    return 3.0 * h * h / 6.0 * third + 1e3 * np.finfo(float).eps * np.abs(x).max() / h


def slider(driver, case, mesh_dir, out_dir):
    os.makedirs(out_dir, exist_ok=True)
    run = subprocess.run([driver, case, "--mesh-dir", mesh_dir, "--output-dir", out_dir],
                         capture_output=True, text=True)
    log = run.stdout + run.stderr
    if run.returncode != 0:
        fail("the driver failed (%d):\n%s" % (run.returncode, log))
    check("crank" not in log.lower(), "the log of a crank-less run says nothing of a crank")
    name = os.path.splitext(os.path.basename(case))[0]
    with h5py.File(os.path.join(out_dir, name + ".h5"), "r") as f:
        words = []
        f.visit(words.append)
        check(not [w for w in words if "crank" in w.lower()],
              "no dataset or group of the results file names a crank")
        t = f["/time/t"][()]
        n = len(t)
        h = t[1] - t[0]
        s = {k: f["/sensors/" + k][()] for k in f["/sensors"]}
        attrs = {k: dict(f["/sensors/" + k].attrs) for k in f["/sensors"]}
        joint_reaction = f["/joints/bearing/reaction"][()]
    sizes = {"bearing_angle": 1, "guide_travel": 1, "slider_position": 3, "pin_position": 3,
             "pin_velocity": 3, "pin_acceleration": 3, "wheel_orientation": 9, "wheel_omega": 3,
             "bearing_reaction": 12, "wheel_energy": 2, "ground_point": 3}
    check(sorted(s) == sorted(sizes), "the sensors of the case: %s" % sorted(s))
    for k, size in sizes.items():
        check(s[k].shape == (n, size), "%s is (num_steps, %d) = %s" % (k, size, s[k].shape))
    def text(x):
        return x.decode() if isinstance(x, bytes) else str(x)
    check(text(attrs["pin_velocity"]["type"]) == "velocity" and
          text(attrs["pin_velocity"]["units"]) == "m/s" and
          text(attrs["pin_velocity"]["body"]) == "wheel" and
          text(attrs["pin_velocity"]["marker"]) == "P", "attributes of a marker sensor")
    check(text(attrs["bearing_angle"]["units"]) == "rad" and
          text(attrs["guide_travel"]["units"]) == "m" and
          text(attrs["bearing_angle"]["joint"]) == "bearing", "attributes of joint sensors")

    phi = PHI0 + s["bearing_angle"][:, 0]
    turned = np.ptp(phi)
    check(turned > 0.3, "the wheel turns (%.3f rad over the run)" % turned)
    check(np.all(np.abs(s["bearing_angle"]) <= math.pi), "a revolute angle lies in [-pi, pi]")
    closed = R * np.cos(phi) + np.sqrt(L**2 - (R * np.sin(phi))**2)
    err = np.abs(s["slider_position"][:, 0] - closed).max()
    check(err < 1e-9, "slider x = r cos phi + sqrt(l^2 - r^2 sin^2 phi): max error %.2e m" % err)
    err = np.abs(s["slider_position"][:, 1:]).max()
    check(err < 1e-9, "slider stays on the x axis: max |y|, |z| %.2e m" % err)
    pin = np.stack([R * np.cos(phi), R * np.sin(phi)], axis=1)
    err = np.abs(s["pin_position"][:, :2] - pin).max()
    check(err < 1e-9, "pin position = r (cos phi, sin phi): max error %.2e m" % err)
    x_axis = s["wheel_orientation"][:, 0:3]
    from_frame = np.arctan2(x_axis[:, 1], x_axis[:, 0])
    err = np.abs(np.angle(np.exp(1j * (from_frame - s["bearing_angle"][:, 0])))).max()
    check(err < 1e-12, "revolute angle = the wheel's rotation about z from its orientation: "
          "max error %.2e rad" % err)
    travel = s["slider_position"][:, 0] - s["slider_position"][0, 0]
    err = np.abs(s["guide_travel"][:, 0] - travel).max()
    check(err < 1e-9, "prismatic travel = slider displacement along the guide: %.2e m" % err)

    # the same run at h/2: the differences must fall as h^2 (observed order 2 +- 0.3)
    half = os.path.join(out_dir, name + "_half.h5")
    run = subprocess.run([driver, case, "--mesh-dir", mesh_dir, "--output-dir", out_dir,
                          "--output", os.path.basename(half), "--set",
                          "integrator.h=%r" % (h / 2.0)], capture_output=True, text=True)
    if run.returncode != 0:
        fail("the run at h/2 failed (%d):\n%s" % (run.returncode, run.stdout + run.stderr))
    with h5py.File(half, "r") as f:
        s2 = {k: f["/sensors/" + k][()] for k in ("pin_position", "pin_velocity",
                                                   "pin_acceleration")}
    for position, velocity in (("pin_position", "pin_velocity"),
                               ("pin_velocity", "pin_acceleration")):
        fd = central(s[position], h)
        err = np.abs(s[velocity][1:-1] - fd).max()
        bound = o_h2_bound(s[position], h)
        check(err <= bound, "%s = central difference of %s: max error %.2e <= O(h^2) bound %.2e"
              % (velocity, position, err, bound))
        err2 = np.abs(s2[velocity][1:-1] - central(s2[position], h / 2.0)).max()
        order = math.log(err / err2, 2.0)
        check(1.7 <= order <= 2.3, "%s - central difference of %s falls as h^%.2f (%.2e at h, "
              "%.2e at h/2)" % (velocity, position, order, err, err2))
    angle = np.unwrap(s["bearing_angle"], axis=0)  # the sensor gives (-pi, pi]
    err = np.abs(s["wheel_omega"][1:-1, 2] - central(angle, h)[:, 0]).max()
    bound = o_h2_bound(angle, h)
    check(err <= bound, "angular velocity z = central difference of the angle: %.2e <= %.2e"
          % (err, bound))
    check(np.abs(s["wheel_omega"][:, :2]).max() < 1e-9, "the wheel turns about z only")

    check(np.array_equal(s["bearing_reaction"], joint_reaction.reshape(n, 12)),
          "reaction sensor = /joints/bearing/reaction, bitwise")
    energy = s["wheel_energy"]
    check(np.all(energy[:, 1] == 0.0) and np.all(energy[:, 0] >= 0.0),
          "rigid body: strain energy 0, kinetic energy >= 0")
    c = np.array([0.0216506350945, 0.0125])
    j_o = 1.0e-3 + 1.0 * (c @ c)
    expected = 0.5 * j_o * s["wheel_omega"][:, 2]**2
    err = np.abs(energy[:, 0] - expected).max()
    check(err <= 1e-9 * max(expected.max(), 1e-12),
          "kinetic energy = J_O omega^2 / 2 about the fixed axis: max error %.2e J" % err)
    # --restart to a later end against the uninterrupted run
    results = os.path.join(out_dir, name + ".h5")
    outputs = []
    for label, extra in (("restarted", ["--restart", results]), ("straight", [])):
        output = name + "_" + label + ".h5"
        run = subprocess.run([driver, case, "--mesh-dir", mesh_dir, "--output-dir", out_dir,
                              "--output", output, "--set", "integrator.t_end=%r" % (t[-1] + 0.1)]
                             + extra, capture_output=True, text=True)
        if run.returncode != 0:
            fail("the %s run failed (%d):\n%s" % (label, run.returncode, run.stdout + run.stderr))
        outputs.append(os.path.join(out_dir, output))
    with h5py.File(outputs[0], "r") as a, h5py.File(outputs[1], "r") as b:
        same = all(np.array_equal(a["/sensors/" + k][()], b["/sensors/" + k][()])
                   for k in b["/sensors"]) and len(a["/sensors"]) == len(b["/sensors"])
        check(same and a["/time/t"].shape == b["/time/t"].shape and len(a["/time/t"]) > n,
              "--restart of the crank-less run: its sensors equal the uninterrupted run's, "
              "bitwise (%d steps)" % len(a["/time/t"]))
    check(np.all(s["ground_point"] == s["ground_point"][0]) and
          abs(s["ground_point"][0, 0] - 0.241732618519) < 1e-15,
          "a ground marker stays where it is")


def euler_rotation(e):
    """A(theta) = (2 e0^2 - 1) I + 2 (e e^T + e0 e~) (docs/theory.md 3.1)."""
    e0, v = e[0], np.asarray(e[1:])
    skew = np.array([[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]])
    return (2 * e0 ** 2 - 1) * np.eye(3) + 2 * (np.outer(v, v) + e0 * skew)


def flexible(driver, case, mesh_dir, out_dir):
    os.makedirs(out_dir, exist_ok=True)
    run = subprocess.run([driver, case, "--mesh-dir", mesh_dir, "--output-dir", out_dir],
                         capture_output=True, text=True)
    if run.returncode != 0:
        fail("the driver failed (%d):\n%s" % (run.returncode, run.stdout + run.stderr))
    name = os.path.splitext(os.path.basename(case))[0]
    with h5py.File(os.path.join(out_dir, name + ".h5"), "r") as f:
        t = f["/time/t"][()]
        h = t[1] - t[0]
        g = f["/bodies/conrod"]
        R, E, Z = g["position"][()], g["euler_parameters"][()], g["modal_coordinates"][()]
        order = [text_of(x) for x in g["interfaces/order"][()]]
        x_v = g["interfaces/small_end/virtual_node"][()]
        rows = g["modes/virtual_node_shape"][()]                       # (m, 6 n_if)
        freq = g["modes/frequency"][()]
        basis = text_of(g["modes"].attrs.get("basis", b"rc_normal"))
        shape = g["modes/shape"][()]                                   # (m, 3 n)
        node_u = f["/sensors/conrod_node_u"][()]
        node_x = f["/sensors/conrod_node_x"][()]
        node_attrs = dict(f["/sensors/conrod_node_u"].attrs)
        position = f["/sensors/small_end_position"][()]
        velocity = f["/sensors/small_end_velocity"][()]
        energy = f["/sensors/conrod_energy"][()]
        attrs = dict(f["/sensors/small_end_position"].attrs)
    check(text_of(attrs["body"]) == "conrod" and text_of(attrs["marker"]) == "small_end",
          "attributes name the flexible body and its interface")
    j = order.index("small_end")
    psi = rows[:, 6 * j:6 * j + 3]                                    # (m, 3)
    rigid = np.array([R[s] + euler_rotation(E[s]) @ x_v for s in range(len(t))])
    expected = np.array([R[s] + euler_rotation(E[s]) @ (x_v + psi.T @ Z[s])
                         for s in range(len(t))])
    err = np.abs(position - expected).max()
    check(err <= 1e-14 * max(1.0, np.abs(expected).max()) * 100,
          "flexible marker position = R + A (x_V + Psi_V zeta): max error %.2e m" % err)
    elastic = np.abs(position - rigid).max()
    check(elastic > 1e3 * max(err, 1e-18),
          "the elastic motion is in the sensor: %.2e m beyond the rigid motion of x_V" % elastic)
    fd = central(position, h)
    err = np.abs(velocity[1:-1] - fd).max()
    bound = o_h2_bound(position, h)
    check(err <= bound, "flexible marker velocity = central difference of its position: "
          "%.2e <= O(h^2) bound %.2e" % (err, bound))
    check(np.all(energy[:, 0] >= 0.0), "kinetic energy >= 0")
    tags, xyz = msh41_nodes(os.path.join(mesh_dir, "conrod_lc8.msh"))
    i = tags.index(100)
    check(int(node_attrs["node"]) == 100 and text_of(node_attrs["units"]) == "m",
          "a node sensor's attributes: node 100, m")
    u = Z @ shape[:, 3 * i:3 * i + 3]
    err = np.abs(node_u - u).max()
    check(err <= 1e-12 * max(np.abs(u).max(), 1e-30) + 1e-20 and np.abs(u).max() > 0.0,
          "node displacement = its /modes/shape rows times zeta: max error %.2e m of %.2e m"
          % (err, np.abs(u).max()))
    x_n = np.array([R[s] + euler_rotation(E[s]) @ (xyz[i] + u[s]) for s in range(len(t))])
    err = np.abs(node_x - x_n).max()
    check(err <= 1e-12, "node position = R + A (x_n + u), x_n from the mesh file: max error "
          "%.2e m" % err)
    if basis == "rc_normal":
        strain = 0.5 * ((2.0 * math.pi * freq) ** 2 * Z ** 2).sum(axis=1)
        err = np.abs(energy[:, 1] - strain).max()
        check(err <= 1e-10 * max(strain.max(), 1e-30),
              "strain energy = 1/2 sum (2 pi f_i)^2 zeta_i^2: max error %.2e J (max %.2e J)"
              % (err, strain.max()))


def msh41_nodes(path):
    """Node tags (file order) and coordinates of a Gmsh 4.1 ASCII mesh."""
    with open(path) as f:
        lines = f.read().split("\n")
    k = lines.index("$Nodes") + 1
    blocks = int(lines[k].split()[0])
    k += 1
    tags, xyz = [], []
    for _ in range(blocks):
        count = int(lines[k].split()[3])
        tags += [int(x) for x in lines[k + 1:k + 1 + count]]
        xyz += [[float(v) for v in x.split()[:3]] for x in lines[k + 1 + count:k + 1 + 2 * count]]
        k += 1 + 2 * count
    return tags, np.array(xyz)


def text_of(x):
    return x.decode() if isinstance(x, bytes) else str(x)


def engine(results):
    with h5py.File(results, "r") as f:
        for name in ("crank_angle", "crank_speed"):
            series = f["/time/" + name][()]
            sensor = f["/sensors/" + name][()]
            check(sensor.shape == (len(series), 1), "/sensors/%s is (num_steps, 1)" % name)
            check(np.array_equal(sensor[:, 0], series),
                  "/sensors/%s = /time/%s, bitwise" % (name, name))


if __name__ == "__main__":
    if len(sys.argv) == 6 and sys.argv[1] == "slider":
        slider(*sys.argv[2:])
    elif len(sys.argv) == 6 and sys.argv[1] == "flexible":
        flexible(*sys.argv[2:])
    elif len(sys.argv) == 3 and sys.argv[1] == "engine":
        engine(sys.argv[2])
    else:
        print(__doc__)
        sys.exit(2)
