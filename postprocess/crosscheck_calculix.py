#!/usr/bin/env python3
"""Cross-check of ffrf's constrained normal modes with CalculiX (ccx), an independent FE code, on
the same mesh: the ffrf results file provides the mesh, the interfaces (nodes, weights, virtual
node, MPC type) and the reference conditions; this script writes a CalculiX deck, runs ccx and
compares the frequencies. With --tolerance it is a test (ctest's calculix_* cases): it exits 1
when a frequency up to --max-hz differs from CalculiX's by more than the tolerance.

CalculiX's frequencies lie slightly above ffrf's, by a relative amount that grows with the
frequency (measured on the crank, lc = 10 mm, all six RC/MPC cases: 1e-6 at 1.4 kHz, <= 3e-5 up
to 10 kHz, 1e-4 at 20 kHz), as a lower-order integration of the element matrices would give:
CalculiX's C3D10 has 4 integration points (CalculiX manual, element C3D10), while ffrf
integrates the Tet10 mass exactly (14-point rule, src/fe/tet.f90). The tests compare the modes
up to 10 kHz at 1e-4.

Independent modelling in CalculiX:
- Tet10 -> C3D10 (Gmsh's nodes 9 and 10 swapped), steel from the ffrf input echo;
- RBE2 -> *RIGID BODY with a reference node at the virtual node and a rotation node; the
  reference conditions are *BOUNDARY on those nodes;
- RBE3 reference conditions -> *EQUATION rows sum_j G[d, j] u_j = 0 with G recomputed here from
  Nastran's RBE3 definition G = (S^T W S)^-1 S^T W (not read from ffrf); RBE3 interfaces without
  reference conditions add nothing (an RBE3 adds no stiffness).
- RBE3 weights recomputed here too (not read from ffrf): 'uniform' w_i = 1; 'area' (tributary)
  and 'area_consistent' (int N_i dA) from the Tri6 faces of the Tet10 mesh on the interface
  (boundary faces whose six nodes are interface nodes), integrated with a 10 x 10 collapsed
  Gauss-Legendre rule (converged to 3e-15), independent of ffrf's rules. ffrf's weights must
  agree to --weights-tolerance, relative to the largest weight (the difference is the error of
  ffrf's quadrature on the curved faces; measured on the lc = 10 mm crank: 2.2e-9 for 'area',
  3.8e-9 for 'area_consistent').
"""
import argparse
import os
import re
import subprocess
import sys

import h5py
import numpy as np

GMSH_TO_C3D10 = [0, 1, 2, 3, 4, 5, 6, 7, 9, 8]
DOFS = ["Tx", "Ty", "Tz", "Rx", "Ry", "Rz"]


def text(value):
    return value.decode() if isinstance(value, bytes) else str(value)


def num(value):
    """A real in at most 20 characters (CalculiX reads fields of up to 20 characters)."""
    return f"{value:.12e}"


def skew(a):
    return np.array([[0.0, -a[2], a[1]], [a[2], 0.0, -a[0]], [-a[1], a[0], 0.0]])


def rbe3_matrix(xyz, weights, x_v):
    """Nastran RBE3 for translational independent nodes: q_V = G q_B (6 x 3 nB)."""
    rows = []
    stws = np.zeros((6, 6))
    for x, w in zip(xyz, weights):
        s = np.hstack([np.eye(3), -skew(x - x_v)])
        stws += w * s.T @ s
        rows.append(w * s.T)
    return np.linalg.solve(stws, np.hstack(rows))


# Tet10 edges in Gmsh's node order, 0-based: node 4 + k sits on edge TET10_EDGES[k]
TET10_EDGES = [(0, 1), (1, 2), (0, 2), (0, 3), (2, 3), (1, 3)]


def tet10_faces():
    """The four faces of a Tet10 as Tri6 (three corners, then the mid-side nodes of the edges
    1-2, 2-3, 3-1), local 0-based node numbers."""
    mid = {frozenset(e): 4 + k for k, e in enumerate(TET10_EDGES)}
    faces = []
    for a, b, c in [(1, 2, 3), (0, 2, 3), (0, 1, 3), (0, 1, 2)]:
        faces.append((a, b, c, mid[frozenset((a, b))], mid[frozenset((b, c))],
                      mid[frozenset((c, a))]))
    return faces


