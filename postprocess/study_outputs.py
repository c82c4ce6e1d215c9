"""The outputs that matter, read from ffrf results files, for the speed-against-accuracy study.

Only reading and arithmetic on stored results (no solver logic):

* `stage_summary(path)`: wall time of the modes (every per-body stage), of the integration and of
  the output, ffrf's total, and the largest peak resident memory at the end of any stage
  (/timings/peak_memory_mib, the process's high-water mark VmHWM);
* `crank_frequencies(path, body, count)`: the first `count` natural (or, for a Craig-Bampton
  basis, Ritz) frequencies of a body, Hz;
* `engine_outputs(path, ...)`: on the regime window, the last `cycles` complete engine cycles
  (engine_summary.py's definitions, four-stroke cycles of 4 pi counted from crank angle 0):
  - mean_speed, amplitude: the crank-angle mean of the crank speed and (max - min) / 2 (rad/s),
    from engine_summary.regime;
  - peak_axial_force: max |F . a| (N), F the reaction force of joint `force_joint` on its body
    `force_side` (1 or 2: /joints/<joint>/reaction rows 0:3 or 6:9, global) and a the rod axis,
    the y axis of body `force_body`'s frame, A(e) e_y with A the rotation matrix of the body's
    Euler parameters e (theory.md 3.1);
  - peak_pin_deflection: max |d| (m), the crank-pin virtual node's elastic displacement
    relative to the main-journal axis, independent of the floating frame (of the RC set):
        u_V(t) = Psi_V zeta(t)       (virtual-node rows of the modes, body frame)
        d = u_pin - [a + w x (x_pin - x_mid)],   a = (u_1 + u_3) / 2,  x_mid = (x_1 + x_3) / 2,
        w_x = -(u_3,y - u_1,y) / L,  w_y = (u_3,x - u_1,x) / L,  w_z = (theta_1,z + theta_3,z) / 2
    with 1, 3 the journal virtual nodes on the crank (z) axis, L = z_3 - z_1: a + w x (x - x_mid)
    is the small rigid motion that carries both journal centres and their mean twist, so d is
    zero for any rigid motion of the crank and the same whatever RC set defines the frame.
    A crank without modes (the automatic model may keep none: the body moves rigidly) has no
    modal coordinates and no deflection: peak_pin_deflection = 0;
* `model_selection(path)`: the automatic model's choice and predicted errors (/model_selection
  of a mechanism run with &model selection = 'auto'), None when the selection did not run.
"""
import math
import os

import h5py
import numpy as np

import engine_summary
import ffrf_results

__all__ = ["stage_summary", "crank_frequencies", "engine_outputs", "rotation_matrix",
           "pin_deflection", "model_selection"]


def stage_summary(path):
    """{'modes_s', 'integration_s', 'output_s', 'ffrf_total_s', 'peak_stage_mib'} of a
    results file (0 for a part the run does not have; peak None without the dataset)."""
    with h5py.File(path, "r") as h5:
        if "timings/stage" not in h5:
            raise ffrf_results.ResultsError(f"{path}: no /timings (the run did not finish)")
        names = [ffrf_results.text(s).strip() for s in np.atleast_1d(h5["timings/stage"][()])]
        seconds = np.atleast_1d(h5["timings/seconds"][()]).astype(float)
        peak = (float(np.max(h5["timings/peak_memory_mib"][()]))
                if "timings/peak_memory_mib" in h5 else None)
    summary = {"modes_s": 0.0, "integration_s": 0.0, "output_s": 0.0, "ffrf_total_s": 0.0,
               "peak_stage_mib": peak}
    for name, value in zip(names, seconds):
        if name == "total":
            summary["ffrf_total_s"] = float(value)
        elif name in ("integration", "start of the integration"):
            summary["integration_s"] += float(value)
        elif name == "output" or name.endswith(": output"):
            summary["output_s"] += float(value)
        elif ": " in name:
            summary["modes_s"] += float(value)
    return summary


def crank_frequencies(path, body, count):
    """The first `count` frequencies (Hz) of `body` (fewer if the body has fewer modes, none
    when it has no modes: a flexible body the automatic model left rigid)."""
    with ffrf_results.open_results(path) as results:
        name = results.body(body)
        if f"bodies/{name}/modes/frequency" not in results.file:
            return np.zeros(0)
        return results.frequencies(name)[:count]


