#!/usr/bin/env python3
"""Benchmark of the results output (issue 29; docs/results.md "Output rate, peaks, compression,
size"): results size per simulated second and output overhead, for the engine and a mechanism
of two flexible bodies, at full rate and every 1 ms, compressed and not, against a run that
writes no history (&output histories = 'none': /time/t only).

Per run: the results file's size, its growth per simulated second over the 'none' run (the
histories' bytes), the wall time of the integration (/timings 'integration', which includes
the output written during it), and the CPU time of the integration: the run's CPU time (user +
system, getrusage of the child) less that of the same case stopped after 0.1 % of its run, a
step or two (the modes and the start, the same work in every run). The overhead is that CPU time over the 'none'
run's (the wall time of a machine shared with other jobs varies by several times; the CPU time
much less). Animations are off in all runs. Each configuration runs --repeat times; the
smallest CPU time counts.

Usage (the target `benchmark_output` runs it):
    benchmark_output.py --ffrf FFRF --mesh-dir MESHES --work DIR --csv OUT.csv \\
        --engine ENGINE.nml --engine-t-end 1.0 --mechanism MECH.nml --mechanism-t-end 2.0 \\
        --mechanism-h 1e-4
"""
import argparse
import csv
import os
import resource
import subprocess
import sys

import h5py

CONFIGS = [  # (name, --set items)
    ("none", ["output.histories='none'"]),
    ("full", []),
    ("full, deflate 4", ["output.compression=4"]),
    ("1 ms", ["output.every_seconds=1.0e-3"]),
    ("1 ms, deflate 4", ["output.every_seconds=1.0e-3", "output.compression=4"]),
]


def child_cpu():
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def run(args, case, t_end, name, sets, work, step=None):
    out = os.path.join(work, name.replace(" ", "").replace(",", "_"))
    os.makedirs(out, exist_ok=True)
    command = [args.ffrf, case, "--mesh-dir", args.mesh_dir, "--output-dir", out, "--quiet",
               "--set", f"integrator.t_end={t_end}", "--set", "mechanism.animation_frames=0"]
    if step:
        command += ["--set", f"integrator.h={step}"]
    for item in sets:
        command += ["--set", item]
    best = None
    for _ in range(args.repeat):
        before = child_cpu()
        subprocess.run(command, check=True, stdout=subprocess.DEVNULL,
                       env=dict(os.environ, OPENBLAS_NUM_THREADS="1"))
        cpu = child_cpu() - before
        path = os.path.join(out, os.path.splitext(os.path.basename(case))[0] + ".h5")
        with h5py.File(path) as f:
            stages = [s.decode().strip() if isinstance(s, bytes) else str(s).strip()
                      for s in f["timings/stage"][()]]
            seconds = f["timings/seconds"][()]
            integration = float(seconds[stages.index("integration")])
            steps = int(f["integrator/counters"][()][0])
            samples = len(f["time/t"])
        if best is None or cpu < best[4]:
            best = (integration, os.path.getsize(path), steps, samples, cpu)
    return best


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--ffrf", required=True)
    parser.add_argument("--mesh-dir", required=True)
    parser.add_argument("--work", required=True)
    parser.add_argument("--csv", required=True)
    parser.add_argument("--engine", required=True)
    parser.add_argument("--engine-t-end", type=float, default=1.0)
    parser.add_argument("--mechanism", required=True)
    parser.add_argument("--mechanism-t-end", type=float, default=2.0)
    parser.add_argument("--mechanism-h", type=float, default=None,
                        help="the mechanism's step (default: the case's)")
    parser.add_argument("--repeat", type=int, default=1)
    args = parser.parse_args()
    rows = []
    for label, case, t_end, step in (
            ("engine", args.engine, args.engine_t_end, None),
            ("two flexible links", args.mechanism, args.mechanism_t_end, args.mechanism_h)):
        work = os.path.join(args.work, label.replace(" ", "_"))
        # the modes and the start: the case stopped after 0.1 % of the run (a step or two)
        start_cpu = run(args, case, 1.0e-3 * t_end, "start", ["output.histories='none'"], work,
                        step)
        base = None
        for name, sets in CONFIGS:
            integration, size, steps, samples, cpu = run(args, case, t_end, name, sets, work,
                                                         step)
            cpu -= start_cpu[4]
            if base is None:
                base = (cpu, size)
            rows.append({
                "mechanism": label, "output": name, "t_end_s": t_end, "steps": steps,
                "samples": samples, "file_bytes": size,
                "history_bytes_per_simulated_s": round((size - base[1]) / t_end),
                "integration_wall_s": round(integration, 3),
                "integration_cpu_s": round(cpu, 3),
                "overhead_percent": round(100 * (cpu - base[0]) / base[0], 1)})
            print(", ".join(f"{k} = {v}" for k, v in rows[-1].items()), flush=True)
    os.makedirs(os.path.dirname(os.path.abspath(args.csv)), exist_ok=True)
    with open(args.csv, "w", newline="") as handle:
        writer = csv.DictWriter(handle, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)
    print(f"benchmark_output.py: {len(rows)} rows in {args.csv}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
