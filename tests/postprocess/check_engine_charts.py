#!/usr/bin/python3
"""Run postprocess/engine_summary.py and plot_engine.py on the files make_engine_sample.py wrote
and check what they write.

References (make_engine_sample.py): in the regime the speed is omega = w0 + a sin(theta/2 - phase),
so over whole engine cycles the angle mean is w0 and (max - min)/2 = a, peak-to-peak 2 a.
Tolerances from the sampling, with dtheta the largest crank-angle step in the window:
- mean: trapezoidal rule in theta, error <= dtheta^2 / 12 * max|omega''(theta)| = dtheta^2 a / 48
  (the interpolated window ends are within this bound too), plus the spin-up left at the window
  start, (w0 + a) exp(-t_start / TAU) (~1e-5 rad/s). That is 1.0e-3 rad/s at dtheta = 0.079
  (dt = 5e-4 s); the time mean sqrt(w0^2 - a^2) is 0.21 .. 0.34 rad/s away, so a summary that
  averaged over time fails (checked below).
- amplitude: a sampled extremum is at most dtheta/2 in theta, dtheta/4 in phase, from the true
  one, so it falls short by <= a (1 - cos(dtheta/4)) <= a dtheta^2 / 32 (and never exceeds a).
- rpm = rad/s * 30 / pi, peak-to-peak = 2 * amplitude, CSV numbers: round-off (1e-12 relative).
- regime window: from crank angle 4 pi (K - 2) to 4 pi K, K = floor(theta_end / 4 pi); its
  times are recomputed here with np.interp on the stored samples (1e-9 s).
- wall time: the 'total' stage, else the sum of the stages written (exact); steps: len(/time/t)
  read with h5py (exact); for the killed run, the shortest series (CHUNK steps fewer than t).
- pressure over the last complete cycle (through ffrf_results): the interior samples equal the
  analytic p(theta) at the stored angles (1e-12 relative), the window spans exactly 720 deg.
Pictures: each PNG exists, has the size its layout gives at --dpi 100 (speed 900 x 800, pressure
800 x 450), is not blank (> 3% non-white pixels, > 20 colours) and shows each run's curve
colour (matplotlib C0, C1, C2; the pressure C3) on > 200 pixels. Error paths: a killed run
(status 'running') is refused without --allow-incomplete and its message names the status and
the flag, and accepted with it; a file without /time and a request for more cycles than the run
holds are refused with a clear message. Whether the pictures are right is for a person to see:
open engine_speed.png and engine_pressure.png in the test folder.
"""
import argparse
import csv
import math
import os
import subprocess
import sys

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.image as mpimg  # noqa: E402
import numpy as np  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "..", "postprocess"))
import ffrf_results  # noqa: E402
import make_engine_sample as sample  # noqa: E402

CHECKS, FAILURES = [], []
CYCLE = 4.0 * math.pi


def expect(what, condition):
    print(("ok   " if condition else "FAIL ") + what)
    CHECKS.append(what)
    if not condition:
        FAILURES.append(what)


def run(script, *args):
    return subprocess.run([sys.executable, script, *args], capture_output=True, text=True)


def regime_reference(path):
    """(t_start, t_end, dtheta_max) of the last two complete cycles, computed with h5py."""
    with h5py.File(path, "r") as f:
        t, theta = f["/time/t"][()], f["/time/crank_angle"][()]
    last = math.floor(theta[-1] / CYCLE)
    theta_a, theta_b = CYCLE * (last - 2), CYCLE * last
    inside = (theta >= theta_a) & (theta <= theta_b)
    first, final = np.flatnonzero(inside)[[0, -1]]
    dtheta = np.diff(theta[first - 1:final + 2]).max()
    return float(np.interp(theta_a, theta, t)), float(np.interp(theta_b, theta, t)), dtheta


