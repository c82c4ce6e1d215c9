#!/usr/bin/env python3
"""Output rate, peaks, compression, chosen histories and the predicted size (&output, issue 29;
docs/results.md "Output rate, peaks, compression, size").

Usage:
  check_output_rate.py crankless FFRF CASE MESH_DIR WORK [--sample T]
  check_output_rate.py engine FFRF CASE MESH_DIR WORK [--sample T]
  check_output_rate.py free_space FFRF CASE MESH_DIR WORK

crankless (a mechanism without a crank, e.g. input/spatial_pendulum.nml shortened by --set):
  1. the full-rate run has none of the engine's histories (/engine, /time/pressure,
     /time/crank_angle, /time/crank_speed);
  2. a run with every_seconds = T (T a multiple of h: step-aligned samples) holds, at each of its
     sample times, exactly the full-rate run's values (every series), and the last state;
  3. its /peaks/<series>/{min, max, t_min, t_max} equal, per output interval (t_{k-1}, t_k], the
     extremes of the full-rate run's rows in it and the time of the first of each, exactly;
  4. every_steps = T/h gives the same file values as every_seconds = T;
  5. compression = 6 holds the values of the uncompressed file exactly, with shuffle + gzip on
     every series;
  6. a run to a t_end between two samples continued by --restart equals the straight run
     (series and peaks), exactly;
  7. histories = 'energies' writes /time/t and /energy only;
  8. the predicted size in the log is within 10 % of the written file (full rate and decimated),
     and that of the animations within 10 % of the .msh files written.
engine (the lc 8 mm engine, shortened): the full-rate run keeps /engine and /time/pressure; the
  conrod's peak joint force (the largest and smallest of each reaction component over the run)
  from the decimated output equals the full-rate one exactly; the prediction is within 10 %.
free_space: on a 2 MB tmpfs (mount -t tmpfs; root), a run whose predicted results exceed it is
  refused before the integration (exit 3, the figure and the remedies in the message, no file
  left); where mounting is impossible, the same on WORK with a run predicted larger than WORK's
  real free space (said in the output).
"""
import math
import os
import re
import shutil
import subprocess
import sys

import h5py
import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..",
                                "postprocess"))
import ffrf_results  # noqa: E402

FAILURES = []


def check(ok, text):
    print(f"{'ok  ' if ok else 'FAIL'} {text}")
    if not ok:
        FAILURES.append(text)


def run(ffrf, case, mesh_dir, out, sets, extra=(), expect=0):
    os.makedirs(out, exist_ok=True)
    command = [ffrf, case, "--mesh-dir", mesh_dir, "--output-dir", out]
    for item in sets:
        command += ["--set", item]
    command += list(extra)
    proc = subprocess.run(command, capture_output=True, text=True)
    if proc.returncode != expect:
        print(proc.stdout[-3000:], proc.stderr[-3000:])
        raise SystemExit(f"FAIL {' '.join(command)}: exit {proc.returncode}, expected {expect}")
    return proc


def results_path(out, case):
    return os.path.join(out, os.path.splitext(os.path.basename(case))[0] + ".h5")


def series(h5):
    """Every growing series (path -> (steps, ...) array), /peaks apart."""
    found = {}

    def visit(name, obj):
        if isinstance(obj, h5py.Dataset) and obj.maxshape and obj.maxshape[0] is None \
                and not name.startswith("peaks/"):
            found[name] = obj[()]
    h5.visititems(visit)
    return found


def peaks(h5):
    found = {}
    if "peaks" not in h5:
        return found

    def visit(name, obj):
        if isinstance(obj, h5py.Dataset):
            found[name] = obj[()]
    h5["peaks"].visititems(visit)
    return found


def predicted_mb(log):
    match = re.search(r"predicted size: results ([0-9.Ee+-]+) MB", log)
    return float(match.group(1)) if match else math.nan


def check_prediction(what, proc, path):
    predicted = predicted_mb(proc.stdout + proc.stderr) * 1e6
    written = os.path.getsize(path)
    error = abs(predicted - written) / written
    check(error <= 0.10, f"{what}: predicted {predicted / 1e6:.4f} MB, written "
          f"{written / 1e6:.4f} MB ({100 * error:.2f} % <= 10 %)")


