"""Gather the results files of a sweep (a job array: one file per task) into one table and one
chart.

One row per file: the file, its status (a failed or interrupted task is listed, not skipped), the
overrides it was run with (the comment lines `! ORIGIN = VALUE` that end /input/namelist: one
column per key, `modes.num_modes`, `interface[B2].rc`, whatever the --set or sweep table named),
the first N natural frequencies of a body and the wall time. CSV keeps full precision (Python's
shortest round-trip repr of each double); Markdown shows 1 decimal. The chart: frequency of
each mode over the files, in the table's order (one line per mode, Hz, log scale).

    ffrf-gather sweep/crank_rc1_*.h5 --csv sweep.csv --markdown sweep.md --chart sweep.png

(ffrf-gather is the console script of `pip install ./postprocess`;
postprocess/gather_results.py runs the same code.)
"""
import argparse
import csv
import os
import re
import sys

import ffrf_results

#: "! --set modes.num_modes = 12", "! table.csv:3 interface[B2].rc = Tx", "! --output = a.h5"
OVERRIDE_LINE = re.compile(r"^! (?:--set (?P<set>\S+)|(?P<table>\S+:\d+) (?P<key>\S+)|"
                           r"(?P<option>--\w+)) = (?P<value>.*)$")


def overrides_of(namelist):
    """{key: value} of the override comment lines of an /input/namelist text (later wins)."""
    found = {}
    for line in namelist.splitlines():
        match = OVERRIDE_LINE.match(line.strip())
        if not match:
            continue
        key = match.group("set") or match.group("key") or match.group("option")
        found[key] = match.group("value")
    return found


def read_row(path, body, num_modes):
    """One table row: file, status, overrides, frequencies (Hz, [] if none), wall time (s)."""
    with ffrf_results.open_results(path, require_complete=False) as results:
        status = results.attribute("status", default="unknown")
        namelist = ""
        if "input/namelist" in results.file:
            namelist = ffrf_results.text(results.file["input/namelist"][()])
        frequencies = []
        if results.bodies() and status == "complete":
            frequencies = list(results.frequencies(results.body(body))[:num_modes])
        wall = results.timings().get("total", float("nan"))
    return {"file": os.path.basename(path), "status": status,
            "overrides": overrides_of(namelist), "frequencies": frequencies, "wall": wall}


def table(rows):
    """Header and cell lists (frequencies as floats) of the rows."""
    keys = []
    for row in rows:
        keys += [k for k in row["overrides"] if k not in keys and k != "--output"]
    num_modes = max((len(r["frequencies"]) for r in rows), default=0)
    header = ["file", "status"] + keys + [f"f{k + 1} [Hz]" for k in range(num_modes)] + \
        ["wall time [s]"]
    cells = []
    for row in rows:
        freqs = row["frequencies"] + [None] * (num_modes - len(row["frequencies"]))
        cells.append([row["file"], row["status"]] + [row["overrides"].get(k, "") for k in keys] +
                     freqs + [row["wall"]])
    return header, cells


def write_csv(path, header, cells):
    with open(path, "w", newline="") as stream:
        writer = csv.writer(stream)
        writer.writerow(header)
        for row in cells:
            writer.writerow(["" if c is None else repr(float(c)) if isinstance(c, float) else c
                             for c in row])


def write_markdown(stream, header, cells):
    stream.write("| " + " | ".join(header) + " |\n")
    stream.write("|" + "|".join("---:" if " [" in h else "---" for h in header) + "|\n")
    for row in cells:
        shown = ["" if c is None else f"{c:.1f}" if isinstance(c, float) else str(c)
                 for c in row]
        stream.write("| " + " | ".join(shown) + " |\n")


def write_chart(path, rows, body):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    num_modes = max((len(r["frequencies"]) for r in rows), default=0)
    fig, ax = plt.subplots(figsize=(max(6.0, 0.5 * len(rows) + 3.0), 4.5))
    x = range(len(rows))
    for k in range(num_modes):
        y = [r["frequencies"][k] if k < len(r["frequencies"]) else float("nan") for r in rows]
        ax.plot(x, y, marker="o", label=f"mode {k + 1}")
    ax.set_xticks(list(x))
    ax.set_xticklabels([os.path.splitext(r["file"])[0] for r in rows], rotation=45,
                       ha="right", fontsize=8)
    ax.set_yscale("log")
    ax.set_ylabel("natural frequency (Hz)")
    ax.set_title(f"Natural frequencies{', body ' + body if body else ''} over the runs")
    ax.grid(True, which="both", alpha=0.3)
    if num_modes:
        ax.legend(fontsize=7, ncol=2)
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("files", nargs="+", help="results files (.h5), one row each")
    parser.add_argument("--body", help="body name (default: the first body of each file)")
    parser.add_argument("--modes", type=int, default=6, help="frequencies per row (6)")
    parser.add_argument("--csv", help="write the CSV table here")
    parser.add_argument("--markdown", help="write the Markdown table here")
    parser.add_argument("--chart", help="write the chart (PNG) here")
    args = parser.parse_args(argv)
    try:
        rows = [read_row(path, args.body, args.modes) for path in args.files]
    except (ffrf_results.ResultsError, OSError) as exc:
        return ffrf_results.command_error("gather_results.py", exc)
    header, cells = table(rows)
    if args.csv:
        write_csv(args.csv, header, cells)
    if args.markdown:
        with open(args.markdown, "w") as stream:
            write_markdown(stream, header, cells)
    if args.chart:
        write_chart(args.chart, rows, args.body)
    if not (args.csv or args.markdown or args.chart):
        write_markdown(sys.stdout, header, cells)
    return 0


if __name__ == "__main__":
    sys.exit(main())
