#!/usr/bin/env python3
"""Check the automatic model of a scene without a crank (&model targets on its sensors;
docs/mechanisms.md "Targets on sensors") against a converged run of the same scene (every one of
the candidate modes of each chosen body and a step a quarter of the chosen one or smaller):
- the selection ran for the scene and its predicted errors meet the targets;
- it is smaller than the reference: fewer modes than the reference's;
- the target is met: the actual relative error of each target's peak (or mean over the run)
  against the reference is within its tolerance;
- the prediction bounds the actual error: actual <= PREDICTION_FACTOR x predicted for every
  target.
A sensor's value at a step is the norm of its first three values (a joint_coordinate: the
absolute value); its peak the largest over the written steps, its mean the time average
(trapezoid rule over the written steps). Measured errors are in docs/mechanisms.md "Targets on
sensors".
Usage: check_scene_auto_model.py AUTO.h5 REFERENCE.h5
"""
import sys

import h5py
import numpy as np

PREDICTION_FACTOR = 1.5


def fail(message):
    sys.exit(f"FAIL {message}")


def text(value):
    return value.decode() if isinstance(value, bytes) else str(value)


def statistic(f, name, kind):
    values = f[f"sensors/{name}"][()]
    values = values.reshape(len(values), -1)
    magnitude = np.linalg.norm(values[:, :3], axis=1)
    if kind == "mean":
        t = f["time/t"][()]
        return float(np.trapz(magnitude, t) / (t[-1] - t[0]))
    return float(np.max(magnitude))


def main():
    auto_path, reference_path = sys.argv[1:3]
    with h5py.File(auto_path, "r") as f:
        selection = f["model_selection"]
        if selection["active"][()][0] != 1.0:
            fail("the automatic model did not run (/model_selection/active = 0)")
        names = [text(n) for n in selection["target_names"][()]]
        kinds = [text(n) for n in selection["target_statistics"][()]]
        tolerances = selection["target_tolerances"][()]
        predicted = selection["predicted_error"][()]
        h = selection["time_step"][()][0]
        bodies = [b for b in selection if isinstance(selection[b], h5py.Group)]
        modes = sum(len(selection[f"{b}/kept_modes"][()]) for b in bodies)
        auto = {name: statistic(f, name, kind) for name, kind in zip(names, kinds)}
    with h5py.File(reference_path, "r") as f:
        reference = {name: statistic(f, name, kind) for name, kind in zip(names, kinds)}
        reference_modes = sum(len(f[f"bodies/{b}/modes/frequency"][()]) for b in bodies)
    print(f"automatic model: {modes} modes of {', '.join(bodies)}, h = {h:.3g} s; reference "
          f"{reference_modes} modes")
    if not modes < reference_modes:
        fail(f"the automatic model keeps {modes} modes, not fewer than the reference's "
             f"{reference_modes}")
    for name, kind, tolerance, prediction in zip(names, kinds, tolerances, predicted):
        actual = abs(auto[name] - reference[name]) / abs(reference[name])
        print(f"{name} ({kind}): {auto[name]:.6g} (reference {reference[name]:.6g}), actual "
              f"relative error {actual:.3g}, predicted {prediction:.3g}, target {tolerance:.3g}")
        if not 0.0 < prediction <= tolerance:
            fail(f"{name}: predicted error {prediction:.3g} not within the target {tolerance:.3g}")
        if not actual <= tolerance:
            fail(f"{name}: actual error {actual:.3g} above the target {tolerance:.3g}")
        if not actual <= PREDICTION_FACTOR * prediction:
            fail(f"{name}: actual error {actual:.3g} above {PREDICTION_FACTOR} x the predicted "
                 f"{prediction:.3g}")
    print("ok   automatic model of a scene without a crank")


if __name__ == "__main__":
    main()
