#!/usr/bin/env python3
"""Read an ffrf results file of the reference crank back with h5py and check it against
independent references: the schema of docs/results.md "Results file (HDF5)", the crank's mass and
centre of mass from its geometry (closed form, scene.md), the interface areas 2 pi r L and the virtual nodes
at the journal/pin axes (area centroids by symmetry), frequencies ascending and positive, RC rows
of the virtual-node mode shapes zero (the floating frame is attached to them)."""
import argparse
import math
import sys

import h5py
import numpy as np


def close(what, actual, expected, rtol=0.0, atol=0.0):
    tol = max(atol, rtol * abs(expected))
    if not abs(actual - expected) <= tol:
        sys.exit(f"FAIL {what}: {actual!r}, expected {expected!r} within {tol:.3g}")
    print(f"ok   {what}: {actual:.9g} (expected {expected:.9g}, tol {tol:.3g})")


def main():
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("results")
    args = parser.parse_args()
    rho = 7850.0
    # Crank volume: two journals r 0.020 L 0.025, pin r 0.018 L 0.025, two webs 0.06 x 0.105 x 0.0225.
    journal = math.pi * 0.020**2 * 0.025
    pin = math.pi * 0.018**2 * 0.025
    web = 0.060 * 0.105 * 0.0225
    volume = 2 * journal + pin + 2 * web
    # Centre of mass: only the webs (centre y = 0.0225) and the pin (y = 0.045) are off axis.
    y_com = (2 * web * 0.0225 + pin * 0.045) / volume
    with h5py.File(args.results, "r") as h5:
        status = h5.attrs["status"]
        status = status.decode() if isinstance(status, bytes) else status
        if status != "complete":
            sys.exit(f"FAIL status = {status!r}")
        print("ok   status complete")
        for path in ["/input/namelist", "/build/versions", "/timings/stage", "/timings/seconds",
                     "/bodies/crank/mesh/coordinates", "/bodies/crank/mesh/tets",
                     "/bodies/crank/modes/shape", "/bodies/crank/modes/virtual_node_shape",
                     "/bodies/crank/modes/residual", "/bodies/crank/interfaces/order"]:
            if path not in h5:
                sys.exit(f"FAIL missing {path}")
        print("ok   schema: every documented dataset is present")
        body = h5["/bodies/crank"]
        # Curved Tet10 geometry of the lc = 8 mm mesh: measured errors are 6.5e-6 (mass), 3e-8 m
        # (centre of mass) and 1.3e-5..1.6e-5 (face areas); tolerances are about three times those
        # (the geometry error falls as h^4, so a wrong element or face set shows far above them).
        close("mass (kg)", float(body["mass/mass"][()]), rho * volume, rtol=2e-5)
        com = body["mass/center_of_mass"][()]
        close("centre of mass y (m)", float(com[1]), y_com, atol=1e-7)
        close("centre of mass x (m)", float(com[0]), 0.0, atol=1e-7)
        expected = {"B1": (0.020, (0.0, 0.0, -0.0475)), "B2": (0.018, (0.0, 0.045, 0.0)),
                    "B3": (0.020, (0.0, 0.0, 0.0475))}
        order = [s.decode().strip() for s in body["interfaces/order"][()]]
        for name, (radius, centre) in expected.items():
            face = body["interfaces/" + name]
            close(f"{name} area (m^2)", float(face["area"][()]), 2 * math.pi * radius * 0.025,
                  rtol=5e-5)
            node = face["virtual_node"][()]
            # Area centroids of the meshed faces sit within ~6e-8 m of the exact axes (measured).
            for k in range(3):
                close(f"{name} virtual node[{k}] (m)", float(node[k]), centre[k], atol=2e-7)
        freq = body["modes/frequency"][()]
        if not (np.all(np.diff(freq) > 0) and freq[0] > 100.0):
            sys.exit(f"FAIL frequencies not ascending and above 100 Hz: {freq}")
        print(f"ok   {len(freq)} frequencies ascending, {freq[0]:.2f} .. {freq[-1]:.2f} Hz")
        shape = body["modes/shape"][()]
        if shape.shape != (len(freq), 3 * body["mesh/coordinates"].shape[0]):
            sys.exit(f"FAIL shape array {shape.shape}")
        vshape = body["modes/virtual_node_shape"][()]
        names = ["Tx", "Ty", "Tz", "Rx", "Ry", "Rz"]
        for k, name in enumerate(order):
            rc = body[f"interfaces/{name}/rc_dofs"][()]
            rc = (rc.decode() if isinstance(rc, bytes) else rc).split()
            for d in rc:
                row = vshape[:, 6 * k + names.index(d)]
                scale = np.abs(vshape[:, 6 * k:6 * k + 3]).max() + np.abs(shape).max()
                if np.abs(row).max() > 1e-9 * scale:
                    sys.exit(f"FAIL {name} {d}: RC row of the virtual-node shapes is not zero")
        print("ok   RC rows of the virtual-node mode shapes vanish (to 1e-9 of the shape scale)")
        if body["modes/residual"][()].max() > 1e-7:
            sys.exit("FAIL eigen residual above 1e-7")
        print("ok   eigen residuals <= 1e-7")
    print("check_results: all checks passed")


if __name__ == "__main__":
    main()
