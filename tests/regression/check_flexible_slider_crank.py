#!/usr/bin/env python3
"""The flexible slider-crank (input/flexible_slider_crank.nml, issue 24 item 4;
docs/validation.md "Flexible benchmarks") against Exudyn and against beam theory.

    check_flexible_slider_crank.py FFRF MESH_DIR CASE WORK --python VENV_PYTHON [--h H]
        [--t-end T] [--csv FILE]

Runs the ffrf driver twice: the case itself, and a modal run of its rod (the same &body,
&interface and num_modes) with `export = 'exudyn'` (docs/results.md "Exudyn export"); the two
runs' mode fingerprints must agree. Then, in the Exudyn environment (postprocess/exudyn_venv.py):

1. Peer code. Exudyn's ObjectFFRFreducedOrder built from the exported rod (its M, K and ffrf's
   mass-normalised simply supported modes; every inertia term from the whole mesh), its ends
   MarkerSuperElementRigid on the end faces' node sets with ffrf's RBE3 weights (offset to the
   virtual nodes), the crank a rigid body held to the ground by a GenericJoint whose rotation
   about z is the driver's angle theta(t) (offsetUserFunction: the integral of the smooth step
   of the speed, docs/mechanisms.md "Laws over time"), the slider a rigid body on a GenericJoint
   that leaves x free, revolute joints (five rows each) at the crank pin and the wrist; the
   same generalized-alpha (index 3, the case's rho_inf and h, consistent initial accelerations).
   Compared at every step: the mid-span deflection Psi_mid zeta (the mesh node at (L/2, 0, 0),
   ffrf's sensor "midspan", body frame = the chord frame of the simply supported modes),
   the slider's travel (ffrf's sensor "slider") and the crank angle (sensor "motor").
   Both codes integrate the same discrete equations, so they agree to the Newton tolerances and
   round-off, whatever h (the step error of either is the same): tolerance MIDSPAN_TOL of the
   peak deflection (the issue asks 1e-6), SLIDER_TOL m on the travel, ANGLE_TOL rad.
   The rod's RBE3 weights are area-consistent, so its virtual nodes are the weighted means of
   their faces' nodes (no lever arm): with uniform weights they lie 3.2e-5 m off, the two codes
   carry that lever arm through the interface's elastic rotation (0.055 rad here) differently,
   and the histories differ by 3.2e-4 of the peak (measured).
2. Physical check, loose: the mid-span deflection history of an Euler-Bernoulli pinned-pinned
   beam (its first three modes, section A and I of the mesh's end face, E and rho of the case)
   moved by the rigid slider-crank's kinematics (the transverse inertia load -rho A a_n(s),
   linear in s), integrated by scipy; no rotating-frame terms, no axial load. Its peak against
   ffrf's within PEAK_TOL (relative) and the histories within HISTORY_TOL of the peak: the
   difference is the FFRF coupling that the one-way beam model leaves out (the rod's rotation
   softens and couples its modes, the slider's inertia loads it axially), the 3D ends (RBE3
   faces, not ideal pins) and the Tet10 mesh (its first frequency 0.09 % below the beam's).

Exit 0 pass, 1 fail (the failing line names the check), 77 when the Exudyn environment is
missing (ctest's skip code).
"""
import argparse
import math
import os
import sys

from exudyn_export import (add_exported_body, check, in_exudyn_environment, modes_mismatch,
                           run_ffrf)

# Peer code: the same discrete equations; what is left is Exudyn's Newton tolerance (NEWTON_RTOL,
# relative to the residual) and round-off: measured 8.4e-11 of the peak, 5.1e-13 m, 3.0e-12 rad
# at h = 2e-5 s over 0.1 s; the bounds leave about 100 x for another CPU's BLAS.
MIDSPAN_TOL = 1e-8      # of the peak mid-span deflection (the issue asks 1e-6)
SLIDER_TOL = 1e-10      # m, slider travel
ANGLE_TOL = 1e-10       # rad, crank angle
# Beam theory: measured 2.7e-3 (peak) and 1.27e-2 (history); what the beam model leaves out is
# of the order (Omega_rod / omega_1)^2 = (75 / 767)^2 = 1 % (the rod's rotation softening its
# bending) plus the mesh's 3D ends; bounds about 3 x the measured values.
PEAK_TOL = 0.01         # relative difference of the peaks
HISTORY_TOL = 0.04      # max history difference over the beam's peak
NEWTON_RTOL, NEWTON_ATOL = 1e-8, 1e-10   # Exudyn's Newton tolerances