def check_decimated(full_path, part_path, what):
    """Items 2 and 3: values at the samples and the peaks per interval, exactly."""
    with h5py.File(full_path) as full, h5py.File(part_path) as part:
        t_full = full["time/t"][()]
        t_part = part["time/t"][()]
        rows = np.searchsorted(t_full, t_part)
        check(np.array_equal(t_full[rows], t_part), f"{what}: {len(t_part)} sample times are "
              f"steps of the full-rate run ({len(t_full)} steps)")
        check(t_part[-1] == t_full[-1], f"{what}: the last state (t = {t_full[-1]}) is written")
        a, b = series(full), series(part)
        check(sorted(a) == sorted(b), f"{what}: the same {len(a)} series")
        same = all(np.array_equal(a[k][rows], b[k]) for k in a if k in b)
        check(same, f"{what}: every series equals the full-rate one at the sample times")
        p = peaks(part)
        bad = []
        counted = 0
        for name, values in a.items():
            if name == "time/t":
                continue
            starts = np.concatenate([[0], rows[:-1] + 1])
            for column, reduce, pick in (("min", np.min, np.argmin), ("max", np.max, np.argmax)):
                stored = p.get(f"{name}/{column}")
                times = p.get(f"{name}/t_{column}")
                if stored is None or times is None:
                    bad.append(f"{name}/{column} missing")
                    continue
                for k, (first, last) in enumerate(zip(starts, rows)):
                    window = values[first:last + 1]
                    extreme = reduce(window, axis=0)
                    at = t_full[first + pick(window, axis=0)]
                    counted += 1
                    if not (np.array_equal(extreme, stored[k]) and np.array_equal(at, times[k])):
                        bad.append(f"{name}/{column} interval {k}")
        check(not bad, f"{what}: {counted} interval extremes and their times equal the "
              f"full-rate rows exactly" + (f" (first bad: {bad[:3]})" if bad else ""))


def same_values(path_a, path_b, what, with_peaks=True):
    with h5py.File(path_a) as a, h5py.File(path_b) as b:
        sa, sb = series(a), series(b)
        same = sorted(sa) == sorted(sb) and all(np.array_equal(sa[k], sb[k]) for k in sa)
        if with_peaks:
            pa, pb = peaks(a), peaks(b)
            same = same and sorted(pa) == sorted(pb) and all(np.array_equal(pa[k], pb[k])
                                                              for k in pa)
        check(same, f"{what}: {len(sa)} series" + (" and their peaks" if with_peaks else "")
              + " equal exactly")


def crankless(ffrf, case, mesh_dir, work, sample, h, t_end):
    base = [f"integrator.t_end={t_end}", f"integrator.h={h}"]
    full = run(ffrf, case, mesh_dir, os.path.join(work, "full"), base)
    full_path = results_path(os.path.join(work, "full"), case)
    with h5py.File(full_path) as f:
        present = [p for p in ("engine", "time/pressure", "time/crank_angle", "time/crank_speed")
                   if p in f]
        check(not present, f"no engine histories without a crank (present: {present})")
    check_prediction("full rate", full, full_path)
    match = re.search(r"animations ([0-9.Ee+-]+) MB", full.stdout + full.stderr)
    animations = sum(os.path.getsize(os.path.join(work, "full", n))
                     for n in os.listdir(os.path.join(work, "full")) if n.endswith("animation.msh"))
    predicted = float(match.group(1)) * 1e6 if match else math.nan
    check(animations > 0 and abs(predicted - animations) <= 0.10 * animations,
          f"animations: predicted {predicted / 1e6:.4f} MB, written {animations / 1e6:.4f} MB "
          f"(within 10 %)")

    seconds = run(ffrf, case, mesh_dir, os.path.join(work, "seconds"),
                  base + [f"output.every_seconds={sample}"])
    seconds_path = results_path(os.path.join(work, "seconds"), case)
    check_decimated(full_path, seconds_path, f"every_seconds = {sample}")
    check_prediction("every_seconds", seconds, seconds_path)

    steps = round(sample / h)
    run(ffrf, case, mesh_dir, os.path.join(work, "steps"),
        base + [f"output.every_steps={steps}"])
    same_values(seconds_path, results_path(os.path.join(work, "steps"), case),
                f"every_steps = {steps} vs every_seconds = {sample}")

    run(ffrf, case, mesh_dir, os.path.join(work, "compressed"),
        base + [f"output.every_seconds={sample}", "output.compression=6"])
    compressed_path = results_path(os.path.join(work, "compressed"), case)
    same_values(seconds_path, compressed_path, "compression = 6 vs none")
    with h5py.File(compressed_path) as f:
        filters = {name: (d.compression, d.shuffle) for name, d in series(f).items()
                   for d in [f[name]]}
        check(all(v == ("gzip", True) for v in filters.values()),
              f"compression = 6: shuffle + gzip on all {len(filters)} series")
    with ffrf_results.Results(compressed_path) as r, h5py.File(seconds_path) as f:
        name = "joints/shoulder/reaction"
        p = r.peaks(name)
        check(r.decimated and p is not None and
              np.array_equal(r.history(name), f[name][()]) and
              np.array_equal(p["max"], f[f"peaks/{name}/max"][()]),
              "ffrf_results reads the compressed, decimated crank-less file (history, peaks)")

    # restart from a run that ends between two samples (its last state forced, then replaced)
    part_dir = os.path.join(work, "restart")
    middle = (math.floor(t_end / 2 / sample) + 0.5) * sample
    run(ffrf, case, mesh_dir, part_dir, [f"integrator.t_end={middle}", f"integrator.h={h}",
                                         f"output.every_seconds={sample}"])
    part_path = results_path(part_dir, case)
    continued = os.path.join(work, "continued")
    run(ffrf, case, mesh_dir, continued, base + [f"output.every_seconds={sample}"],
        extra=["--restart", part_path])
    same_values(seconds_path, results_path(continued, case),
                f"--restart at t = {middle} (between samples) vs the straight run")

    run(ffrf, case, mesh_dir, os.path.join(work, "energies"),
        base + ["output.histories='energies'"])
    with h5py.File(results_path(os.path.join(work, "energies"), case)) as f:
        names = sorted(series(f))
        check(all(n == "time/t" or n.startswith("energy/") for n in names) and
              "time/t" in names and any(n.startswith("energy/") for n in names),
              f"histories = 'energies': only /time/t and /energy ({names})")


