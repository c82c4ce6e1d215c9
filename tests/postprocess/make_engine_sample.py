#!/usr/bin/python3
"""Write synthetic engine results files that follow the engine results schema, for the tests of
plot_engine.py and engine_summary.py.

The crank starts at rest at crank angle 0 and spins up to a regime where its speed is a known
function of the crank angle theta, one oscillation per engine cycle (4 pi, the firing order of a
single-cylinder four-stroke engine):

    omega = g(t) (w0 + a sin(theta / 2 - PHASE)),   g(t) = 1 - exp(-t / TAU),

integrated as d theta / dt = omega by RK4 on quarter steps. The samples store omega computed from
the stored theta by this formula, so omega(theta) holds to round-off at every sample whatever the
RK4 error of theta(t). Over whole cycles in the regime (g = 1 to exp(-1.6 / 0.1) ~ 1e-7):

    angle mean (1/4pi) int omega d theta = w0,      (max - min) / 2 = a,    peak-to-peak = 2 a,

while the time mean is sqrt(w0^2 - a^2) (Adler's equation: one period of the oscillation takes
4 pi / sqrt(w0^2 - a^2) s), so a summary that averaged over time would be off by a^2 / (2 w0)
(0.21 .. 0.34 rad/s here). The in-cylinder pressure is a function of the cycle angle
phi = theta mod 4 pi: p = P_INTAKE + (P_PEAK - P_INTAKE) exp(-((phi - PEAK_ANGLE) / WIDTH)^2).

Files written (RUNS, one per entry): engine_rigid.h5 (the reference, rigid crank; /timings has a
'total' stage), engine_rc1.h5 and engine_rc2.h5 (status 'complete'; no 'total', so the wall time
is the sum of the stages; rc2 has half the time step), engine_rc3_killed.h5 (status 'running',
killed at 1.2 s: crank_speed and pressure one chunk of CHUNK steps shorter than t and
crank_angle, no /timings yet) and engine_no_time.h5 (status 'complete' but no /time group).
Strings are fixed-length bytes, as the Fortran writer's; Fortran (n, m) arrays are stored (m, n).
"""
import argparse
import math
import os

import h5py
import numpy as np

TAU = 0.1                  # s, spin-up time constant
PHASE = 0.4                # rad, phase of the speed oscillation
P_INTAKE = 1.0e5           # Pa
P_PEAK = 55.0e5            # Pa
PEAK_ANGLE = math.radians(372.0)   # rad of the 720 deg cycle (firing TDC at 360 deg)
WIDTH = math.radians(28.0)         # rad
CHUNK = 50                 # steps per flushed chunk of the killed run
NUM_MODES = 4

RUNS = [
    {"file": "engine_rigid.h5", "rc_set": "rigid crank", "mpc": "rigid", "w0": 150.0,
     "a": 8.0, "dt": 5.0e-4, "t_end": 2.0, "status": "complete",
     "timings": {"setup": 0.05, "integration": 1.5, "output": 0.1, "total": 1.75}},
    {"file": "engine_rc1.h5", "rc_set": "RC set 1", "mpc": "RBE3", "w0": 149.25,
     "a": 9.0, "dt": 5.0e-4, "t_end": 2.0, "status": "complete",
     "timings": {"setup": 0.5, "integration": 2.25, "output": 0.125}},
    {"file": "engine_rc2.h5", "rc_set": "RC set 2", "mpc": "RBE3", "w0": 148.5,
     "a": 10.0, "dt": 2.5e-4, "t_end": 2.0, "status": "complete",
     "timings": {"setup": 0.5, "integration": 4.5, "output": 0.25}},
    {"file": "engine_rc3_killed.h5", "rc_set": "RC set 3", "mpc": "RBE3", "w0": 148.0,
     "a": 9.5, "dt": 5.0e-4, "t_end": 1.2, "status": "running", "timings": None},
]


def pressure(theta):
    """In-cylinder pressure, Pa, as a function of the unwrapped crank angle theta (rad)."""
    phi = np.mod(theta, 4.0 * math.pi)
    return P_INTAKE + (P_PEAK - P_INTAKE) * np.exp(-((phi - PEAK_ANGLE) / WIDTH) ** 2)


