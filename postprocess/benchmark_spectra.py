#!/usr/bin/env python3
"""Benchmark of many modes and of the Sturm check (issue 22, docs/method.md "Modes: spectra
you can trust"): the crank meshed at one size (default lc = 4 mm), RC set 1 (RBE3), run with each
setting of --runs: `N` modes (num_modes = N), `N-nosturm` (num_modes = N, sturm_check = .false.)
or `fK` (max_frequency_hz = K kHz). One CSV row per run: modes returned, shift windows, count
factorisations (the Sturm check and the window boundaries), recoveries, the time of the
factorisation at the eigen shift, of the eigen loop and of the count factorisations (their
share of the whole run), the whole run and its peak memory, first and last frequency.
Not a test: timings depend on the machine; report them with the machine named."""
import argparse
import csv
import os
import re
import subprocess
import sys
import time

import h5py


def stage_seconds(names, seconds, suffix):
    """Sum of the stage times whose name ends with `suffix`."""
    return sum(s for n, s in zip(names, seconds) if n.endswith(suffix))


def modes_group(run):
    """The &modes group of a run setting."""
    if run.endswith("-nosturm"):
        return f"&modes num_modes = {int(run.split('-')[0])}, sturm_check = .false., " \
               "rc_label = 'RC set 1' /"
    if run.startswith("f"):
        return f"&modes max_frequency_hz = {float(run[1:]) * 1000:g}, rc_label = 'RC set 1' /"
    return f"&modes num_modes = {int(run)}, rc_label = 'RC set 1' /"


def main():
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--ffrf", required=True, help="the ffrf program")
    parser.add_argument("--gmsh", default="gmsh", help="the gmsh program")
    parser.add_argument("--geo", required=True, help="crank.geo")
    parser.add_argument("--case", required=True, help="crank_rc1.nml")
    parser.add_argument("--lc", type=float, default=0.004, help="mesh size in metres")
    parser.add_argument("--runs", default="12,12-nosturm,50,200,f10,f20,f40",
                        help="comma-separated run settings (N, N-nosturm, fK)")
    parser.add_argument("--work", default="benchmark", help="folder for meshes and results")
    parser.add_argument("--csv", default=None, help="also write the CSV here")
    args = parser.parse_args()
    os.makedirs(args.work, exist_ok=True)
    mesh = os.path.join(args.work, f"crank_lc{args.lc * 1000:g}mm.msh")
    if not os.path.exists(mesh):
        subprocess.run([args.gmsh, "-3", "-setnumber", "lc", str(args.lc), "-format", "msh41",
                        "-o", mesh, args.geo], check=True, stdout=subprocess.DEVNULL)
    with open(args.case) as f:
        case_text = f.read()
    columns = ["lc_mm", "dofs", "run", "modes", "windows", "count_factorisations",
               "recoveries", "factorisation_s", "eigen_loop_s", "sturm_s", "sturm_share",
               "ffrf_total_s", "wall_s", "peak_memory_mib", "f_first_hz", "f_last_hz"]
    writer = csv.writer(sys.stdout)
    writer.writerow(columns)
    rows = []
    for run in args.runs.split(","):
        tag = f"spectra_lc{args.lc * 1000:g}mm_{run}"
        text = re.sub(r"mesh_file\s*=\s*'[^']*'", f"mesh_file = '{os.path.abspath(mesh)}'",
                      case_text)
        text = re.sub(r"&run[^/]*/", f"&run title = '{tag}', mode_shapes_msh = 'none' /", text)
        text = re.sub(r"&modes[^/]*/", modes_group(run), text)
        case = os.path.join(args.work, tag + ".nml")
        with open(case, "w") as f:
            f.write(text)
        env = dict(os.environ, OPENBLAS_NUM_THREADS=os.environ.get("OPENBLAS_NUM_THREADS", "1"))
        t0 = time.perf_counter()
        subprocess.run([args.ffrf, case, "--output-dir", args.work, "--quiet"], check=True,
                       env=env)
        wall_s = time.perf_counter() - t0
        with h5py.File(os.path.join(args.work, tag + ".h5"), "r") as h5:
            names = [n.decode().strip() for n in h5["/timings/stage"][()]]
            seconds = list(h5["/timings/seconds"][()])
            peak = float(max(h5["/timings/peak_memory_mib"][()]))
            body = list(h5["/bodies"].keys())[0]
            modes = h5[f"/bodies/{body}/modes"]
            freq = modes["frequency"][()]
            sturm = modes["sturm_check"]
            total = stage_seconds(names, seconds, "total")
            sturm_s = stage_seconds(names, seconds, ": Sturm check")
            count_factorisations = int(sturm["count_factorisations"][()])
            row = [args.lc * 1000, int(h5[f"/bodies/{body}/sizes/num_dofs"][()]), run,
                   len(freq), int(sturm["windows"][()]), count_factorisations,
                   int(sturm["recoveries"][()]),
                   round(stage_seconds(names, seconds, ": factorisation"), 3),
                   round(stage_seconds(names, seconds, ": eigen loop"), 3), round(sturm_s, 3),
                   round(sturm_s / total, 3) if total > 0 else 0.0, round(total, 3),
                   round(wall_s, 3), round(peak, 1), round(float(freq[0]), 4),
                   round(float(freq[-1]), 4)]
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
