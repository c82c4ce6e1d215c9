#!/usr/bin/env python3
"""Check the automatic engine model (input/engine_rc1.nml, &model selection = 'auto') against the
hand-set model of the same engine (input/engine_rc1_manual.nml: 10 RC normal modes per body on
the 6/5 mm meshes, h = 1e-4 s), both run for the full 2 s:
- the selection ran and its predicted relative errors (peak conrod force, regime speed) are
  within the targets it was given;
- it is smaller: fewer modes in all and a crank mesh no finer than the hand-set one;
- it meets its targets against a second model: the regime mean speed and the peak conrod axial
  force over the last two 720 deg cycles agree with the hand-set model's within the targets
  (1e-3 and 1e-2). The hand-set model is not converged itself (the study's Craig-Bampton
  reference is: docs/mechanisms.md "Model no more than the scene needs"); this guards the whole
  chain;
- its modes are those the joints leave free (issue 30): every kept crank mode leaves the
  journal rotations across the crank axis at B1 and B3 (which the revolute bearings hold) at
  round-off, below LOCK_RTOL = 1e-9 of the mode's largest virtual-node entry, while the
  computed candidates include modes the joints mostly lock (free share below 1/2); the crank
  keeps a mode because the targets need it (dropping all its free modes would cost more than
  the truncation budget, a third of the force target), and the kept modes move: the crank's
  largest strain energy over the last two cycles is within [1/2, 2] of the quasi-static one,
  max_t F_b(t)^T C F_b(t) / 2, C = sum_j u_j u_j^T / omega_j^2 its compliance at the crank pin
  (u_j the B2 translations of kept mode j) and F_b the crank-pin reaction in the crank frame
  (measured 0.79: the forcing harmonics lie far below the kept mode's 2.6 kHz). Before the
  issue the kept crank mode moved by 1e-21 (locked by the bearings);
- with --converged (the same engine on its finest meshes with every mode the joints leave free
  among 30 candidates that moves a joint force by more than 1e-5, h = 2.5e-5 s): the actual
  errors of the automatic model, regime mean speed and peak conrod axial force against it, are
  at most PREDICTION_FACTOR = 1.5 times the predicted ones (the issue: they were up to 2.4 times
  before), and within the targets.
Speed is measured by the benchmark (cmake --build --preset benchmark-engine), not here.
"""
import argparse
import os
import sys

import math

import h5py
import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "..", "postprocess"))
import study_outputs  # noqa: E402


def fail(message):
    sys.exit(f"FAIL {message}")


def ok(message):
    print(f"ok   {message}")


def strings(dataset):
    return [s.decode() if isinstance(s, bytes) else str(s) for s in dataset[()]]


def main():
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("auto", help="results of the automatic model")
    parser.add_argument("manual", help="results of the hand-set model")
    parser.add_argument("--converged", help="results of the converged reference")
    args = parser.parse_args()
    with h5py.File(args.auto, "r") as f:
        if f["model_selection/active"][()][0] != 1.0:
            fail("the automatic model did not run (/model_selection/active = 0)")
        speed_target, force_target = f["model_selection/targets"][()]
        force, speed = f["model_selection/predicted_error"][()][:2]
        if not (0.0 < force <= force_target and 0.0 < speed <= speed_target):
            fail(f"predicted errors force {force:.3g}, speed {speed:.3g} against the targets "
                 f"{force_target:.3g}, {speed_target:.3g}")
        ok(f"predicted errors force {force:.3g} <= {force_target:.3g}, speed {speed:.3g} <= "
           f"{speed_target:.3g}")
        auto_modes = {body: len(f[f"model_selection/{body}/kept_modes"][()])
                      for body in ("crank", "conrod")}
        auto_mesh = strings(f["model_selection/crank/mesh_file"])[0]
        tried = strings(f["model_selection/crank/meshes_tried"])
        h = f["model_selection/time_step"][()][0]
    with h5py.File(args.manual, "r") as f:
        manual_modes = {body: len(f[f"bodies/{body}/modes/frequency"][()])
                        for body in ("crank", "conrod")}
    if sum(auto_modes.values()) >= sum(manual_modes.values()):
        fail(f"not smaller: modes {auto_modes} against the hand-set {manual_modes}")
    if os.path.basename(auto_mesh) not in tried:
        fail(f"crank mesh {auto_mesh} is not one of the candidates {tried}")
    ok(f"smaller: modes {auto_modes} against {manual_modes}, crank mesh {auto_mesh} "
       f"(candidates {tried}), h = {h:.3g} s")
    check_joint_free(args.auto)
    auto = study_outputs.engine_outputs(args.auto)
    manual = study_outputs.engine_outputs(args.manual)
    for key, target in (("mean_speed", speed_target), ("peak_axial_force", force_target)):
        difference = abs(auto[key] / manual[key] - 1.0)
        if not difference <= target:
            fail(f"{key}: automatic {auto[key]:.6g} against hand-set {manual[key]:.6g}, "
                 f"relative difference {difference:.3g} > target {target:.3g}")
        ok(f"{key}: automatic {auto[key]:.6g}, hand-set {manual[key]:.6g}, relative "
           f"difference {difference:.3g} <= {target:.3g}")
    if args.converged:
        converged = study_outputs.engine_outputs(args.converged)
        for key, target, predicted in (("mean_speed", speed_target, speed),
                                       ("peak_axial_force", force_target, force)):
            actual = abs(auto[key] / converged[key] - 1.0)
            if not (actual <= PREDICTION_FACTOR * predicted and actual <= target):
                fail(f"{key}: automatic {auto[key]:.6g} against converged {converged[key]:.6g}, "
                     f"actual error {actual:.3g}, predicted {predicted:.3g} (at most "
                     f"{PREDICTION_FACTOR} x predicted and the target {target:.3g})")
            ok(f"{key}: automatic {auto[key]:.6g}, converged {converged[key]:.6g}: actual error "
               f"{actual:.3g}, predicted {predicted:.3g} (ratio {actual / predicted:.2f} <= "
               f"{PREDICTION_FACTOR}), target {target:.3g}")


