#!/usr/bin/env python3
"""The Exudyn export (&run export = 'exudyn', docs/results.md "Exudyn export") checked with Exudyn
itself (issue 26, item 4). Runs the ffrf driver, then Exudyn (the peer virtual environment of
postprocess/exudyn_venv.py) on the files it wrote.

    exudyn_export.py load  FFRF MESH_DIR INPUT_DIR WORK --python VENV_PYTHON --body crank|conrod
    exudyn_export.py hinge FFRF MESH_DIR INPUT_DIR WORK --python VENV_PYTHON
    exudyn_export.py mechanism FFRF MESH_DIR INPUT_DIR WORK --python VENV_PYTHON --case ENGINE
    exudyn_export.py hinge_mechanism FFRF MESH_DIR INPUT_DIR WORK --python VENV_PYTHON

load: the crank (crank_lc8.msh) or the conrod (conrod_lc8.msh), free-free (every interface
without reference conditions, 12 modes), each exported and loaded by FEMinterface.LoadFromFile.
Reference: scipy's shift-invert Lanczos (ARPACK on SuperLU, not ffrf's MUMPS) on the loaded M
and K gives ffrf's free-free frequencies to 1e-8 relative (both solve to ~1e-12). Besides: the
mass of M (sum of its x-x entries) against ffrf's /mass (1e-12), the Tet10 mid-side nodes at the
midpoints of Exudyn's C3D10 edges (1e-12 of the edge length), the surface triangles closed and
outward (the divergence theorem's volume, (1/3) sum A n.x, equal to the tetrahedra's volume to
1e-10), the node sets against ffrf's interfaces (nodes exact, weights to 1e-14); and the RC set 1
crank (RC normal and Craig-Bampton) and the simply supported conrod: Psi^T M Psi = I and
Psi^T K Psi = diag(eigenValues) to 1e-9 (the modes' own residual level), basis type recorded.

hinge: an Exudyn ObjectFFRFreducedOrder built from the exported conrod (big_end clamped RC set,
6 RC normal modes) on a revolute joint to the ground at big_end (MarkerSuperElementRigid on the
interface node set with its RBE3 weights, GenericJoint), driven by a torque of 1 N m about z,
against ffrf's own run of the same scene (generalized-alpha, rho_inf 0.8, h = 1e-4 s, 0.05 s).
Reference: ffrf's rotation angle of the body at every step: 1e-10 rad (measured 4.9e-13; the
issue asks 1e-6), and the strain energy of the modal coordinates, 3e-9 of its maximum (measured
3.1e-10).

mechanism: the engine (ENGINE: engine_lc8_rc1.nml, crank RC set 1 and conrod, 10 modes each)
run for 5 ms with --set run.export=exudyn writes each flexible body (none of the rigid ones);
each file loads; scipy on its M and K gives the free-free frequencies of ffrf's modal run of
the body (12 modes, 1e-8 relative); its mode basis is the mechanism's modes (the same numbers)
with Psi^T M Psi = I and Psi^T K Psi = diag(eigenValues) (1e-9); mesh and node sets as in load.

hinge_mechanism: hinge, with the body file the mechanism run writes itself (--set
run.export=exudyn on the scene; no modal run): the same tolerances.

Exit 0 pass, 1 fail (the failing line names the check), 77 when the Exudyn environment is
missing (ctest's skip code).
"""
import argparse
import math
import os
import subprocess
import sys
import warnings

warnings.filterwarnings("ignore", category=DeprecationWarning)   # Exudyn's old setting names

SKIP = 77


