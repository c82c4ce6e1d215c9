#!/usr/bin/python3
"""Run postprocess/frequency_table.py on the sample files and check its output.

Reference: the frequencies in the sample files, read here with h5py directly (not through
ffrf_results). The CSV holds each double's shortest round-trip repr, so float(cell) must equal
the stored value exactly. The Markdown must exist and name every column; a failed run must make
the script exit non-zero with the status in its message.
"""
import argparse
import csv
import os
import subprocess
import sys

import h5py


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--script", required=True, help="postprocess/frequency_table.py")
    parser.add_argument("folder", help="folder with the sample files")
    args = parser.parse_args()
    checks, failures = [], []

    def expect(what, condition):
        print(("ok   " if condition else "FAIL ") + what)
        checks.append(what)
        if not condition:
            failures.append(what)

    files = [os.path.join(args.folder, f"sample_rc{k}.h5") for k in (1, 2, 3)]
    csv_path = os.path.join(args.folder, "frequencies.csv")
    md_path = os.path.join(args.folder, "frequencies.md")
    for path in (csv_path, md_path):
        if os.path.exists(path):
            os.remove(path)
    run = subprocess.run([sys.executable, args.script, *files, "--csv", csv_path,
                          "--markdown", md_path], capture_output=True, text=True)
    expect(f"frequency_table.py exits 0 (stderr: {run.stderr.strip()})", run.returncode == 0)
    expect("CSV and Markdown exist", os.path.isfile(csv_path) and os.path.isfile(md_path))
    if failures:
        print(f"{len(checks) - len(failures)} passed, {len(failures)} failed")
        return 1

    stored = []
    for path in files:
        with h5py.File(path, "r") as f:
            stored.append(f["/bodies/box/modes/frequency"][()])
    with open(csv_path, newline="") as stream:
        rows = list(csv.reader(stream))
    expect(f"CSV header {rows[0]}",
           rows[0] == ["mode"] + [f"RC set {k}, RBE3 [Hz]" for k in (1, 2, 3)])
    expect(f"CSV has one row per mode ({len(rows) - 1})", len(rows) - 1 == len(stored[0]))
    mismatches = [(r, c) for r, row in enumerate(rows[1:]) for c, cell in enumerate(row[1:])
                  if float(cell) != stored[c][r]]
    expect(f"every CSV number equals the stored frequency exactly ({mismatches})",
           not mismatches)
    expect("CSV mode numbers 1..n", [row[0] for row in rows[1:]] ==
           [str(k + 1) for k in range(len(stored[0]))])
    with open(md_path) as stream:
        markdown = stream.read()
    expect("Markdown names the three RC sets and shows 812.4",
           all(f"RC set {k}, RBE3" in markdown for k in (1, 2, 3)) and "| 812.4 |" in markdown)

    failed = subprocess.run([sys.executable, args.script,
                             os.path.join(args.folder, "sample_failed.h5")],
                            capture_output=True, text=True)
    expect(f"a failed run gives a non-zero exit and its status: {failed.stderr.strip()}",
           failed.returncode != 0 and "ARPACK did not converge" in failed.stderr)
    print(f"{len(checks) - len(failures)} passed, {len(failures)} failed")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
