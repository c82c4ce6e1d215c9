"""Regime speed, speed oscillation and wall time of several ffrf engine runs, one row per run.

The first file is the reference (e.g. the rigid crank): every row gives the relative difference
of its mean speed to the first file's. Per run: label (rc_set and mpc of /engine), regime mean
crank speed in rad/s and rpm, averaged over crank angle on the last --cycles complete engine
cycles (4 pi of crank angle each, counted from crank angle 0), the speed oscillation on the same
cycles ((max - min) / 2 and peak-to-peak, rad/s), the wall time of the run from /timings (the
stage 'total', else the sum of the stages) and its ratio to the simulated time, the number of
stored steps, and the time span of the cycles used; what flexibility did on the same cycles:
per flexible body its number of modes (or "rigid" when the automatic model kept none), its
largest strain energy (J, sum of omega_j^2 eta_j^2 / 2 over its mass-normalised modes) and the
largest elastic deflection of its virtual nodes (um, the translation rows of
/bodies/<b>/modes/virtual_node_shape times /bodies/<b>/modal_coordinates); and over the run the
largest strain energy (/energy/strain) and deflection. Markdown rounds for reading; the CSV keeps
every double (shortest round-trip repr). With neither option the Markdown goes to standard
output. A run whose status is not 'complete' is an error unless --allow-incomplete.

    ffrf-engine-summary engine_rigid.h5 engine_rc1.h5 engine_rc2.h5 --markdown s.md --csv s.csv

(ffrf-engine-summary is the console script of `pip install ./postprocess`;
postprocess/engine_summary.py runs the same code.)
"""
import argparse
import csv
import math
import sys

import h5py
import numpy as np

import ffrf_results

RPM = 30.0 / math.pi   # rpm per rad/s

# (key, CSV header); the CSV writes them in this order
COLUMNS = [
    ("label", "run"),
    ("mean_speed", "mean speed [rad/s]"),
    ("mean_rpm", "mean speed [rpm]"),
    ("amplitude", "oscillation (max-min)/2 [rad/s]"),
    ("peak_to_peak", "oscillation max-min [rad/s]"),
    ("relative_difference", "mean speed relative to reference [1]"),
    ("elastic_modes", "per body: modes, max strain energy, max deflection"),
    ("max_strain_energy", "max strain energy [J]"),
    ("max_deflection_um", "max virtual-node deflection [um]"),
    ("wall_time", "wall time [s]"),
    ("wall_per_simulated", "wall time / simulated time [1]"),
    ("num_steps", "steps"),
    ("cycles", "cycles averaged"),
    ("t_start", "regime from t [s]"),
    ("t_end", "regime to t [s]"),
    ("status", "status"),
    ("file", "file"),
]


def regime(run, num_cycles):
    """Mean speed and oscillation over the last num_cycles complete engine cycles of a run.

    The mean is taken over crank angle, (1 / (4 pi N)) int omega d theta, not over time, for
    three reasons. (1) The regime is periodic in crank angle, not in time: pressure, piston
    kinematics and so the speed fluctuation repeat every 4 pi, so the window is cut at whole
    cycles in angle, and a mean over whole periods is then exact for any sampling. (2) The
    closed-form check of the regime (issue 3) balances the indicated work per cycle against the
    load, an integral over crank angle: int (T_ind - c omega^2) d theta = 0 gives the angle
    mean of omega^2, and the angle mean of omega differs from its square root only by the
    fluctuation's variance. (3) A time mean weights slow phases more (the crank lingers
    there): it equals 4 pi N / (time of the N cycles), which for omega = w0 + a sin(theta / 2)
    is sqrt(w0^2 - a^2), not w0, a bias of a^2 / (2 w0) that is no property of the engine.
    """
    theta_a, theta_b = ffrf_results.cycle_window(run.crank_angle, num_cycles)
    theta, omega = ffrf_results.window_samples(run.crank_angle, run.crank_speed, theta_a,
                                               theta_b)
    _, times = ffrf_results.window_samples(run.crank_angle, run.t, theta_a, theta_b)
    mean = ffrf_results.angle_mean(theta, omega)
    peak_to_peak = float(omega.max() - omega.min())
    return {"mean_speed": mean, "mean_rpm": mean * RPM, "amplitude": peak_to_peak / 2.0,
            "peak_to_peak": peak_to_peak, "cycles": num_cycles,
            "t_start": float(times[0]), "t_end": float(times[-1])}


