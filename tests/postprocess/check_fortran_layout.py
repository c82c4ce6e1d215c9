#!/usr/bin/python3
"""Check what h5py sees of the file test_io_hdf5 writes (test_io_hdf5_layout.h5).

The Fortran array a(i, j) = 10 i + j of shape (2, 3) must read as shape (3, 2) with
A[j-1, i-1] = a(i, j) (HDF5's Fortran API reverses the dimensions); the 2D time series,
Fortran (2 rows, 2 steps), reads as (steps, rows); fixed-length strings and attributes read
as bytes. Every comparison is exact: the bytes are the same.
"""
import argparse
import sys

import h5py
import numpy as np


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("file", help="test_io_hdf5_layout.h5")
    args = parser.parse_args()
    failures = []
    checks = []

    def expect(what, condition):
        print(("ok   " if condition else "FAIL ") + what)
        checks.append(what)
        if not condition:
            failures.append(what)

    with h5py.File(args.file, "r") as f:
        a = f["layout/a"][()]
        reference = np.array([[10.0 * i + j for i in (1, 2)] for j in (1, 2, 3)])
        expect(f"a has h5py shape (3, 2): {a.shape}", a.shape == (3, 2))
        expect("A[j-1, i-1] == 10 i + j", a.shape == (3, 2) and np.array_equal(a, reference))
        expect("units of a == 'm'", f["layout/a"].attrs["units"].decode() == "m")
        tets = f["layout/tets"][()]
        expect(f"tets (4, 2) in Fortran read as (2, 4): {tets.shape}", tets.shape == (2, 4))
        expect("tets rows are the Fortran columns",
               np.array_equal(tets, np.arange(1, 9).reshape(2, 4)))
        names = [s.decode() for s in f["layout/names"][()]]
        expect(f"names == ['B1', 'B2', 'B3']: {names}", names == ["B1", "B2", "B3"])
        series = f["layout/series"][()]
        expect(f"series (steps, rows) == [[1, 2], [3, 4]]: {series.tolist()}",
               np.array_equal(series, [[1.0, 2.0], [3.0, 4.0]]))
        expect("series maxshape (None, 2)", f["layout/series"].maxshape == (None, 2))
        expect("status == 'complete'", f.attrs["status"].decode() == "complete")
    print(f"{len(checks) - len(failures)} passed, {len(failures)} failed")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
