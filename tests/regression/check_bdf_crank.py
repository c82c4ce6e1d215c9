#!/usr/bin/env python3
"""The crank as Nastran bulk data written by pyNastran gives the frequencies of the Gmsh path
(issue 26, item 4, bulk-data line).

The Gmsh mesh (crank_lc10.msh, read with meshio: its Tet10 come in VTK order, which is Nastran's)
becomes a deck through pyNastran's card objects and field writers: GRIDs in large fields (`GRID*`
and its `*` continuation line; half of them in a file the deck INCLUDEs), every 50th in free
(comma) fields (pyNastran has no free-field writer: its card fields joined by commas, reals with
17 digits); CTETRA, PSOLID, RBE3 in small fields with blank continuation lines; RBE2 in large
fields (print_card_16: `*` continuation lines); MAT1 in free fields, the material then coming
from MAT1 (the bulk-data case leaves young, poisson, density out). Not pyNastran's double-
precision writer: it keeps 10 digits (print_scientific_double, %16.9e), and the frequencies then
move by up to 2.6e-11 (measured), above the tolerance. Each interface B1, B2, B3 of the physical surfaces
becomes an RBE3 (uniform weights 1.0, element 101..103) and an RBE2 (201..203), their reference
grids at the virtual node the Gmsh run placed (the face's area centroid, read from its results
file: an input of the deck, not a result compared). For each case crank_rc1/2/3 and
crank_rc1/2/3_rbe2, ffrf runs the Gmsh case and the bulk-data case; every frequency must agree to
1e-12 relative (measured worst 5.07e-13, crank_rc3_rbe2): the same model up to the last digits
of the coordinates (pyNastran's large fields keep 14 to 15 significant digits).

Exit 77 when pyNastran cannot be installed (no venv module or no network): `--venv DIR` makes
`python3 -m venv --system-site-packages DIR` (Debian's numpy, scipy, h5py, meshio stay visible),
installs pyNastran from PyPI there and runs this script again with that interpreter.
"""
import argparse
import os
import re
import subprocess
import sys

SKIP = 77
PYNASTRAN = "pyNastran==1.4.1"
RTOL = 1e-12


def in_venv(venv, script=__file__):
    """Run `script` (this one by default) in `venv` (made with pyNastran if needed); its exit
    status, or SKIP."""
    python = os.path.join(venv, "bin", "python")
    probe = [python, "-c", "import pyNastran.bdf.bdf, meshio, h5py"]
    if not os.path.exists(python) or subprocess.call(probe, stderr=subprocess.DEVNULL) != 0:
        for step in ([sys.executable, "-m", "venv", "--system-site-packages", venv],
                     [python, "-m", "pip", "install", "--disable-pip-version-check", "--quiet",
                      PYNASTRAN]):
            if subprocess.call(step) != 0:
                print(f"check_bdf_crank: '{' '.join(step)}' failed: no pyNastran, test skipped "
                      "(Debian: python3-venv, python3-meshio; PyPI must be reachable)",
                      file=sys.stderr)
                return SKIP
        if subprocess.call(probe) != 0:
            print(f"check_bdf_crank: {python} cannot import pyNastran, meshio, h5py",
                  file=sys.stderr)
            return SKIP
    args = [a for a in sys.argv[1:]]
    k = args.index("--venv")
    del args[k:k + 2]
    return subprocess.call([python, os.path.abspath(script)] + args)


def run(driver, case, mesh_dir, out_dir, extra=()):
    os.makedirs(out_dir, exist_ok=True)
    # Ritz values to machine precision (&modes tolerance = 0), so that what is compared is the
    # model and not the eigensolver's stopping point (with 1e-9 the worst case moved between
    # 3.4e-13 and 5.1e-13 from run to run; with 0 it is 5.07e-13, crank_rc3_rbe2, every run)
    command = [driver, case, "--mesh-dir", mesh_dir, "--output-dir", out_dir,
               "--set", "modes.tolerance=0"] + list(extra)
    done = subprocess.run(command, capture_output=True, text=True)
    if done.returncode != 0:
        sys.exit(f"check_bdf_crank: {' '.join(command)} exited {done.returncode}:\n"
                 f"{done.stderr}")
    return os.path.join(out_dir, os.path.splitext(os.path.basename(case))[0] + ".h5")


