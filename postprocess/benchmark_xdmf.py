#!/usr/bin/env python3
"""Benchmark of the XDMF export (&run export = 'xdmf'; docs/results.md "XDMF export"): what it
adds to a run in time and in size. Each case runs twice with the same input, without and with
--set run.export=xdmf: the crank, RC set 1, modal, on the mesh given (the target benchmark_xdmf:
lc = 4 mm, meshed by gmsh), and the engine with its animation (the target:
input/engine_rc1_manual.nml, flexible crank and conrod, 2 s, 24 frames). One CSV row per case: nodes of the flexible bodies, the run's wall time
without and with the export, the export's time (its stages '... xdmf export' of /timings: the
mesh and the mode or frame datasets written into the results file; the small .xdmf file is
written after the timings), its share of the run without it, the results file without the
export, the bytes the export adds to it and the .xdmf file's size.
Not a test: timings depend on the machine; report them with the machine named."""
import argparse
import csv
import os
import re
import subprocess
import sys
import time

import h5py


def export_seconds(h5):
    """Sum of the stage times named '... xdmf export' (modal: per body; mechanism: one)."""
    names = [n.decode().strip() for n in h5["/timings/stage"][()]]
    return sum(s for n, s in zip(names, h5["/timings/seconds"][()])
               if n.endswith("xdmf export"))


def run(ffrf, case, mesh_dir, work, export):
    """Wall time, the export's stage time, results size and .xdmf size of one run."""
    out = os.path.join(work, "export" if export else "plain")
    os.makedirs(out, exist_ok=True)
    command = [ffrf, case, "--output-dir", out, "--quiet"]
    if mesh_dir:
        command += ["--mesh-dir", mesh_dir]
    if export:
        command += ["--set", "run.export=xdmf"]
    env = dict(os.environ, OPENBLAS_NUM_THREADS=os.environ.get("OPENBLAS_NUM_THREADS", "1"))
    t0 = time.perf_counter()
    subprocess.run(command, check=True, env=env)
    wall = time.perf_counter() - t0
    stem = os.path.splitext(os.path.basename(case))[0]
    results = os.path.join(out, stem + ".h5")
    with h5py.File(results, "r") as h5:
        seconds = export_seconds(h5)
        nodes = sum(h5[f"/xdmf/{b}/geometry"].shape[0] for b in h5["/xdmf"]) if "xdmf" in h5 \
            else 0
    xdmf = os.path.join(out, stem + ".xdmf")
    return wall, seconds, os.path.getsize(results), \
        os.path.getsize(xdmf) if os.path.exists(xdmf) else 0, nodes


def main():
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--ffrf", required=True, help="the ffrf program")
    parser.add_argument("--crank", required=True,
                        help="crank_rc1.nml and the crank mesh to run it on, comma-separated")
    parser.add_argument("--engine", required=True,
                        help="the engine case (with its animation) and its mesh folder, "
                             "comma-separated")
    parser.add_argument("--work", default="benchmark", help="folder for the results")
    parser.add_argument("--cases", default="crank,engine", help="which: crank, engine or both")
    parser.add_argument("--csv", default=None, help="also write the CSV here")
    args = parser.parse_args()
    crank_case, crank_mesh = args.crank.split(",")
    engine_case, engine_meshes = args.engine.split(",")
    os.makedirs(args.work, exist_ok=True)
    with open(crank_case) as f:
        text = re.sub(r"mesh_file\s*=\s*'[^']*'", f"mesh_file = '{os.path.abspath(crank_mesh)}'",
                      f.read())
    crank = os.path.join(args.work, "xdmf_" + os.path.basename(crank_case))
    with open(crank, "w") as f:
        f.write(text)
    cases = {"crank": ("crank RC set 1 modal, " + os.path.basename(crank_mesh), crank, None),
             "engine": ("engine animation", engine_case, engine_meshes)}
    table = [["case", "nodes", "run_s", "run_export_s", "export_s", "export_share",
              "results_mb", "export_datasets_mb", "xdmf_kb"]]
    for label, case, mesh_dir in [cases[name] for name in args.cases.split(",")]:
        wall, _, plain_size, _, _ = run(args.ffrf, case, mesh_dir, args.work, False)
        wall_export, export_s, export_size, xdmf_size, nodes = run(args.ffrf, case, mesh_dir,
                                                                   args.work, True)
        table.append([label, nodes, f"{wall:.2f}", f"{wall_export:.2f}", f"{export_s:.3f}",
                      f"{export_s / wall:.4f}", f"{plain_size / 1e6:.2f}",
                      f"{(export_size - plain_size) / 1e6:.2f}", f"{xdmf_size / 1e3:.1f}"])
    csv.writer(sys.stdout).writerows(table)
    if args.csv:
        with open(args.csv, "w", newline="") as f:
            csv.writer(f).writerows(table)


if __name__ == "__main__":
    main()
