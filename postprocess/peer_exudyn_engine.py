#!/usr/bin/env python3
"""The engine of docs/scene.md in Exudyn, on ffrf's bodies and modes: an independent computation of
the undamped engine of issue 30 (docs/theory.md 4.5). Python only; no solver logic of ffrf.

What comes from ffrf: the mesh (Tet10 nodes and connectivity), each interface's node set, RBE3
weights and virtual node, and the mode shapes Psi, from the results of a modal run of the same
bodies (`--modes`, checked against the mechanism run's mode fingerprints), and the case itself
(the input echo of the mechanism run, `--ffrf`: step, rho_inf, t_end, modal damping). What does
not: the mass and stiffness matrices (assembled in numpy, peer_tet10.py; checked by the Rayleigh
quotients of ffrf's modes), every reduced FFRF term (Exudyn's ObjectFFRFreducedOrderInterface
computes them from M, K and Psi), the RBE3 (theory.md 1.2 in numpy, carried by Exudyn's
MarkerSuperElementRigid on six points around the virtual node; --marker nodes: the marker's own
fit of the interface nodes, slow), the joints (Exudyn GenericJoint), the
pressure (single-zone model of theory.md 6, re-implemented here with scipy), the integrator
(Exudyn's generalized-alpha, index 3, or its index-2 trapezoidal rule).

    peer_exudyn_engine.py --modes modes.h5 --ffrf run.h5 [--t-end T] [--solver alpha|trapezoidal]
                          [--csv out.csv] [--npz series.npz] [--speed-tol RAD_S ...]

Prints a CSV (quantity, ffrf, exudyn, unit) to stdout (and --csv): body check (step 1), crank
speed difference over time, strain-energy envelopes per 0.1 s window, growth rate and frequency
of the crank vibration. With --speed-tol / --mean-speed-tol / --strain-tol it is a check:
exit 1 when a tolerance is exceeded (the failing line names it).
"""
import argparse
import math
import os
import sys
import time

import h5py
import numpy as np
import scipy.integrate
import scipy.interpolate
import scipy.optimize

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import namelist  # noqa: E402
import peer_tet10  # noqa: E402


# ---------------------------------------------------------------------------------------------
# The scene (docs/scene.md), SI units; the parts the input echo does not hold as numbers
PISTON_MASS, PISTON_INERTIA = 0.45, 3.0e-4
FLYWHEEL_MASS, FLYWHEEL_INERTIA, FLYWHEEL_COM_Z = 4.0, (0.016, 0.016, 0.030), 0.080
BORE, STROKE, ROD, COMPRESSION = 0.080, 0.090, 0.150, 10.0
P_INTAKE, P_EXHAUST, P_REF, POLYTROPIC = 1.0e5, 1.05e5, 1.0e5, 1.32
WIEBE_START, WIEBE_DURATION, WIEBE_A, WIEBE_M = math.radians(350.0), math.radians(60.0), 5.0, 2.0
WINDOW = 0.1   # envelope window (s), as the energy watch (theory.md 4.5)


def text(value):
    if isinstance(value, np.ndarray) and value.shape == ():
        value = value[()]
    if isinstance(value, (bytes, np.bytes_)):
        return bytes(value).rstrip(b"\0").decode()
    return str(value)


# ---------------------------------------------------------------------------------------------
# In-cylinder pressure, theory.md 6 (single zone, Wiebe, constant polytropic exponent)
class Pressure:
    """p(theta) of the four-stroke cycle (theta unwrapped, period 4 pi, 0 = TDC of the intake):
    intake p_in on [0, pi), the closed part [pi, 3 pi] from the first law with Wiebe heat, blow-down
    to p_ex at 3 pi, exhaust on [3 pi, 4 pi). The heat per cycle gives the target peak."""

    def __init__(self, peak_target):
        self.area = math.pi * BORE ** 2 / 4.0
        self.r = STROKE / 2.0
        self.v_c = self.area * STROKE / (COMPRESSION - 1.0)
        self.grid = np.linspace(math.pi, 3.0 * math.pi, 14401)
        self.heat = scipy.optimize.brentq(lambda q: self._solve(q)[0].max() - peak_target,
                                          1.0, 5000.0, xtol=1e-10)
        p, dp = self._solve(self.heat)
        self.closed = scipy.interpolate.CubicHermiteSpline(self.grid, p, dp)
        self.peak = p.max()

    def volume(self, th):
        return self.v_c + self.area * (ROD + self.r - self.r * np.cos(th)
                                       - np.sqrt(ROD ** 2 - (self.r * np.sin(th)) ** 2))

    def dvolume(self, th):
        s, c = np.sin(th), np.cos(th)
        return self.area * (self.r * s + self.r ** 2 * s * c / np.sqrt(ROD ** 2 - (self.r * s) ** 2))

    def _rhs(self, th, p, heat):
        x = (th - WIEBE_START) / WIEBE_DURATION
        dq = 0.0
        if 0.0 < x:
            dq = heat * WIEBE_A * (WIEBE_M + 1.0) / WIEBE_DURATION * x ** WIEBE_M * \
                math.exp(-WIEBE_A * x ** (WIEBE_M + 1.0))
        return [((POLYTROPIC - 1.0) * dq - POLYTROPIC * p[0] * self.dvolume(th)) / self.volume(th)]

    def _solve(self, heat):
        sol = scipy.integrate.solve_ivp(self._rhs, (self.grid[0], self.grid[-1]), [P_INTAKE],
                                        t_eval=self.grid, args=(heat,), rtol=1e-11, atol=1e-6,
                                        method="DOP853")
        p = sol.y[0]
        dp = np.array([self._rhs(t, [v], heat)[0] for t, v in zip(self.grid, p)])
        return p, dp

    def __call__(self, theta):
        c = math.fmod(theta, 4.0 * math.pi)
        if c < 0.0:
            c += 4.0 * math.pi
        if c < math.pi:
            return P_INTAKE
        if c < 3.0 * math.pi:
            return float(self.closed(c))
        return P_EXHAUST


