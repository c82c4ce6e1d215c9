#!/usr/bin/env python3
"""Content checks of the postprocess outputs made in the regression tests (not just their exit code).

    check_outputs.py table CSV RESULTS.h5 [BODY]   every frequency cell equals the results file's
                                                  /bodies/<body>/modes/frequency exactly (the
                                                  CSV holds each double's round-trip repr)
    check_outputs.py png FILE [FILE ...]          each a PNG (signature, IHDR) of at least 400 x 300
                                                  pixels whose pixels are not all one colour

The reference of the table is the HDF5 file read here with h5py, not through the script's own
reader; a chart is read back with matplotlib's PNG reader.
"""
import csv
import struct
import sys

import h5py
import numpy as np


def check_table(csv_file, results, body=None):
    with h5py.File(results, "r") as f:
        body = body or sorted(f["/bodies"].keys())[0]
        expected = f[f"/bodies/{body}/modes/frequency"][()]
    with open(csv_file, newline="") as f:
        rows = list(csv.reader(f))
    got = [float(row[1]) for row in rows[1:]]
    if len(got) != len(expected):
        sys.exit(f"{csv_file}: {len(got)} frequencies, the results file has {len(expected)}")
    bad = [(k + 1, a, b) for k, (a, b) in enumerate(zip(got, expected)) if a != b]
    if bad:
        sys.exit(f"{csv_file}: mode {bad[0][0]}: {bad[0][1]!r} Hz, results file {bad[0][2]!r} Hz")
    print(f"{csv_file}: {len(got)} frequencies equal the results file's "
          f"({got[0]:.6f} .. {got[-1]:.6f} Hz)")


def check_png(path):
    with open(path, "rb") as f:
        head = f.read(24)
    if head[:8] != b"\x89PNG\r\n\x1a\n" or head[12:16] != b"IHDR":
        sys.exit(f"{path}: not a PNG file")
    width, height = struct.unpack(">II", head[16:24])
    if width < 400 or height < 300:
        sys.exit(f"{path}: {width} x {height} pixels, expected at least 400 x 300")
    import matplotlib.image
    pixels = matplotlib.image.imread(path)
    spread = float(np.ptp(pixels[..., :3]))
    if not spread > 0.1:
        sys.exit(f"{path}: blank image (pixel values spread {spread})")
    print(f"{path}: PNG {width} x {height}, pixel spread {spread:.2f}")


def main(argv):
    if len(argv) >= 4 and argv[1] == "table":
        check_table(*argv[2:5])
    elif len(argv) >= 3 and argv[1] == "png":
        for path in argv[2:]:
            check_png(path)
    else:
        sys.exit(__doc__)


if __name__ == "__main__":
    main(sys.argv)
