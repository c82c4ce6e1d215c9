#!/usr/bin/python3
"""Write synthetic ffrf results files that follow the results schema, for the postprocess tests.

A box L x W x H = 0.20 x 0.04 x 0.03 m cut into NX x NY x NZ hexahedra of 6 tetrahedra each
(tet4; the RC set 3 file uses tet10 with mid-edge nodes, corners first, Gmsh order) carries
analytic mode shapes: mode k bends in y (k odd) or z (k even) as sin(k pi x / L), scaled to unit
mass-weighted norm with the lumped nodal mass rho V / num_nodes. Frequencies are made-up numbers
per RC set (sample_frequencies), the ones the checks compare against. Files written:
sample_rc1.h5, sample_rc2.h5, sample_rc3.h5 (status 'complete') and sample_failed.h5
(status = an error message). Strings are fixed-length bytes, like the Fortran writer's.
"""
import argparse
import os

import h5py
import numpy as np

LENGTH, WIDTH, HEIGHT = 0.20, 0.04, 0.03
NX, NY, NZ = 10, 2, 2
DENSITY = 7850.0
NUM_MODES = 4

# the 6 tetrahedra of a hexahedron (Kuhn split along the diagonal 0-7), local corner numbers
# 0..7 = (i, j, k) bits (x, y, z); all positively oriented
HEX_TETS = [(0, 1, 3, 7), (0, 3, 2, 7), (0, 2, 6, 7), (0, 6, 4, 7), (0, 4, 5, 7), (0, 5, 1, 7)]
# Gmsh tet10 mid-edge order: edges 0-1, 1-2, 2-0, 3-0, 3-2, 3-1
TET10_EDGES = [(0, 1), (1, 2), (2, 0), (3, 0), (3, 2), (3, 1)]


def sample_frequencies(rc_set):
    """The frequencies (Hz) written for RC set 1, 2 or 3."""
    base = {1: 812.4, 2: 1034.25, 3: 1612.875}[rc_set]
    return np.array([base * (k + 1) ** 1.5 + 0.125 * k for k in range(NUM_MODES)])


def box_mesh(quadratic=False):
    """Coordinates (n, 3) and 0-based tets (ne, 4 or 10) of the box."""
    xs = np.linspace(0.0, LENGTH, NX + 1)
    ys = np.linspace(-WIDTH / 2, WIDTH / 2, NY + 1)
    zs = np.linspace(-HEIGHT / 2, HEIGHT / 2, NZ + 1)
    grid = np.stack(np.meshgrid(xs, ys, zs, indexing="ij"), axis=-1).reshape(-1, 3)

    def node(i, j, k):
        return (i * (NY + 1) + j) * (NZ + 1) + k

    tets = []
    for i in range(NX):
        for j in range(NY):
            for k in range(NZ):
                corner = [node(i + (c & 1), j + (c >> 1 & 1), k + (c >> 2 & 1))
                          for c in range(8)]
                tets.extend([[corner[c] for c in t] for t in HEX_TETS])
    tets = np.array(tets, dtype=np.int64)
    if not quadratic:
        return grid, tets
    coordinates = list(grid)
    edge_nodes = {}
    tet10 = []
    for t in tets:
        mids = []
        for a, b in TET10_EDGES:
            key = (min(t[a], t[b]), max(t[a], t[b]))
            if key not in edge_nodes:
                edge_nodes[key] = len(coordinates)
                coordinates.append(0.5 * (grid[t[a]] + grid[t[b]]))
            mids.append(edge_nodes[key])
        tet10.append(list(t) + mids)
    return np.array(coordinates), np.array(tet10, dtype=np.int64)


def mode_shapes(xyz):
    """(num_modes, num_nodes, 3) bending shapes, unit norm with the lumped mass matrix."""
    nodal_mass = DENSITY * LENGTH * WIDTH * HEIGHT / len(xyz)
    shapes = np.zeros((NUM_MODES, len(xyz), 3))
    for m in range(NUM_MODES):
        direction = 1 if m % 2 == 0 else 2
        shapes[m, :, direction] = np.sin((m + 1) * np.pi * xyz[:, 0] / LENGTH + 0.3)
        shapes[m] /= np.sqrt(nodal_mass * np.sum(shapes[m] ** 2))
    return shapes


def fixed(strings):
    """Fixed-length byte strings (NUL-padded), as the Fortran wrapper writes them."""
    if isinstance(strings, str):
        return np.bytes_(strings.encode())
    return np.array([s.encode() for s in strings], dtype=f"S{max(1, *map(len, strings))}")


