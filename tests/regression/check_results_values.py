#!/usr/bin/env python3
"""The value comparison of results_* can fail: faults planted in a copy of a run's files.

    check_results_values.py REFERENCE.json RUN_DIR CASE

RUN_DIR holds the files of CASE written by results_<CASE> (its fixture). Each check copies them,
plants one change and asks results_values.py's comparison whether it passes:
- unchanged files, a mode shape with its sign flipped (with its view), a frequency moved by 0.2
  of its tolerance: pass;
- a frequency moved by 2 tolerances, one shape entry that is not among the stored samples moved
  by 1.1 n tolerances (n entries per mode: the bound of the per-mode sums, which is what a change
  confined to unsampled entries must exceed to be seen), one number of a mode view moved, a NaN
  eigen residual, a residual 100 x its reference, a dataset removed, a dataset added, the status
  attribute changed, the text of a view changed: fail, each with a message naming the entry.
"""
import json
import os
import shutil
import sys
import tempfile

import h5py
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import results_values  # noqa: E402

failures = []


def outcome(label, problems, expect_pass, must_name=None):
    passed = not problems
    named = must_name is None or any(must_name in p for p in problems)
    good = passed == expect_pass and (expect_pass or named)
    print("%s %s: %s" % ("ok  " if good else "FAIL", label,
                         "passes" if passed else "fails: " + problems[0][:160]))
    if not good:
        failures.append(label)


def main(argv):
    reference_path, run_dir, case = argv[1], argv[2], argv[3]
    with open(reference_path) as f:
        reference = json.load(f)
    files = sorted(f for f in os.listdir(run_dir)
                   if f == case + ".h5" or (f.startswith(case + "_") and ".msh" in f))
    h5, view = case + ".h5", case + "_modes.msh"
    body = "bodies/%s" % next(iter(h5py.File(os.path.join(run_dir, h5), "r")["bodies"]))
    frequency_tol = results_values.rule_for(h5 + ":" + body + "/modes/frequency").rtol

    def check(label, plant, expect_pass, must_name=None):
        with tempfile.TemporaryDirectory() as work:
            for name in files:
                shutil.copy(os.path.join(run_dir, name), work)
            plant(work)
            problems, _ = results_values.compare_entries(
                reference, results_values.read_files([os.path.join(work, n) for n in files]))
            outcome(label, problems, expect_pass, must_name)

    def edit(work, path, change):
        with h5py.File(os.path.join(work, h5), "r+") as f:
            f[path][...] = change(np.array(f[path][()]))

    def scale_frequency(factor):
        def plant(work):
            def change(f):
                f[1] *= factor
                return f
            edit(work, body + "/modes/frequency", change)
        return plant

    def flip_mode(work):
        for path in (body + "/modes/shape", body + "/modes/virtual_node_shape"):
            def change(s):
                s[2] = -s[2]
                return s
            edit(work, path, change)
        with open(os.path.join(work, view)) as f:
            lines = f.read().split("\n")
        # the third $NodeData block holds mode 3: negate its values (not its tags)
        starts = [i for i, line in enumerate(lines) if line == "$NodeData"]
        i = starts[2] + 9
        while not lines[i].startswith("$End"):
            tag, *values = lines[i].split()
            lines[i] = tag + " " + " ".join("%.16E" % -float(v) for v in values)
            i += 1
        with open(os.path.join(work, view), "w") as f:
            f.write("\n".join(lines))

    def move_unsampled_entry(work):
        entry = reference[h5 + ":" + body + "/modes/shape"]
        rows = set(entry["rows"])
        k = next(r for r in range(len(rows) + 1, 10 ** 7) if r not in rows)
        # the statistics see one entry once it exceeds n tol (the sums' bound)
        step = 1.1 * entry["shape"][1] * \
            results_values.tolerance(results_values.rule_for(h5 + ":" + body + "/modes/shape"),
                                     entry["scale"])

        def change(s):
            s[0, k] += step
            return s
        edit(work, body + "/modes/shape", change)

    def move_view_number(work):
        with open(os.path.join(work, view)) as f:
            lines = f.read().split("\n")
        i = [j for j, line in enumerate(lines) if line == "$NodeData"][0] + 20
        tag, *values = lines[i].split()
        values[0] = "%.16E" % (float(values[0]) + 1e-3)
        lines[i] = tag + " " + " ".join(values)
        with open(os.path.join(work, view), "w") as f:
            f.write("\n".join(lines))

    def residual(value):
        def plant(work):
            def change(r):
                r[0] = value
                return r
            edit(work, body + "/modes/residual", change)
        return plant

    def remove(work):
        with h5py.File(os.path.join(work, h5), "r+") as f:
            del f[body + "/mass/mass"]

    def add(work):
        with h5py.File(os.path.join(work, h5), "r+") as f:
            f[body + "/mass/extra"] = 1.0

    def change_status(work):
        with h5py.File(os.path.join(work, h5), "r+") as f:
            f.attrs["status"] = "error: planted"

    def retitle_view(work):
        with open(os.path.join(work, view)) as f:
            text = f.read()
        with open(os.path.join(work, view), "w") as f:
            f.write(text.replace('"mode 1:', '"mode one:', 1))

    reference_residual = reference[h5 + ":" + body + "/modes/residual"]["values"][0][0]
    check("unchanged", lambda work: None, True)
    check("mode 3 with its sign flipped (shape, virtual-node shape, view)", flip_mode, True)
    check("frequency 2 moved by 0.2 tolerance", scale_frequency(1 + 0.2 * frequency_tol), True)
    check("frequency 2 moved by 2 tolerances", scale_frequency(1 + 2 * frequency_tol), False,
          "modes/frequency")
    check("one unsampled shape entry moved by 1.1 n tolerances", move_unsampled_entry, False,
          "modes/shape")
    check("one number of a mode view moved by 1e-3", move_view_number, False, "$NodeData[1]")
    check("a NaN eigen residual", residual(np.nan), False, "modes/residual")
    check("an eigen residual 100 x its reference", residual(100 * max(reference_residual, 1e-9)),
          False, "modes/residual")
    check("a dataset removed", remove, False, "mass/mass")
    check("a dataset added", add, False, "mass/extra")
    check("the status attribute changed", change_status, False, "@status")
    check("the text of a view changed", retitle_view, False, "<text without numbers>")
    if failures:
        print("%d of the checks above went wrong: %s" % (len(failures), ", ".join(failures)))
        return 1
    print("the comparison passes what it should and fails every planted fault")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
