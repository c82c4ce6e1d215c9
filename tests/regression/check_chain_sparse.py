#!/usr/bin/env python3
"""A chain of flexible links (postprocess/chain_case.py: 4 links of input/link.geo, Craig-Bampton
6 + 8 modes each, revolute joints about z, 100 N m on link 1 from rest; 200 steps of 1e-4 s) run
by ffrf twice: with the iteration matrix factorised by the sparse LU (MUMPS, &integrator
sparse_threshold = 1) and by the dense LU (LAPACK, sparse_threshold = 10**9). Asserted: both runs
complete the same 200 steps, and their trajectories agree (issue 24):

  every body's position (m), Euler parameters and modal coordinates (the coordinates q), and
  every joint's reaction (N, N m), at every step.

Tolerance from the Newton tolerance: each step's iterate is accepted when the weighted RMS of the
last increment is <= 1, |dq_i| <= newton_atol + newton_rtol |q_i| in the mean square, so one
component may be off by up to sqrt(n) times that; the two routes' round-off differs, so each
step's converged states may differ by that much, and over S steps the differences add up at most
linearly (the generalized-alpha map is stable): tol_q = S sqrt(n) (newton_atol + newton_rtol
max|q|); for the reactions likewise with lambda_atol and the largest reaction. The measured
differences (printed) are far smaller: the routes take the same Newton iterations.

Then chains of 8 and 16 links (6 + 8 modes, 50 steps of 1e-4 s, 100 N m), the sparse path
(M, Phi_q and the tangents block-sparse, the iteration matrix assembled as triplets for MUMPS)
against the dense path (dense matrices, LAPACK): the final angle of every link about z agrees
to 1e-10 of the largest angle. Both paths evaluate the same residuals and the same tangents (up
to the order of three sums per entry, test_mbs_tangents) and take the same Newton iterations;
they differ by the round-off of the two LU solves, cond(S) eps per increment. Measured
3e-13 (8 links) and 7e-13 (16 links) of an angle of 0.03 rad.

The chain of 8 links again with the stabilized index-2 constraints (docs/theory.md 4.6,
`constraints = 'index2'`, rho_inf = 1: the velocity rows and nu's columns, order n + 2 nr, also
assembled block-sparse on the sparse path): the same test and tolerance. Measured 4e-13 (8 links;
16 links: 7e-13)."""
import argparse
import os
import subprocess
import sys

import h5py
import numpy as np

STEPS = 200
# Longer chains, sparse against dense: final link angles (issue 24, the block-sparse assembly)
LONG_CHAINS, LONG_STEPS, ANGLE_RTOL = (8, 16), 50, 1.0e-10
INDEX2_CHAIN = 8
INDEX2 = ["integrator.constraints=index2", "integrator.rho_inf=1"]
NEWTON_ATOL, NEWTON_RTOL, LAMBDA_ATOL = 1.0e-10, 1.0e-8, 1.0e-8


def run(ffrf, case, mesh_dir, out_dir, threshold, overrides=()):
    os.makedirs(out_dir, exist_ok=True)
    extra = [arg for setting in overrides for arg in ("--set", setting)]
    done = subprocess.run([ffrf, case, "--mesh-dir", mesh_dir, "--output-dir", out_dir,
                           "--threads", "1", "--set", f"integrator.sparse_threshold={threshold}"]
                          + extra, capture_output=True, text=True)
    log = done.stdout + done.stderr
    if done.returncode != 0:
        sys.exit(f"FAIL: ffrf with sparse_threshold = {threshold} exited {done.returncode}:\n{log}")
    solver = "sparse LU" if threshold == 1 else "dense LU"
    if f"iteration matrix: order" not in log or solver not in log:
        sys.exit(f"FAIL: the log of sparse_threshold = {threshold} does not name the {solver}:\n"
                 f"{log}")
    name = os.path.splitext(os.path.basename(case))[0]
    return os.path.join(out_dir, name + ".h5")


