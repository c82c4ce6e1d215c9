#!/usr/bin/python3
"""The automatic model of scenes without a crank (&model targets on sensors; docs/mechanisms.md
"Targets on sensors"): per scene and tolerance, the modes, mesh and step chosen, the predicted
and the actual error of each target against a converged reference run, and the cost of both
runs. One CSV row per target and run.

Scenes (cases in tests/data/scene/, the meshes of the build):
  double_pendulum  auto_double_pendulum.nml: targets as in the case (3e-2) and 1e-1;
                   reference 10 + 10 modes, h = 2.5e-6 s
  boom             auto_driven_boom.nml: targets as in the case and three times looser;
                   reference 10 modes, h = 2.5e-6 s
  boom_mesh        the boom on mesh_file beam_lc4.msh with coarse_meshes beam_lc40.msh,
                   beam_lc6.msh (the mesh chosen); reference beam_lc4.msh, 10 modes,
                   h = 2.5e-6 s
The actual error of a target is |auto / reference - 1| of its peak or mean
(tests/regression/check_scene_auto_model.py statistic). Columns: scene, targets, target,
statistic, tolerance, predicted, actual, actual / predicted, the kept modes per body, the
meshes taken, h, the reference's modes and h, the wall time of each whole run and of its
integration (s; one process at a time, --threads 1).

    benchmark_scene_model.py --ffrf build/release/driver/ffrf --mesh-dir build/release/meshes \\
        --cases tests/data/scene --work build/release/benchmark/scene_model --csv OUT.csv
"""
import argparse
import csv
import os
import subprocess
import sys
import time

import h5py

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests",
                                "regression"))
from check_scene_auto_model import statistic, text  # noqa: E402

BOOM_LOOSE = "tip_deflection 1e-1 hinge_force 1e-1 tip_speed 1e-1 tip_spin mean 3e-2"
BOOM_MESHES = ["body[boom].mesh_file=beam_lc4.msh",
               "body[boom].coarse_meshes='beam_lc40.msh', 'beam_lc6.msh'"]
SCENES = [  # (scene, case, overrides of the automatic runs, target lists, reference overrides)
    ("double_pendulum", "auto_double_pendulum", [],
     [None, "tip_deflection 1e-1 shoulder_force 1e-1"],
     ["body[link1].num_modes=10", "body[link2].num_modes=10", "integrator.h=2.5e-6"]),
    ("boom", "auto_driven_boom", [], [None, BOOM_LOOSE],
     ["body[boom].num_modes=10", "integrator.h=2.5e-6"]),
    ("boom_mesh", "auto_driven_boom", BOOM_MESHES, [None],
     ["body[boom].mesh_file=beam_lc4.msh", "body[boom].num_modes=10", "integrator.h=2.5e-6"]),
]


def run(args, case, folder, overrides):
    os.makedirs(folder, exist_ok=True)
    command = [args.ffrf, case, "--mesh-dir", args.mesh_dir, "--output-dir", folder,
               "--threads", "1"]
    for item in overrides:
        command += ["--set", item]
    start = time.perf_counter()
    subprocess.run(command, check=True, stdout=subprocess.DEVNULL)
    seconds = time.perf_counter() - start
    return os.path.join(folder, os.path.basename(case)[:-4] + ".h5"), seconds


def integration_seconds(f):
    return float(f["integrator/wall_seconds"][()].ravel()[0])


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--ffrf", required=True)
    parser.add_argument("--mesh-dir", required=True)
    parser.add_argument("--cases", required=True, help="tests/data/scene")
    parser.add_argument("--work", required=True)
    parser.add_argument("--csv", required=True)
    args = parser.parse_args()
    rows = []
    for scene, name, auto_overrides, target_lists, reference_overrides in SCENES:
        case = os.path.join(args.cases, name + ".nml")
        reference_path, reference_seconds = run(args, case, os.path.join(args.work, scene,
                                                                          "reference"),
                                                reference_overrides)
        reference_h = float([o for o in reference_overrides
                             if o.startswith("integrator.h=")][0].split("=")[1])
        with h5py.File(reference_path, "r") as f:
            reference_integration = integration_seconds(f)
            reference_modes = {b: len(f[f"bodies/{b}/modes/frequency"][()])
                               for b in f["bodies"] if f"bodies/{b}/modes/frequency" in f}
        for k, targets in enumerate(target_lists):
            overrides = list(auto_overrides) + ([f"model.targets={targets}"] if targets else [])
            auto_path, auto_seconds = run(args, case, os.path.join(args.work, scene, f"auto{k}"),
                                          overrides)
            with h5py.File(auto_path, "r") as f:
                selection = f["model_selection"]
                names = [text(n) for n in selection["target_names"][()]]
                kinds = [text(n) for n in selection["target_statistics"][()]]
                tolerances = selection["target_tolerances"][()]
                predicted = selection["predicted_error"][()]
                h = float(selection["time_step"][()][0])
                bodies = [b for b in selection if isinstance(selection[b], h5py.Group)]
                modes = " ".join(f"{b}:{len(selection[f'{b}/kept_modes'][()])}" for b in bodies)
                meshes = " ".join(f"{b}:{text(selection[f'{b}/mesh_file'][()][0])}"
                                  for b in bodies)
                auto = {n: statistic(f, n, s) for n, s in zip(names, kinds)}
                auto_integration = integration_seconds(f)
            with h5py.File(reference_path, "r") as f:
                reference = {n: statistic(f, n, s) for n, s in zip(names, kinds)}
            for n, s, tolerance, prediction in zip(names, kinds, tolerances, predicted):
                actual = abs(auto[n] / reference[n] - 1.0)
                rows.append({
                    "scene": scene, "targets": targets or "(the case's)", "target": n,
                    "statistic": s, "tolerance": f"{tolerance:.3g}",
                    "predicted": f"{prediction:.3g}", "actual": f"{actual:.3g}",
                    "actual_over_predicted": f"{actual / prediction:.3g}",
                    "modes": modes, "meshes": meshes, "h": f"{h:.3g}",
                    "reference_modes": " ".join(f"{b}:{m}" for b, m in reference_modes.items()),
                    "reference_h": f"{reference_h:.3g}",
                    "auto_seconds": f"{auto_seconds:.2f}",
                    "reference_seconds": f"{reference_seconds:.2f}",
                    "auto_integration_seconds": f"{auto_integration:.2f}",
                    "reference_integration_seconds": f"{reference_integration:.2f}"})
            print(f"{scene} {targets or '(the case)'}: {modes}, h = {h:.3g} s, "
                  f"{auto_seconds:.1f} s against {reference_seconds:.1f} s", flush=True)
    os.makedirs(os.path.dirname(os.path.abspath(args.csv)), exist_ok=True)
    with open(args.csv, "w", newline="") as out:
        writer = csv.DictWriter(out, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)
    writer = csv.DictWriter(sys.stdout, fieldnames=list(rows[0]))
    writer.writeheader()
    writer.writerows(rows)


if __name__ == "__main__":
    main()
