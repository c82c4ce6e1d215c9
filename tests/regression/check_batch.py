#!/usr/bin/env python3
"""Batch command line of the ffrf driver on the small crank (lc = 8 mm, RC set 2), checked against
independent references:
  --set modes.num_modes=4: 4 frequencies, the lowest 4 of the 8-mode run (same eigenproblem);
  --set interface[B2].rc=...: bitwise the frequencies of the case file edited to that value, and
    each frequency at least that of the less constrained run (Rayleigh's theorem of constraint:
    fixing more dofs raises every eigenvalue), the lowest strictly;
  --sweep TABLE --task 1 / SLURM_ARRAY_TASK_ID=2: bitwise the equivalent --set runs, written to
    the --output '{case}_{task}.h5' names;
  the overrides in the results' /input/namelist, gathered by postprocess/gather_results.py into
    one CSV (override columns, frequencies bitwise the files') and a chart (a real PNG); --threads 2 reported by OpenBLAS itself and the
  frequencies of the 1-thread run within 1e-9; --print-input and --version exit 0 and write
  nothing."""
import argparse
import csv
import os
import re
import subprocess
import sys

import h5py
import numpy as np


def run(args, env_extra=None, expect_files=(), stdin=None):
    env = dict(os.environ)
    for name in ("SLURM_ARRAY_TASK_ID", "PBS_ARRAY_INDEX", "LSB_JOBINDEX"):
        env.pop(name, None)
    env.setdefault("OPENBLAS_NUM_THREADS", "1")
    env.update(env_extra or {})
    done = subprocess.run(args, env=env, capture_output=True, text=True, timeout=120,
                          input=stdin)
    if done.returncode != 0:
        sys.exit(f"FAIL {' '.join(args)}: exit {done.returncode}\n{done.stdout}\n{done.stderr}")
    for name in expect_files:
        if not os.path.isfile(name):
            sys.exit(f"FAIL {' '.join(args)}: {name} not written")
    return done.stdout


def frequencies(path):
    with h5py.File(path, "r") as h5:
        return np.array(h5["bodies/crank/modes/frequency"][()])


def echo(path):
    with h5py.File(path, "r") as h5:
        text = h5["input/namelist"][()]
        if hasattr(text, "__len__") and not isinstance(text, (bytes, str)):
            text = text[0]
        return text.decode() if isinstance(text, bytes) else str(text)


def ok(what, condition, detail=""):
    if not condition:
        sys.exit(f"FAIL {what} {detail}")
    print(f"ok   {what} {detail}")


