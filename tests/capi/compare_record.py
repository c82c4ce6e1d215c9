"""The C API's recorded run against the driver's (issue 11: one integration path).

Runs the ffrf driver on MECHANISM_CASE into OUT_DIR/driver and test_capi_record, which advances
the same case through the C API with an output folder in chunks of CHUNK seconds
(OUT_DIR/chunked), and once only to t_end / 2 before closing it (OUT_DIR/stopped). Checked:
  - the chunked results file and its Gmsh animations equal the driver's bitwise: the SHA-256 of
    every dataset and attribute (tests/regression/bitwise.py digest, which leaves out the
    wall-clock figures: /timings, /build, /integrator/wall_seconds and the time statistics in
    /checkpoint/integrator_reals);
  - the stopped file is complete and readable: status "stopped: ...", and its time series are
    the driver's first rows, bitwise.
Usage: compare_record.py FFRF TEST_CAPI_RECORD MECHANISM_CASE MESH_DIR OUT_DIR CHUNK
"""
import glob
import os
import subprocess
import sys

import h5py
import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', 'regression'))
import bitwise  # noqa: E402
from compare_driver import output_name  # noqa: E402


def run(command, cwd=None):
    print('+', ' '.join(command), flush=True)
    if subprocess.run(command, cwd=cwd).returncode != 0:
        sys.exit(f'{command[0]} failed')


def files(folder, name):
    stem = os.path.splitext(name)[0]
    return [os.path.join(folder, name)] + sorted(glob.glob(os.path.join(folder,
                                                                        stem + '_*.msh')))


def main(ffrf, program, case, mesh_dir, out_dir, chunk):
    ffrf, program, case, mesh_dir, out_dir = map(os.path.abspath, (ffrf, program, case,
                                                                   mesh_dir, out_dir))
    name = output_name(case)
    driver_dir = os.path.join(out_dir, 'driver')
    os.makedirs(driver_dir, exist_ok=True)
    run([ffrf, case, '--mesh-dir', mesh_dir, '--output-dir', driver_dir, '--quiet'])
    run([program, case, mesh_dir, out_dir, chunk, name], cwd=out_dir)
    failures = []

    driver_files = files(driver_dir, name)
    chunked_files = files(os.path.join(out_dir, 'chunked'), name)
    if [os.path.basename(f) for f in driver_files] != [os.path.basename(f) for f in chunked_files]:
        failures.append(f'files differ: {driver_files} vs {chunked_files}')
    # per file, the digest of every dataset and attribute (h5) or of the whole file (msh)
    reference = bitwise.digest(driver_files)
    chunked = bitwise.digest(chunked_files)
    entries = {(f, k): e['sha256'] for f, d in reference.items() for k, e in d.items()}
    got = {(f, k): e['sha256'] for f, d in chunked.items() for k, e in d.items()}
    differ = sorted(k for k in set(entries) | set(got) if entries.get(k) != got.get(k))
    print(f'chunked ({chunk} s) vs driver: {len(entries)} digests of {len(reference)} files, '
          f'{len(differ)} differ')
    if len(entries) < 50:
        failures.append(f'only {len(entries)} digests: nothing compared?')
    failures += [f'chunked differs: {f} {k}' for f, k in differ]

    with h5py.File(driver_files[0], 'r') as d, \
            h5py.File(os.path.join(out_dir, 'stopped', name), 'r') as s:
        status = s.attrs['status']
        status = status.decode() if isinstance(status, bytes) else str(status)
        rows = s['/time/t'].shape[0]
        print(f'stopped: status "{status}", {rows} of {d["/time/t"].shape[0]} rows')
        if not status.startswith('stopped:'):
            failures.append(f'stopped run: status "{status}"')
        if not 1 < rows < d['/time/t'].shape[0]:
            failures.append(f'stopped run: {rows} rows')
        for path in ('/time/t', '/time/crank_angle', '/time/crank_speed'):
            if not np.array_equal(s[path][()], d[path][()][:rows]):
                failures.append(f'stopped run: {path} is not the driver\'s first {rows} rows')
    if failures:
        print('FAILED:\n  ' + '\n  '.join(failures))
        return 1
    print('compare_record: the C API records the driver\'s results')
    return 0


if __name__ == '__main__':
    if len(sys.argv) != 7:
        sys.exit(__doc__)
    sys.exit(main(*sys.argv[1:]))
