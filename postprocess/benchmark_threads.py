#!/usr/bin/env python3
"""Benchmark of the BLAS threads and the linear solver of the integration (issue 24): chains of
N = 1, 2, 4, 8, 16 flexible links (postprocess/chain_case.py: input/link.geo, Craig-Bampton
6 + 8 and 6 + 32 modes per link, revolute joints about z, a torque on link 1), each run

  threads=1        --threads 1
  threads=default  no --threads and OPENBLAS_NUM_THREADS unset (OpenBLAS: every core)

with the default linear solver (dense LU below the sparse threshold, MUMPS from it), and, with
--solvers, also on one thread with the dense LU forced (sparse_threshold = 10**9) and the sparse
LU forced (sparse_threshold = 1): the evidence for the threshold. Prints one CSV row per run:
the integration time per step and its parts (residuals, tangents, factorisations, solves) as the
log prints them ("[run] ... ms/step", "integration time: ..."), the order of the iteration
matrix, the solver used, the [threads] line, and the 1-minute load average when the run started.
With --repeat R the runs of one chain are made R times, interleaved round after round, and the
fastest of each kept (the machine is shared and its load drifts).
Not a test: timings depend on the machine and its load; report them with both."""
import argparse
import csv
import os
import re
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from chain_case import chain_case  # noqa: E402

STEPS_RE = re.compile(r"\[run\]\s+(\d+) steps, (\d+) rejected, (\d+) Newton iterations, "
                      r"(\d+) Jacobian factorisations.*?, ([0-9.eE+-]+) s "
                      r"\(([0-9.eE+-]+) ms/step\)")
PARTS_RE = re.compile(r"integration time: residuals ([0-9.eE+-]+) s \(\d+\), tangents "
                      r"([0-9.eE+-]+) s, factorisations ([0-9.eE+-]+) s, solves ([0-9.eE+-]+) s")
MATRIX_RE = re.compile(r"iteration matrix: order (\d+), (dense|sparse)")
THREADS_RE = re.compile(r"\[threads\] (.*)")


def load_average():
    with open("/proc/loadavg", encoding="ascii") as f:
        return float(f.read().split()[0])


def run_once(args, case_file, out_dir, threads):
    env = dict(os.environ)
    command = [args.ffrf, case_file, "--mesh-dir", args.mesh_dir, "--output-dir", out_dir]
    if threads == "1":
        command += ["--threads", "1"]
    else:
        env.pop("OPENBLAS_NUM_THREADS", None)
    load = load_average()
    done = subprocess.run(command, env=env, capture_output=True, text=True)
    log = done.stdout + done.stderr
    if done.returncode != 0:
        sys.exit(f"benchmark_threads: {' '.join(command)} failed ({done.returncode}):\n{log}")
    steps = STEPS_RE.search(log)
    parts = PARTS_RE.search(log)
    matrix = MATRIX_RE.search(log)
    line = THREADS_RE.search(log)
    if not (steps and parts and matrix):
        sys.exit(f"benchmark_threads: no integration statistics in the log of {case_file}:\n{log}")
    return {
        "steps": int(steps.group(1)), "rejected": int(steps.group(2)),
        "newton_iterations": int(steps.group(3)), "factorisations": int(steps.group(4)),
        "integration_s": float(steps.group(5)), "ms_per_step": float(steps.group(6)),
        "residual_s": float(parts.group(1)), "tangent_s": float(parts.group(2)),
        "factor_s": float(parts.group(3)), "solve_s": float(parts.group(4)),
        "matrix_order": int(matrix.group(1)), "solver_used": matrix.group(2),
        "threads_log": line.group(1).strip() if line else "", "load1": load,
    }


def main():
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--ffrf", required=True, help="the ffrf program")
    parser.add_argument("--mesh-dir", required=True, help="folder of link.msh")
    parser.add_argument("--work", default="benchmark/threads", help="folder for cases, results")
    parser.add_argument("--csv", default=None, help="also write the CSV here")
    parser.add_argument("--links", type=int, nargs="+", default=[1, 2, 4, 8, 16])
    parser.add_argument("--modes", type=int, nargs="+", default=[8, 32],
                        help="fixed-interface modes per link (plus 6 static modes)")
    parser.add_argument("--steps", type=int, default=50, help="steps of 1e-4 s per run")
    parser.add_argument("--repeat", type=int, default=1, help="runs per row; the fastest kept")
    parser.add_argument("--solvers", action="store_true",
                        help="also the dense and the sparse LU forced, on one thread")
    parser.add_argument("--sparse-only", action="store_true",
                        help="only the sparse LU forced, on one thread (growth with N)")
    args = parser.parse_args()
    os.makedirs(args.work, exist_ok=True)
    columns = ["links", "modes_per_link", "threads", "solver", "matrix_order", "solver_used",
               "steps", "rejected", "newton_iterations", "factorisations", "ms_per_step",
               "integration_s", "residual_s", "tangent_s", "factor_s", "solve_s", "load1",
               "threads_log"]
    writer = csv.DictWriter(sys.stdout, fieldnames=columns)
    writer.writeheader()
    rows = []
    variants = [("1", "auto", None), ("default", "auto", None)]
    if args.solvers:
        variants += [("1", "dense", 10**9), ("1", "sparse", 1)]
    if args.sparse_only:
        variants = [("1", "sparse", 1)]
    for modes in args.modes:
        for links in args.links:
            # the variants of one chain interleaved, round after round (the load of a shared
            # machine drifts), the fastest run of each kept
            best = {}
            for _ in range(args.repeat):
                for threads, solver, threshold in variants:
                    name = f"chain_n{links}_m{modes}_{solver}"
                    case_file = os.path.join(args.work, name + ".nml")
                    with open(case_file, "w", encoding="utf-8") as out:
                        out.write(chain_case(links, modes, steps=args.steps,
                                             sparse_threshold=threshold))
                    out_dir = os.path.join(args.work, f"{name}_t{threads}")
                    os.makedirs(out_dir, exist_ok=True)
                    result = run_once(args, case_file, out_dir, threads)
                    key = (threads, solver)
                    if key not in best or result["ms_per_step"] < best[key]["ms_per_step"]:
                        best[key] = result
            for threads, solver, _ in variants:
                row = dict(best[(threads, solver)], links=links, modes_per_link=6 + modes,
                           threads=threads, solver=solver)
                writer.writerow(row)
                sys.stdout.flush()
                rows.append(row)
    if args.csv:
        os.makedirs(os.path.dirname(os.path.abspath(args.csv)), exist_ok=True)
        with open(args.csv, "w", newline="", encoding="utf-8") as f:
            w = csv.DictWriter(f, fieldnames=columns)
            w.writeheader()
            w.writerows(rows)


if __name__ == "__main__":
    main()
