#!/usr/bin/env python3
"""Compares the frequencies a C API program printed ("<body> <mode> <Hz>" lines, '#' comments)
with the driver's results file of the same case (/bodies/<body>/modes/frequency). Both come from
the same library on the same machine, so they agree to round-off: the tolerance is 1e-12
relative. Exit status 1 on any difference, a missing or extra body or mode."""
import argparse
import sys

import h5py
import numpy as np


def read_printed(path):
    bodies = {}
    with open(path) as f:
        for line in f:
            if not line.strip() or line.startswith('#'):
                continue
            name, mode, hz = line.split()
            bodies.setdefault(name, []).append((int(mode), float(hz)))
    return {name: np.array([hz for _, hz in sorted(modes)]) for name, modes in bodies.items()}


def main():
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument('printed', help='text output of the C API program')
    parser.add_argument('results', help="the driver's .h5 results file of the same case")
    parser.add_argument('--rtol', type=float, default=1e-12)
    args = parser.parse_args()
    printed = read_printed(args.printed)
    ok = True
    with h5py.File(args.results, 'r') as f:
        names = sorted(f['bodies'])
        if sorted(printed) != names:
            print(f'bodies differ: printed {sorted(printed)}, results file {names}')
            return 1
        for name in names:
            expected = f[f'bodies/{name}/modes/frequency'][()]
            actual = printed[name]
            if actual.shape != expected.shape:
                print(f'{name}: {actual.size} modes printed, {expected.size} in the results file')
                ok = False
                continue
            error = np.max(np.abs(actual - expected) / np.abs(expected))
            print(f'{name}: {actual.size} modes, {actual[0]:.6f} .. {actual[-1]:.6f} Hz, '
                  f'largest relative difference {error:.3g} (tolerance {args.rtol:g})')
            ok = ok and bool(error <= args.rtol)
    print('check: ' + ('passed' if ok else 'FAILED'))
    return 0 if ok else 1


if __name__ == '__main__':
    sys.exit(main())