# ---------------------------------------------------------------------------------------------
# ffrf's case and bodies
class Case:
    """The mechanism run's input echo and the bodies of the modal run."""

    def __init__(self, run_path, modes_path):
        with h5py.File(run_path, "r") as run:
            self.groups = namelist.parse(text(run["input/namelist"][()]), source=run_path)
            self.ffrf_t = run["time/t"][()]
            self.ffrf_speed = run["time/crank_speed"][()]
            self.ffrf_angle = run["time/crank_angle"][()]
            self.ffrf_pressure = run["time/pressure"][()]
            self.ffrf_wall = float(run["integrator/wall_seconds"][0])
            self.ffrf_dropped = run["integrator/dropped_rows"][()]
            self.ffrf_modal = {}
            self.run_hash = {}
            for b in ("crank", "conrod"):
                self.ffrf_modal[b] = run[f"bodies/{b}/modal_coordinates"][()]
                self.run_hash[b] = text(run[f"bodies/{b}/modes/fingerprint/hash"][()][-1])
        integ = namelist.find(self.groups, "integrator")
        self.h = float(integ.get("h"))
        self.t_end = float(integ.get("t_end"))
        self.rho_inf = float(integ.get("rho_inf", 0.8))
        self.rc_label = namelist.find(self.groups, "mechanism").get("label", "")
        self.bodies = {}
        with h5py.File(modes_path, "r") as modes:
            for b in ("crank", "conrod"):
                g = modes[f"bodies/{b}"]
                digest = text(g["modes/fingerprint/hash"][()][-1])
                if digest != self.run_hash[b]:
                    raise SystemExit(f"peer_exudyn_engine: body {b}: the modes of {modes_path} "
                                     f"({digest}) are not those of {run_path} "
                                     f"({self.run_hash[b]}); run the modal case of the same "
                                     "bodies and interfaces")
                group = namelist.find(self.groups, "body", name=b)
                body = {
                    "xyz": g["mesh/coordinates"][()],
                    "tets": g["mesh/tets"][()].astype(np.int64) - 1,
                    "psi": g["modes/shape"][()].T.copy(),
                    "freq": g["modes/frequency"][()],
                    "psi_v_ffrf": g["modes/virtual_node_shape"][()].T.copy(),
                    "mass": float(g["mass/mass"][()]),
                    "com": g["mass/center_of_mass"][()],
                    "inertia": g["mass/inertia"][()],
                    "young": float(group.get("young")),
                    "poisson": float(group.get("poisson")),
                    "density": float(group.get("density")),
                    "damping": float(group.get("modal_damping", 0.0)),
                    "position": [float(v) for v in (group.get("position") or [0.0, 0.0, 0.0])],
                    "interfaces": {},
                }
                for name in g["interfaces/order"][()]:
                    name = text(name).strip()
                    i = g[f"interfaces/{name}"]
                    body["interfaces"][name] = {
                        "nodes": i["nodes"][()].astype(np.int64) - 1,
                        "weights": i["weights"][()],
                        "virtual_node": i["virtual_node"][()],
                        "rc": text(i["rc_dofs"][()]),
                    }
                self.bodies[b] = body


