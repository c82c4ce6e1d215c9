#!/usr/bin/env python3
"""Markers at the centre of a physical curve or point of a flexible body (&marker group = a
curve's or a point's name; issue 24 item 1; docs/mechanisms.md "Markers at mesh points") on the
clamped cantilever of input/cantilever.geo meshed with its groups (mesh cantilever_groups: L = 0.4
m, a = 10 mm, Tet10; the physical point 'tip_corner' at (L, -a/2, -a/2), the physical curve
'tip_edge' the tip's lower edge y = -a/2, its five Line3 nodes). The root face is an RBE2 interface
with all six reference conditions held by a fixed joint; the tip is no interface.

usage: check_group_markers.py DRIVER MESH_DIR WORK_DIR

1. Static tip load against beam theory: F = 10 N along -y at the curve's marker, the scene run to
   rest (modal damping 0.95 of critical, 0.1 s, 16 modes); the sag w of the marker's position
   sensor against Timoshenko's w_T = F L^3 / (3 E I) + F L / (kappa G A) (I = a^4 / 12, kappa =
   10 (1 + nu) / (12 + 11 nu), Cowper's rectangle): |w / w_T - 1| <= BEAM_TOL, the bound of the
   cantilever's own-weight sag on this mesh (tests/regression/check_cantilever_sag.py: mesh and
   3-D clamp), and the sag at rest (change over the last 10 % <= REST_TOL of it). The edge spans
   the section symmetrically in z, so the load bends the bar without twisting it.
2. The curve's marker is the centre of its nodes (second method): its position sensor equals the
   mean of the position sensors of node markers at its five nodes, every recorded step, to
   POSITION_TOL (round-off of a mean of five), and its starting position is the edge's midpoint
   (L, -a/2, 0) to MIDPOINT_TOL (the mesh's coordinates).
3. A point group of one node is that node's marker: in the same run the orientation and
   position sensors of the marker at 'tip_corner' equal those of the marker at its node (node =
   its tag, found in the mesh), bitwise; and a run with the load at the point-group marker
   equals the run with the load at the node marker, every sensor bitwise.
4. Errors: a group that is no surface, curve or point of the mesh fails --check with exit 2 and
   one line naming the marker and listing the curves and points.
"""
import argparse
import os
import subprocess
import sys

import h5py
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from check_cantilever_sag import A_SIDE, LENGTH, read_msh  # noqa: E402
from check_mesh_markers import check  # noqa: E402

FORCE = 10.0
MODES = 16
# the own-weight sag's bound on this mesh (check_cantilever_sag.py BEAM_TOL: 1.6e-3 mesh +
# 2.3e-3 3-D clamp, times 1.5); measured here: see the commit and docs/mechanisms.md
BEAM_TOL = 6.0e-3         # measured 3.08e-3 (16 modes)
REST_TOL = 1.0e-6
POSITION_TOL = 1.0e-15   # m, positions of size 0.4 m: a few eps (measured 2.2e-16)
# m: the mesh's own coordinates (gmsh sums 80 extrusion layers of 5 mm: 0.4 + ~1e-14); measured
# 5.1e-15
MIDPOINT_TOL = 1.0e-13

SCENE = """&run title = 'cantilever: markers at a physical curve and point' /
&body name = 'bar', mesh_file = 'cantilever_groups.msh', volumes = 'bar', young = 210e9,
      poisson = 0.3, density = 7850, num_modes = {modes}, modal_damping = 0.95 /
&interface body = 'bar', name = 'root', mpc = 'RBE2', rc = 'Tx Ty Tz Rx Ry Rz' /
&marker body = 'ground', name = 'clamp', position = 0, 0, 0 /
&marker body = 'bar', name = 'edge', group = '{edge}' /
&marker body = 'bar', name = 'corner', group = 'tip_corner' /
&marker body = 'bar', name = 'corner_node', node = {corner} /
{edge_nodes}
&joint name = 'clamp', type = 'fixed', body1 = 'ground', marker1 = 'clamp',
       body2 = 'bar', marker2 = 'root' /
&integrator h = 1.0e-3, t_end = 0.1, rho_inf = 0.9 /
&load name = 'tip', type = 'force', body = 'bar', marker = '{loaded}', direction = 0, -1, 0,
      value = {force} /
&sensor name = 'edge', type = 'position', body = 'bar', marker = 'edge' /
&sensor name = 'corner', type = 'position', body = 'bar', marker = 'corner' /
&sensor name = 'corner_node', type = 'position', body = 'bar', marker = 'corner_node' /
&sensor name = 'corner_frame', type = 'orientation', body = 'bar', marker = 'corner' /
&sensor name = 'corner_node_frame', type = 'orientation', body = 'bar', marker = 'corner_node' /
{edge_sensors}
"""


def tip_nodes(msh):
    """Tags of the corner node (L, -a/2, -a/2) and of the nodes on the edge x = L, y = -a/2."""
    nodes, tets = read_msh(msh)
    used = set(tets.ravel())
    edge = sorted(tag for tag, x in nodes.items() if tag in used and
                  abs(x[0] - LENGTH) < 1e-9 and abs(x[1] + A_SIDE / 2) < 1e-9)
    corner = [tag for tag in edge if abs(nodes[tag][2] + A_SIDE / 2) < 1e-9]
    if len(edge) != 5 or len(corner) != 1:
        sys.exit(f"check_group_markers: {len(edge)} nodes on the tip edge, {len(corner)} at the "
                 "corner (expected 5 and 1); the mesh changed")
    return corner[0], edge