def number(group, key):
    value = group.get(key)
    return [float(v) for v in value] if isinstance(value, list) else float(value)


class Scene:
    """The case's numbers the peer model and the beam model need (from its namelist)."""

    def __init__(self, case_path):
        import namelist
        self.groups = namelist.read(case_path)
        g = self.groups
        self.rod = namelist.find(g, "body", name="rod")
        self.crank = namelist.find(g, "body", name="crank")
        self.slider = namelist.find(g, "body", name="slider")
        self.pin = number(namelist.find(g, "marker", body="crank", name="A"), "position")
        self.rail = number(namelist.find(g, "marker", body="ground", name="rail"), "position")
        driver = namelist.find(g, "driver", name="motor")
        if (driver.get("quantity"), driver.get("law")) != ("rate", "smooth_step") or \
                number(driver, "initial") != 0.0 or number(driver, "t_start") != 0.0:
            raise SystemExit("check_flexible_slider_crank: the peer model knows the driver "
                             "quantity = 'rate', law = 'smooth_step' from 0 at t = 0 only")
        self.speed = number(driver, "final")
        self.ramp = number(driver, "duration")
        integrator = namelist.find(g, "integrator")
        self.h = number(integrator, "h")
        self.t_end = number(integrator, "t_end")
        self.rho_inf = number(integrator, "rho_inf")
        self.young = number(self.rod, "young")
        self.density = number(self.rod, "density")

    def angle(self, t):
        """The driver's angle: the integral of the smooth step of the speed (0 -> speed over
        ramp, s(tau) = tau - sin(2 pi tau)/(2 pi)), then constant speed."""
        tau = min(t / self.ramp, 1.0)
        ramp = self.speed * self.ramp * (0.5 * tau * tau
                                         + (math.cos(2.0 * math.pi * tau) - 1.0)
                                         / (4.0 * math.pi ** 2))
        return ramp + self.speed * max(t - self.ramp, 0.0)

    def modal_case(self):
        """A modal case of the rod alone: its &body (no mechanism keys), &interface groups and
        its num_modes as &modes."""
        import namelist
        body = namelist.Group("body", [(k, v) for k, v in self.rod.items
                                       if k in ("name", "mesh_file", "volumes", "young",
                                                "poisson", "density")])
        groups = [namelist.Group("run", [("title", ["slider-crank rod, modes for Exudyn"])]),
                  body] + namelist.find_all(self.groups, "interface", body="rod") + \
            [namelist.Group("modes", [("num_modes", [int(number(self.rod, "num_modes"))])])]
        return namelist.format_groups(groups)