def check_body(body):
    """Step 1: M and K assembled here against ffrf's modes and mass properties."""
    k, m = peer_tet10.assemble(body["xyz"], body["tets"], body["young"], body["poisson"],
                               body["density"])
    psi = body["psi"]
    mr = psi.T @ (m @ psi)
    kr = psi.T @ (k @ psi)
    f_rq = np.sqrt(np.diag(kr) / np.diag(mr)) / (2.0 * math.pi)
    mass, com, inertia = peer_tet10.rigid_inertia(body["xyz"], m)
    body.update(K=k, M=m, Kr=kr, Mr=mr)
    return {
        "rayleigh_freq_rel_err": float(np.max(np.abs(f_rq / body["freq"] - 1.0))),
        "modal_mass_err": float(np.max(np.abs(mr - np.eye(len(mr))))),
        "mass_rel_err": abs(mass / body["mass"] - 1.0),
        "com_err_m": float(np.max(np.abs(com - body["com"]))),
        "inertia_rel_err": float(np.max(np.abs(inertia - body["inertia"]))
                                 / np.max(np.abs(body["inertia"]))),
    }


# ---------------------------------------------------------------------------------------------
# RBE3 (theory.md 1.2), for the 'virtual' markers
VIRTUAL_POINTS = 0.01 * np.vstack([np.eye(3), -np.eye(3)])     # V +- d e_k, d = 10 mm


def skew(a):
    return np.array([[0.0, -a[2], a[1]], [a[2], 0.0, -a[0]], [-a[1], a[0], 0.0]])


def rbe3_virtual_shapes(body, interface):
    """Virtual-node rows [u_V; theta_V] (6, m) of the modes: the weighted least-squares rigid
    fit q_V = G q_B, G = (S^T W S)^-1 S^T W, S_i = [I3, -skew(x_i - x_V)] (theory.md 1.2)."""
    nodes, w = interface["nodes"], interface["weights"]
    r = body["xyz"][nodes] - interface["virtual_node"]
    s = np.zeros((3 * len(nodes), 6))
    for k in range(len(nodes)):
        s[3 * k:3 * k + 3, :3] = np.eye(3)
        s[3 * k:3 * k + 3, 3:] = -skew(r[k])
    ww = np.repeat(w, 3)
    rows = (3 * nodes[:, None] + np.arange(3)).ravel()
    return np.linalg.solve(s.T @ (ww[:, None] * s), s.T @ (ww[:, None] * body["psi"][rows]))


# ---------------------------------------------------------------------------------------------
# Exudyn model
def add_reduced_body(exu, mbs, cms, position, basis, positions, damping=None):
    """An ObjectFFRFreducedOrder at rest at `position` (Euler-parameter node, modal node) from
    the reduced terms of `cms` (ObjectFFRFreducedOrderInterface: every inertia term from the
    whole mesh), with the mode rows `basis` at the mesh points `positions` the markers use and
    an optional modal damping matrix: (object, rigid node, modal node)."""
    import exudyn.itemInterface as eii
    node_rigid = mbs.AddNode(eii.NodeRigidBodyEP(
        referenceCoordinates=list(position) + [1.0, 0.0, 0.0, 0.0], initialVelocities=[0.0] * 7))
    num_modes = cms.nModes
    node_modal = mbs.AddNode(eii.NodeGenericODE2(numberOfODE2Coordinates=num_modes,
                                                 referenceCoordinates=[0.0] * num_modes,
                                                 initialCoordinates=[0.0] * num_modes,
                                                 initialCoordinates_t=[0.0] * num_modes))
    kmc = exu.MatrixContainer()
    kmc.SetWithDenseMatrix(cms.stiffnessMatrixReduced, useDenseMatrix=False)
    mmc = exu.MatrixContainer()
    mmc.SetWithDenseMatrix(cms.massMatrixReduced, useDenseMatrix=False)
    dmc = []
    if damping is not None:
        dmc = exu.MatrixContainer()
        dmc.SetWithDenseMatrix(damping, useDenseMatrix=False)
    obj = mbs.AddObject(eii.ObjectFFRFreducedOrder(
        nodeNumbers=[node_rigid, node_modal], stiffnessMatrixReduced=kmc,
        massMatrixReduced=mmc, dampingMatrixReduced=dmc, modeBasis=basis,
        referencePositions=positions, mass=cms.totalMass, inertia=cms.inertiaLocal,
        centerOfMass=cms.chiU, mPsiTildePsi=cms.mPsiTildePsi,
        mPsiTildePsiTilde=cms.mPsiTildePsiTilde, mPhitTPsi=cms.mPhitTPsi,
        mPhitTPsiTilde=cms.mPhitTPsiTilde, mXRefTildePsi=cms.mXRefTildePsi,
        mXRefTildePsiTilde=cms.mXRefTildePsiTilde, computeFFRFterms=True,
        visualization=eii.VObjectFFRFreducedOrder(show=False)))
    return obj, node_rigid, node_modal