def engine(ffrf, case, mesh_dir, work, sample, t_end):
    base = [f"integrator.t_end={t_end}", "mechanism.animation_frames=0"]
    full = run(ffrf, case, mesh_dir, os.path.join(work, "engine_full"), base)
    full_path = results_path(os.path.join(work, "engine_full"), case)
    check_prediction("engine, full rate", full, full_path)
    part = run(ffrf, case, mesh_dir, os.path.join(work, "engine_part"),
               base + [f"output.every_seconds={sample}"])
    part_path = results_path(os.path.join(work, "engine_part"), case)
    check_prediction("engine, every_seconds", part, part_path)
    with h5py.File(full_path) as f, h5py.File(part_path) as p:
        check("engine" in f and "time/pressure" in f and "time/crank_angle" in f,
              "the engine keeps /engine, /time/pressure and the crank series")
        joints = [j for j in f["joints"] if "conrod" in j or "big" in j or "pin" in j]
        check(bool(joints), f"a conrod joint among {list(f['joints'])}")
        for joint in joints:
            reaction = f[f"joints/{joint}/reaction"][()][:, :6]
            high = p[f"peaks/joints/{joint}/reaction/max"][()][:, :6].max(axis=0)
            low = p[f"peaks/joints/{joint}/reaction/min"][()][:, :6].min(axis=0)
            peak = np.abs(reaction).max()
            check(np.array_equal(high, reaction.max(axis=0)) and
                  np.array_equal(low, reaction.min(axis=0)),
                  f"joint '{joint}': peak force and moment components from the decimated "
                  f"output equal the full-rate ones (largest |component| {peak:.6g})")
            sampled = np.abs(p[f"joints/{joint}/reaction"][()][:, :6]).max()
            print(f"     joint '{joint}': the samples alone reach {sampled:.6g} "
                  f"({100 * (1 - sampled / peak):.2f} % below the peak)")
    check_decimated(full_path, part_path, f"engine, every_seconds = {sample}")
    full_run = ffrf_results.read_engine(full_path)
    part_run = ffrf_results.read_engine(part_path)
    rows = np.searchsorted(full_run.t, part_run.t)
    check(np.array_equal(full_run.crank_speed[rows], part_run.crank_speed),
          f"read_engine reads the decimated engine file ({part_run.num_steps} samples of "
          f"{full_run.num_steps} steps)")


def free_space(ffrf, case, mesh_dir, work):
    folder = os.path.join(work, "tmpfs")
    os.makedirs(folder, exist_ok=True)
    mounted = subprocess.run(["mount", "-t", "tmpfs", "-o", "size=2m", "tmpfs", folder],
                             capture_output=True, text=True).returncode == 0
    try:
        if mounted:
            sets = ["integrator.t_end=5.0"]
            where = "a 2 MB tmpfs"
        else:
            print("note: cannot mount a tmpfs here (not root or no CAP_SYS_ADMIN); checking "
                  "against the real free space of the output folder instead")
            sets = ["integrator.t_end=1.0e6", "integrator.max_steps=100000000000"]
            where = "the output folder"
        proc = run(ffrf, case, mesh_dir, folder, sets, expect=3)
        message = proc.stderr
        check("would not fit" in message and "ignore_free_space" in message and
              "every_seconds" in message and " MB" in message,
              f"refused on {where}: exit 3, figure and remedies ({message.strip()[:160]}...)")
        check("[run] t =" not in proc.stdout, "refused before the integration")
        left = [n for n in os.listdir(folder) if n.endswith(".h5") or ".h5." in n]
        check(not [n for n in left if not n.endswith(".lock")],
              f"no results file left ({left})")
    finally:
        if mounted:
            subprocess.run(["umount", folder])


def main():
    mode, ffrf, case, mesh_dir, work = sys.argv[1:6]
    sample = float(sys.argv[sys.argv.index("--sample") + 1]) if "--sample" in sys.argv \
        else 0.005
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    if mode == "crankless":
        crankless(ffrf, case, mesh_dir, work, sample, 5.0e-4, 0.06)
    elif mode == "engine":
        engine(ffrf, case, mesh_dir, work, sample, 0.02)
    else:
        free_space(ffrf, case, mesh_dir, work)
    if FAILURES:
        print(f"{len(FAILURES)} check(s) failed")
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