def speed(t, theta, w0, a):
    """omega(t, theta), rad/s."""
    return (1.0 - np.exp(-t / TAU)) * (w0 + a * np.sin(theta / 2.0 - PHASE))


def motion(w0, a, dt, t_end):
    """t, theta, omega at the steps 0, dt, ..., t_end (theta by RK4 on dt/4 substeps)."""
    num_steps = int(round(t_end / dt)) + 1
    t = dt * np.arange(num_steps)
    theta = np.zeros(num_steps)
    h = dt / 4.0
    value, time = 0.0, 0.0
    for k in range(1, num_steps):
        for _ in range(4):
            k1 = speed(time, value, w0, a)
            k2 = speed(time + h / 2, value + h / 2 * k1, w0, a)
            k3 = speed(time + h / 2, value + h / 2 * k2, w0, a)
            k4 = speed(time + h, value + h * k3, w0, a)
            value += h / 6.0 * (k1 + 2 * k2 + 2 * k3 + k4)
            time += h
        theta[k] = value
    return t, theta, speed(t, theta, w0, a)


def fixed(strings):
    """Fixed-length byte strings (NUL-padded), as the Fortran wrapper writes them."""
    if isinstance(strings, str):
        return np.bytes_(strings.encode())
    return np.array([s.encode() for s in strings], dtype=f"S{max(1, *map(len, strings))}")


def series(f, path, values, units):
    f.create_dataset(path, data=values, maxshape=(None,) + np.shape(values)[1:],
                     chunks=(CHUNK,) + np.shape(values)[1:])
    f[path].attrs["units"] = fixed(units)


def write_run(path, run, with_time=True):
    t, theta, omega = motion(run["w0"], run["a"], run["dt"], run["t_end"])
    killed = run["status"] != "complete"
    short = len(t) - CHUNK if killed else len(t)    # the last chunk of these was not flushed
    name = os.path.splitext(os.path.basename(path))[0]
    with h5py.File(path, "w") as f:
        f.attrs["status"] = fixed(run["status"])
        f.attrs["case_name"] = fixed(name)
        f.attrs["title"] = fixed(f"synthetic engine run, {run['rc_set']}")
        f.create_group("engine")
        f["engine"].attrs["rc_set"] = fixed(run["rc_set"])
        f["engine"].attrs["mpc"] = fixed(run["mpc"])
        if with_time:
            series(f, "/time/t", t, "s")
            series(f, "/time/crank_angle", theta, "rad")
            series(f, "/time/crank_speed", omega[:short], "rad/s")
            series(f, "/time/pressure", pressure(theta[:short]), "Pa")
        q = 1e-5 * np.sin(np.outer(theta, np.arange(1, NUM_MODES + 1)))
        series(f, "/bodies/crank/modal_coordinates", q, "1")
        kinetic = 0.5 * 0.05 * omega ** 2
        series(f, "/energy/kinetic", kinetic, "J")
        series(f, "/energy/strain", np.zeros_like(t), "J")
        series(f, "/energy/external_work", kinetic, "J")
        series(f, "/energy/numerical_dissipation", np.zeros_like(t), "J")
        reaction = np.zeros((len(t), 12))
        reaction[:, 1] = -pressure(theta) * math.pi * 0.080 ** 2 / 4
        reaction[:, 7] = -reaction[:, 1]
        series(f, "/joints/piston_pin/reaction", reaction, "N, N m")
        if run["timings"]:
            f["/timings/stage"] = fixed(list(run["timings"]))
            f["/timings/seconds"] = np.array(list(run["timings"].values()))
            f["/timings/seconds"].attrs["units"] = fixed("s")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("-o", "--output-dir", default=".", help="folder for the sample files")
    args = parser.parse_args()
    os.makedirs(args.output_dir, exist_ok=True)
    for run in RUNS:
        write_run(os.path.join(args.output_dir, run["file"]), run)
    write_run(os.path.join(args.output_dir, "engine_no_time.h5"), RUNS[1], with_time=False)
    print(f"wrote {', '.join(run['file'] for run in RUNS)}, engine_no_time.h5 "
          f"to {args.output_dir}")


if __name__ == "__main__":
    main()
