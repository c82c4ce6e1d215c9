#!/usr/bin/env python3
"""Out-of-core factors (issue 12, item 2) on the small crank (lc = 8 mm, RC set 2) against the
in-core run of the same case as reference: the same factorisation written to disk and read back
(&modes out_of_core, files in a folder of the test), so the frequencies equal the in-core ones
to 1e-12 (relative), the factor entries are the same, and no ffrf_ooc_* file is left in the
folder; the analysis estimates are in the results file (estimated_factor_entries = INFOG(20) > 0,
estimated memory in-core > out-of-core > 0, predicted_memory_mb the one of the options).
Block low-rank factors are refused on this toolchain (docs/performance.md "Large meshes"), an input
error checked by memory_error_compression_refused."""
import argparse
import glob
import os
import subprocess
import sys

import h5py
import numpy as np


def run(ffrf, case, mesh_dir, out_dir, name, sets):
    args = [ffrf, case, "--mesh-dir", mesh_dir, "--output-dir", out_dir, "--quiet",
            "--output", name + ".h5", "--set", "run.mode_shapes_msh=none"]
    for s in sets:
        args += ["--set", s]
    env = dict(os.environ, OPENBLAS_NUM_THREADS="1")
    done = subprocess.run(args, env=env, capture_output=True, text=True, timeout=120)
    if done.returncode != 0:
        sys.exit(f"FAIL {' '.join(args)}: exit {done.returncode}\n{done.stdout}\n{done.stderr}")
    with h5py.File(os.path.join(out_dir, name + ".h5"), "r") as h5:
        modes = h5["bodies/crank/modes"]
        solver = modes["solver"]
        return {"f": np.array(modes["frequency"][()]),
                "residual": np.array(modes["residual"][()]),
                "shape": np.array(modes["shape"][()]),
                **{k: solver[k][()] for k in solver.keys()}}


def ok(what, condition, detail=""):
    if not condition:
        sys.exit(f"FAIL {what} {detail}")
    print(f"ok   {what} {detail}")


def arguments(description):
    """FFRF CASE MESH_DIR WORK from the command line; WORK and an empty WORK/ooc_files made."""
    parser = argparse.ArgumentParser(description=description)
    parser.add_argument("ffrf")
    parser.add_argument("case")
    parser.add_argument("mesh_dir")
    parser.add_argument("work")
    args = parser.parse_args()
    ooc_dir = os.path.join(args.work, "ooc_files")
    os.makedirs(ooc_dir, exist_ok=True)
    for old in glob.glob(os.path.join(ooc_dir, "*")):
        os.remove(old)
    return args, ooc_dir


def main():
    args, ooc_dir = arguments(__doc__)

    ref = run(args.ffrf, args.case, args.mesh_dir, args.work, "incore", [])
    ooc = run(args.ffrf, args.case, args.mesh_dir, args.work, "ooc",
              ["modes.out_of_core=.true.", f"modes.ooc_tmpdir={ooc_dir}"])

    ok("estimates recorded", ref["estimated_factor_entries"] > 0 and
       ref["estimated_memory_incore_mb"] > ref["estimated_memory_ooc_mb"] > 0 and
       ref["predicted_memory_mb"] == ref["estimated_memory_incore_mb"] and
       ooc["predicted_memory_mb"] == ooc["estimated_memory_ooc_mb"] and ref["out_of_core"] == 0,
       f"(INFOG(20) = {ref['estimated_factor_entries']}, in-core "
       f"{ref['estimated_memory_incore_mb']} MB, out-of-core {ref['estimated_memory_ooc_mb']} MB, "
       f"predicted in-core run {ref['predicted_memory_mb']} MB, out-of-core run "
       f"{ooc['predicted_memory_mb']} MB)")
    ok("full-rank factor entries unchanged by the options",
       ref["factor_entries"] == ooc["factor_entries"] == ref["compressed_factor_entries"])

    dev = np.max(np.abs(ooc["f"] / ref["f"] - 1.0))
    ok("out-of-core frequencies = in-core to 1e-12", dev <= 1e-12 and ooc["out_of_core"] == 1,
       f"(max relative deviation {dev:.2e}, bitwise: {bool(np.array_equal(ooc['f'], ref['f']))})")
    left = glob.glob(os.path.join(ooc_dir, "*"))
    ok("out-of-core files removed at the end", not left, f"({left})")


if __name__ == "__main__":
    main()
