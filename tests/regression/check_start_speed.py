#!/usr/bin/env python3
"""A mechanism started at a crank speed starts undeformed and moving rigidly (issue 30, noticed
while probing the undamped RC set 2 engine): the kinetic energy at t = 0 of the engine with the
flexible crank of RC set 2 and the flexible conrod (10 modes each) equals that of the all-rigid
engine with the meshes' inertia (a second model of the same rigid motion: the FFRF mass matrix at
zero deformation is the mesh's rigid inertia), to 1e-9 relative. Before the fix the flexible
crank's initial velocities were the minimum-norm solution of the velocity constraints, which
twists the crank so that the flywheel at B3 (whose rotation about the axis RC set 2 leaves to the
modes) stays at rest: 8 times less kinetic energy.

    check_start_speed.py flexible.h5 rigid.h5 --speed 424
"""
import argparse
import sys

import h5py


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("flexible")
    parser.add_argument("rigid")
    parser.add_argument("--speed", type=float, required=True)
    args = parser.parse_args()
    energies = []
    for path in (args.flexible, args.rigid):
        with h5py.File(path, "r") as f:
            speed = f["time/crank_speed"][0]
            if abs(speed / args.speed - 1.0) > 1e-12:
                sys.exit(f"FAIL {path}: crank speed at t = 0 is {speed}, expected {args.speed}")
            energies.append(float(f["energy/kinetic"][0]))
    flexible, rigid = energies
    difference = abs(flexible / rigid - 1.0)
    if not difference <= 1e-9:
        sys.exit(f"FAIL kinetic energy at t = 0: flexible {flexible:.12g} J, rigid {rigid:.12g} "
                 f"J, relative difference {difference:.3g} > 1e-9 (the bodies must start rigid)")
    print(f"ok   kinetic energy at t = 0: flexible {flexible:.12g} J, rigid {rigid:.12g} J, "
          f"relative difference {difference:.2g} <= 1e-9")


if __name__ == "__main__":
    main()