def peer_exudyn(scene, fem, h, t_end):
    """Exudyn's run of the scene: (t, mid-span modal coordinates zeta, slider x, crank angle)."""
    import numpy as np
    import exudyn as exu
    import exudyn.itemInterface as eii
    import peer_exudyn_engine
    sc = exu.SystemContainer()
    mbs = sc.AddSystem()
    ground = mbs.AddObject(eii.ObjectGround())
    _, _, _, rod_modal, ends = add_exported_body(exu, mbs, fem, number(scene.rod, "position"))

    def rigid_body(group, position):
        """A rigid body with the case's mass properties, its node at the centre of mass."""
        com = number(group, "center_of_mass") if group.get("center_of_mass") is not None \
            else [0.0, 0.0, 0.0]
        inertia = number(group, "inertia")          # Jxx Jyy Jzz Jxy Jyz Jxz about the centre
        node = mbs.AddNode(eii.NodeRigidBodyEP(
            referenceCoordinates=list(np.add(position, com)) + [1.0, 0.0, 0.0, 0.0],
            initialVelocities=[0.0] * 7))
        body = mbs.AddObject(eii.ObjectRigidBody(
            nodeNumber=node, physicsMass=number(group, "mass"),
            physicsInertia=inertia[:3] + [inertia[4], inertia[5], inertia[3]]))
        return node, body, np.asarray(com)

    crank_node, crank, crank_com = rigid_body(scene.crank, [0.0, 0.0, 0.0])
    slider_position = number(scene.slider, "position")
    slider_node, slider, slider_com = rigid_body(scene.slider, slider_position)

    def body_marker(body, com, point):
        return mbs.AddMarker(eii.MarkerBodyRigid(bodyNumber=body,
                                                 localPosition=list(np.subtract(point, com))))

    def ground_marker(p):
        return mbs.AddMarker(eii.MarkerBodyRigid(bodyNumber=ground, localPosition=list(p)))

    def drive(mbs_, t, item, parameters):
        return [0.0, 0.0, 0.0, 0.0, 0.0, scene.angle(t)]

    revolute = [1, 1, 1, 1, 1, 0]
    joints = [
        (ground_marker([0.0] * 3), body_marker(crank, crank_com, [0.0] * 3), [1] * 6, drive),
        (body_marker(crank, crank_com, scene.pin), ends["end_a"], revolute, 0),
        (ends["end_b"], body_marker(slider, slider_com, [0.0] * 3), revolute, 0),
        (ground_marker(scene.rail), body_marker(slider, slider_com, [0.0] * 3),
         [0, 1, 1, 1, 1, 1], 0),
    ]
    for m0, m1, axes, user in joints:
        mbs.AddObject(eii.GenericJoint(markerNumbers=[m0, m1], constrainedAxes=axes,
                                       offsetUserFunction=user,
                                       visualization=eii.VGenericJoint(show=False)))
    sensors = {
        "zeta": mbs.AddSensor(eii.SensorNode(nodeNumber=rod_modal, storeInternal=True,
                              outputVariableType=exu.OutputVariableType.Coordinates)),
        "slider": mbs.AddSensor(eii.SensorNode(nodeNumber=slider_node, storeInternal=True,
                                outputVariableType=exu.OutputVariableType.Position)),
        "crank": mbs.AddSensor(eii.SensorNode(nodeNumber=crank_node, storeInternal=True,
                               outputVariableType=exu.OutputVariableType.RotationMatrix)),
    }
    mbs.Assemble()
    ss = peer_exudyn_engine.simulation_settings(exu, h, t_end, scene.rho_inf, NEWTON_RTOL,
                                             NEWTON_ATOL)
    exu.SolveDynamic(mbs, ss, solverType=exu.DynamicSolverType.GeneralizedAlpha,
                     showHints=False)
    zeta = mbs.GetSensorStoredData(sensors["zeta"])
    slider_x = mbs.GetSensorStoredData(sensors["slider"])[:, 1] - slider_com[0]
    rot = mbs.GetSensorStoredData(sensors["crank"])
    angle = np.unwrap(np.arctan2(rot[:, 4], rot[:, 1]))
    return zeta[:, 0], zeta[:, 1:], slider_x - slider_position[0], angle


def section(fem, face):
    """Area and second moments (about the y = 0 and z = 0 lines) of a planar end face, from
    the exported surface triangles whose corners all lie on the face's node set."""
    import numpy as np
    nodes = set(int(n) for n in {s["Name"]: s for s in fem.nodeSets}[face]["NodeNumbers"])
    xyz = fem.nodes["Position"]
    area = iz = 0.0
    for tri in fem.surface[0]["Trigs"]:
        if all(int(n) in nodes for n in tri):
            p = xyz[tri]
            a = 0.5 * abs(np.cross(p[1] - p[0], p[2] - p[0])[0])
            y = p[:, 1]
            area += a
            iz += a / 6.0 * (y @ y + y[0] * y[1] + y[1] * y[2] + y[2] * y[0])
    return area, iz