def build(case, exu, marker="virtual", full_basis=False):
    import exudyn.itemInterface as eii
    from exudyn.FEM import FEMinterface, ObjectFFRFreducedOrderInterface

    sc = exu.SystemContainer()
    mbs = sc.AddSystem()
    ground = mbs.AddObject(eii.ObjectGround())
    info = {"mbs": mbs, "sc": sc}
    markers = {}

    for b in ("crank", "conrod"):
        body = case.bodies[b]
        fem = FEMinterface()
        fem.nodes = {"Position": body["xyz"]}
        fem.massMatrix = body["M"].tocsr()
        fem.stiffnessMatrix = body["K"].tocsr()
        fem.modeBasis = {"matrix": body["psi"], "type": "NormalModes"}
        cms = ObjectFFRFreducedOrderInterface(fem, roundMassMatrix=0.0, roundStiffnessMatrix=0.0)
        body["cms"] = cms
        # modal damping xi in every mode: D = 2 xi omega (the modes are mass-normalised)
        damping = None
        if body["damping"] > 0.0:
            damping = np.diag(2.0 * body["damping"] * 2.0 * math.pi * body["freq"])
        # Interface markers (Exudyn MarkerSuperElementRigid: the weighted rigid fit of its mesh
        # nodes, offset to ffrf's virtual node). marker = 'nodes': on the interface node sets
        # with ffrf's weights, as the RBE3 itself; Exudyn evaluates the fit over all of them at
        # every residual (~45 ms a step on this engine). marker = 'virtual' (default): the same
        # linear RBE3 fit (theory.md 1.2) computed here once, q_V = G Psi_B zeta, carried by four
        # marker points rigidly attached to the virtual node (V and V + d e_k, k = x, y, z);
        # the marker's fit of those four points is the virtual node's motion. Checked against
        # 'nodes' (--marker nodes, a short run) and against ffrf's virtual-node mode rows.
        # The object needs mode rows only where markers ask for mesh nodes; every inertia term
        # comes from the whole mesh (cms), so only those rows are given (full_basis: all rows
        # and the marker 'nodes'; same results).
        if marker == "nodes":
            kept = np.arange(len(body["xyz"])) if full_basis else \
                np.unique(np.concatenate([i["nodes"] for i in body["interfaces"].values()]))
            local = -np.ones(len(body["xyz"]), dtype=np.int64)
            local[kept] = np.arange(len(kept))
            rows = (3 * kept[:, None] + np.arange(3)).ravel()
            basis, positions = cms.modeBasis[rows], cms.xRef[rows]
        else:
            basis_rows, position_rows = [], []
            for name, i in body["interfaces"].items():
                psi_v = rbe3_virtual_shapes(body, i)          # (6, m): u_V, theta_V
                i["psi_v"] = psi_v
                for d in VIRTUAL_POINTS:
                    basis_rows.append(psi_v[:3] - skew(d) @ psi_v[3:])
                    position_rows.append(i["virtual_node"] + d)
            basis = np.vstack(basis_rows)
            positions = np.concatenate(position_rows)
        obj, node_rigid, node_modal = add_reduced_body(exu, mbs, cms, body["position"], basis,
                                                       positions, damping)
        info[b] = {"object": obj, "node_rigid": node_rigid, "node_modal": node_modal}
        for k, (name, i) in enumerate(body["interfaces"].items()):
            if marker == "nodes":
                nodes = local[i["nodes"]]
                w = i["weights"] / i["weights"].sum()
                centroid = w @ body["xyz"][i["nodes"]]
            else:
                num = len(VIRTUAL_POINTS)
                nodes = np.arange(num * k, num * k + num)
                w = np.full(num, 1.0 / num)
                centroid = i["virtual_node"] + VIRTUAL_POINTS.mean(axis=0)
            markers[(b, name)] = mbs.AddMarker(eii.MarkerSuperElementRigid(
                bodyNumber=obj, meshNodeNumbers=nodes.tolist(), weightingFactors=w.tolist(),
                offset=(i["virtual_node"] - centroid).tolist(), useAlternativeApproach=True,
                rotationsExponentialMap=2))

    piston_y = case.bodies["conrod"]["position"][1] + 0.150
    node_piston = mbs.AddNode(eii.NodeRigidBodyEP(
        referenceCoordinates=[0.0, piston_y, 0.0, 1.0, 0.0, 0.0, 0.0], initialVelocities=[0.0] * 7))
    piston = mbs.AddObject(eii.ObjectRigidBody(
        nodeNumber=node_piston, physicsMass=PISTON_MASS,
        physicsInertia=[PISTON_INERTIA] * 3 + [0.0] * 3))
    node_fly = mbs.AddNode(eii.NodeRigidBodyEP(
        referenceCoordinates=[0.0, 0.0, FLYWHEEL_COM_Z, 1.0, 0.0, 0.0, 0.0],
        initialVelocities=[0.0] * 7))
    flywheel = mbs.AddObject(eii.ObjectRigidBody(
        nodeNumber=node_fly, physicsMass=FLYWHEEL_MASS,
        physicsInertia=list(FLYWHEEL_INERTIA) + [0.0] * 3))
    info["piston"] = node_piston

    def ground_marker(p):
        return mbs.AddMarker(eii.MarkerBodyRigid(bodyNumber=ground, localPosition=list(p)))

    b1 = case.bodies["crank"]["interfaces"]["B1"]["virtual_node"]
    b3 = case.bodies["crank"]["interfaces"]["B3"]["virtual_node"]
    m_pin = mbs.AddMarker(eii.MarkerBodyRigid(bodyNumber=piston, localPosition=[0.0, 0.0, 0.0]))
    m_hub = mbs.AddMarker(eii.MarkerBodyRigid(bodyNumber=flywheel,
                                              localPosition=[0.0, 0.0, b3[2] - FLYWHEEL_COM_Z]))
    revolute = [1, 1, 1, 1, 1, 0]
    # ffrf drops redundant constraint rows (theory.md 4.3): with RC set 1 the main bearing B3's
    # axial row (the crank's frame fixes both journals' Tz); Exudyn gets the same row released
    b3_axes = list(revolute)
    if case.ffrf_dropped.size:
        if case.bodies["crank"]["interfaces"]["B3"]["rc"].split() != ["Tx", "Ty", "Tz", "Rz"] \
                or case.ffrf_dropped.size != 1:
            raise SystemExit(f"peer_exudyn_engine: ffrf dropped rows {case.ffrf_dropped}: only "
                             "the RC set 1 case (B3's axial row) is mapped to Exudyn")
        b3_axes[2] = 0
    joints = [
        (ground_marker(b1), markers[("crank", "B1")], revolute),
        (ground_marker(b3), markers[("crank", "B3")], b3_axes),
        (markers[("crank", "B3")], m_hub, [1] * 6),
        (markers[("crank", "B2")], markers[("conrod", "big_end")], revolute),
        (markers[("conrod", "small_end")], m_pin, revolute),
        (ground_marker([0.0, piston_y, 0.0]), m_pin, [1, 0, 1, 1, 1, 1]),
    ]
    for m0, m1, axes in joints:
        mbs.AddObject(eii.GenericJoint(markerNumbers=[m0, m1], constrainedAxes=axes,
                                       visualization=eii.VGenericJoint(show=False)))

    # loads: gas force on the piston pin (+y), starter and drag torques at the crank's B3
    pressure = Pressure(float(namelist.find(case.groups, "pressure").get("target_peak_pressure")))
    info["pressure"] = pressure
    starter = namelist.find(case.groups, "load", name="starter")
    drag = namelist.find(case.groups, "load", name="load")
    stall, free_speed, switch_off = (float(starter.get(k)) for k in
                                     ("stall_torque", "free_speed", "switch_off"))
    drag_c = float(drag.get("coefficient"))
    crank_node = info["crank"]["node_rigid"]
    state = {"angle": 0.0}

    def crank_angle_speed(mbs_):
        rot = mbs_.GetNodeOutput(crank_node, exu.OutputVariableType.RotationMatrix)
        wrapped = math.atan2(rot[3], rot[0])           # rotation about z, row-major A
        last = state["angle"]
        angle = last + math.remainder(wrapped - last, 2.0 * math.pi)
        state["angle"] = angle
        speed = mbs_.GetNodeOutput(crank_node, exu.OutputVariableType.AngularVelocityLocal)[2]
        return angle, speed

    def gas_force(mbs_, t, load):
        angle, _ = crank_angle_speed(mbs_)
        return [0.0, -(pressure(angle) - P_REF) * pressure.area, 0.0]

    def crank_torque(mbs_, t, load):
        _, speed = crank_angle_speed(mbs_)
        torque = -drag_c * speed * abs(speed)
        if t <= switch_off:
            torque += max(0.0, stall * (1.0 - speed / free_speed))
        return [0.0, 0.0, torque]

    mbs.AddLoad(eii.LoadForceVector(markerNumber=m_pin, loadVectorUserFunction=gas_force))
    mbs.AddLoad(eii.LoadTorqueVector(markerNumber=markers[("crank", "B3")],
                                     loadVectorUserFunction=crank_torque))

    sensors = {}
    for b in ("crank", "conrod"):
        sensors[b] = mbs.AddSensor(eii.SensorNode(
            nodeNumber=info[b]["node_modal"], storeInternal=True,
            outputVariableType=exu.OutputVariableType.Coordinates))
    sensors["omega"] = mbs.AddSensor(eii.SensorNode(
        nodeNumber=crank_node, storeInternal=True,
        outputVariableType=exu.OutputVariableType.AngularVelocityLocal))
    sensors["rotation"] = mbs.AddSensor(eii.SensorNode(
        nodeNumber=crank_node, storeInternal=True,
        outputVariableType=exu.OutputVariableType.RotationMatrix))
    info["sensors"] = sensors
    mbs.Assemble()
    return info