TET10_FACES = tet10_faces()
# Tri6 sub-triangles (reference coordinates of their vertices, local nodes) for the tributary
# weights: corner-mid-mid at each corner and the middle one
TRI6_REFERENCE = np.array([[0, 0], [1, 0], [0, 1], [0.5, 0], [0.5, 0.5], [0, 0.5]])
TRI6_SUBTRIANGLES = [(0, 3, 5), (3, 1, 4), (5, 4, 2), (3, 4, 5)]


def triangle_rule(order=10):
    """Collapsed Gauss-Legendre rule on the reference triangle u, v >= 0, u + v <= 1."""
    x, w = np.polynomial.legendre.leggauss(order)
    x, w = 0.5 * (x + 1.0), 0.5 * w
    u = np.repeat(x, order)
    t = np.tile(x, order)
    return np.column_stack([u, (1.0 - u) * t]), np.repeat(w, order) * np.tile(w, order) * (1.0 - u)


def tri6_shape(p):
    """Tri6 shape functions (n, 6) and derivatives (n, 2, 6) at reference points p (n, 2)."""
    u, v = p[:, 0], p[:, 1]
    L = np.array([1.0 - u - v, u, v])
    dL = np.array([[-1.0, -1.0], [1.0, 0.0], [0.0, 1.0]])
    N = np.empty((len(u), 6))
    dN = np.empty((len(u), 2, 6))
    for c in range(3):
        N[:, c] = L[c] * (2.0 * L[c] - 1.0)
        dN[:, :, c] = np.outer(4.0 * L[c] - 1.0, dL[c])
    for e, (i, j) in enumerate([(0, 1), (1, 2), (2, 0)]):
        N[:, 3 + e] = 4.0 * L[i] * L[j]
        dN[:, :, 3 + e] = 4.0 * (np.outer(L[i], dL[j]) + np.outer(L[j], dL[i]))
    return N, dN


def interface_triangles(tets, nodes):
    """The Tri6 boundary faces of the Tet10 mesh whose six nodes are all interface nodes."""
    inside = set(int(n) for n in nodes)
    count, faces = {}, {}
    for tet in tets:
        for face in TET10_FACES:
            tri = tuple(int(tet[k]) for k in face)
            key = tuple(sorted(tri[:3]))
            count[key] = count.get(key, 0) + 1
            faces[key] = tri
    return [faces[k] for k, c in count.items() if c == 1 and inside.issuperset(faces[k])]


def area_weights(xyz, tets, nodes, weighting):
    """RBE3 weights of the interface nodes (1-based, ascending): tributary ('area') or
    consistent ('area_consistent') areas of its Tri6 faces."""
    position = {int(n): i for i, n in enumerate(nodes)}
    weights = np.zeros(len(nodes))
    points, rule = triangle_rule()
    tris = interface_triangles(tets, nodes)
    if not tris:
        sys.exit("crosscheck: no Tri6 face of the mesh lies on the interface")
    for tri in tris:
        x = xyz[np.array(tri) - 1]
        if weighting == "area_consistent":
            N, dN = tri6_shape(points)
            da = np.linalg.norm(np.cross(dN[:, 0] @ x, dN[:, 1] @ x), axis=1)
            values = (rule * da) @ N
            for a in range(6):
                weights[position[tri[a]]] += values[a]
        else:
            for sub in TRI6_SUBTRIANGLES:
                p = TRI6_REFERENCE[list(sub)]
                mapped = p[0] + points[:, :1] * (p[1] - p[0]) + points[:, 1:] * (p[2] - p[0])
                jac = abs(np.cross(p[1] - p[0], p[2] - p[0]))
                N, dN = tri6_shape(mapped)
                da = np.linalg.norm(np.cross(dN[:, 0] @ x, dN[:, 1] @ x), axis=1)
                for a in sub:
                    weights[position[tri[a]]] += jac * (rule @ da) / 3.0
    return weights


def interface_weighting(h5, name):
    """The weighting of interface `name` from the input echo."""
    echo = text(h5["/input/namelist"][()])
    for group in re.findall(r"&interface\b[^/]*/", echo):
        if re.search(r"\bname\s*=\s*'" + re.escape(name) + "'", group):
            match = re.search(r"\bweighting\s*=\s*'(\w+)'", group)
            return match.group(1).lower() if match else "uniform"
    sys.exit(f"crosscheck: interface {name} not in the input echo")