def main():
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("ffrf")
    parser.add_argument("mesh_dir")
    parser.add_argument("work")
    parser.add_argument("--postprocess", required=True, help="folder of chain_case.py")
    args = parser.parse_args()
    sys.path.insert(0, args.postprocess)
    global chain_case
    from chain_case import chain_case
    os.makedirs(args.work, exist_ok=True)
    case = os.path.join(args.work, "chain4.nml")
    with open(case, "w", encoding="utf-8") as out:
        out.write(chain_case(4, 8, h=1.0e-4, steps=STEPS, torque=100.0))
    sparse = run(args.ffrf, case, args.mesh_dir, os.path.join(args.work, "sparse"), 1)
    dense = run(args.ffrf, case, args.mesh_dir, os.path.join(args.work, "dense"), 10**9)
    failures = []
    with h5py.File(sparse, "r") as fs, h5py.File(dense, "r") as fd:
        n = fd["final_state/q"].shape[0]
        q_max = float(np.max(np.abs(fd["final_state/q"][()])))
        tol_q = STEPS * np.sqrt(n) * (NEWTON_ATOL + NEWTON_RTOL * q_max)
        for f in (fs, fd):
            if f["bodies/link1/position"].shape[0] != STEPS + 1:
                failures.append(f"{f.filename}: {f['bodies/link1/position'].shape[0]} states, "
                                f"expected {STEPS + 1}")
        for body in fd["bodies"]:
            for field in ("position", "euler_parameters", "modal_coordinates"):
                a = fs[f"bodies/{body}/{field}"][()]
                b = fd[f"bodies/{body}/{field}"][()]
                diff = float(np.max(np.abs(a - b)))
                print(f"{body}/{field}: max |sparse - dense| = {diff:.3e} (tolerance {tol_q:.3e}, "
                      f"max |value| {np.max(np.abs(b)):.3e})")
                if not diff <= tol_q:
                    failures.append(f"{body}/{field}: {diff:.3e} > {tol_q:.3e}")
        nc = fd["final_state/lambda"].shape[0]
        for joint in fd["joints"]:
            a = fs[f"joints/{joint}/reaction"][()]
            b = fd[f"joints/{joint}/reaction"][()]
            r_max = float(np.max(np.abs(b)))
            tol_r = STEPS * np.sqrt(nc) * (LAMBDA_ATOL + NEWTON_RTOL * r_max)
            diff = float(np.max(np.abs(a - b)))
            print(f"{joint}/reaction: max |sparse - dense| = {diff:.3e} N (tolerance {tol_r:.3e}, "
                  f"max |reaction| {r_max:.3e})")
            if not diff <= tol_r:
                failures.append(f"{joint}/reaction: {diff:.3e} > {tol_r:.3e}")
    for links in LONG_CHAINS:
        failures += compare_angles(args, links)
    failures += compare_angles(args, INDEX2_CHAIN, INDEX2)
    if failures:
        sys.exit("FAIL: " + "; ".join(failures))
    print("chain sparse/dense: trajectories agree")


def link_angles(path, links):
    """Final rotation angle about z of every link, 2 atan2(e3, e0) of its Euler parameters."""
    with h5py.File(path, "r") as f:
        angles = []
        for k in range(1, links + 1):
            e = f[f"bodies/link{k}/euler_parameters"][-1]
            angles.append(2.0 * np.arctan2(e[3], e[0]))
        return np.array(angles)


def compare_angles(args, links, overrides=()):
    """The chain of `links` links (6 + 8 modes each, LONG_STEPS steps) with the sparse path
    (block-sparse assembly, MUMPS) and the dense one, the `overrides` (--set) given to both: the
    final link angles agree to ANGLE_RTOL relative to the largest."""
    tag = "_index2" if overrides else ""
    case = os.path.join(args.work, f"chain{links}.nml")
    with open(case, "w", encoding="utf-8") as out:
        out.write(chain_case(links, 8, h=1.0e-4, steps=LONG_STEPS, torque=100.0))
    sparse = run(args.ffrf, case, args.mesh_dir, os.path.join(args.work, f"sparse{links}{tag}"),
                 1, overrides)
    dense = run(args.ffrf, case, args.mesh_dir, os.path.join(args.work, f"dense{links}{tag}"),
                10**9, overrides)
    a_s = link_angles(sparse, links)
    a_d = link_angles(dense, links)
    scale = float(np.max(np.abs(a_d)))
    diff = float(np.max(np.abs(a_s - a_d)))
    print(f"chain of {links}{' ' + ' '.join(overrides) if overrides else ''}: final link angles max |sparse - dense| = {diff:.3e} rad, "
          f"{diff / scale:.3e} of the largest angle {scale:.3e} rad (tolerance {ANGLE_RTOL:.0e})")
    if not diff <= ANGLE_RTOL * scale:
        return [f"chain of {links}{tag}: final angles differ by {diff:.3e} rad > {ANGLE_RTOL:.0e} x "
                f"{scale:.3e}"]
    return []


if __name__ == "__main__":
    main()