def main():
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("ffrf")
    parser.add_argument("case")
    parser.add_argument("mesh_dir")
    parser.add_argument("work_dir")
    a = parser.parse_args()
    os.makedirs(a.work_dir, exist_ok=True)
    os.chdir(a.work_dir)
    for name in os.listdir("."):
        if name.endswith((".h5", ".msh", ".csv", ".nml")):
            os.remove(name)
    stem = os.path.splitext(os.path.basename(a.case))[0]
    ffrf = [a.ffrf, a.case, "--mesh-dir", a.mesh_dir, "--quiet"]

    run(ffrf + ["--output", "base.h5"], expect_files=["base.h5", "base_modes.msh"])
    f0 = frequencies("base.h5")
    ok("base run: 8 frequencies", f0.size == 8, f"{f0}")

    run(ffrf + ["--set", "modes.num_modes=4", "--output", "n4.h5"], expect_files=["n4.h5"])
    f4 = frequencies("n4.h5")
    rel = np.max(np.abs(f4 - f0[:4]) / f0[:4]) if f4.size == 4 else np.inf
    # the same eigenproblem, Lanczos converged to 1e-9 (&modes tolerance) in both: measured 0
    ok("--set modes.num_modes=4: 4 frequencies, the lowest 4 of the 8", f4.size == 4 and
       rel <= 1e-8, f"max rel diff {rel:.2e} (tol 1e-8)")
    text = echo("n4.h5")
    ok("overrides in /input/namelist", "num_modes = 4," in text and
       "! --set modes.num_modes = 4" in text)
    ok("mode shapes named after --output", os.path.isfile("n4_modes.msh"))

    rc = "Tx Ty Tz"
    run(ffrf + ["--set", f"interface[B2].rc={rc}", "--output", "rc.h5"])
    frc = frequencies("rc.h5")
    with open(a.case) as source:
        case_text = source.read()
    edited, count = re.subn(r"(name = 'B2', mpc = 'RBE3', rc = )'Tx'", rf"\1'{rc}'", case_text)
    ok("case file edited (B2 rc)", count == 1)
    with open(f"{stem}_edited.nml", "w") as out:
        out.write(edited)
    run([a.ffrf, f"{stem}_edited.nml", "--mesh-dir", a.mesh_dir, "--quiet", "--output",
         "edited.h5"])
    fed = frequencies("edited.h5")
    ok("--set interface[B2].rc bitwise the edited case file", np.array_equal(frc, fed),
       f"{frc} vs {fed}")
    ok("more RC dofs raise every frequency (constraint theorem)",
       np.all(frc >= f0 * (1 - 1e-9)) and frc[0] > f0[0] * (1 + 1e-3),
       f"{frc / f0}")

    with open("table.csv", "w") as out:
        out.write("# sweep of the regression crank\n")
        out.write("modes.num_modes,interface[B2].rc\n")
        out.write("4,Tx\n")
        out.write(f"8,{rc}\n")
    name1, name2 = f"{stem}_1.h5", f"{stem}_2.h5"
    template = "{case}_{task}.h5"
    run(ffrf + ["--sweep", "table.csv", "--task", "1", "--output", template],
        expect_files=[name1, f"{stem}_1_modes.msh"])
    ok("--sweep row 1 (--task 1) bitwise --set modes.num_modes=4",
       np.array_equal(frequencies(name1), f4))
    run(ffrf + ["--sweep", "table.csv", "--output", template],
        env_extra={"SLURM_ARRAY_TASK_ID": "2", "PBS_ARRAY_INDEX": "1"}, expect_files=[name2])
    ok("--sweep row 2 (SLURM_ARRAY_TASK_ID=2, before PBS_ARRAY_INDEX) bitwise --set rc",
       np.array_equal(frequencies(name2), frc))
    ok("sweep origin in /input/namelist", "! table.csv:4 interface[B2].rc = Tx Ty Tz" in
       echo(name2), echo(name2).splitlines()[-2:])

    here = os.path.dirname(os.path.abspath(__file__))
    gather = os.path.join(here, "..", "..", "postprocess", "gather_results.py")
    run([sys.executable, gather, "base.h5", name1, name2, "--modes", "8", "--csv", "sweep.csv",
         "--chart", "sweep.png", "--markdown", "sweep.md"])
    with open("sweep.csv", newline="") as stream:
        rows = list(csv.DictReader(stream))
    ok("gathered: 3 rows with the override columns", len(rows) == 3 and
       [r["modes.num_modes"] for r in rows] == ["", "4", "8"] and
       [r["interface[B2].rc"] for r in rows] == ["", "Tx", rc] and
       all(r["status"] == "complete" for r in rows), str(rows[2])[:120])
    got = [float(rows[2][f"f{k + 1} [Hz]"]) for k in range(8)]
    ok("gathered frequencies bitwise the file's", np.array_equal(got, frequencies(name2)))
    ok("gathered row 1: 4 frequencies, the others empty",
       rows[1]["f4 [Hz]"] != "" and rows[1]["f5 [Hz]"] == "")
    sys.path.insert(0, here)
    import check_outputs  # noqa: E402  (the PNG check of the regression plots)
    check_outputs.check_png("sweep.png")
    ok("gathered chart: a PNG", True)

    out = run(ffrf + ["--output", "{case}_{task}.h5", "--print-input"],
              env_extra={"PBS_ARRAY_INDEX": "5"})
    ok("PBS_ARRAY_INDEX gives {task}", f"output = '{stem}_5.h5'" in out)
    out = run(ffrf + ["--output", "{case}_{task}.h5", "--print-input"],
              env_extra={"LSB_JOBINDEX": "6"})
    ok("LSB_JOBINDEX gives {task}", f"output = '{stem}_6.h5'" in out)
    out = run([a.ffrf, "-", "--output", "{case}_{task}.h5", "--task", "3", "--print-input"],
              stdin=case_text)
    ok("{case} of a case on standard input: stdin", "output = 'stdin_3.h5'" in out)
    out = run(ffrf + ["--set", "modes.num_modes=3", "--set", f"interface[B2].rc={rc}",
                      "--print-input"])
    ok("--print-input: the resolved case with the overrides, nothing written",
       "&modes num_modes = 3," in out and f"name = 'B2', mpc = 'RBE3'" in out and
       f"rc = '{rc}' /" in out and not os.path.exists(f"{stem}.h5"))

    out = run([a.ffrf, a.case, "--mesh-dir", a.mesh_dir, "--threads", "2", "--output",
               "t2.h5"], env_extra={"OPENBLAS_NUM_THREADS": "1"})
    ok("--threads 2: OpenBLAS reports 2 threads", "BLAS threads: 2" in out)
    ft = frequencies("t2.h5")
    rel = np.max(np.abs(ft - f0) / f0)
    # threaded BLAS sums in another order; both converged to 1e-9 (&modes tolerance): 4e-13
    ok("--threads 2: frequencies of the 1-thread run", rel <= 1e-9, f"max rel {rel:.2e}")

    out = run([a.ffrf, "--version"])
    ok("--version", re.match(r"ffrf \d+\.\d+\.\d+ ", out) is not None, out.splitlines()[0])


if __name__ == "__main__":
    main()