def check_summary(script, folder):
    files = [os.path.join(folder, r["file"]) for r in sample.RUNS[:3]]
    csv_path = os.path.join(folder, "engine_summary.csv")
    md_path = os.path.join(folder, "engine_summary.md")
    for path in (csv_path, md_path):
        if os.path.exists(path):
            os.remove(path)
    result = run(script, *files, "--csv", csv_path, "--markdown", md_path)
    expect(f"engine_summary.py exits 0 (stderr: {result.stderr.strip()[-300:]})",
           result.returncode == 0)
    expect("CSV and Markdown exist", os.path.isfile(csv_path) and os.path.isfile(md_path))
    if FAILURES:
        return
    with open(csv_path, newline="") as stream:
        rows = list(csv.DictReader(stream))
    expect(f"one CSV row per run ({len(rows)})", len(rows) == 3)
    w_ref = sample.RUNS[0]["w0"]
    tol_ref = None
    for spec, row, path in zip(sample.RUNS, rows, files):
        name = spec["file"]
        w0, a = spec["w0"], spec["a"]
        t_start, t_end, dtheta = regime_reference(path)
        ramp = (w0 + a) * math.exp(-t_start / sample.TAU)
        tol_mean = dtheta ** 2 * a / 48.0 + ramp
        tol_amp = a * dtheta ** 2 / 32.0 + ramp
        if tol_ref is None:
            tol_ref = tol_mean
        mean = float(row["mean speed [rad/s]"])
        amp = float(row["oscillation (max-min)/2 [rad/s]"])
        p2p = float(row["oscillation max-min [rad/s]"])
        label = row["run"]
        expected_label = {"rigid": "rigid crank"}.get(spec["mpc"],
                                                     f"{spec['rc_set']}, {spec['mpc']}")
        expect(f"{name}: label '{label}'", label == expected_label)
        expect(f"{name}: mean {mean:.9f} = w0 {w0} rad/s (error {abs(mean - w0):.1e}, "
               f"tol {tol_mean:.1e})", abs(mean - w0) <= tol_mean)
        time_mean = math.sqrt(w0 ** 2 - a ** 2)
        expect(f"{name}: the time mean {time_mean:.4f} would fail (|diff| "
               f"{abs(time_mean - w0):.3f} > 10 tol)", abs(time_mean - w0) > 10 * tol_mean)
        expect(f"{name}: (max-min)/2 {amp:.9f} = a {a} (error {abs(amp - a):.1e}, "
               f"tol {tol_amp:.1e}, never above a)",
               abs(amp - a) <= tol_amp and amp <= a + ramp)
        expect(f"{name}: peak-to-peak {p2p} = 2 (max-min)/2",
               abs(p2p - 2 * amp) <= 1e-12 * p2p)
        rpm = float(row["mean speed [rpm]"])
        expect(f"{name}: rpm {rpm} = mean * 30 / pi",
               abs(rpm - mean * 30 / math.pi) <= 1e-12 * rpm)
        relative = float(row["mean speed relative to reference [1]"])
        expected = (w0 - w_ref) / w_ref
        tol_rel = (tol_mean + tol_ref) / w_ref
        expect(f"{name}: relative difference {relative:.6e} = {expected:.6e} "
               f"(tol {tol_rel:.1e})", abs(relative - expected) <= tol_rel)
        with h5py.File(path, "r") as f:
            steps = len(f["/time/t"])
        expect(f"{name}: steps {row['steps']} = {steps}", int(row["steps"]) == steps)
        timings = spec["timings"]
        wall = timings.get("total", sum(timings.values()))
        expect(f"{name}: wall time {row['wall time [s]']} = {wall}",
               float(row["wall time [s]"]) == wall)
        expect(f"{name}: wall / simulated = {wall / spec['t_end']}",
               abs(float(row["wall time / simulated time [1]"]) - wall / spec["t_end"])
               <= 1e-12)
        window = (float(row["regime from t [s]"]), float(row["regime to t [s]"]))
        expect(f"{name}: regime window {window[0]:.9f} .. {window[1]:.9f} s = last two "
               f"cycles {t_start:.9f} .. {t_end:.9f}",
               abs(window[0] - t_start) <= 1e-9 and abs(window[1] - t_end) <= 1e-9)
    with open(md_path) as stream:
        markdown = stream.read()
    expect("Markdown names every run and shows 150.000 rad/s and -1.000%",
           all(f"| {r['run']} |" in markdown for r in rows) and "| 150.000 |" in markdown
           and "| -1.000% |" in markdown)

    killed = os.path.join(folder, "engine_rc3_killed.h5")
    refused = run(script, files[0], killed, "--csv", csv_path)
    expect(f"killed run refused without --allow-incomplete: {refused.stderr.strip()}",
           refused.returncode != 0 and "'running'" in refused.stderr
           and "--allow-incomplete" in refused.stderr)
    accepted = run(script, files[0], killed, "--csv", csv_path, "--allow-incomplete")
    expect(f"killed run accepted with --allow-incomplete (stderr: {accepted.stderr.strip()})",
           accepted.returncode == 0)
    if accepted.returncode == 0:
        with open(csv_path, newline="") as stream:
            row = list(csv.DictReader(stream))[1]
        with h5py.File(killed, "r") as f:
            shortest = len(f["/time/crank_speed"])
            longest = len(f["/time/t"])
        expect(f"killed run: steps {row['steps']} = shortest series {shortest} (t has "
               f"{longest}), wall time empty, label says incomplete",
               int(row["steps"]) == shortest and shortest == longest - sample.CHUNK
               and row["wall time [s]"] == "" and "incomplete: running" in row["run"])
    no_time = run(script, os.path.join(folder, "engine_no_time.h5"))
    expect(f"file without /time refused: {no_time.stderr.strip()}",
           no_time.returncode != 0 and "no /time group" in no_time.stderr)
    too_many = run(script, files[0], "--cycles", "30")
    expect(f"30 cycles refused: {too_many.stderr.strip()}",
           too_many.returncode != 0 and "22 complete engine cycle(s)" in too_many.stderr)