def write_case(work, name, corner, edge, loaded, group="tip_edge"):
    folder = os.path.join(work, name)
    os.makedirs(folder, exist_ok=True)
    case = os.path.join(folder, name + ".nml")
    edge_nodes = "\n".join(f"&marker body = 'bar', name = 'e{k}', node = {tag} /"
                           for k, tag in enumerate(edge))
    edge_sensors = "\n".join(f"&sensor name = 'e{k}', type = 'position', body = 'bar', "
                             f"marker = 'e{k}' /" for k in range(len(edge)))
    with open(case, "w") as f:
        f.write(SCENE.format(modes=MODES, edge=group, corner=corner, edge_nodes=edge_nodes,
                             edge_sensors=edge_sensors, loaded=loaded, force=FORCE))
    return folder, case


def run(driver, mesh_dir, work, name, corner, edge, loaded):
    folder, case = write_case(work, name, corner, edge, loaded)
    subprocess.run([driver, case, "--mesh-dir", mesh_dir, "--output-dir", folder, "--quiet"],
                   check=True, env=dict(os.environ, OPENBLAS_NUM_THREADS="1"))
    return os.path.join(folder, name + ".h5")


def sensors(path):
    with h5py.File(path, "r") as h5:
        status = h5.attrs["status"]
        status = status.decode() if isinstance(status, bytes) else str(status)
        return status, {name: h5["sensors"][name][()] for name in h5["sensors"]
                        if isinstance(h5["sensors"][name], h5py.Dataset)}


def main():
    if len(sys.argv) != 4:
        sys.exit(__doc__)
    args = argparse.Namespace(driver=sys.argv[1], mesh_dir=sys.argv[2], work=sys.argv[3])
    corner, edge = tip_nodes(os.path.join(args.mesh_dir, "cantilever_groups.msh"))
    print(f"corner node {corner}, edge nodes {edge}")
    ok = True

    # 1-3: the load at the curve's marker
    status, s = sensors(run(args.driver, args.mesh_dir, args.work, "edge_load", corner, edge,
                            "edge"))
    ok &= check(f"run status {status}", 0.0 if status == "complete" else 1.0, 0.0)
    y = s["edge"][:, 1]
    sag = -(y[-1] - y[0])
    tail = np.abs(y[int(0.9 * len(y)):] - y[-1]).max() / sag
    e, nu = 210e9, 0.3
    inertia, area = A_SIDE**4 / 12.0, A_SIDE**2
    kappa = 10.0 * (1.0 + nu) / (12.0 + 11.0 * nu)
    bending = FORCE * LENGTH**3 / (3.0 * e * inertia)
    w_t = bending + FORCE * LENGTH / (kappa * e / (2.0 * (1.0 + nu)) * area)
    print(f"sag of the curve's marker {sag:.9e} m; Timoshenko {w_t:.9e} m (bending "
          f"{bending:.9e}): w / w_T - 1 = {sag / w_t - 1:.3e}")
    ok &= check("curve marker: |w / w_T - 1|", abs(sag / w_t - 1.0), BEAM_TOL)
    ok &= check("curve marker at rest: change over the last 10 % / w", tail, REST_TOL)
    mean = np.mean([s[f"e{k}"] for k in range(len(edge))], axis=0)
    ok &= check("curve marker - mean of its node markers, every step (m)",
                float(np.abs(s["edge"] - mean).max()), POSITION_TOL)
    ok &= check("curve marker's start - edge midpoint (L, -a/2, 0) (m)",
                float(np.abs(s["edge"][0] - [LENGTH, -A_SIDE / 2, 0.0]).max()), MIDPOINT_TOL)
    for what in ("", "_frame"):
        ok &= check(f"point-group marker - node marker, sensor corner{what} (bitwise)",
                    float(np.abs(s["corner" + what] - s["corner_node" + what]).max()), 0.0)

    # 3: the load at the point group's marker against the load at the node marker
    _, at_group = sensors(run(args.driver, args.mesh_dir, args.work, "corner_group", corner,
                              edge, "corner"))
    _, at_node = sensors(run(args.driver, args.mesh_dir, args.work, "corner_node", corner, edge,
                             "corner_node"))
    worst = max(float(np.abs(at_group[k] - at_node[k]).max()) for k in at_group)
    ok &= check(f"load at the point group - load at the node, {len(at_group)} sensors "
                "(bitwise)", worst, 0.0)
    sag_corner = -(at_group["corner"][-1, 1] - at_group["corner"][0, 1])
    print(f"corner load: corner sag {sag_corner:.9e} m (w / w_T - 1 = "
          f"{sag_corner / w_t - 1:.3e}: the load off the axis twists the bar too)")

    # 4: an unknown group refused by --check, naming the marker, listing curves and points
    folder, case = write_case(args.work, "unknown_group", corner, edge, "edge", group="tip_eddge")
    done = subprocess.run([args.driver, case, "--mesh-dir", args.mesh_dir, "--output-dir", folder,
                           "--check"], capture_output=True, text=True)
    lines = [line for line in done.stderr.splitlines() if line.strip()]
    print(f"--check exit {done.returncode}: {lines[-1] if lines else '(no message)'}")
    message = lines[-1] if lines else ""
    ok &= check("unknown group: exit 2 and one line naming marker, curves and points",
                0.0 if (done.returncode == 2 and len(lines) == 1 and '&marker "edge"' in message
                        and "curves: tip_edge" in message and "points: tip_corner" in message)
                else 1.0, 0.0)
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