def simulation_settings(exu, h, t_end, rho_inf, relative_tolerance=1e-10,
                        absolute_tolerance=1e-12):
    """Exudyn's settings of a fixed-step run (h, t_end) with sensors at every step: modified
    Newton to the tolerances, dense solver, generalized-alpha index 3 with rho_inf (the solver
    type is the caller's)."""
    ss = exu.SimulationSettings()
    ti = ss.timeIntegration
    ti.endTime = t_end
    ti.numberOfSteps = int(round(t_end / h))
    ti.verboseMode = 0
    ti.adaptiveStep = False
    ti.newton.useModifiedNewton = True
    ti.newton.relativeTolerance = relative_tolerance
    ti.newton.absoluteTolerance = absolute_tolerance
    ti.generalizedAlpha.computeInitialAccelerations = True
    ti.generalizedAlpha.spectralRadius = rho_inf
    ti.generalizedAlpha.useIndex2Constraints = False
    ti.generalizedAlpha.useNewmark = False
    ss.solutionSettings.writeSolutionToFile = False
    ss.solutionSettings.sensorsWritePeriod = h
    ss.linearSolverType = exu.LinearSolverType.EXUdense
    ss.displayStatistics = False
    ss.displayComputationTime = False
    return ss


def simulate(case, exu, info, solver, t_end, rho_inf):
    mbs = info["mbs"]
    ss = simulation_settings(exu, case.h, t_end, rho_inf)
    if solver == "alpha":
        kind = exu.DynamicSolverType.GeneralizedAlpha
    else:
        kind = exu.DynamicSolverType.TrapezoidalIndex2
    start = time.perf_counter()
    ok = exu.SolveDynamic(mbs, ss, solverType=kind, showHints=False)
    wall = time.perf_counter() - start
    s = info["sensors"]
    crank = mbs.GetSensorStoredData(s["crank"])
    conrod = mbs.GetSensorStoredData(s["conrod"])
    omega = mbs.GetSensorStoredData(s["omega"])
    rot = mbs.GetSensorStoredData(s["rotation"])
    t = crank[:, 0]
    angle = np.unwrap(np.arctan2(rot[:, 4], rot[:, 1]))
    return {"ok": bool(ok), "wall": wall, "t": t, "zeta_crank": crank[:, 1:],
            "zeta_conrod": conrod[:, 1:], "speed": omega[:, 3], "angle": angle}


