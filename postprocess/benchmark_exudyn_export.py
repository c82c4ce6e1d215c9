#!/usr/bin/env python3
"""Benchmark of the Exudyn export (&run export = 'exudyn', docs/results.md "Exudyn export"): the
crank meshed with gmsh at lc = 4 mm (default), its modal case (RC set 1, 12 modes) run with and
without the export, alternated (--repeat pairs, best of each), and one CSV row: the run's wall
time without and with the export, the export's own time (the log line "Exudyn body written ...
s"), its share of the run, the results file's and the Exudyn file's sizes. Not a test: timings
depend on the machine; report them with the machine and its load named.

    benchmark_exudyn_export.py --ffrf FFRF --gmsh GMSH --geo crank.geo --case crank_rc1.nml
                               [--lc 0.004] [--repeat 2] [--work DIR] [--csv FILE]
"""
import argparse
import os
import re
import subprocess
import sys
import time


def run(args, mesh_dir, out, export):
    os.makedirs(out, exist_ok=True)
    command = [args.ffrf, args.case, "--mesh-dir", mesh_dir, "--output-dir", out,
               "--set", "body[crank].mesh_file=crank.msh", "--set", "run.mode_shapes_msh=none"]
    if export:
        command += ["--set", "run.export=exudyn"]
    start = time.perf_counter()
    done = subprocess.run(command, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    wall = time.perf_counter() - start
    if done.returncode != 0:
        sys.exit(f"benchmark_exudyn_export: {' '.join(command)} exited {done.returncode}:\n"
                 f"{done.stdout}")
    match = re.search(r"Exudyn body written: \S+ \.\.\. ([0-9.eE+-]+) s", done.stdout)
    return wall, float(match.group(1)) if match else 0.0


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--ffrf", required=True)
    parser.add_argument("--gmsh", default="gmsh")
    parser.add_argument("--geo", required=True, help="input/crank.geo")
    parser.add_argument("--case", required=True, help="input/crank_rc1.nml")
    parser.add_argument("--lc", type=float, default=0.004, help="mesh size (m)")
    parser.add_argument("--repeat", type=int, default=2, help="alternated pairs of runs")
    parser.add_argument("--work", default="benchmark_exudyn_export")
    parser.add_argument("--csv", help="also write the CSV here")
    args = parser.parse_args()
    mesh_dir = os.path.join(args.work, "mesh")
    os.makedirs(mesh_dir, exist_ok=True)
    subprocess.run([args.gmsh, "-3", "-setnumber", "lc", str(args.lc), "-format", "msh41",
                    "-o", os.path.join(mesh_dir, "crank.msh"), args.geo], check=True,
                   stdout=subprocess.DEVNULL)
    plain, exported, export_s = [], [], []
    for _ in range(args.repeat):
        plain.append(run(args, mesh_dir, os.path.join(args.work, "plain"), False)[0])
        wall, seconds = run(args, mesh_dir, os.path.join(args.work, "export"), True)
        exported.append(wall)
        export_s.append(seconds)
    stem = os.path.splitext(os.path.basename(args.case))[0]
    results = os.path.getsize(os.path.join(args.work, "export", stem + ".h5"))
    body = os.path.getsize(os.path.join(args.work, "export", f"{stem}_crank.exudyn.hdf5"))
    header = ("lc_mm,run_s,run_with_export_s,export_s,export_share_of_run,results_mb,"
              "exudyn_file_mb")
    row = (f"{args.lc * 1000:g},{min(plain):.3f},{min(exported):.3f},{min(export_s):.3f},"
           f"{min(export_s) / min(plain):.4f},{results / 1e6:.2f},{body / 1e6:.2f}")
    text = header + "\n" + row + "\n"
    sys.stdout.write(text)
    if args.csv:
        with open(args.csv, "w") as fh:
            fh.write(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