def run_ffrf(args, case, out, sets):
    os.makedirs(out, exist_ok=True)
    command = [args.ffrf, case, "--mesh-dir", args.mesh_dir, "--output-dir", out]
    for s in sets:
        command += ["--set", s]
    done = subprocess.run(command, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    if done.returncode != 0:
        sys.exit(f"exudyn_export: {' '.join(command)} exited {done.returncode}:\n{done.stdout}")


# ---------------------------------------------------------------------------------------------
FREE_FREE = {"crank": ("crank_rc1.nml", ["B1", "B2", "B3"], "crank_lc8.msh"),
             "conrod": ("conrod.nml", ["big_end", "small_end"], "conrod_lc8.msh")}


def in_exudyn_environment(python, who):
    """None when Exudyn imports in this interpreter; else the exit code of this script run again
    by the Exudyn environment's `python`, or SKIP when that environment is missing or broken."""
    try:
        import exudyn  # noqa: F401
        return None
    except ImportError:
        pass
    if not os.path.exists(python):
        print(f"{who}: no Exudyn environment ({python}): skipped", file=sys.stderr)
        return SKIP
    venv = os.path.dirname(os.path.dirname(os.path.abspath(python)))
    if os.path.abspath(sys.prefix) == venv:
        print(f"{who}: {python} does not import exudyn: skipped", file=sys.stderr)
        return SKIP
    return subprocess.call([python] + sys.argv)


def check(failures, what, value, tol):
    ok = value <= tol
    print(f"  {what}: {value:.3e} (tolerance {tol:g}) {'ok' if ok else 'FAIL'}")
    if not ok:
        failures.append(what)


def load_body(path):
    from exudyn.FEM import FEMinterface
    fem = FEMinterface()
    fem.LoadFromFile(path)
    return fem


def nearest_mismatch(xyz, elements, corners, edges, first):
    """Count of mid-side nodes first + k that are not the nearest, among the element's mid-side
    nodes, to the midpoint of edges[k]."""
    import numpy as np
    mids = xyz[elements[:, first:first + len(edges)]]                 # (ne, n_edges, 3)
    wrong = 0
    for k, (a, b) in enumerate(edges):
        target = 0.5 * (corners[:, a] + corners[:, b])
        d = np.linalg.norm(mids - target[:, None, :], axis=2)
        wrong += int((d.argmin(axis=1) != k).sum())
    return wrong


def check_mesh(failures, fem, results, body):
    import h5py
    import numpy as np
    xyz = fem.nodes["Position"]
    elements = fem.elements[0]
    with h5py.File(results, "r") as h5:
        g = h5[f"bodies/{body}"]
        mass = float(g["mass/mass"][()])
        order = [n.decode().strip() for n in g["interfaces/order"][()]]
        sets = {n: (g[f"interfaces/{n}/nodes"][()] - 1, g[f"interfaces/{n}/weights"][()])
                for n in order}
    m = fem.massMatrix
    check(failures, f"{body}: mass of M (sum of its x-x entries) vs ffrf's, rel.",
          abs(m[0::3, 0::3].sum() / mass - 1.0), 1e-12)
    asym = max(abs(m - m.T).max() / abs(m).max(),
               abs(fem.stiffnessMatrix - fem.stiffnessMatrix.T).max()
               / abs(fem.stiffnessMatrix).max())
    check(failures, f"{body}: M and K symmetric, max |A - A^T| / max |A|", asym, 1e-14)
    tet = elements["Tet10"]
    c = xyz[tet[:, :4]]
    # Exudyn's (C3D10) mid-side nodes 4..9 on edges 0-1, 1-2, 2-0, 0-3, 1-3, 2-3. The mesh is
    # curved (Gmsh puts them on the geometry), so each is checked to be the one nearest to its
    # own edge's midpoint (Gmsh's order, 8 on 2-3 and 9 on 1-3, fails this at every element)
    edges = [(0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3)]
    wrong = nearest_mismatch(xyz, tet, c, edges, 4)
    check(failures, f"{body}: Tet10 mid-side nodes not nearest their C3D10 edge's midpoint",
          wrong, 0)
    tv = np.einsum("ij,ij->i", np.cross(c[:, 1] - c[:, 0], c[:, 2] - c[:, 0]), c[:, 3] - c[:, 0])
    volume = abs(tv).sum() / 6.0
    trig = fem.surface[0]["Trigs"]
    p = xyz[trig]
    n2 = np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0])          # 2 A n
    surface_volume = np.einsum("ij,ij->i", n2, p.mean(axis=1)).sum() / 6.0
    check(failures, f"{body}: volume by the surface's divergence theorem vs tets, rel.",
          abs(surface_volume / volume - 1.0), 1e-10)
    t6 = fem.surface[0]["Trigs6"]
    wrong = nearest_mismatch(xyz, t6, xyz[t6[:, :3]], [(0, 1), (1, 2), (2, 0)], 3)
    check(failures, f"{body}: Trigs6 mid nodes not nearest their edge's midpoint", wrong, 0)
    names = [s["Name"] for s in fem.nodeSets]
    if names != order:
        failures.append(f"{body}: node sets {names} are not ffrf's interfaces {order}")
    for s in fem.nodeSets:
        nodes, w = sets[s["Name"]]
        same = np.array_equal(s["NodeNumbers"], nodes)
        werr = float(np.abs(s["NodeWeights"] - w / w.sum()).max())
        print(f"  {body}, {s['Name']}: {len(nodes)} nodes {'equal' if same else 'DIFFER'}, "
              f"weights {werr:.1e} from ffrf's normalised")
        if not same or werr > 1e-14:
            failures.append(f"{body}: node set {s['Name']}")


