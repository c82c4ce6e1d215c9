#!/usr/bin/env python3
"""Check the automatic model of a scene without a crank (tests/data/scene/auto_double_pendulum.nml:
&model targets on the tip deflection of link2 and the shoulder joint force, each 3e-2 of its
peak; docs/mechanisms.md "Targets on sensors") against a converged run of the same scene (every
one of the 10 candidate modes of both links, h = 2.5e-6 s, a quarter of the chosen step):
- the selection ran for the scene and its predicted errors meet the targets;
- it is smaller than the reference: fewer modes than the 20 candidates;
- the target is met: the actual relative error of each target's peak against the reference
  is within its tolerance;
- the prediction bounds the actual error: actual <= PREDICTION_FACTOR x predicted for every
  target (measured: tip deflection 7.9e-3 against 1.69e-2 predicted, shoulder force 7.3e-6
  against 2.1e-5).
"""
import sys

import h5py
import numpy as np

PREDICTION_FACTOR = 1.5


def fail(message):
    sys.exit(f"FAIL {message}")


def peak(f, name):
    values = f[f"sensors/{name}"][()]
    return float(np.max(np.linalg.norm(values[:, :3], axis=1)))


def main():
    auto_path, reference_path = sys.argv[1:3]
    with h5py.File(auto_path, "r") as f:
        if f["model_selection/active"][()][0] != 1.0:
            fail("the automatic model did not run (/model_selection/active = 0)")
        names = [n.decode() if isinstance(n, bytes) else str(n)
                 for n in f["model_selection/target_names"][()]]
        tolerances = f["model_selection/target_tolerances"][()]
        predicted = f["model_selection/predicted_error"][()]
        h = f["model_selection/time_step"][()][0]
        modes = sum(len(f[f"model_selection/{b}/kept_modes"][()]) for b in ("link1", "link2"))
        auto = {name: peak(f, name) for name in names}
    with h5py.File(reference_path, "r") as f:
        reference = {name: peak(f, name) for name in names}
        reference_modes = sum(len(f[f"bodies/{b}/modes/frequency"][()])
                              for b in ("link1", "link2"))
    print(f"automatic model: {modes} modes, h = {h:.3g} s; reference {reference_modes} modes")
    if not modes < reference_modes:
        fail(f"the automatic model keeps {modes} modes, not fewer than the reference's "
             f"{reference_modes}")
    for name, tolerance, prediction in zip(names, tolerances, predicted):
        actual = abs(auto[name] - reference[name]) / reference[name]
        print(f"{name}: peak {auto[name]:.6g} (reference {reference[name]:.6g}), actual "
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