def rotation_matrix(e):
    """Rotation matrices A(e) of Euler parameters e = (e0, e1, e2, e3), (..., 4) -> (..., 3, 3):
    A = (2 e0^2 - 1) I + 2 (e e^T + e0 skew(e)) (theory.md 3.1)."""
    e = np.asarray(e, dtype=float)
    e0, v = e[..., 0], e[..., 1:]
    outer = v[..., :, None] * v[..., None, :]
    skew = np.zeros(e.shape[:-1] + (3, 3))
    skew[..., 0, 1], skew[..., 0, 2] = -v[..., 2], v[..., 1]
    skew[..., 1, 0], skew[..., 1, 2] = v[..., 2], -v[..., 0]
    skew[..., 2, 0], skew[..., 2, 1] = -v[..., 1], v[..., 0]
    eye = np.broadcast_to(np.eye(3), skew.shape)
    return (2.0 * e0**2 - 1.0)[..., None, None] * eye + 2.0 * (outer + e0[..., None, None] * skew)


def pin_deflection(u_journal1, u_pin, u_journal3, x_journal1, x_pin, x_journal3):
    """d = u_pin - [a + w x (x_pin - x_mid)] of the module header. u_*: (n, 6) virtual-node
    motions [u; theta] in the body frame, x_*: (3,) virtual-node positions; journals on the z
    axis. Returns (n, 3)."""
    u1, u2, u3 = (np.asarray(u, dtype=float) for u in (u_journal1, u_pin, u_journal3))
    length = float(x_journal3[2] - x_journal1[2])
    if abs(length) < 1e-12:
        raise ValueError("the journal virtual nodes coincide along z: no journal axis")
    a = 0.5 * (u1[:, :3] + u3[:, :3])
    w = np.stack([-(u3[:, 1] - u1[:, 1]) / length, (u3[:, 0] - u1[:, 0]) / length,
                  0.5 * (u1[:, 5] + u3[:, 5])], axis=1)
    arm = np.asarray(x_pin, dtype=float) - 0.5 * (np.asarray(x_journal1, dtype=float)
                                                  + np.asarray(x_journal3, dtype=float))
    return u2[:, :3] - a - np.cross(w, arm)


def _window(run, values, cycles):
    theta_a, theta_b = ffrf_results.cycle_window(run.crank_angle, cycles)
    return ffrf_results.window_samples(run.crank_angle, values, theta_a, theta_b)[1]


def engine_outputs(path, cycles=2, force_joint="piston_pin", force_side=1, force_body="conrod",
                   crank_body="crank", pin="B2", journals=("B1", "B3")):
    """{'mean_speed', 'amplitude', 'peak_axial_force', 'peak_pin_deflection'} of an engine run
    (module header); raises ResultsError naming what is missing."""
    run = ffrf_results.read_engine(path)
    regime = engine_summary.regime(run, cycles)
    outputs = {"mean_speed": regime["mean_speed"], "amplitude": regime["amplitude"]}
    with h5py.File(path, "r") as h5:
        def dataset(name):
            if name not in h5:
                raise ffrf_results.ResultsError(f"{path}: no dataset {name}")
            return np.asarray(h5[name][()], dtype=float)

        steps = len(run.t)
        reaction = dataset(f"/joints/{force_joint}/reaction")[:steps]
        force = reaction[:, 0:3] if force_side == 1 else reaction[:, 6:9]
        axis = rotation_matrix(dataset(f"/bodies/{force_body}/euler_parameters")[:steps])[:, :, 1]
        axial = np.einsum("ij,ij->i", force, axis)
        outputs["peak_axial_force"] = float(np.max(np.abs(_window(run, axial, cycles))))

        root = f"/bodies/{crank_body}"
        if root not in h5:
            raise ffrf_results.ResultsError(f"{path}: no body {crank_body}")
        if f"{root}/modal_coordinates" not in h5 or h5[f"{root}/modal_coordinates"].size == 0:
            # no modes kept (automatic model): the crank moves rigidly, it does not deflect
            outputs["peak_pin_deflection"] = 0.0
            return _finite(path, outputs)
        zeta = dataset(f"{root}/modal_coordinates")[:steps]
        shapes = dataset(f"{root}/modes/virtual_node_shape")      # h5py: (m, 6 n_if)
        order = [ffrf_results.text(s).strip()
                 for s in np.atleast_1d(h5[f"{root}/interfaces/order"][()])]
        u_v = zeta @ shapes                                       # (steps, 6 n_if)

        def node(name):
            if name not in order:
                raise ffrf_results.ResultsError(f"{path}: body {crank_body} has no interface "
                                                f"{name!r} (interfaces: {', '.join(order)})")
            k = order.index(name)
            return u_v[:, 6 * k:6 * k + 6], dataset(f"{root}/interfaces/{name}/virtual_node")

        (u1, x1), (u2, x2), (u3, x3) = node(journals[0]), node(pin), node(journals[1])
        d = pin_deflection(u1, u2, u3, x1, x2, x3)
        outputs["peak_pin_deflection"] = float(np.max(_window(run, np.linalg.norm(d, axis=1),
                                                             cycles)))
    return _finite(path, outputs)