def check_basis(failures, fem, results, body, basis_type):
    import h5py
    import numpy as np
    psi = fem.modeBasis["matrix"]
    with h5py.File(results, "r") as h5:
        f_ffrf = h5[f"bodies/{body}/modes/frequency"][()]
    if fem.modeBasis["type"] != basis_type:
        failures.append(f"{body}: modeBasis type {fem.modeBasis['type']}, not {basis_type}")
    lam = fem.eigenValues
    check(failures, f"{body} ({basis_type}): eigenValues vs ffrf's (2 pi f)^2, rel.",
          float(np.abs(lam / (2 * math.pi * f_ffrf) ** 2 - 1).max()), 1e-14)
    mr = psi.T @ (fem.massMatrix @ psi)
    kr = psi.T @ (fem.stiffnessMatrix @ psi)
    check(failures, f"{body} ({basis_type}): max |Psi^T M Psi - I|",
          float(np.abs(mr - np.eye(len(lam))).max()), 1e-9)
    check(failures, f"{body} ({basis_type}): max |Psi^T K Psi - diag(eigenValues)| / max lambda",
          float(np.abs(kr - np.diag(lam)).max() / lam.max()), 1e-9)


def free_free_run(args, body, export):
    """ffrf's modal run of `body` free-free (every interface without reference conditions, 12
    modes; lc 8 mm): the stem of its files and its frequencies."""
    import h5py
    case, interfaces, mesh = FREE_FREE[body]
    out = os.path.join(args.work, f"{body}_free")
    sets = [f"body[{body}].mesh_file={mesh}", "modes.num_modes=12",
            "run.mode_shapes_msh=none"] + [f"interface[{i}].rc=''" for i in interfaces]
    run_ffrf(args, os.path.join(args.input_dir, case), out,
             sets + (["run.export=exudyn"] if export else []))
    stem = os.path.join(out, case[:-4])
    with h5py.File(stem + ".h5", "r") as h5:
        return stem, h5[f"bodies/{body}/modes/frequency"][()]


def check_free_free(failures, fem, f_ffrf, body, what):
    """scipy's shift-invert Lanczos on the loaded M and K against ffrf's free-free frequencies
    f_ffrf (1e-8 relative)."""
    import numpy as np
    import scipy.sparse.linalg as sla
    print(f"{body} ({what}): loaded, {len(fem.nodes['Position'])} nodes, "
          f"{len(fem.elements[0]['Tet10'])} Tet10, {fem.massMatrix.shape[0]} dofs")
    # shift below zero: K - sigma M is definite although K is singular (six rigid modes)
    sigma = -(2 * math.pi * 10.0) ** 2
    vals = sla.eigsh(fem.stiffnessMatrix.tocsc(), k=len(f_ffrf) + 6, M=fem.massMatrix.tocsc(),
                     sigma=sigma, which="LM", tol=1e-14, return_eigenvectors=False)
    vals = np.sort(vals)
    f_scipy = np.sqrt(np.abs(vals[6:])) / (2 * math.pi)
    print(f"  {body}: rigid eigenvalues (scipy) max |lambda| {abs(vals[:6]).max():.2e}, "
          f"flexible {f_scipy[0]:.4f} .. {f_scipy[-1]:.4f} Hz")
    check(failures, f"{body} ({what}): free-free frequencies, scipy on the exported M, K vs "
          "ffrf's modal run, max rel.", float(np.abs(f_scipy / f_ffrf - 1).max()), 1e-8)


