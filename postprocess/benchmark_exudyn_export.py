#!/usr/bin/env python3
"""Benchmark of the Exudyn export (&run export = 'exudyn', docs/results.md "Exudyn export"): the
crank meshed with gmsh at lc = 4 mm (default), its modal case (RC set 1, 12 modes) run with and
without the export, alternated (--repeat pairs, best of each), and one CSV row: the run's wall
time without and with the export, the export's own time (the log line "Exudyn body written ...
s"), its share of the run, the results file's and the Exudyn file's sizes. With --engine (a
mechanism case, engine_lc8_rc1.nml, meshes in --mesh-dir) a second row: the mechanism run
(--t-end, 0.1 s) with and without the export, the export time and file sizes summed over its
flexible bodies (crank and conrod). Not a test: timings depend on the machine; report them
with the machine and its load named.

    benchmark_exudyn_export.py --ffrf FFRF --gmsh GMSH --geo crank.geo --case crank_rc1.nml
                               [--lc 0.004] [--repeat 2] [--work DIR] [--csv FILE]
                               [--engine engine_lc8_rc1.nml --mesh-dir DIR [--t-end 0.1]]
"""
import argparse
import os
import re
import subprocess
import sys
import time


def run(args, case, mesh_dir, out, export, sets):
    """Wall time of one run and the export's time (every "Exudyn body written" line summed)."""
    os.makedirs(out, exist_ok=True)
    command = [args.ffrf, case, "--mesh-dir", mesh_dir, "--output-dir", out]
    for s in sets + (["run.export=exudyn"] if export else []):
        command += ["--set", s]
    start = time.perf_counter()
    done = subprocess.run(command, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    wall = time.perf_counter() - start
    if done.returncode != 0:
        sys.exit(f"benchmark_exudyn_export: {' '.join(command)} exited {done.returncode}:\n"
                 f"{done.stdout}")
    seconds = re.findall(r"Exudyn body written: \S+ \.\.\. ([0-9.eE+-]+) s", done.stdout)
    return wall, sum(float(x) for x in seconds)


def measure(args, label, case, mesh_dir, sets, bodies):
    """One CSV row: runs without and with the export alternated, best of each."""
    plain, exported, export_s = [], [], []
    work = os.path.join(args.work, label)
    for _ in range(args.repeat):
        plain.append(run(args, case, mesh_dir, os.path.join(work, "plain"), False, sets)[0])
        wall, seconds = run(args, case, mesh_dir, os.path.join(work, "export"), True, sets)
        exported.append(wall)
        export_s.append(seconds)
    stem = os.path.splitext(os.path.basename(case))[0]
    results = os.path.getsize(os.path.join(work, "export", stem + ".h5"))
    body = sum(os.path.getsize(os.path.join(work, "export", f"{stem}_{b}.exudyn.hdf5"))
               for b in bodies)
    return (f"{label},{args.lc * 1000 if label == 'crank_modal' else 8:g},{min(plain):.3f},"
            f"{min(exported):.3f},{min(export_s):.3f},{min(export_s) / min(plain):.4f},"
            f"{results / 1e6:.2f},{body / 1e6:.2f}")


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
    parser.add_argument("--engine", help="a mechanism case (engine_lc8_rc1.nml): second row")
    parser.add_argument("--mesh-dir", help="--engine: its meshes (crank_lc8.msh, conrod_lc8.msh)")
    parser.add_argument("--t-end", type=float, default=0.1, help="--engine: its t_end (s)")
    args = parser.parse_args()
    mesh_dir = os.path.join(args.work, "mesh")
    os.makedirs(mesh_dir, exist_ok=True)
    subprocess.run([args.gmsh, "-3", "-setnumber", "lc", str(args.lc), "-format", "msh41",
                    "-o", os.path.join(mesh_dir, "crank.msh"), args.geo], check=True,
                   stdout=subprocess.DEVNULL)
    rows = [measure(args, "crank_modal", args.case, mesh_dir, [
        "body[crank].mesh_file=crank.msh", "run.mode_shapes_msh=none"], ["crank"])]
    if args.engine:
        rows.append(measure(args, "engine_mechanism", args.engine, args.mesh_dir, [
            f"integrator.t_end={args.t_end}", "mechanism.animation_frames=0"],
            ["crank", "conrod"]))
    header = ("run,lc_mm,run_s,run_with_export_s,export_s,export_share_of_run,results_mb,"
              "exudyn_files_mb")
    row = "\n".join(rows)
    text = header + "\n" + row + "\n"
    sys.stdout.write(text)
    if args.csv:
        with open(args.csv, "w") as fh:
            fh.write(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