def material(h5):
    echo = text(h5["/input/namelist"][()])
    values = {}
    for key in ["young", "poisson", "density"]:
        match = re.search(key + r"\s*=\s*([0-9.eE+-]+)", echo)
        if not match:
            sys.exit(f"crosscheck: no {key} in the input echo")
        values[key] = float(match.group(1))
    return values


def independent_rows(rows):
    """Reduced row echelon on pivot columns: each row gets a dependent dof absent from the others."""
    rows = np.array(rows, dtype=float)
    pivots = []
    for i in range(rows.shape[0]):
        scale = np.abs(rows[i]).max()
        p = int(np.argmax(np.abs(rows[i])))
        if abs(rows[i, p]) < 1e-10 * scale:
            sys.exit("crosscheck: dependent reference-condition rows")
        rows[i] /= rows[i, p]
        for k in range(rows.shape[0]):
            if k != i:
                rows[k] -= rows[k, p] * rows[i]
        pivots.append(p)
    return rows, pivots


def write_deck(h5, body, path, num_modes, weights_tolerance):
    group = h5[f"/bodies/{body}"]
    xyz = group["mesh/coordinates"][()]
    tets = group["mesh/tets"][()]
    if tets.shape[1] != 10:
        sys.exit("crosscheck: only Tet10 meshes are converted")
    mat = material(h5)
    n = xyz.shape[0]
    lines = ["*HEADING", f"ffrf cross-check of body {body}", "*NODE"]
    lines += [f"{i + 1}, {num(x[0])}, {num(x[1])}, {num(x[2])}" for i, x in enumerate(xyz)]
    extra = n
    boundary = []
    equations = []
    rigid = []
    for name in [text(s).strip() for s in group["interfaces/order"][()]]:
        face = group[f"interfaces/{name}"]
        nodes = face["nodes"][()]
        x_v = face["virtual_node"][()]
        rc = text(face["rc_dofs"][()]).split()
        mpc = text(face["mpc"][()]).strip()
        if mpc == "RBE2":
            ref, rot = extra + 1, extra + 2
            extra += 2
            lines.append(f"{ref}, {num(x_v[0])}, {num(x_v[1])}, {num(x_v[2])}")
            lines.append(f"{rot}, {num(x_v[0])}, {num(x_v[1])}, {num(x_v[2])}")
            rigid.append((name, ref, rot, nodes))
            for d in rc:
                k = DOFS.index(d)
                node = ref if k < 3 else rot
                boundary.append(f"{node}, {k % 3 + 1}, {k % 3 + 1}")
        elif rc:
            weighting = interface_weighting(h5, name)
            if weighting == "uniform":
                weights = np.ones(len(nodes))
            else:
                weights = area_weights(xyz, tets, nodes, weighting)
            ours = face["weights"][()]
            deviation = np.max(np.abs(ours - weights)) / np.max(np.abs(weights))
            print(f"{name}: {weighting} weights, max |ffrf - here| / max w = {deviation:.1e}")
            if not deviation <= weights_tolerance:
                sys.exit(f"crosscheck: {name}: ffrf's {weighting} weights differ from those "
                         f"recomputed here by {deviation:.1e} > {weights_tolerance:.1e}")
            G = rbe3_matrix(xyz[nodes - 1], weights, x_v)
            rows, pivots = independent_rows([G[DOFS.index(d)] for d in rc])
            for row, p in zip(rows, pivots):
                order = [p] + [j for j in range(row.size) if j != p and abs(row[j]) > 0.0]
                terms = [(int(nodes[j // 3]), j % 3 + 1, row[j]) for j in order]
                equations.append(terms)
    lines.append("*ELEMENT, TYPE=C3D10, ELSET=BODY")
    for e, tet in enumerate(tets):
        lines.append(", ".join([str(e + 1)] + [str(int(tet[k])) for k in GMSH_TO_C3D10]))
    for name, ref, rot, nodes in rigid:
        lines.append(f"*NSET, NSET={name}")
        lines += [", ".join(str(int(v)) for v in nodes[i:i + 8]) for i in range(0, len(nodes), 8)]
        lines.append(f"*RIGID BODY, NSET={name}, REF NODE={ref}, ROT NODE={rot}")
    lines += ["*MATERIAL, NAME=STEEL", "*ELASTIC", f"{num(mat['young'])}, {num(mat['poisson'])}",
              "*DENSITY", f"{num(mat['density'])}", "*SOLID SECTION, ELSET=BODY, MATERIAL=STEEL"]
    if equations:
        lines.append("*EQUATION")
        for terms in equations:
            lines.append(str(len(terms)))
            for i in range(0, len(terms), 4):
                lines.append(", ".join(f"{nd}, {dof}, {num(c)}" for nd, dof, c in terms[i:i + 4]))
    if boundary:
        lines += ["*BOUNDARY"] + boundary
    lines += ["*STEP", "*FREQUENCY", f"{num_modes}", "*END STEP"]
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")


def ccx_frequencies(dat):
    freqs = []
    with open(dat) as f:
        inside = False
        for line in f:
            if "E I G E N V A L U E   O U T P U T" in line:
                inside = True
                continue
            if inside:
                parts = line.split()
                if len(parts) == 5 and parts[0].isdigit():
                    freqs.append(float(parts[3]))   # cycles/time
                elif freqs and not parts:
                    break
    return np.array(freqs)


def main():
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("results", nargs="+", help="ffrf results files")
    parser.add_argument("--body", default=None, help="body (default: the first)")
    parser.add_argument("--work", default="crosscheck", help="folder for the CalculiX decks")
    parser.add_argument("--ccx", default="ccx", help="the CalculiX program")
    parser.add_argument("--csv", default=None, help="write the comparison here too")
    parser.add_argument("--tolerance", type=float, default=None,
                        help="fail (exit 1) when |f_ffrf / f_ccx - 1| exceeds this")
    parser.add_argument("--max-hz", type=float, default=None,
                        help="compare only the modes up to this frequency (Hz)")
    parser.add_argument("--weights-tolerance", type=float, default=2e-8,
                        help="fail when ffrf's RBE3 weights differ from those recomputed here "
                             "by more than this, relative to the largest weight")
    args = parser.parse_args()
    os.makedirs(args.work, exist_ok=True)
    out = ["case,mode,ffrf_hz,calculix_hz,relative_difference"]
    worst = 0.0
    for results in args.results:
        with h5py.File(results, "r") as h5:
            body = args.body or list(h5["/bodies"].keys())[0]
            ours = h5[f"/bodies/{body}/modes/frequency"][()]
            case = os.path.splitext(os.path.basename(results))[0]
            deck = os.path.join(args.work, case)
            write_deck(h5, body, deck + ".inp", len(ours), args.weights_tolerance)
        env = dict(os.environ, OMP_NUM_THREADS="1")
        subprocess.run([args.ccx, "-i", os.path.basename(deck)], cwd=args.work, env=env,
                       check=True, stdout=subprocess.DEVNULL)
        theirs = ccx_frequencies(deck + ".dat")
        if len(theirs) < len(ours):
            sys.exit(f"crosscheck: ccx returned {len(theirs)} frequencies for {case}")
        if args.max_hz is not None:
            ours = ours[ours <= args.max_hz]
            if len(ours) == 0:
                sys.exit(f"crosscheck: no mode of {case} below {args.max_hz} Hz")
        for k, (a, b) in enumerate(zip(ours, theirs)):
            rel = (a - b) / b
            worst = max(worst, abs(rel))
            out.append(f"{case},{k + 1},{a:.6f},{b:.6f},{rel:.3e}")
        print(f"{case}: max |ffrf/ccx - 1| = "
              f"{np.max(np.abs(ours / theirs[:len(ours)] - 1)):.2e}", flush=True)
    print("\n".join(out))
    if args.csv:
        with open(args.csv, "w") as f:
            f.write("\n".join(out) + "\n")
    print(f"crosscheck: worst relative difference {worst:.2e}")
    if args.tolerance is not None and not worst <= args.tolerance:
        sys.exit(f"crosscheck: ffrf and CalculiX differ by {worst:.2e} > {args.tolerance:.1e}")


if __name__ == "__main__":
    main()
