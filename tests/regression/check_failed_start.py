#!/usr/bin/env python3
"""A mechanism run that fails after its modes, before its integration (issue 24; docs/faults.md
"Faults: two runs on one output, a full disk, signals, restart"): the joints of
tests/data/faults/failed_start.nml close only by deforming the link 5.6 m, which the assembly
refuses (docs/mechanisms.md "Starting pose").

Reference: what the docs promise, checked on the file itself: a non-zero exit with one
`ffrf: error:` line naming the assembly; the results file in place (no `.part` left) with status
`error: ...` carrying the same message, the input echo, and the link's modes, whose frequencies
are those of a second run of the same body in a modal case (the same mesh and `&body`, through
`--set` nothing else changes: the modes of a failed start are the modes a modal run computes,
to 1e-9 relative), and no motion (/time absent or empty).

    check_failed_start.py FFRF CASE MESH_DIR WORK_DIR
"""
import re
import shutil
import subprocess
import sys
from pathlib import Path

import h5py
import numpy as np


def fail(message):
    print('FAIL: ' + message)
    sys.exit(1)


def main():
    ffrf, case, mesh_dir, work = sys.argv[1], Path(sys.argv[2]), sys.argv[3], Path(sys.argv[4])
    shutil.rmtree(work, ignore_errors=True)
    work.mkdir(parents=True)
    run = subprocess.run([ffrf, str(case), '--mesh-dir', mesh_dir, '--output-dir', str(work)],
                         capture_output=True, text=True)
    last = (run.stderr.strip().splitlines() or [''])[-1]
    print(f'exit {run.returncode}: {last}')
    if run.returncode == 0:
        fail('the run that cannot assemble its start exited 0')
    if not last.startswith('ffrf: error:') or 'close only by deforming body "link"' not in last:
        fail('the last line is not one error line about the deformed starting pose')
    if run.returncode != 2:
        fail(f'exit {run.returncode}, expected 2 (an input error: the geometry)')
    results = work / (case.stem + '.h5')
    if not results.is_file():
        fail(f'no results file {results} after a failure that followed the modes')
    if list(work.glob('*.part')):
        fail('a .part file is left')
    with h5py.File(results, 'r') as h5:
        status = h5.attrs['status']
        status = status.decode() if isinstance(status, bytes) else str(status)
        print(f'status: {status[:160]}')
        if not status.startswith('error: ') or 'close only by deforming' not in status:
            fail('status is not "error: ..." with the run\'s message')
        echo = h5['input/namelist'][()]
        echo = echo.decode() if isinstance(echo, bytes) else str(echo)
        if "name = 'hold'" not in echo.replace('"', "'"):
            fail('the input echo lacks the case\'s joints')
        freq = h5['bodies/link/modes/frequency'][()]
        steps = h5['time/t'].shape[0] if 'time/t' in h5 else 0
    print(f'modes of the link: {np.array2string(freq, precision=6)} Hz; time steps: {steps}')
    if steps != 0:
        fail('a failed start recorded motion')
    # the second method: the same body in a modal case (no joints) computes the same modes
    text = case.read_text()
    modal = re.sub(r'^&(marker|joint|integrator).*?/\s*$', '', text, flags=re.M | re.S)
    modal_case = work / 'link_modes.nml'
    modal_case.write_text(modal)
    done = subprocess.run([ffrf, str(modal_case), '--mesh-dir', mesh_dir, '--output-dir',
                           str(work)], capture_output=True, text=True)
    if done.returncode != 0:
        fail('the modal run of the same body failed: ' + done.stderr[-500:])
    with h5py.File(work / 'link_modes.h5', 'r') as h5:
        ref = h5['bodies/link/modes/frequency'][()]
    err = np.max(np.abs(freq - ref) / ref)
    print(f'against the modal run: {np.array2string(ref, precision=6)} Hz, max relative '
          f'difference {err:.2e} (tolerance 1e-9)')
    if freq.shape != ref.shape or not err <= 1e-9:
        fail('the failed start\'s modes differ from the modal run\'s')
    print('ok')


main()