def _finite(path, outputs):
    for key, value in outputs.items():
        if not math.isfinite(value):
            raise ffrf_results.ResultsError(f"{path}: {key} is {value}")
    return outputs


def model_selection(path):
    """The automatic model of a mechanism run, from /model_selection, or None when the
    selection did not run (no group, or active = 0):
        {'speed_tolerance', 'force_tolerance': the targets,
         'regime_speed_estimate': rad/s,
         'h': the time step chosen (s; 0 when &integrator gave h),
         'predicted_force', 'predicted_speed': predicted relative error of the peak joint
             (conrod) force and of the regime mean speed, truncation + mesh + step,
         'predicted_step_force', 'predicted_step_speed': the time-step part,
         'bodies': {name: {'kept_modes': 1-based indices of the kept candidates,
                           'kept_hz': their frequencies (Hz, free), 'mesh_file': the mesh
                           taken (base name), 'meshes_tried': base names, 'errors':
                           [truncation force, truncation speed, mesh force, mesh speed]}}}
    Raises ResultsError when the group is incomplete or a prediction is not finite."""
    root = "model_selection"
    with h5py.File(path, "r") as h5:
        if root not in h5 or "active" not in h5[root]:
            return None
        if not float(np.atleast_1d(h5[f"{root}/active"][()])[0]) > 0.5:
            return None

        def values(name):
            if name not in h5:
                raise ffrf_results.ResultsError(f"{path}: no dataset /{name}")
            return np.atleast_1d(np.asarray(h5[name][()], dtype=float))

        def names(name):
            if name not in h5:
                return []
            return [os.path.basename(ffrf_results.text(v).strip())
                    for v in np.atleast_1d(h5[name][()])]

        targets = values(f"{root}/targets")
        predicted = values(f"{root}/predicted_error")
        if targets.size != 2 or predicted.size != 4:
            raise ffrf_results.ResultsError(f"{path}: /{root}/targets has {targets.size} values "
                                            f"(2 expected), predicted_error {predicted.size} (4)")
        choice = {"speed_tolerance": float(targets[0]), "force_tolerance": float(targets[1]),
                  "regime_speed_estimate": float(values(f"{root}/regime_speed_estimate")[0]),
                  "h": float(values(f"{root}/time_step")[0]),
                  "predicted_force": float(predicted[0]),
                  "predicted_speed": float(predicted[1]),
                  "predicted_step_force": float(predicted[2]),
                  "predicted_step_speed": float(predicted[3]), "bodies": {}}
        for body, group in h5[root].items():
            if not isinstance(group, h5py.Group):
                continue
            kept = (np.atleast_1d(np.asarray(group["kept_modes"][()], dtype=int))
                    if "kept_modes" in group else np.zeros(0, dtype=int))
            hz = values(f"{root}/{body}/candidate_hz") if "candidate_hz" in group else []
            choice["bodies"][body] = {
                "kept_modes": [int(k) for k in kept],
                "kept_hz": [float(hz[k - 1]) for k in kept if 1 <= k <= len(hz)],
                "mesh_file": (names(f"{root}/{body}/mesh_file") or [""])[0],
                "meshes_tried": names(f"{root}/{body}/meshes_tried"),
                "errors": ([float(v) for v in values(f"{root}/{body}/errors")]
                           if "errors" in group else [])}
    for key in ("predicted_force", "predicted_speed", "h"):
        if not math.isfinite(choice[key]):
            raise ffrf_results.ResultsError(f"{path}: /{root}: {key} is {choice[key]}")
    return choice
