"""Natural frequencies of one body from several ffrf results files, side by side.

One row per mode number, one column per file (labelled by its RC set and MPC, the attributes
rc_set and mpc of /bodies/<body>/modes, prefixed by the body name when the files hold different
bodies). Writes Markdown (frequencies in Hz, 1 decimal) and/or
CSV (full precision: Python's shortest round-trip repr of each double); with neither option
the Markdown table goes to standard output. A file whose run did not complete is an error.

    ffrf-frequency-table crank_rc1.h5 crank_rc2.h5 crank_rc3.h5 --markdown f.md --csv f.csv

(ffrf-frequency-table is the console script of `pip install ./postprocess`;
postprocess/frequency_table.py runs the same code.)
"""
import argparse
import csv
import os
import sys

import ffrf_results


def column_labels(labels, files):
    """Labels made unique by appending the file name where two coincide."""
    out = []
    for label, path in zip(labels, files):
        if labels.count(label) > 1:
            label = f"{label} ({os.path.basename(path)})"
        out.append(label)
    return out


def read_columns(files, body):
    """Column labels and frequencies; labels name the body when the files hold different ones
    (crank and conrod side by side)."""
    bodies, labels, columns = [], [], []
    for path in files:
        with ffrf_results.open_results(path) as results:
            name = results.body(body)
            bodies.append(name)
            labels.append(results.label(name))
            columns.append(results.frequencies(name))
    if len(set(bodies)) > 1:
        labels = [f"{name}: {label}" for name, label in zip(bodies, labels)]
    return column_labels(labels, files), columns


def write_markdown(stream, labels, columns, body_text):
    num_modes = max((len(c) for c in columns), default=0)
    stream.write(f"Natural frequencies (Hz){body_text}\n\n")
    stream.write("| mode | " + " | ".join(labels) + " |\n")
    stream.write("|---:|" + "---:|" * len(labels) + "\n")
    for k in range(num_modes):
        cells = [f"{c[k]:.1f}" if k < len(c) else "" for c in columns]
        stream.write(f"| {k + 1} | " + " | ".join(cells) + " |\n")


def write_csv(path, labels, columns):
    num_modes = max((len(c) for c in columns), default=0)
    with open(path, "w", newline="") as stream:
        writer = csv.writer(stream)
        writer.writerow(["mode"] + [f"{label} [Hz]" for label in labels])
        for k in range(num_modes):
            writer.writerow([k + 1] + [repr(float(c[k])) if k < len(c) else "" for c in columns])


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("files", nargs="+", help="results files (.h5), one column each")
    parser.add_argument("--body", help="body name (default: the first body of each file)")
    parser.add_argument("--markdown", help="write the Markdown table here")
    parser.add_argument("--csv", help="write the CSV table here")
    args = parser.parse_args(argv)
    try:
        labels, columns = read_columns(args.files, args.body)
    except ffrf_results.ResultsError as exc:
        return ffrf_results.command_error("frequency_table.py", exc)
    body_text = f", body {args.body}" if args.body else ""
    if args.markdown:
        with open(args.markdown, "w") as stream:
            write_markdown(stream, labels, columns, body_text)
    if args.csv:
        write_csv(args.csv, labels, columns)
    if not (args.markdown or args.csv):
        write_markdown(sys.stdout, labels, columns, body_text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
