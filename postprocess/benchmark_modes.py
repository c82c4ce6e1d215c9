#!/usr/bin/env python3
"""Benchmark of the modal pipeline on the reference crank: for each mesh size, mesh crank.geo
with gmsh, run ffrf on a case (default: RC set 1, RBE3, 12 modes) and print one CSV row with the
mesh size and the wall time and peak memory of every stage, read from the results file.
Not a test: timings depend on the machine; report them with the machine named.

--ranks N runs `mpirun -np N FFRF` (FFRF the MPI build's ffrf, -DFFRF_MPI=ON); the last columns
give the ranks, the wall time of the whole ffrf run (mpirun included) and the largest peak
memory of one rank (/timings/peak_memory_mib_per_rank; one process: /timings/peak_memory_mib).
--mesh FILE[,FILE...] takes existing meshes instead of meshing (lc read from a name like
crank_lc0.002.msh, else from --lc in the same order)."""
import argparse
import csv
import os
import re
import subprocess
import sys
import time

import h5py


def stage_seconds(names, seconds, suffix):
    """Sum of the stage times whose name ends with `suffix` (one body: one stage)."""
    return sum(s for n, s in zip(names, seconds) if n.endswith(suffix))


def main():
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--ffrf", required=True, help="the ffrf program")
    parser.add_argument("--gmsh", default="gmsh", help="the gmsh program")
    parser.add_argument("--geo", required=True, help="crank.geo")
    parser.add_argument("--case", required=True, help="case file to run (crank_rc1.nml)")
    parser.add_argument("--lc", default="0.008,0.006,0.004,0.003",
                        help="comma-separated mesh sizes in metres")
    parser.add_argument("--work", default="benchmark", help="folder for meshes and results")
    parser.add_argument("--csv", default=None, help="also write the CSV here")
    parser.add_argument("--ranks", type=int, default=1,
                        help="MPI ranks: mpirun -np RANKS FFRF (FFRF: the MPI build)")
    parser.add_argument("--mpirun", default="mpirun", help="the mpirun program")
    parser.add_argument("--mesh", default=None,
                        help="comma-separated existing mesh files (no gmsh run)")
    args = parser.parse_args()
    meshes = args.mesh.split(",") if args.mesh else None
    lcs = [float(x) for x in args.lc.split(",")]
    if meshes:
        lcs = []
        for k, name in enumerate(meshes):
            found = re.search(r"lc([0-9.]*[0-9])", os.path.basename(name))
            lcs.append(float(found.group(1)) if found else float(args.lc.split(",")[k]))
    launcher = []
    if args.ranks > 1:
        launcher = [args.mpirun, "-np", str(args.ranks)]
        if os.geteuid() == 0:
            launcher.append("--allow-run-as-root")

    os.makedirs(args.work, exist_ok=True)
    with open(args.case) as f:
        case_text = f.read()
    columns = ["lc_mm", "nodes", "dofs", "nnz_K", "reduced", "constraints", "gmsh_s", "read_s",
               "assembly_s", "rc_matrix_s", "ordering_s", "factorisation_s", "eigen_loop_s",
               "output_s", "ffrf_total_s", "peak_memory_mib", "factor_entries",
               "f1_hz", "f12_hz", "ranks", "wall_s", "peak_memory_per_rank_max_mib"]
    rows = []
    writer = csv.writer(sys.stdout)
    writer.writerow(columns)
    for k, lc in enumerate(lcs):
        tag = f"crank_lc{lc * 1000:g}mm"
        if args.ranks > 1:
            tag += f"_np{args.ranks}"
        gmsh_s = 0.0
        if meshes:
            mesh = meshes[k]
        else:
            mesh = os.path.join(args.work, tag + ".msh")
            t0 = time.perf_counter()
            subprocess.run([args.gmsh, "-3", "-setnumber", "lc", str(lc), "-format", "msh41",
                            "-o", mesh, args.geo], check=True, stdout=subprocess.DEVNULL)
            gmsh_s = time.perf_counter() - t0
        case = os.path.join(args.work, tag + ".nml")
        text = re.sub(r"mesh_file\s*=\s*'[^']*'", f"mesh_file = '{os.path.abspath(mesh)}'",
                      case_text)
        # The Gmsh animation file is optional and not part of the pipeline being timed.
        text = re.sub(r"&run[^/]*/", f"&run title = '{tag}', mode_shapes_msh = 'none' /", text)
        with open(case, "w") as f:
            f.write(text)
        env = dict(os.environ, OPENBLAS_NUM_THREADS=os.environ.get("OPENBLAS_NUM_THREADS", "1"))
        t0 = time.perf_counter()
        subprocess.run(launcher + [args.ffrf, case, "--output-dir", args.work, "--quiet"],
                       check=True, env=env)
        wall_s = time.perf_counter() - t0
        with h5py.File(os.path.join(args.work, tag + ".h5"), "r") as h5:
            names = [n.decode().strip() for n in h5["/timings/stage"][()]]
            seconds = list(h5["/timings/seconds"][()])
            peak = float(max(h5["/timings/peak_memory_mib"][()]))
            body = list(h5["/bodies"].keys())[0]
            sizes = h5[f"/bodies/{body}/sizes"]
            freq = h5[f"/bodies/{body}/modes/frequency"][()]
            factor_entries = int(h5[f"/bodies/{body}/modes/solver/factor_entries"][()])
            row = [lc * 1000, int(sizes["num_dofs"][()]) // 3, int(sizes["num_dofs"][()]),
                   int(sizes["stiffness_nnz"][()]), int(sizes["num_reduced"][()]),
                   int(sizes["num_constraints"][()]), round(gmsh_s, 3)]
            for suffix in [": mesh", ": assembly", ": interfaces and RC matrix", ": ordering",
                           ": factorisation", ": eigen loop", ": output", "total"]:
                # ordering includes the MUMPS analysis
                if suffix == ": ordering":
                    row.append(round(stage_seconds(names, seconds, ": ordering")
                                     + stage_seconds(names, seconds, ": analysis"), 3))
                    continue
                row.append(round(stage_seconds(names, seconds, suffix), 3))
            rank_peak = peak
            if "/timings/peak_memory_mib_per_rank" in h5:
                rank_peak = float(max(h5["/timings/peak_memory_mib_per_rank"][()]))
            row += [round(peak, 1), factor_entries, round(float(freq[0]), 4),
                    round(float(freq[-1]), 4), args.ranks, round(wall_s, 3),
                    round(rank_peak, 1)]
        rows.append(row)
        writer.writerow(row)
        sys.stdout.flush()
    if args.csv:
        with open(args.csv, "w", newline="") as f:
            w = csv.writer(f)
            w.writerow(columns)
            w.writerows(rows)


if __name__ == "__main__":
    main()
