#!/usr/bin/python3
"""Checks of postprocess/ffrf_results (the package) on the files make_sample.py wrote.

References: the box's exterior has 2 triangles per hexahedron face on its boundary,
4 (NX NY + NY NZ + NX NZ) in all (closed form); the outward orientation is checked by the
divergence theorem, V = sum over triangles of (centroid . area normal) / 3 = L W H, and by the
closure sum of area normals = 0 (identities; tolerance 1e-12 relative, round-off of ~1e3
terms of size ~1e-4). Frequencies and shapes are compared exactly with what the sample wrote
(same bytes). A failed run must raise ResultsError quoting its status.
"""
import argparse
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..",
                                "postprocess"))
import ffrf_results  # noqa: E402
import make_sample  # noqa: E402

CHECKS = []
FAILURES = []


def expect(what, condition):
    print(("ok   " if condition else "FAIL ") + what)
    CHECKS.append(what)
    if not condition:
        FAILURES.append(what)


def check_surface(xyz, triangles, what):
    nx, ny, nz = make_sample.NX, make_sample.NY, make_sample.NZ
    expected = 4 * (nx * ny + ny * nz + nx * nz)
    expect(f"{what}: {len(triangles)} exterior triangles, expected {expected}",
           len(triangles) == expected)
    p = xyz[triangles]
    area_normals = 0.5 * np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0])
    volume = np.sum(np.einsum("ij,ij->i", p.mean(axis=1), area_normals)) / 3.0
    box = make_sample.LENGTH * make_sample.WIDTH * make_sample.HEIGHT
    expect(f"{what}: divergence-theorem volume {volume:.12e} = L W H {box:.12e} (outward)",
           abs(volume - box) <= 1e-12 * box)
    closure = np.abs(area_normals.sum(axis=0)).max()
    expect(f"{what}: sum of area normals {closure:.1e} = 0",
           closure <= 1e-12 * np.abs(area_normals).sum())


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("folder", help="folder with sample_rc1.h5 ... from make_sample.py")
    args = parser.parse_args()
    for rc_set in (1, 3):
        path = os.path.join(args.folder, f"sample_rc{rc_set}.h5")
        with ffrf_results.open_results(path) as results:
            expect(f"rc{rc_set}: bodies == ['box']", results.bodies() == ["box"])
            body = results.body()
            f = results.frequencies(body)
            expect(f"rc{rc_set}: frequencies equal the written ones",
                   np.array_equal(f, make_sample.sample_frequencies(rc_set)))
            xyz = results.coordinates(body)
            u = results.shapes(body)
            reference = make_sample.mode_shapes(make_sample.box_mesh(rc_set == 3)[0])
            expect(f"rc{rc_set}: shapes (num_modes, num_nodes, 3) equal the written ones",
                   u.shape == reference.shape and np.array_equal(u, reference))
            tets = results.tets(body)
            expect(f"rc{rc_set}: tets 0-based, {tets.shape[1]} nodes each",
                   tets.min() == 0 and tets.max() == len(xyz) - 1
                   and tets.shape[1] == (10 if rc_set == 3 else 4))
            check_surface(xyz, results.surface_triangles(body), f"rc{rc_set}")
            info = results.modes_info(body)
            expect(f"rc{rc_set}: modes attributes {info}",
                   info == {"rc_set": f"RC set {rc_set}", "mpc": "RBE3",
                            "formulation": "null space"})
            expect(f"rc{rc_set}: label '{results.label(body)}'",
                   results.label(body) == f"RC set {rc_set}, RBE3")
            expect(f"rc{rc_set}: case_name", results.case_name == f"box_rc{rc_set}")

    # tets listed with negative orientation (two corners swapped) give the same outward surface
    xyz, tets = make_sample.box_mesh()
    flipped = tets.copy()
    flipped[::2, [1, 2]] = flipped[::2, [2, 1]]
    check_surface(xyz, ffrf_results.exterior_faces(flipped, xyz), "half the tets flipped")

    failed = os.path.join(args.folder, "sample_failed.h5")
    try:
        ffrf_results.open_results(failed)
        expect("failed run raises ResultsError", False)
    except ffrf_results.ResultsError as exc:
        expect(f"failed run raises ResultsError quoting the status: {exc}",
               "ARPACK did not converge" in str(exc) and "sample_failed.h5" in str(exc))
    with ffrf_results.open_results(failed, require_complete=False) as results:
        expect("require_complete=False opens it", results.bodies() == ["box"])
    try:
        with ffrf_results.open_results(os.path.join(args.folder, "sample_rc1.h5")) as results:
            results.body("crank")
        expect("unknown body raises", False)
    except ffrf_results.ResultsError as exc:
        expect(f"unknown body raises ResultsError listing the bodies: {exc}", "box" in str(exc))
    print(f"{len(CHECKS) - len(FAILURES)} passed, {len(FAILURES)} failed")
    return 1 if FAILURES else 0


if __name__ == "__main__":
    sys.exit(main())
