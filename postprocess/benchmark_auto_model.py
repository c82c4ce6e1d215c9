#!/usr/bin/python3
"""The automatic model's choice, its predicted errors, its actual errors and its cost against a
converged reference, on the reference engine and three variants (issue 30; docs/mechanisms.md "Model
no more than the scene needs"). One CSV row per run.

Variants (--set overrides of the engine case, input/engine_rc1.nml by default):
  reference   the case as it is
  heavy       piston mass x 2 (0.9 kg), compression ratio 12
  loaded      drag load x 3 (c = 1.08e-3 N m s^2), starter stall torque 60 N m
  titanium    conrod E = 110 GPa, rho = 4430 kg/m^3, peak pressure 80 bar
Per variant three runs:
  auto        the case's automatic model (its targets)
  converged   the same bodies on their finest meshes (mesh_file) with every mode the joints leave
              free among 30 candidates that moves a joint force by more than 1e-5 (targets 1e-6
              speed, 1e-5 force, which keep every such mode), h = 2.5e-5 s
  check       the converged run one level coarser in modes and step (20 candidates, h = 5e-5 s):
              |check / converged - 1| says how converged the reference is in modes and step
  fine        with --gmsh: the converged run on finer meshes (crank lc 4 mm, conrod lc 3.5 mm,
              Tet10, made here from input/crank.geo and conrod.geo): |converged / fine - 1| says
              how converged it is in mesh
Errors are relative: the regime mean crank speed and the peak conrod axial force over the last
two 720 deg cycles (study_outputs.engine_outputs). Columns: variant, run, predicted force and
speed errors (auto: /model_selection/predicted_error), actual errors against the converged
run, actual / predicted, kept modes per body, h, wall time (s), mean speed, peak force.

The reference is the 'converged' run (finest candidate meshes: crank lc 6 mm, conrod lc 5 mm);
the 'check' and 'fine' rows give its distance from one level coarser in modes and step and one
level finer in mesh (their 'actual' columns: against the converged run).

    benchmark_auto_model.py input/engine_rc1.nml --ffrf build/release/driver/ffrf \\
        --mesh-dir build/release/meshes --work build/release/benchmark --csv auto.csv
"""
import argparse
import csv
import os
import subprocess
import sys
import time

import h5py
import numpy as np

import study_outputs

VARIANTS = [
    ("reference", []),
    ("heavy", ["body[piston].mass=0.9", "pressure.compression_ratio=12"]),
    ("loaded", ["load[load].coefficient=1.08e-3", "load[starter].stall_torque=60"]),
    ("titanium", ["body[conrod].young=110e9", "body[conrod].density=4430",
                  "pressure.target_peak_pressure=80e5"]),
]
CONVERGED = ["model.speed_tolerance=1e-6", "model.force_tolerance=1e-5",
             "model.candidate_modes=30", "integrator.h=2.5e-5",
             "body[crank].coarse_meshes=''", "body[conrod].coarse_meshes=''"]
CHECK = ["model.speed_tolerance=1e-6", "model.force_tolerance=1e-5",
         "model.candidate_modes=20", "integrator.h=5e-5",
         "body[crank].coarse_meshes=''", "body[conrod].coarse_meshes=''"]
COLUMNS = ["variant", "run", "predicted_force", "predicted_speed", "actual_force",
           "actual_speed", "force_ratio", "speed_ratio", "kept_modes", "h", "wall_time",
           "mean_speed", "peak_axial_force"]


def run(args, case, name, overrides):
    """One ffrf run; its results file."""
    output = os.path.join(args.work, f"{name}.h5")
    command = [args.ffrf, case, "--mesh-dir", args.mesh_dir, "--output-dir", args.work,
               "--output", f"{name}.h5", "--quiet"]
    for item in overrides:
        command += ["--set", item]
    start = time.perf_counter()
    done = subprocess.run(command, env=dict(os.environ, OPENBLAS_NUM_THREADS="1"),
                          capture_output=True, text=True)
    wall = time.perf_counter() - start
    if done.returncode != 0:
        sys.exit(f"benchmark_auto_model.py: {' '.join(command)} failed "
                 f"({done.returncode}): {done.stderr.strip()}")
    return output, wall