LOCK_RTOL = 1.0e-9
PREDICTION_FACTOR = 1.5


def check_joint_free(path):
    """The crank's kept modes are free of the bearing locks and carry strain energy (module
    docstring)."""
    with h5py.File(path, "r") as f:
        order = strings(f["bodies/crank/interfaces/order"])
        shape = np.atleast_2d(f["bodies/crank/modes/virtual_node_shape"][()])   # (modes, 6 n_i)
        omega = 2.0 * math.pi * np.atleast_1d(f["bodies/crank/modes/frequency"][()])
        share = f["model_selection/crank/free_share"][()]
        force_error = f["model_selection/crank/force_error"][()]
        kept = f["model_selection/crank/kept_modes"][()]
        force_target = f["model_selection/targets"][()][1]
        q = np.atleast_2d(f["bodies/crank/modal_coordinates"][()])
        euler = f["bodies/crank/euler_parameters"][()]
        reaction = f["joints/crank_pin/reaction"][()]
    if len(kept) == 0:
        fail("the crank keeps no mode")
    for name in ("B1", "B3"):
        i = order.index(name)
        held = np.abs(shape[:, 6 * i + 3:6 * i + 5]).max(axis=1) / np.abs(shape).max(axis=1)
        if not held.max() <= LOCK_RTOL:
            fail(f"kept crank modes rotate the journal {name} across the axis by "
                 f"{held.max():.3g} of their size (> {LOCK_RTOL:.0e}): the bearing locks them")
        ok(f"journal {name}: kept modes' rotations across the axis {held.max():.2g} of their "
           f"size <= {LOCK_RTOL:.0e}")
    if not share.min() < 0.5:
        fail(f"no computed candidate is mostly locked (free shares {share})")
    needed = force_error.sum()
    if not needed > force_target / 3.0:
        fail(f"the crank's free modes together cost {needed:.3g} of force if dropped, within "
             f"the budget {force_target / 3.0:.3g}: keeping one is not needed")
    ok(f"{int((share < 0.5).sum())} candidates mostly locked (free share down to "
       f"{share.min():.3f}); the free modes would cost {needed:.3g} > budget "
       f"{force_target / 3.0:.3g} if dropped: kept {len(kept)}")
    pin = order.index("B2")
    u = shape[:, 6 * pin:6 * pin + 3]
    compliance = (u.T / omega**2) @ u
    window = slice(len(q) - len(q) // 5, len(q))   # the last 0.4 s: two cycles and more
    frame_force = np.einsum("nji,nj->ni", study_outputs.rotation_matrix(euler[window]),
                            reaction[window, :3])
    quasi_static = 0.5 * np.einsum("ni,ij,nj->n", frame_force, compliance, frame_force).max()
    strain = (0.5 * (q[window] ** 2) @ omega**2).max()
    ratio = strain / quasi_static
    if not 0.5 <= ratio <= 2.0:
        fail(f"crank strain energy {strain:.3g} J against the quasi-static {quasi_static:.3g} J "
             f"(ratio {ratio:.3g}, expected in [0.5, 2])")
    ok(f"crank strain energy {strain:.3g} J, quasi-static {quasi_static:.3g} J, ratio "
       f"{ratio:.3g} in [0.5, 2]")


if __name__ == "__main__":
    main()