# ---------------------------------------------------------------------------------------------
# Analysis
def strain_energy(zeta, kr):
    return 0.5 * np.einsum("ti,ij,tj->t", zeta, kr, zeta)


def envelope(t, u, t_end):
    """Largest value in each window of WINDOW seconds: (window end times, maxima)."""
    edges = np.arange(0.0, t_end + 1e-12, WINDOW)
    ends, peaks = [], []
    for a, b in zip(edges[:-1], edges[1:]):
        sel = (t > a + 1e-12) & (t <= b + 1e-12)
        if sel.any():
            ends.append(b)
            peaks.append(u[sel].max())
    return np.array(ends), np.array(peaks)


def growth_rate(ends, peaks, t_from):
    """Least-squares slope of ln(envelope) over the windows ending after t_from (1/s)."""
    sel = ends > t_from + 1e-9
    if sel.sum() < 2:
        return float("nan")
    return float(np.polyfit(ends[sel], np.log(peaks[sel]), 1)[0])


def vibration_frequency(t, zeta, kr, t_from):
    """Frequency (Hz) of the largest spectral peak above 500 Hz of the crank's modal coordinate
    carrying most strain energy over t > t_from."""
    sel = t > t_from
    q = zeta[sel]
    j = int(np.argmax(0.5 * np.diag(kr) * (q ** 2).mean(axis=0)))
    x = q[:, j] - q[:, j].mean()
    dt = t[1] - t[0]
    spec = np.abs(np.fft.rfft(x * np.hanning(len(x))))
    freq = np.fft.rfftfreq(len(x), dt)
    band = freq > 500.0
    return float(freq[band][np.argmax(spec[band])]), j + 1


