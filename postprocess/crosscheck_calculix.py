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


def write_deck(h5, body, path, num_modes):
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
            G = rbe3_matrix(xyz[nodes - 1], face["weights"][()], x_v)
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
            write_deck(h5, body, deck + ".inp", len(ours))
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
