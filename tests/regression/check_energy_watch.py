#!/usr/bin/env python3
"""The energy watch of a mechanism run (issue 30, part 3; src/mbs/energy_watch.f90) read back
with h5py and recomputed independently from the recorded series:

- criterion 1 (energy created), from the end of the first window on: S = -D_s from
  /energy/scheme_dissipation against tolerance x E_ref, E_ref the running maximum of T + U + |W| (no
  modal damping in these cases) from /energy/{kinetic, strain, external_work};
- criterion 2 (strain energy growing unpaid): each flexible body's strain energy recomputed from
  its modal coordinates and frequencies, U_b = 1/2 sum (2 pi f_j)^2 zeta_j^2 (mass-normalised
  modes; not the code's strain energy), its largest value per window (0.1 s unless --window) and
  the largest T per window; warned when the envelope rose in 5 consecutive windows by more than
  4 max(1, (T ratio)^2), the latest envelope above 1e-4 of E_ref.

--expect none: no /warnings, status 'complete', and neither criterion holds anywhere in the
recorded series (the largest S / E_ref and growth ratio are printed: the margins).
--expect created | growth: the first warning is that criterion's, at the time recomputed here
(within one step) and, for growth, naming the body recomputed here; --stopped: the run ended
with status 'error: ... energy watch ...' at that time (energy_watch = 'stop', exit 4 checked by
ctest), else status 'complete' with the warning in /warnings.
"""
import argparse
import sys

import h5py
import numpy as np

GROWTH_WINDOWS = 5
GROWTH_FACTOR = 4.0
GROWTH_FLOOR = 1e-4


def fail(message):
    sys.exit(f"FAIL {message}")


def ok(message):
    print(f"ok   {message}")


def created_time(t, energy, tolerance, window):
    """First time with -D_s > tolerance x running max(T + U + |W|), and the largest ratio."""
    scale = np.maximum.accumulate(energy["kinetic"] + energy["strain"]
                                  + np.abs(energy["external_work"]))
    spurious = -energy["scheme_dissipation"]
    ratio = np.where(scale > 0, spurious / np.where(scale > 0, scale, 1.0), 0.0)
    ratio[t < t[0] + window * (1.0 - 1e-9)] = 0.0  # checked from the end of the first window
    hits = np.nonzero(ratio > tolerance)[0]
    return (t[hits[0]] if hits.size else None), ratio.max()