def growth_onset(ends, peaks, factor=1.5):
    """First window end after which the envelope stays above `factor` times its value at 0.5 s
    and keeps rising to the end (nan when it never does)."""
    base = peaks[np.argmin(np.abs(ends - 0.5))]
    above = peaks > factor * base
    for k in range(len(peaks)):
        if above[k:].all() and peaks[-1] > 2.0 * factor * base:
            return float(ends[k])
    return float("nan")


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--modes", required=True, help="ffrf results of the modal run")
    parser.add_argument("--ffrf", required=True, help="ffrf results of the mechanism run")
    parser.add_argument("--t-end", type=float, help="end time (default: the case's)")
    parser.add_argument("--solver", choices=("alpha", "trapezoidal"), default="alpha")
    parser.add_argument("--rho-inf", type=float, help="default: the case's")
    parser.add_argument("--csv", help="also write the CSV here")
    parser.add_argument("--npz", help="write the Exudyn series here")
    parser.add_argument("--marker", choices=("virtual", "nodes"), default="virtual",
                        help="interface markers: on the RBE3 virtual node (default, fast) or on "
                        "the interface node sets with ffrf's weights (Exudyn's own fit, slow)")
    parser.add_argument("--full-basis", action="store_true",
                        help="give Exudyn the mode shapes at every mesh node (slow; the default "
                        "keeps the interface nodes' rows, which is all the markers use)")
    parser.add_argument("--label", default="", help="first column of every CSV row")
    parser.add_argument("--speed-tol", type=float,
                        help="check: max |speed_exudyn - speed_ffrf| (rad/s) over the run")
    parser.add_argument("--mean-speed-tol", type=float,
                        help="check: mean |speed_exudyn - speed_ffrf| (rad/s)")
    parser.add_argument("--strain-tol", type=float,
                        help="check: max |U_exudyn - U_ffrf| / max U_ffrf of each body's strain "
                        "energy over the run")
    parser.add_argument("--rayleigh-tol", type=float, default=1e-7,
                        help="check: Rayleigh quotients of ffrf's modes with M, K assembled here")
    args = parser.parse_args(argv)

    import exudyn as exu

    case = Case(args.ffrf, args.modes)
    t_end = args.t_end or case.t_end
    rho_inf = case.rho_inf if args.rho_inf is None else args.rho_inf
    rows = []
    failures = []
    label = args.label or f"{case.rc_label}"

    def row(quantity, ffrf_value, exudyn_value, unit):
        rows.append((label, quantity, ffrf_value, exudyn_value, unit))

    for b in ("crank", "conrod"):
        c = check_body(case.bodies[b])
        row(f"{b}: Rayleigh quotients of ffrf's modes, max |f/f_ffrf - 1|", 0.0,
            c["rayleigh_freq_rel_err"], "-")
        row(f"{b}: max |Psi^T M Psi - I|", 0.0, c["modal_mass_err"], "-")
        row(f"{b}: mass (M assembled here) rel. error", 0.0, c["mass_rel_err"], "-")
        if c["rayleigh_freq_rel_err"] > args.rayleigh_tol:
            failures.append(f"{b}: Rayleigh quotient error {c['rayleigh_freq_rel_err']:.3g} > "
                            f"{args.rayleigh_tol:g}")

    setup = time.perf_counter()
    info = build(case, exu, args.marker, args.full_basis)
    setup = time.perf_counter() - setup
    for b in ("crank", "conrod"):
        body, cms = case.bodies[b], case.bodies[b]["cms"]
        com = np.asarray(cms.chiU)
        inertia_o = np.asarray(cms.inertiaLocal)
        inertia_c = inertia_o - cms.totalMass * (com @ com * np.eye(3) - np.outer(com, com))
        row(f"{b}: mass", body["mass"], cms.totalMass, "kg")
        row(f"{b}: centre of mass y", body["com"][1], com[1], "m")
        for k, axis in enumerate("xyz"):
            row(f"{b}: J{axis}{axis} about the centre of mass", body["inertia"][k, k],
                inertia_c[k, k], "kg m^2")
    if args.marker == "virtual":
        for b in ("crank", "conrod"):
            body = case.bodies[b]
            mine = np.vstack([i["psi_v"] for i in body["interfaces"].values()])
            row(f"{b}: virtual-node mode rows G Psi_B, max |here - ffrf| / max |ffrf|", 0.0,
                float(np.abs(mine - body["psi_v_ffrf"]).max() / np.abs(body["psi_v_ffrf"]).max()),
                "-")
    p_check = np.array([info["pressure"](a) for a in case.ffrf_angle[::50]])
    row("pressure at ffrf's crank angles, max |p - p_ffrf|", 0.0,
        float(np.max(np.abs(p_check - case.ffrf_pressure[::50]))), "Pa")
    row("peak pressure (ffrf: largest recorded in the run)", float(case.ffrf_pressure.max()),
        info["pressure"].peak, "Pa")

    res = simulate(case, exu, info, args.solver, t_end, rho_inf)
    row("Exudyn solver", "generalized-alpha index 3, rho_inf %g" % case.rho_inf,
        ("generalized-alpha index 3, rho_inf %g" % rho_inf) if args.solver == "alpha"
        else "trapezoidal index 2", "")
    row("step h", case.h, case.h, "s")
    row("completed", 1, int(res["ok"] and abs(res["t"][-1] - t_end) < 0.5 * case.h), "-")
    row("wall time (Exudyn: solve only; set-up %.1f s)" % setup, case.ffrf_wall, res["wall"], "s")

    # speeds on the common grid
    t = res["t"]
    n = min(len(t), np.searchsorted(case.ffrf_t, t_end + 0.5 * case.h))
    ffrf_speed = np.interp(t, case.ffrf_t[:n], case.ffrf_speed[:n])
    diff = np.abs(res["speed"] - ffrf_speed)
    row("crank speed, mean |difference|", 0.0, float(diff.mean()), "rad/s")
    row("crank speed, max |difference|", 0.0, float(diff.max()), "rad/s")
    row("crank speed at t = %.3g s" % t[-1], float(ffrf_speed[-1]), float(res["speed"][-1]), "rad/s")
    steady = t > min(1.0, 0.5 * t_end)
    row("crank speed, mean over t > %.3g s" % t[steady][0], float(ffrf_speed[steady].mean()),
        float(res["speed"][steady].mean()), "rad/s")
    if args.speed_tol is not None and diff.max() > args.speed_tol:
        failures.append(f"max speed difference {diff.max():.4g} rad/s > {args.speed_tol:g}")
    if args.mean_speed_tol is not None and diff.mean() > args.mean_speed_tol:
        failures.append(f"mean speed difference {diff.mean():.4g} rad/s > {args.mean_speed_tol:g}")

    series = {"t": t, "speed": res["speed"], "angle": res["angle"], "ffrf_speed": ffrf_speed}
    for b in ("crank", "conrod"):
        kr = case.bodies[b]["Kr"]
        u_ex = strain_energy(res[f"zeta_{b}"], kr)
        omega2 = (2.0 * math.pi * case.bodies[b]["freq"]) ** 2
        zf = np.column_stack([np.interp(t, case.ffrf_t[:n], col)
                              for col in case.ffrf_modal[b][:n].T])
        u_ff = 0.5 * (zf ** 2 * omega2).sum(axis=1)
        series[f"strain_{b}"] = u_ex
        strain_diff = float(np.abs(u_ex - u_ff).max() / u_ff.max())
        row(f"{b}: strain energy, max |U - U_ffrf| / max U_ffrf", 0.0, strain_diff, "-")
        if args.strain_tol is not None and not strain_diff <= args.strain_tol:
            failures.append(f"{b}: strain energy difference {strain_diff:.3g} of its maximum > "
                            f"{args.strain_tol:g}")
        series[f"ffrf_strain_{b}"] = u_ff
        series[f"zeta_{b}"] = res[f"zeta_{b}"]
        e_end, e_ex = envelope(t, u_ex, t_end)
        _, e_ff = envelope(t, u_ff, t_end)
        for k in range(len(e_end)):
            if b == "crank" or abs(e_end[k] - round(e_end[k] * 2) / 2) < 1e-9:
                row(f"{b}: largest strain energy in the window ending {e_end[k]:.1f} s",
                    float(e_ff[k]), float(e_ex[k]), "J")
        if t_end >= 1.0:
            tf = t_end - 0.5
            row(f"{b}: envelope growth rate over {tf:.1f}-{t_end:.1f} s",
                growth_rate(e_end, e_ff, tf), growth_rate(e_end, e_ex, tf), "1/s")
            row(f"{b}: growth onset (envelope > 1.5x its 0.5 s value for good)",
                growth_onset(e_end, e_ff), growth_onset(e_end, e_ex), "s")
            f_ex, j_ex = vibration_frequency(t, res[f"zeta_{b}"], kr, tf)
            f_ff, j_ff = vibration_frequency(t, zf, np.diag(omega2), tf)
            row(f"{b}: vibration frequency (FFT of the most energetic mode over {tf:.1f}-{t_end:.1f} s)",
                f_ff, f_ex, "Hz")
            row(f"{b}: that mode", j_ff, j_ex, "-")
    if args.npz:
        np.savez_compressed(args.npz, **series)

    out = ["label,quantity,ffrf,exudyn,unit"]
    for r in rows:
        out.append(",".join(f'"{v}"' if isinstance(v, str) and ("," in v or " " in v) else
                            (f"{v:.6g}" if isinstance(v, float) else str(v)) for v in r))
    text_out = "\n".join(out) + "\n"
    sys.stdout.write(text_out)
    if args.csv:
        with open(args.csv, "w") as fh:
            fh.write(text_out)
    for f in failures:
        print(f"peer_exudyn_engine: FAIL: {f}", file=sys.stderr)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
