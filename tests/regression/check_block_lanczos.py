#!/usr/bin/env python3
"""Block shift-invert Lanczos (&modes eigensolver = 'block', docs/theory.md 5.5) against
ARPACK (eigensolver = 'arpack') on the small crank (lc = 8 mm, RC set 2, RBE3, 8 modes): two
methods on one factorisation, so the frequencies agree to 1e-9 (relative; the Rayleigh quotients
are accurate to about the squared residual, below 1e-12 for both) and the M-normalised mode
shapes to 1e-6 of their largest entry (a shape's error is its residual over the relative gap to
the next mode, residuals below 1e-6 here); the same with out-of-core factors (the combination
for meshes whose factor does not fit in memory). The block run records its method, block size
and block solves in /bodies/crank/modes/solver, and needs fewer solves than right-hand sides."""
import numpy as np

from check_memory import arguments, ok, run   # the same driver call and result reading


def compare(label, ref, other):
    dev = np.max(np.abs(other["f"] / ref["f"] - 1.0))
    ok(f"{label}: frequencies = ARPACK's to 1e-9", dev <= 1e-9, f"(max relative deviation "
       f"{dev:.2e}; f = {', '.join(f'{x:.4f}' for x in other['f'])} Hz)")
    a, b = ref["shape"], other["shape"]
    if a.shape[0] == len(ref["f"]):   # one row per mode as stored: make modes the columns
        a, b = a.T, b.T
    worst = 0.0
    for j in range(a.shape[1]):
        sign = 1.0 if np.dot(a[:, j], b[:, j]) >= 0 else -1.0
        worst = max(worst, np.max(np.abs(sign * b[:, j] - a[:, j])) / np.max(np.abs(a[:, j])))
    ok(f"{label}: mode shapes = ARPACK's to 1e-6 (up to sign)", worst <= 1e-6,
       f"(largest deviation / largest entry {worst:.2e})")
    ok(f"{label}: residuals below 1e-6", np.max(other["residual"]) <= 1e-6,
       f"(max {np.max(other['residual']):.2e})")


def main():
    args, ooc_dir = arguments(__doc__)

    ref = run(args.ffrf, args.case, args.mesh_dir, args.work, "arpack",
              ["modes.eigensolver=arpack"])
    block = run(args.ffrf, args.case, args.mesh_dir, args.work, "block",
                ["modes.eigensolver=block"])
    ooc = run(args.ffrf, args.case, args.mesh_dir, args.work, "block_ooc",
              ["modes.eigensolver=block", "modes.out_of_core=.true.",
               f"modes.ooc_tmpdir={ooc_dir}"])
    ok("ARPACK run records no block figures", "eigensolver" not in ref)
    method = block["eigensolver"]
    method = method.decode() if isinstance(method, bytes) else str(method)
    ok("block run records its method", method == "block" and block["block_size"] > 1 and
       0 < block["num_block_solves"] < block["num_solves"],
       f"({block['num_block_solves']} block solves of {block['block_size']} right-hand sides = "
       f"{block['num_solves']} vectors; ARPACK: {ref['num_solves']} solves)")
    compare("block", ref, block)
    compare("block, out-of-core", ref, ooc)


if __name__ == "__main__":
    main()