def free_card(fields):
    """Free-field text of pyNastran's card fields (reals with a point and 17 digits)."""
    def text(v):
        if v is None:
            return ""
        if isinstance(v, float):
            return f"{v:.17E}"
        return str(v)
    lines, rest = [], list(fields)
    head = text(rest.pop(0))
    while True:
        chunk, rest = rest[:8], rest[8:]
        lines.append(",".join([head] + [text(v) for v in chunk]))
        if not rest:
            return "\n".join(lines) + "\n"
        head = "+"


def write_deck(msh, centroids, deck, names=("B1", "B2", "B3")):
    """The deck of module notes for the body of `msh` with an RBE3 (101, 102, ...) and an RBE2
    (201, 202, ...) on each physical surface of `names`, reference grids at `centroids`; half
    the GRIDs in `<deck stem>_grids.bdf` (INCLUDEd). The face nodes (tags) of each name."""
    import meshio
    from pyNastran.bdf.bdf import BDF
    from pyNastran.bdf.field_writer_16 import print_card_16
    mesh = meshio.read(msh)
    model = BDF(debug=None)
    for i, xyz in enumerate(mesh.points):
        model.add_grid(i + 1, [float(x) for x in xyz])
    eid = 0
    faces = {}
    for block, physical in zip(mesh.cells, mesh.cell_data["gmsh:physical"]):
        if block.type == "tetra10":
            for nodes in block.data:
                eid += 1
                model.add_ctetra(eid, 1, [int(n) + 1 for n in nodes])
        elif block.type == "triangle6":
            for name, (tag, dim) in mesh.field_data.items():
                if dim == 2 and tag == physical[0]:
                    faces.setdefault(name, set()).update(int(n) + 1 for n in block.data.ravel())
    model.add_psolid(1, 1)
    model.add_mat1(1, 210.0e9, None, 0.3, rho=7850.0)
    ref = len(mesh.points) + 1000
    rbes = []
    for k, name in enumerate(names):
        nodes = sorted(faces[name])
        model.add_grid(ref + 2 * k, [float(x) for x in centroids[name]])
        model.add_grid(ref + 2 * k + 1, [float(x) for x in centroids[name]])
        rbes.append(model.add_rbe3(101 + k, ref + 2 * k, "123456", [1.0], ["123"], [nodes]))
        rbes.append(model.add_rbe2(201 + k, ref + 2 * k + 1, "123456", nodes))
    grids = sorted(model.nodes)
    folder = os.path.dirname(deck)
    grids_file = os.path.splitext(os.path.basename(deck))[0] + "_grids.bdf"
    with open(os.path.join(folder, grids_file), "w") as f:
        f.write("$ GRIDs of the body, large fields (pyNastran)\n")
        for nid in grids[1::2]:
            f.write(model.nodes[nid].write_card(size=16))
    with open(deck, "w") as f:
        f.write("$ The body as bulk data, written by pyNastran (check_bdf_crank.py)\n"
                "SOL 103\nCEND\nBEGIN BULK\n")
        f.write(f"INCLUDE '{grids_file}'\n")
        for n, nid in enumerate(grids[0::2]):
            if n % 50 == 0:
                f.write(free_card(model.nodes[nid].repr_fields()))
            else:
                f.write(model.nodes[nid].write_card(size=16))
        for e in model.elements.values():
            f.write(e.write_card(size=8))
        f.write(model.properties[1].write_card(size=8))
        f.write(free_card(model.materials[1].repr_fields()))
        for r in rbes:
            if r.type == "RBE3":
                f.write(r.write_card(size=8))
            else:
                f.write(print_card_16(r.repr_fields()))
        f.write("ENDDATA\n")
    return faces


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--driver", required=True)
    parser.add_argument("--input-dir", required=True, help="folder of crank_rc*.nml")
    parser.add_argument("--mesh-dir", required=True, help="folder of crank_lc10.msh")
    parser.add_argument("--work", required=True)
    parser.add_argument("--venv", help="run in this virtual environment (made if needed)")
    args = parser.parse_args()
    if args.venv:
        return in_venv(args.venv)
    import h5py
    import numpy as np
    os.makedirs(args.work, exist_ok=True)
    msh = os.path.join(args.mesh_dir, "crank_lc10.msh")
    cases = ["crank_rc1", "crank_rc2", "crank_rc3",
             "crank_rc1_rbe2", "crank_rc2_rbe2", "crank_rc3_rbe2"]
    results = {}
    for name in cases:
        results[name] = run(args.driver, os.path.join(args.input_dir, name + ".nml"),
                            args.mesh_dir, os.path.join(args.work, "msh", name),
                            ["--set", "body[crank].mesh_file=crank_lc10.msh"])
    with h5py.File(results["crank_rc1"], "r") as f:
        interfaces = f["bodies/crank/interfaces"]
        centroids = {n: interfaces[n]["virtual_node"][()] for n in ("B1", "B2", "B3")}
        tags = f["bodies/crank/mesh/node_tags"][()]
        ffrf_nodes = {n: set(int(tags[i - 1]) for i in interfaces[n]["nodes"][()])
                      for n in ("B1", "B2", "B3")}
    deck = os.path.join(args.work, "crank_lc10.bdf")
    faces = write_deck(msh, centroids, deck)
    for name in ("B1", "B2", "B3"):
        if faces[name] != ffrf_nodes[name]:
            sys.exit(f"check_bdf_crank: interface {name}: meshio's face nodes differ from ffrf's")
    worst = 0.0
    for name in cases:
        text = open(os.path.join(args.input_dir, name + ".nml")).read()
        text = text.replace("mesh_file = 'crank.msh'", "mesh_file = 'crank_lc10.bdf'")
        text = text.replace("volumes = 'crank'", "volumes = '1'")
        text = re.sub(r",\s*young = [^,]*, poisson = [^,]*, density = [^ /]*", "", text)
        first = 201 if name.endswith("rbe2") else 101
        for k in range(3):
            text = text.replace(f"name = 'B{k + 1}'", f"name = '{first + k}'")
        if "young" in text or "crank_lc10.bdf" not in text or "'B1'" in text:
            sys.exit(f"check_bdf_crank: {name}.nml did not take the replacements:\n{text}")
        case = os.path.join(args.work, name + ".nml")
        open(case, "w").write(text)
        h5 = run(args.driver, case, args.work, os.path.join(args.work, "bdf", name))
        with h5py.File(results[name], "r") as a, h5py.File(h5, "r") as b:
            fa = a["bodies/crank/modes/frequency"][()]
            fb = b["bodies/crank/modes/frequency"][()]
        if fa.shape != fb.shape:
            sys.exit(f"check_bdf_crank: {name}: {len(fb)} modes from the deck, {len(fa)} from Gmsh")
        rel = float(np.max(np.abs(fb - fa) / np.abs(fa)))
        worst = max(worst, rel)
        print(f"{name}: {len(fa)} modes {fa[0]:.6f} .. {fa[-1]:.6f} Hz, "
              f"max relative difference {rel:.2e} (tolerance {RTOL:.0e})")
        if not rel <= RTOL:
            sys.exit(f"check_bdf_crank: {name}: frequencies differ by {rel:.3e} > {RTOL:.0e}")
    print(f"check_bdf_crank: 6 cases agree, worst {worst:.2e}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