def colour_pixels(rgb, colour):
    target = np.array([int(colour[i:i + 2], 16) for i in (1, 3, 5)]) / 255.0
    return int(np.sum(np.all(np.abs(rgb - target) < 0.02, axis=2)))


def check_picture(png, size, colours):
    expect(f"{os.path.basename(png)} exists", os.path.isfile(png))
    if not os.path.isfile(png):
        return
    image = mpimg.imread(png)
    height, width = image.shape[:2]
    expect(f"{os.path.basename(png)} is {size[0]} x {size[1]} pixels: {width} x {height}",
           (width, height) == size)
    rgb = image[:, :, :3]
    coloured = np.mean(np.any(rgb < 0.95, axis=2))
    expect(f"{100 * coloured:.1f}% of the pixels are not white (> 3%)", coloured > 0.03)
    distinct = len(np.unique((rgb.reshape(-1, 3) * 255).astype(np.uint8), axis=0))
    expect(f"{distinct} distinct colours (> 20)", distinct > 20)
    for colour in colours:
        count = colour_pixels(rgb, colour)
        expect(f"curve colour {colour} on {count} pixels (> 200)", count > 200)


def check_plots(script, folder):
    files = [os.path.join(folder, r["file"]) for r in sample.RUNS[:3]]
    speed = os.path.join(folder, "engine_speed.png")
    pressure = os.path.join(folder, "engine_pressure.png")
    for path in (speed, pressure):
        if os.path.exists(path):
            os.remove(path)
    result = run(script, *files, "-o", speed, "--pressure", pressure, "--dpi", "100")
    expect(f"plot_engine.py exits 0 (stderr: {result.stderr.strip()[-300:]})",
           result.returncode == 0)
    expect(f"default zoom is the last two cycles (shorter than 0.2 s): {result.stdout.strip()}",
           "zoom 1.832 .. 2.000 s" in result.stdout)
    check_picture(speed, (900, 800), ["#1f77b4", "#ff7f0e", "#2ca02c"])
    check_picture(pressure, (800, 450), ["#d62728"])

    killed = os.path.join(folder, "engine_rc3_killed.h5")
    killed_png = os.path.join(folder, "engine_speed_killed.png")
    refused = run(script, files[0], killed, "-o", killed_png)
    expect(f"killed run refused without --allow-incomplete: {refused.stderr.strip()}",
           refused.returncode != 0 and "'running'" in refused.stderr
           and "--allow-incomplete" in refused.stderr)
    accepted = run(script, files[0], killed, "-o", killed_png, "--allow-incomplete",
                   "--zoom", "1.0", "1.2", "--dpi", "60")
    expect(f"killed run plotted with --allow-incomplete (stderr: {accepted.stderr.strip()})",
           accepted.returncode == 0 and os.path.isfile(killed_png)
           and "zoom 1.000 .. 1.200 s" in accepted.stdout)
    no_time = run(script, os.path.join(folder, "engine_no_time.h5"), "-o", killed_png)
    expect(f"file without /time refused: {no_time.stderr.strip()}",
           no_time.returncode != 0 and "no /time group" in no_time.stderr)


def check_pressure_cycle(folder):
    """The last complete cycle's pressure through ffrf_results, against the analytic curve."""
    engine = ffrf_results.read_engine(os.path.join(folder, sample.RUNS[0]["file"]))
    theta_a, theta_b = ffrf_results.cycle_window(engine.crank_angle, 1)
    last = math.floor(engine.crank_angle[-1] / CYCLE)
    expect(f"last complete cycle is [4 pi {last - 1}, 4 pi {last}]",
           (theta_a, theta_b) == (CYCLE * (last - 1), CYCLE * last))
    theta, pressure = ffrf_results.window_samples(engine.crank_angle, engine.pressure,
                                                  theta_a, theta_b)
    span = math.degrees(theta[-1] - theta[0])
    expect(f"the cycle spans {span:.12f} deg", abs(span - 720.0) <= 1e-9)
    error = np.max(np.abs(pressure[1:-1] / sample.pressure(theta[1:-1]) - 1.0))
    expect(f"pressure samples equal the analytic p(theta) (relative {error:.1e} <= 1e-12)",
           error <= 1e-12)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--summary-script", required=True, help="postprocess/engine_summary.py")
    parser.add_argument("--plot-script", required=True, help="postprocess/plot_engine.py")
    parser.add_argument("folder", help="folder with the files of make_engine_sample.py")
    args = parser.parse_args()
    check_summary(args.summary_script, args.folder)
    check_plots(args.plot_script, args.folder)
    check_pressure_cycle(args.folder)
    print(f"{len(CHECKS) - len(FAILURES)} passed, {len(FAILURES)} failed")
    return 1 if FAILURES else 0


if __name__ == "__main__":
    sys.exit(main())