def stage_load(args):
    import time
    start = time.perf_counter()
    failures = []
    for body in FREE_FREE:
        if body != args.body:
            continue
        stem, f_ffrf = free_free_run(args, body, True)
        fem = load_body(f"{stem}_{body}.exudyn.hdf5")
        check_mesh(failures, fem, stem + ".h5", body)
        check_free_free(failures, fem, f_ffrf, body, "modal run")
        check_basis(failures, fem, stem + ".h5", body, "NormalModes")
        print(f"  ({time.perf_counter() - start:.1f} s)")
    # constrained bases: RC normal and Craig-Bampton (crank RC set 1), conrod simply supported
    for body, case, basis, kind in [("crank", "crank_rc1.nml", "rc_normal", "NormalModes"),
                                    ("crank", "crank_rc1.nml", "craig_bampton", "HCBmodes"),
                                    ("conrod", "conrod.nml", "rc_normal", "NormalModes")]:
        if body != args.body:
            continue
        out = os.path.join(args.work, f"{body}_{basis}")
        run_ffrf(args, os.path.join(args.input_dir, case), out,
                 [f"body[{body}].mesh_file={FREE_FREE[body][2]}", "run.export=exudyn",
                  f"modes.basis={basis}", "run.mode_shapes_msh=none"])
        stem = os.path.join(out, case[:-4])
        fem = load_body(f"{stem}_{body}.exudyn.hdf5")
        check_basis(failures, fem, stem + ".h5", body, kind)
        if fem.metaData.get("basis") != basis:
            failures.append(f"{body}: metaData basis {fem.metaData.get('basis')}, not {basis}")
    return failures


def stage_mechanism(args):
    """The engine (crank RC set 1 and conrod, 10 RC normal modes each, lc 8 mm) run with
    `--set run.export=exudyn` for MECHANISM_T_END s: each flexible body's file, written by the
    mechanism run, loads; its M and K give the body's free-free frequencies of a modal run; its
    mode basis is the mechanism's (bitwise: the same numbers, run against run) and mass-
    normalised (check_basis); mesh, surface and node sets as check_mesh (against the free-free
    modal run, same mesh and interfaces)."""
    import h5py
    import numpy as np
    failures = []
    out = os.path.join(args.work, "engine")
    run_ffrf(args, args.case, out, ["run.export=exudyn", f"integrator.t_end={MECHANISM_T_END}",
                                    "mechanism.animation_frames=0"])
    stem = os.path.join(out, os.path.splitext(os.path.basename(args.case))[0])
    for rigid in ("piston", "flywheel"):
        if os.path.exists(f"{stem}_{rigid}.exudyn.hdf5"):
            failures.append(f"rigid body {rigid} exported")
    for body in FREE_FREE:
        fem = load_body(f"{stem}_{body}.exudyn.hdf5")
        free_stem, f_free = free_free_run(args, body, False)
        check_mesh(failures, fem, free_stem + ".h5", body)
        check_free_free(failures, fem, f_free, body, "mechanism run")
        check_basis(failures, fem, stem + ".h5", body, "NormalModes")
        with h5py.File(stem + ".h5", "r") as h5:
            shape = h5[f"bodies/{body}/modes/shape"][()]
        if not np.array_equal(fem.modeBasis["matrix"], shape.T):
            failures.append(f"{body}: the exported mode basis is not the mechanism's modes")
        else:
            print(f"  {body}: mode basis = the mechanism run's {shape.shape[0]} modes (bitwise)")
    return failures


# ---------------------------------------------------------------------------------------------
MECHANISM_T_END = 0.005
HINGE_TORQUE, HINGE_H, HINGE_T_END, HINGE_RHO = 1.0, 1.0e-4, 0.05, 0.8
HINGE_BODY = """&body name = 'conrod', mesh_file = 'conrod_lc8.msh', volumes = 'conrod',
      young = 210.0e9, poisson = 0.3, density = 7850.0{extra} /
&interface body = 'conrod', name = 'big_end', mpc = 'RBE3', rc = 'Tx Ty Tz Rx Ry Rz',
           virtual_node = 'position', position = 0.0, 0.0, 0.0 /
&interface body = 'conrod', name = 'small_end', mpc = 'RBE3', rc = '',
           virtual_node = 'position', position = 0.0, 0.150, 0.0 /
&modes num_modes = 6 /
"""
HINGE_SCENE = """&run title = 'Exudyn export: the conrod on a hinge, driven by a torque' /
&mechanism label = 'hinge' /
&integrator h = {h}, t_end = {t_end}, rho_inf = {rho} /
&model selection = 'manual' /
&marker body = 'ground', name = 'hinge', position = 0.0, 0.0, 0.0 /
&joint name = 'hinge', type = 'revolute', body1 = 'ground', marker1 = 'hinge',
       body2 = 'conrod', marker2 = 'big_end' /
&load name = 'drive', type = 'torque', body = 'conrod', marker = 'big_end',
      direction = 0.0, 0.0, 1.0, value = {torque} /
"""