def beam_history(scene, area, iz, length, t):
    """Mid-span deflection (body y, the chord frame) of a pinned-pinned Euler-Bernoulli beam
    moved by the rigid slider-crank: modes sin(k pi s/L), k = 1, 2, 3, loaded by the
    transverse inertia -rho A a_n(s) of the rigid rod, from rest."""
    import numpy as np
    from scipy.integrate import solve_ivp
    r = math.hypot(*scene.pin[:2])
    rho_a = scene.density * area
    omega = [(k * math.pi / length) ** 2 * math.sqrt(scene.young * iz / rho_a) for k in (1, 2, 3)]

    def kinematics(time):
        """Angle, rate, acceleration of the crank from the driver's law."""
        tau = min(time / scene.ramp, 1.0)
        rate = scene.speed * (tau - math.sin(2.0 * math.pi * tau) / (2.0 * math.pi))
        acc = scene.speed / scene.ramp * (1.0 - math.cos(2.0 * math.pi * tau)) \
            if time < scene.ramp else 0.0
        return scene.angle(time), rate, acc

    def transverse(time):
        th, w, al = kinematics(time)
        c, s = math.cos(th), math.sin(th)
        a_pin = r * np.array([-al * s - w * w * c, al * c - w * w * s])
        # B on the x axis: x_B = r c + sqrt(L^2 - r^2 s^2); its acceleration by differentiation
        root = math.sqrt(length ** 2 - (r * s) ** 2)
        # x_B' = -r s w - r^2 s c w / root
        g = -r * s - r * r * s * c / root                      # dx_B/dtheta
        dg = -r * c - r * r * (c * c - s * s) / root - (r * r * s * c) ** 2 / root ** 3
        a_b = np.array([g * al + dg * w * w, 0.0])
        chord = np.array([r * c + root, 0.0]) - r * np.array([c, s])
        e = chord / length
        n = np.array([-e[1], e[0]])                            # body y: z x e
        return n @ a_pin, n @ a_b

    def rhs(time, y):
        qa, qb = transverse(time)                              # a_n at s = 0 and s = L
        out = np.empty(6)
        for k in range(3):
            kk = k + 1
            # modal force: int_0^L -rho A (qa + (qb - qa) s/L) sin(k pi s/L) ds / (rho A L/2)
            c0 = (1.0 - math.cos(kk * math.pi)) / (kk * math.pi)
            c1 = -math.cos(kk * math.pi) / (kk * math.pi)
            force = -2.0 * (qa * c0 + (qb - qa) * c1)
            out[2 * k] = y[2 * k + 1]
            out[2 * k + 1] = force - omega[k] ** 2 * y[2 * k]
        return out

    sol = solve_ivp(rhs, (t[0], t[-1]), np.zeros(6), t_eval=t, rtol=1e-10, atol=1e-14,
                    method="DOP853", max_step=scene.h * 20)
    mid = sum(math.sin((k + 1) * math.pi / 2.0) * sol.y[2 * k] for k in range(3))
    return mid, omega[0] / (2.0 * math.pi)