def describe(path):
    with h5py.File(path, "r") as f:
        selection = f["model_selection"]
        predicted = selection["predicted_error"][()] if "predicted_error" in selection else None
        kept = {}
        for name in ("crank", "conrod"):
            if f"{name}/kept_modes" in selection:
                kept[name] = len(selection[f"{name}/kept_modes"][()])
        h = float(f["time/t"][1] - f["time/t"][0])
    return predicted, kept, h


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("case", help="engine case with &model selection = 'auto'")
    parser.add_argument("--ffrf", required=True)
    parser.add_argument("--mesh-dir", required=True)
    parser.add_argument("--work", required=True)
    parser.add_argument("--csv", required=True)
    parser.add_argument("--variants", nargs="*", help="names of the variants to run (default all)")
    parser.add_argument("--gmsh", help="gmsh executable: adds the 'fine' run")
    parser.add_argument("--geo-dir", help="folder of crank.geo and conrod.geo (with --gmsh)")
    args = parser.parse_args(argv)
    os.makedirs(args.work, exist_ok=True)
    runs = [("auto", []), ("converged", CONVERGED), ("check", CHECK)]
    if args.gmsh:
        fine = []
        for body, lc in (("crank", 0.004), ("conrod", 0.0035)):
            mesh = os.path.abspath(os.path.join(args.work, f"{body}_lc{lc * 1000:g}.msh"))
            if not os.path.exists(mesh):
                subprocess.run([args.gmsh, "-3", "-setnumber", "lc", str(lc), "-setnumber",
                                "order", "2", "-format", "msh41", "-o", mesh,
                                os.path.join(args.geo_dir, f"{body}.geo")], check=True,
                               capture_output=True)
            fine.append(f"body[{body}].mesh_file='{mesh}'")
        runs.append(("fine", CONVERGED + fine))
    rows = []
    for variant, overrides in VARIANTS:
        if args.variants and variant not in args.variants:
            continue
        results = {}
        for kind, extra in runs:
            path, wall = run(args, args.case, f"auto_model_{variant}_{kind}", overrides + extra)
            outputs = study_outputs.engine_outputs(path)
            predicted, kept, h = describe(path)
            results[kind] = dict(outputs=outputs, predicted=predicted, kept=kept, h=h, wall=wall)
            print(f"{variant:10s} {kind:9s} wall {wall:7.2f} s, h {h:.3g} s, modes {kept}, "
                  f"speed {outputs['mean_speed']:.6g} rad/s, peak force "
                  f"{outputs['peak_axial_force']:.6g} N", flush=True)
        reference = results["converged"]["outputs"]
        for kind in [kind for kind, _ in runs if kind != "converged"]:
            r = results[kind]
            actual_force = abs(r["outputs"]["peak_axial_force"] / reference["peak_axial_force"]
                               - 1.0)
            actual_speed = abs(r["outputs"]["mean_speed"] / reference["mean_speed"] - 1.0)
            predicted = r["predicted"] if kind == "auto" else None
            row = {"variant": variant, "run": kind,
                   "predicted_force": predicted[0] if predicted is not None else "",
                   "predicted_speed": predicted[1] if predicted is not None else "",
                   "actual_force": actual_force, "actual_speed": actual_speed,
                   "force_ratio": actual_force / predicted[0] if predicted is not None else "",
                   "speed_ratio": actual_speed / predicted[1] if predicted is not None else "",
                   "kept_modes": " ".join(f"{k}:{v}" for k, v in r["kept"].items()),
                   "h": r["h"], "wall_time": r["wall"],
                   "mean_speed": r["outputs"]["mean_speed"],
                   "peak_axial_force": r["outputs"]["peak_axial_force"]}
            rows.append(row)
        rows.append({"variant": variant, "run": "converged", "predicted_force": "",
                     "predicted_speed": "", "actual_force": 0.0, "actual_speed": 0.0,
                     "force_ratio": "", "speed_ratio": "",
                     "kept_modes": " ".join(f"{k}:{v}" for k, v in
                                            results["converged"]["kept"].items()),
                     "h": results["converged"]["h"], "wall_time": results["converged"]["wall"],
                     "mean_speed": reference["mean_speed"],
                     "peak_axial_force": reference["peak_axial_force"]})
    with open(args.csv, "w", newline="") as stream:
        writer = csv.DictWriter(stream, fieldnames=COLUMNS)
        writer.writeheader()
        for row in rows:
            writer.writerow({k: (repr(float(v)) if isinstance(v, (float, np.floating)) else v)
                             for k, v in row.items()})
    with open(args.csv) as stream:
        sys.stdout.write(stream.read())
    return 0


if __name__ == "__main__":
    sys.exit(main())