def modes_mismatch(run_path, modes_path, body):
    """A failure line when the mechanism run's modes of `body` are not the modal run's (their
    fingerprints differ), else None."""
    import h5py
    hashes = []
    for path in (run_path, modes_path):
        with h5py.File(path, "r") as h5:
            hashes.append(h5[f"bodies/{body}/modes/fingerprint/hash"][()][-1])
    if hashes[0] != hashes[1]:
        return f"the modal run's modes ({hashes[1]}) are not the mechanism run's ({hashes[0]})"
    return None


def add_exported_body(exu, mbs, fem, position):
    """The exported body `fem` (FEMinterface) as an Exudyn ObjectFFRFreducedOrder at rest at
    `position`, with a MarkerSuperElementRigid at each interface: its node set with ffrf's RBE3
    weights, offset to the virtual node. Only the interface nodes' mode rows are given (all the
    markers use; every inertia term comes from the whole mesh through cms), as
    postprocess/peer_exudyn_engine.py does. Returns (cms, object, rigid node, modal node,
    {interface name: marker})."""
    import numpy as np
    import exudyn.itemInterface as eii
    from exudyn.FEM import ObjectFFRFreducedOrderInterface
    sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..",
                                    "postprocess"))
    import peer_exudyn_engine
    cms = ObjectFFRFreducedOrderInterface(fem, roundMassMatrix=0.0, roundStiffnessMatrix=0.0)
    kept = np.unique(np.concatenate([s["NodeNumbers"] for s in fem.nodeSets]))
    local = -np.ones(len(fem.nodes["Position"]), dtype=np.int64)
    local[kept] = np.arange(len(kept))
    rows = (3 * kept[:, None] + np.arange(3)).ravel()
    obj, node_rigid, node_modal = peer_exudyn_engine.add_reduced_body(
        exu, mbs, cms, position, cms.modeBasis[rows], cms.xRef[rows])
    markers = {}
    for s in fem.nodeSets:
        w = s["NodeWeights"]
        centroid = w @ fem.nodes["Position"][s["NodeNumbers"]]
        markers[s["Name"]] = mbs.AddMarker(eii.MarkerSuperElementRigid(
            bodyNumber=obj, meshNodeNumbers=local[s["NodeNumbers"]].tolist(),
            weightingFactors=w.tolist(), offset=(s["VirtualNode"] - centroid).tolist(),
            useAlternativeApproach=True, rotationsExponentialMap=2))
    return cms, obj, node_rigid, node_modal, markers