def main_exudyn(args):
    import h5py
    import numpy as np
    from exudyn.FEM import FEMinterface
    here = os.path.dirname(os.path.abspath(__file__))
    sys.path.insert(0, os.path.join(here, "..", "..", "postprocess"))
    scene = Scene(args.case)
    h = args.h if args.h else scene.h
    t_end = args.t_end if args.t_end else scene.t_end
    failures = []
    os.makedirs(args.work, exist_ok=True)
    modal = os.path.join(args.work, "slider_crank_rod.nml")
    with open(modal, "w") as fh:
        fh.write(scene.modal_case())
    out = os.path.join(args.work, "out")
    run_ffrf(args, modal, out, ["run.export=exudyn", "run.mode_shapes_msh=none"])
    run_ffrf(args, args.case, out, [f"integrator.h={h!r}", f"integrator.t_end={t_end!r}",
                                    "mechanism.animation_frames=0"])
    stem = os.path.splitext(os.path.basename(args.case))[0]
    with h5py.File(os.path.join(out, stem + ".h5"), "r") as f5:
        if f5.attrs["status"] not in ("complete", b"complete"):
            return [f"ffrf run status {f5.attrs['status']}"]
        t_ffrf = f5["time/t"][()]
        mid_ffrf = f5["sensors/midspan"][()]
        slider_ffrf = f5["sensors/slider"][()][:, 0]
        motor = f5["sensors/motor"][()]
        zeta_ffrf = f5["bodies/rod/modal_coordinates"][()]
    mismatch = modes_mismatch(os.path.join(out, stem + ".h5"),
                              os.path.join(out, "slider_crank_rod.h5"), "rod")
    if mismatch:
        return [mismatch]
    fem = FEMinterface()
    fem.LoadFromFile(os.path.join(out, "slider_crank_rod_rod.exudyn.hdf5"))
    xyz = fem.nodes["Position"]
    length = float(xyz[:, 0].max() - xyz[:, 0].min())
    mid_node = int(np.argmin(np.linalg.norm(xyz - [length / 2.0, 0.0, 0.0], axis=1)))
    psi_mid = fem.modeBasis["matrix"][3 * mid_node:3 * mid_node + 3]
    print(f"rod: L = {length:.6f} m, mid-span node {mid_node} at {xyz[mid_node]}, "
          f"{psi_mid.shape[1]} modes, {np.sqrt(fem.eigenValues) / (2 * math.pi)} Hz")
    check(failures, "the mid-span node's distance from (L/2, 0, 0) (m)",
          float(np.linalg.norm(xyz[mid_node] - [length / 2.0, 0.0, 0.0])), 1e-12)
    # ffrf's sensor is node 1 of the case: the same point as the exported node's mode rows
    check(failures, "ffrf's sensor 'midspan' against Psi_mid zeta of ffrf's run (m)",
          float(np.abs(mid_ffrf - zeta_ffrf @ psi_mid.T).max()), 1e-15)

    t, zeta, slider, angle = peer_exudyn(scene, fem, h, t_end)
    mid = zeta @ psi_mid.T
    if len(t) != len(t_ffrf) or np.abs(t - t_ffrf).max() > 1e-9 * t_end:
        return failures + [f"time grids differ: Exudyn {len(t)}, ffrf {len(t_ffrf)} samples"]
    peak = float(np.abs(mid_ffrf[:, 1]).max())
    k = int(np.argmax(np.abs(mid_ffrf[:, 1])))
    print(f"ffrf against Exudyn, h = {h:g} s, {len(t) - 1} steps to {t_end:g} s: peak mid-span "
          f"deflection {mid_ffrf[k, 1]:.6e} m at t = {t[k]:.5f} s (Exudyn {mid[k, 1]:.6e} m); "
          f"slider travel {slider_ffrf.min():.6f} .. {slider_ffrf.max():.3e} m; crank angle "
          f"at the end {motor[-1, 0]:.6f} rad (wrapped)")
    check(failures, "max |w_exudyn - w_ffrf| / peak |w| (mid-span, body y)",
          float(np.abs(mid[:, 1] - mid_ffrf[:, 1]).max()) / peak, MIDSPAN_TOL)
    check(failures, "max |u_exudyn - u_ffrf| (mid-span, all three components) / peak |w|",
          float(np.abs(mid - mid_ffrf).max()) / peak, MIDSPAN_TOL)
    check(failures, "max |x_exudyn - x_ffrf| (slider travel, m)",
          float(np.abs(slider - slider_ffrf).max()), SLIDER_TOL)
    wrapped = np.remainder(angle - motor[:, 0] + math.pi, 2.0 * math.pi) - math.pi
    check(failures, "max |theta_exudyn - theta_ffrf| (crank angle, rad)",
          float(np.abs(wrapped).max()), ANGLE_TOL)
    law = np.array([scene.angle(x) for x in t])
    check(failures, "max |theta_ffrf - theta(t)| (the driver's law, rad)",
          float(np.abs(np.remainder(law - motor[:, 0] + math.pi, 2.0 * math.pi) - math.pi).max()),
          1e-9)

    area, iz = section(fem, "end_a")
    beam, f1 = beam_history(scene, area, iz, length, t)
    beam_peak = float(np.abs(beam).max())
    print(f"beam theory: A = {area:.5e} m^2, I = {iz:.5e} m^4 (mesh section; circle d = 6 mm: "
          f"{math.pi * 0.006 ** 2 / 4:.5e}, {math.pi * 0.006 ** 4 / 64:.5e}), first pinned "
          f"frequency {f1:.2f} Hz; peak {beam_peak:.4e} m against ffrf's {peak:.4e} m")
    check(failures, "beam theory: | peak_ffrf / peak_beam - 1 |", abs(peak / beam_peak - 1.0),
          PEAK_TOL)
    check(failures, "beam theory: max |w_ffrf - w_beam| / peak_beam",
          float(np.abs(mid_ffrf[:, 1] - beam).max()) / beam_peak, HISTORY_TOL)
    if args.csv:
        np.savetxt(args.csv, np.column_stack([t, mid_ffrf[:, 1], mid[:, 1], beam, slider_ffrf,
                                              slider]), delimiter=",",
                   header="t_s,w_ffrf_m,w_exudyn_m,w_beam_m,slider_ffrf_m,slider_exudyn_m",
                   comments="")
    return failures


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("ffrf")
    parser.add_argument("mesh_dir")
    parser.add_argument("case")
    parser.add_argument("work")
    parser.add_argument("--python", required=True, help="the Exudyn virtual environment's python")
    parser.add_argument("--h", type=float, help="step (default: the case's)")
    parser.add_argument("--t-end", type=float, help="end time (default: the case's)")
    parser.add_argument("--csv", help="write the histories here")
    args = parser.parse_args()
    code = in_exudyn_environment(args.python, "check_flexible_slider_crank")
    if code is not None:
        return code
    failures = main_exudyn(args)
    for f in failures:
        print(f"check_flexible_slider_crank: FAIL: {f}", file=sys.stderr)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