def growth_time(f, t, kinetic, scale, window):
    """First window close where a flexible body's strain envelope rose GROWTH_WINDOWS times by
    more than GROWTH_FACTOR x max(1, (T ratio)^2); (time, body, largest unpaid growth ratio)."""
    strain = {}
    for name, group in f["bodies"].items():
        if "modal_coordinates" not in group or group["modal_coordinates"].shape[1] == 0:
            continue
        omega = 2.0 * np.pi * group["modes/frequency"][:]
        zeta = group["modal_coordinates"][:]
        strain[name] = 0.5 * (zeta ** 2 * omega ** 2).sum(axis=1)
    # windows as the watch closes them: from the start, closed at the first step t >= start + w
    closes, start = [], t[0]
    for n in range(1, len(t)):
        if t[n] >= start + window * (1.0 - 1e-9):
            closes.append(n)
            start = t[n]
    first, worst, longest = None, 0.0, 0
    for name, u in strain.items():
        env, tenv, lo = [], [], 1
        growing = 0
        for n in closes:
            env.append(u[lo:n + 1].max())
            tenv.append(kinetic[lo:n + 1].max())
            lo = n + 1
            growing = growing + 1 if len(env) >= 2 and env[-1] > env[-2] else 0
            longest = max(longest, growing)
            if (growing >= GROWTH_WINDOWS and len(env) > GROWTH_WINDOWS
                    and env[-1] > GROWTH_FLOOR * scale[n]):
                ratio = env[-1] / env[-1 - GROWTH_WINDOWS]
                paid = max(1.0, (tenv[-1] / tenv[-1 - GROWTH_WINDOWS]) ** 2)
                worst = max(worst, ratio / (GROWTH_FACTOR * paid))
                if ratio > GROWTH_FACTOR * paid:
                    if first is None or t[n] < first[0]:
                        first = (t[n], name)
                    break
    return first, worst, longest


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("results")
    parser.add_argument("--expect", choices=["none", "created", "growth"], required=True)
    parser.add_argument("--tolerance", type=float, default=1e-4)
    parser.add_argument("--window", type=float, default=0.1)
    parser.add_argument("--stopped", action="store_true")
    args = parser.parse_args()
    with h5py.File(args.results, "r") as f:
        status = f.attrs["status"]
        status = status.decode() if isinstance(status, bytes) else str(status)
        t = f["time/t"][:]
        energy = {k: f["energy/" + k][:] for k in f["energy"]}
        h = np.diff(t).max() if len(t) > 1 else 0.0
        t_created, worst_ratio = created_time(t, energy, args.tolerance, args.window)
        scale = np.maximum.accumulate(energy["kinetic"] + energy["strain"]
                                      + np.abs(energy["external_work"]))
        grown, worst_growth, longest = growth_time(f, t, energy["kinetic"], scale, args.window)
        print(f"       recomputed: largest -D_s/E_ref = {worst_ratio:.3g} "
              f"(tolerance {args.tolerance:g}); largest unpaid growth / threshold = "
              f"{worst_growth:.3g}; longest run of rising windows {longest}; energy created at "
              f"{t_created}, growth at {grown}")
        warnings = None
        if "warnings" in f:
            warnings = ([s.decode() if isinstance(s, bytes) else s
                         for s in f["warnings/text"][:]],
                        f["warnings/time"][:],
                        [s.decode() if isinstance(s, bytes) else s
                         for s in f["warnings/body"][:]])
        if args.expect == "none":
            if status != "complete":
                fail(f"status {status!r}, expected 'complete'")
            if warnings is not None:
                fail(f"warnings written: {warnings[0]}")
            if t_created is not None or grown is not None:
                fail(f"recomputed criteria hold (created {t_created}, growth {grown}) but "
                     "the run wrote no warning")
            ok(f"no warning, none recomputed ({len(t)} steps to t = {t[-1]:g} s)")
            return
        expected_t = t_created if args.expect == "created" else (grown[0] if grown else None)
        if expected_t is None:
            fail(f"the recomputed {args.expect} criterion never holds in the series")
        if args.stopped:
            if not status.startswith("error: ") or "energy watch" not in status:
                fail(f"status {status!r}, expected 'error: ... energy watch ...'")
            if abs(t[-1] - expected_t) > 1.5 * h:
                fail(f"run stopped at t = {t[-1]} s, recomputed warning time {expected_t} s")
            ok(f"stopped at t = {t[-1]:.6g} s by the energy watch (recomputed {expected_t:.6g} s)")
            return
        if status != "complete":
            fail(f"status {status!r}, expected 'complete' (a warning does not end the run)")
        if warnings is None:
            fail("no /warnings group")
        text, times, bodies = warnings
        word = "energy created" if args.expect == "created" else "grows without work"
        if word not in text[0]:
            fail(f"first warning is not {args.expect!r}: {text[0]}")
        if abs(times[0] - expected_t) > 1.5 * h:
            fail(f"warning at t = {times[0]} s, recomputed {expected_t} s")
        if args.expect == "growth" and bodies[0] != grown[1]:
            fail(f"warning names body {bodies[0]!r}, recomputed {grown[1]!r}")
        ok(f"warning '{args.expect}' at t = {times[0]:.6g} s, body {bodies[0]!r} "
           f"(recomputed {expected_t:.6g} s); status complete")


if __name__ == "__main__":
    main()