def write_sample(path, rc_set, mpc, status="complete", quadratic=False):
    xyz, tets = box_mesh(quadratic)
    shapes = mode_shapes(xyz)
    frequencies = sample_frequencies(rc_set)
    num_nodes = len(xyz)
    body = "/bodies/box"
    with h5py.File(path, "w") as f:
        f.attrs["status"] = fixed(status)
        f.attrs["ffrf_version"] = fixed("0.1.0")
        f.attrs["case_name"] = fixed(f"box_rc{rc_set}")
        f["/input/namelist"] = fixed(f"&run\n   case_name = 'box_rc{rc_set}'\n/\n")
        f["/build/versions"] = fixed(["gfortran 12.2.0", "MUMPS 5.5.1", "ARPACK-NG 3.8.0",
                                      "HDF5 1.10.8", "gmsh 4.8.4"])
        f["/timings/stage"] = fixed(["mesh", "assembly", "modes"])
        f["/timings/seconds"] = np.array([0.01, 0.02, 0.03])
        f["/timings/seconds"].attrs["units"] = fixed("s")
        f["/timings/peak_memory_mib"] = np.array([10.0, 12.0, 20.0])
        f["/timings/peak_memory_mib"].attrs["units"] = fixed("MiB")
        f[f"{body}/mesh/coordinates"] = xyz
        f[f"{body}/mesh/coordinates"].attrs["units"] = fixed("m")
        f[f"{body}/mesh/tets"] = (tets + 1).astype(np.int32)
        f[f"{body}/mesh/node_tags"] = np.arange(1, num_nodes + 1, dtype=np.int32) + 100
        mass = DENSITY * LENGTH * WIDTH * HEIGHT
        f[f"{body}/mass/mass"] = mass
        f[f"{body}/mass/mass"].attrs["units"] = fixed("kg")
        f[f"{body}/mass/center_of_mass"] = np.array([LENGTH / 2, 0.0, 0.0])
        f[f"{body}/mass/center_of_mass"].attrs["units"] = fixed("m")
        f[f"{body}/mass/inertia"] = np.diag([1.0, 2.0, 3.0]) * 1e-4
        f[f"{body}/mass/inertia"].attrs["units"] = fixed("kg m^2")
        order = ["left", "right"]
        for name, x in zip(order, (0.0, LENGTH)):
            nodes = np.flatnonzero(np.isclose(xyz[:, 0], x)) + 1
            group = f"{body}/interfaces/{name}"
            f[f"{group}/nodes"] = nodes.astype(np.int32)
            f[f"{group}/weights"] = np.full(len(nodes), 1.0)
            f[f"{group}/weights"].attrs["units"] = fixed("1")
            f[f"{group}/virtual_node"] = np.array([x, 0.0, 0.0])
            f[f"{group}/virtual_node"].attrs["units"] = fixed("m")
            f[f"{group}/mpc"] = fixed(mpc)
            f[f"{group}/rc_dofs"] = fixed("Tx Ty Tz" if name == "left" else "")
        f[f"{body}/interfaces/order"] = fixed(order)
        modes = f"{body}/modes"
        f[f"{modes}/frequency"] = frequencies
        f[f"{modes}/frequency"].attrs["units"] = fixed("Hz")
        f[f"{modes}/shape"] = shapes.reshape(NUM_MODES, 3 * num_nodes)
        f[f"{modes}/shape"].attrs["units"] = fixed("kg^-1/2")
        f[f"{modes}/virtual_node_shape"] = np.zeros((NUM_MODES, 6 * len(order)))
        f[f"{modes}/virtual_node_shape"].attrs["units"] = fixed("kg^-1/2")
        f[f"{modes}/residual"] = np.full(NUM_MODES, 1e-11)
        f[f"{modes}/residual"].attrs["units"] = fixed("1")
        f[f"{modes}/orthonormality_error"] = 1e-13
        f[f"{modes}/orthonormality_error"].attrs["units"] = fixed("1")
        f[modes].attrs["rc_set"] = fixed(f"RC set {rc_set}")
        f[modes].attrs["mpc"] = fixed(mpc)
        f[modes].attrs["formulation"] = fixed("null space")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("-o", "--output-dir", default=".", help="folder for the sample files")
    args = parser.parse_args()
    os.makedirs(args.output_dir, exist_ok=True)
    for rc_set in (1, 2, 3):
        write_sample(os.path.join(args.output_dir, f"sample_rc{rc_set}.h5"), rc_set, "RBE3",
                     quadratic=rc_set == 3)
    write_sample(os.path.join(args.output_dir, "sample_failed.h5"), 1, "RBE2",
                 status="modes: ARPACK did not converge (info = 1)")
    print(f"wrote sample_rc1.h5, sample_rc2.h5, sample_rc3.h5, sample_failed.h5 "
          f"to {args.output_dir}")


if __name__ == "__main__":
    main()
