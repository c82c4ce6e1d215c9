#!/usr/bin/env python3
"""Benchmark of the engine dynamics: run ffrf on engine cases (the target runs input/engine_rc1.nml
with its automatic model, input/engine_rc1_manual.nml, the hand-set model: flexible crank RBE3 RC
set 1 and flexible conrod, 10 modes each, h = 1e-4 s, and the rigid crank; 2.0 s simulated) and
print one CSV row per case: the model (modes per flexible body, crank mesh, step), the
simulated time, wall time of the modes stage, of the integration and of the whole run, steps,
rejected attempts, Newton iterations, Jacobian factorisations, residual evaluations, time per step
and the real-time ratio (wall / simulated), read from the results file (/integrator, /timings,
/bodies). Not a test: timings depend on the machine; report them with the machine named."""
import argparse
import csv
import os
import re
import subprocess
import sys

import h5py


def main():
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("cases", nargs="+", help="engine case files (.nml)")
    parser.add_argument("--ffrf", required=True, help="the ffrf program")
    parser.add_argument("--mesh-dir", required=True, help="folder of crank.msh and conrod.msh")
    parser.add_argument("--work", default="benchmark", help="folder for the results")
    parser.add_argument("--csv", default=None, help="also write the CSV here")
    args = parser.parse_args()
    os.makedirs(args.work, exist_ok=True)
    columns = ["case", "modes", "crank_mesh", "h_s", "coordinates", "simulated_s",
               "modes_wall_s", "integration_wall_s", "total_wall_s",
               "steps", "rejected", "newton_iterations", "factorisations",
               "residual_evaluations", "ms_per_step", "wall_per_simulated_s"]
    writer = csv.writer(sys.stdout)
    writer.writerow(columns)
    rows = []
    env = dict(os.environ, OPENBLAS_NUM_THREADS="1")
    for case in args.cases:
        name = os.path.splitext(os.path.basename(case))[0]
        subprocess.run([args.ffrf, case, "--mesh-dir", args.mesh_dir, "--output-dir", args.work,
                        "--quiet"], check=True, env=env)
        with h5py.File(os.path.join(args.work, name + ".h5"), "r") as f:
            steps, rejected, newton, factorisations, evaluations = f["integrator/counters"][()]
            integration = float(f["integrator/wall_seconds"][()][0])
            stages = [s.decode() if isinstance(s, bytes) else str(s)
                      for s in f["timings/stage"][()]]
            seconds = f["timings/seconds"][()]
            total = float(seconds[stages.index("total")])
            modal = sum(float(t) for stage, t in zip(stages, seconds)
                        if ": " in stage and "inertia" not in stage)
            simulated = float(f["final_state/t"][()][0])
            coordinates = len(f["final_state/q"][()])
            modes = " ".join(f"{body}:{len(f[f'bodies/{body}/modes/frequency'][()])}"
                             for body in f["bodies"] if f"bodies/{body}/modes/frequency" in f)
            if "model_selection/crank/mesh_file" in f:
                mesh = f["model_selection/crank/mesh_file"][()][0]
            else:                           # as given: the crank's mesh_file in the input echo
                text = f["input/namelist"][()]
                text = text.decode() if isinstance(text, bytes) else str(text)
                mesh = re.search(r"name = 'crank', mesh_file = '([^']*)'", text).group(1)
            mesh = os.path.basename(mesh.decode() if isinstance(mesh, bytes) else str(mesh))
        row = [name, modes, mesh, round(simulated / steps, 7), coordinates, simulated,
               round(modal, 3), round(integration, 3), round(total, 3), int(steps),
               int(rejected), int(newton), int(factorisations), int(evaluations),
               round(1e3 * integration / steps, 4), round(integration / simulated, 3)]
        writer.writerow(row)
        sys.stdout.flush()
        rows.append(row)
    if args.csv:
        with open(args.csv, "w", newline="") as f:
            out = csv.writer(f)
            out.writerow(columns)
            out.writerows(rows)


if __name__ == "__main__":
    main()