def elasticity(path, t_start, t_end):
    """Per flexible body its modes, largest strain energy and virtual-node deflection in
    [t_start, t_end]; the largest total strain energy and deflection (module docstring)."""
    with h5py.File(path, "r") as results:
        t = np.atleast_1d(results["time/t"][()])
        window = (t >= t_start) & (t <= t_end)
        strain = (np.atleast_1d(results["energy/strain"][()])[:len(t)]
                  if "energy/strain" in results else np.zeros(len(t)))
        selected = results.get("model_selection")
        parts, deflection = [], 0.0
        bodies = results["bodies"] if "bodies" in results else {}
        for name in sorted(bodies):
            body = bodies[name]
            if "modal_coordinates" not in body:
                # a body the automatic model left rigid
                if selected is not None and name in selected:
                    parts.append(f"{name}: rigid")
                continue
            q = np.atleast_2d(body["modal_coordinates"][()])[:len(t)]
            q = q[window[:len(q)]]   # a killed run's series may end a chunk early
            if q.shape[0] == 0:
                parts.append(f"{name}: {q.shape[1]} modes (no step in the regime window)")
                continue
            if "modes/virtual_node_shape" not in body or "modes/frequency" not in body:
                parts.append(f"{name}: {q.shape[1]} modes (no mode data)")
                continue
            shape = np.atleast_2d(body["modes/virtual_node_shape"][()])   # (modes, 6 n_i)
            omega2 = (2.0 * math.pi * np.atleast_1d(body["modes/frequency"][()])) ** 2
            body_strain = float((0.5 * (q ** 2) @ omega2).max())   # mass-normalised modes
            body_deflection = max(float(np.linalg.norm(q @ shape[:, 6 * i:6 * i + 3],
                                                       axis=1).max())
                                  for i in range(shape.shape[1] // 6))
            deflection = max(deflection, body_deflection)
            parts.append(f"{name}: {q.shape[1]} mode{'s' if q.shape[1] > 1 else ''}, "
                         f"{body_strain:.3g} J, {1.0e6 * body_deflection:.3g} um")
    return {"elastic_modes": "; ".join(parts) if parts else "none",
            "max_strain_energy": (float(strain[window[:len(strain)]].max())
                                  if window[:len(strain)].any() else 0.0),
            "max_deflection_um": 1.0e6 * deflection}


def summarise(files, num_cycles, allow_incomplete):
    """One dict per file (keys of COLUMNS); raises ResultsError naming the file."""
    rows = []
    runs = ffrf_results.unique_labels([ffrf_results.read_engine(
        path, allow_incomplete=allow_incomplete) for path in files])
    for path, run in zip(files, runs):
        try:
            row = regime(run, num_cycles)
        except ffrf_results.ResultsError as exc:
            raise ffrf_results.ResultsError(f"{path}: {exc}") from exc
        row.update(elasticity(path, row["t_start"], row["t_end"]))
        simulated = float(run.t[-1] - run.t[0])
        row.update({
            "label": run.label, "num_steps": run.num_steps, "wall_time": run.wall_time,
            "wall_per_simulated": (run.wall_time / simulated
                                   if run.wall_time is not None and simulated > 0.0 else None),
            "status": run.status, "file": path})
        rows.append(row)
    reference = rows[0]["mean_speed"]
    for row in rows:
        row["relative_difference"] = (row["mean_speed"] - reference) / reference
    return rows


def write_markdown(stream, rows, num_cycles):
    stream.write(f"Crank speed in regime (mean over crank angle and oscillation on the last "
                 f"{num_cycles} complete engine cycles); reference: {rows[0]['label']}\n\n")
    stream.write("| run | mean speed (rad/s) | mean speed (rpm) | (max-min)/2 (rad/s) "
                 "| max-min (rad/s) | vs reference | per body: modes, max strain energy, max deflection "
                 "| max strain energy (J) "
                 "| max deflection (um) | wall time (s) | wall / simulated | steps |\n")
    stream.write("|---|---:|---:|---:|---:|---:|---|---:|---:|---:|---:|---:|\n")
    for row in rows:
        wall = "n/a" if row["wall_time"] is None else f"{row['wall_time']:.2f}"
        ratio = ("n/a" if row["wall_per_simulated"] is None
                 else f"{row['wall_per_simulated']:.2f}")
        stream.write(f"| {row['label']} | {row['mean_speed']:.3f} | {row['mean_rpm']:.1f} "
                     f"| {row['amplitude']:.3f} | {row['peak_to_peak']:.3f} "
                     f"| {100 * row['relative_difference']:+.3f}% | {row['elastic_modes']} "
                     f"| {row['max_strain_energy']:.3g} | {row['max_deflection_um']:.2f} "
                     f"| {wall} | {ratio} "
                     f"| {row['num_steps']} |\n")


def csv_cell(value):
    if value is None:
        return ""
    if isinstance(value, (float, np.floating)):
        return repr(float(value))
    return str(value)


def write_csv(path, rows):
    with open(path, "w", newline="") as stream:
        writer = csv.writer(stream)
        writer.writerow([header for _, header in COLUMNS])
        for row in rows:
            writer.writerow([csv_cell(row[key]) for key, _ in COLUMNS])


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("files", nargs="+", help="engine results files (.h5); the first is "
                        "the reference")
    parser.add_argument("--markdown", help="write the Markdown table here")
    parser.add_argument("--csv", help="write the CSV table here")
    parser.add_argument("--cycles", type=int, default=2,
                        help="complete engine cycles (4 pi each) at the end of each run that "
                        "make the regime (default 2)")
    parser.add_argument("--allow-incomplete", action="store_true",
                        help="also use runs whose status is not 'complete' (killed or "
                        "failed: the steps they saved)")
    args = parser.parse_args(argv)
    if args.cycles < 1:
        parser.error(f"--cycles {args.cycles}: must be at least 1")
    try:
        rows = summarise(args.files, args.cycles, args.allow_incomplete)
    except ffrf_results.ResultsError as exc:
        return ffrf_results.command_error("engine_summary.py", exc)
    if args.markdown:
        with open(args.markdown, "w") as stream:
            write_markdown(stream, rows, args.cycles)
    if args.csv:
        write_csv(args.csv, rows)
    if not (args.markdown or args.csv):
        write_markdown(sys.stdout, rows, args.cycles)
    return 0


if __name__ == "__main__":
    sys.exit(main())