def stage_hinge(args):
    import h5py
    import numpy as np
    import exudyn as exu
    import exudyn.itemInterface as eii
    sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..",
                                    "postprocess"))
    import peer_exudyn_engine
    failures = []
    os.makedirs(args.work, exist_ok=True)
    modal = os.path.join(args.work, "hinge_modes.nml")
    scene = os.path.join(args.work, "hinge.nml")
    with open(modal, "w") as fh:
        fh.write("&run title = 'Exudyn export: the hinged conrod, modes' /\n"
                 + HINGE_BODY.format(extra=""))
    with open(scene, "w") as fh:
        fh.write(HINGE_SCENE.format(h=HINGE_H, t_end=HINGE_T_END, rho=HINGE_RHO,
                                    torque=HINGE_TORQUE)
                 + HINGE_BODY.format(extra=", type = 'flexible'"))
    out = os.path.join(args.work, "hinge_out")
    if args.stage == "hinge":
        # the body file of a modal run of the same body, interfaces and modes
        run_ffrf(args, modal, out, ["run.export=exudyn", "run.mode_shapes_msh=none"])
        run_ffrf(args, scene, out, [])
        body_file = os.path.join(out, "hinge_modes_conrod.exudyn.hdf5")
    else:
        # hinge_mechanism: the body file the mechanism run writes itself
        run_ffrf(args, scene, out, ["run.export=exudyn"])
        body_file = os.path.join(out, "hinge_conrod.exudyn.hdf5")
    with h5py.File(os.path.join(out, "hinge.h5"), "r") as h5:
        t_ffrf = h5["time/t"][()]
        ep = h5["bodies/conrod/euler_parameters"][()]
        zeta_ffrf = h5["bodies/conrod/modal_coordinates"][()]
    if args.stage == "hinge":
        mismatch = modes_mismatch(os.path.join(out, "hinge.h5"),
                                  os.path.join(out, "hinge_modes.h5"), "conrod")
        if mismatch:
            return [mismatch]
    angle_ffrf = np.unwrap(2.0 * np.arctan2(ep[:, 3], ep[:, 0]))

    fem = load_body(body_file)
    sc = exu.SystemContainer()
    mbs = sc.AddSystem()
    ground = mbs.AddObject(eii.ObjectGround())
    cms, obj, node_rigid, node_modal, markers = add_exported_body(exu, mbs, fem, [0.0, 0.0, 0.0])
    marker = markers["big_end"]
    hinge = mbs.AddMarker(eii.MarkerBodyRigid(bodyNumber=ground, localPosition=[0.0] * 3))
    mbs.AddObject(eii.GenericJoint(markerNumbers=[hinge, marker], constrainedAxes=[1] * 5 + [0],
                                   visualization=eii.VGenericJoint(show=False)))
    mbs.AddLoad(eii.LoadTorqueVector(markerNumber=marker, loadVector=[0.0, 0.0, HINGE_TORQUE]))
    s_rot = mbs.AddSensor(eii.SensorNode(nodeNumber=node_rigid, storeInternal=True,
                                         outputVariableType=exu.OutputVariableType.RotationMatrix))
    s_modal = mbs.AddSensor(eii.SensorNode(nodeNumber=node_modal, storeInternal=True,
                                           outputVariableType=exu.OutputVariableType.Coordinates))
    mbs.Assemble()
    ss = peer_exudyn_engine.simulation_settings(exu, HINGE_H, HINGE_T_END, HINGE_RHO, 1e-12,
                                                1e-14)
    exu.SolveDynamic(mbs, ss, solverType=exu.DynamicSolverType.GeneralizedAlpha, showHints=False)
    rot = mbs.GetSensorStoredData(s_rot)
    zeta = mbs.GetSensorStoredData(s_modal)[:, 1:]
    t = rot[:, 0]
    angle = np.unwrap(np.arctan2(rot[:, 4], rot[:, 1]))
    angle_ref = np.interp(t, t_ffrf, angle_ffrf)
    inertia = cms.inertiaLocal[2][2] if np.ndim(cms.inertiaLocal) == 2 else cms.inertiaLocal[2]
    rigid = HINGE_TORQUE * t ** 2 / (2.0 * inertia)
    print(f"hinge: {len(t) - 1} steps to {t[-1]:.3f} s; angle at the end ffrf "
          f"{angle_ffrf[-1]:.9f} rad, Exudyn {angle[-1]:.9f} rad (rigid link "
          f"tau t^2 / 2 J_z: {rigid[-1]:.6f} rad)")
    # measured 4.9e-13 rad (0.27 rad at the end); the issue asks 1e-6; 1e-10 leaves room for
    # another CPU's BLAS over 500 Newton-solved steps
    check(failures, "hinge: max |angle_exudyn - angle_ffrf| over the run (rad)",
          float(np.abs(angle - angle_ref).max()), 1e-10)
    k_r = np.diag(fem.eigenValues)
    u_ex = 0.5 * np.einsum("ti,ij,tj->t", zeta, k_r, zeta)
    zf = np.column_stack([np.interp(t, t_ffrf, col) for col in zeta_ffrf.T])
    u_ff = 0.5 * np.einsum("ti,ij,tj->t", zf, k_r, zf)
    print(f"  strain energy max ffrf {u_ff.max():.4e} J, Exudyn {u_ex.max():.4e} J")
    # measured 3.1e-10 of its maximum (2.2e-5 J)
    check(failures, "hinge: max |U_exudyn - U_ffrf| / max U_ffrf",
          float(np.abs(u_ex - u_ff).max() / u_ff.max()), 3e-9)
    return failures


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("stage", choices=("load", "mechanism", "hinge", "hinge_mechanism"))
    parser.add_argument("ffrf")
    parser.add_argument("mesh_dir")
    parser.add_argument("input_dir")
    parser.add_argument("work")
    parser.add_argument("--python", required=True, help="the Exudyn virtual environment's python")
    parser.add_argument("--body", choices=tuple(FREE_FREE), default="crank",
                        help="load: the body checked")
    parser.add_argument("--case", help="mechanism: the engine case (engine_lc8_rc1.nml)")
    args = parser.parse_args()
    code = in_exudyn_environment(args.python, "exudyn_export")
    if code is not None:
        return code
    stages = {"load": stage_load, "mechanism": stage_mechanism, "hinge": stage_hinge,
              "hinge_mechanism": stage_hinge}
    failures = stages[args.stage](args)
    for f in failures:
        print(f"exudyn_export: FAIL: {f}", file=sys.stderr)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
