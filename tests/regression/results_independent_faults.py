#!/usr/bin/env python3
"""The checks of check_results_independent.py can fail: faults planted in copies of the suite's
results files (one per kind of dataset, each far below what a reader would notice and above the
check's stated tolerance) must each be reported, and the unchanged copies must pass.

    results_independent_faults.py MODAL_H5 CB_H5 ENGINE_H5 MESH_DIR WORK_DIR

One process: K and M of each mesh are assembled once for all copies. Exit 1 on any fault not
caught or any clean copy failing.
"""
import os
import shutil
import sys

import h5py

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import check_results_independent as checker  # noqa: E402


def scale(path, index, factor):
    def plant(f):
        f[path][index] = f[path][index] * factor
    return plant


def shift(path, index, delta):
    def plant(f):
        f[path][index] = f[path][index] + delta
    return plant


def main(argv):
    if len(argv) != 6:
        raise SystemExit(__doc__)
    modal, cb, engine, mesh_dir, work = argv[1:]
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    ALL = slice(None)
    # (file, kind, what, plant, the check expected to report it)
    cases = [
        (modal, 'modal', 'virtual-node shapes of B2 x 1.0001',
         lambda f: f['bodies/crank/modes/virtual_node_shape'].__setitem__(
             (ALL, slice(6, 12)), f['bodies/crank/modes/virtual_node_shape'][:, 6:12] * 1.0001),
         '/virtual_node_shape against the fit'),
        (modal, 'modal', 'one frequency x (1 + 1e-9)', scale('bodies/crank/modes/frequency', 3,
                                                             1 + 1e-9), 'Rayleigh quotients'),
        (modal, 'modal', 'one shape entry x 1.001', scale('bodies/crank/modes/shape', (2, 3000),
                                                          1.001), 'Psi M14 Psi^T - I'),
        (modal, 'modal', 'inertia Jxx x (1 + 1e-9)', scale('bodies/crank/mass/inertia', (0, 0),
                                                           1 + 1e-9), '/mass/inertia'),
        (modal, 'modal', 'area of B1 x (1 + 1e-6)', scale('bodies/crank/interfaces/B1/area', (),
                                                          1 + 1e-6), 'B1: /area'),
        (cb, 'craig_bampton', 'first fixed-interface frequency x (1 + 1e-9)',
         scale('bodies/crank/modes/fixed_interface_frequency', 0, 1 + 1e-9),
         '/fixed_interface_frequency'),
        (engine, 'mechanism', 'strain energy of one step x (1 + 1e-9)',
         scale('energy/strain', 500, 1 + 1e-9), '/energy/strain'),
        (engine, 'mechanism', 'kinetic energy at the end x (1 + 1e-12)',
         scale('energy/kinetic', -1, 1 + 1e-12), '/energy/kinetic'),
        (engine, 'mechanism', 'damping dissipation of one step + 1e-6 J',
         shift('energy/damping_dissipation', 600, 1e-6), 'balance D ='),
        (engine, 'mechanism', 'piston pin force on the piston (y) x 1.01',
         scale('joints/piston_pin/reaction', (ALL, 7), 1.01), 'F1 + F2 = 0'),
        (engine, 'mechanism', 'crank angle of one step + 1e-9 rad',
         shift('time/crank_angle', 300, 1e-9), '/time/crank_angle'),
    ]
    problems = []
    for source, kind in ((modal, 'modal'), (cb, 'craig_bampton'), (engine, 'mechanism')):
        failed = checker.check_file(source, mesh_dir, kind)
        ok = not failed
        print(f'{"ok    " if ok else "FAILED"} unchanged {os.path.basename(source)} passes', flush=True)
        if not ok:
            problems.append(f'unchanged {source}')
    for number, (source, kind, what, plant, expected) in enumerate(cases):
        copy = os.path.join(work, f'{number}_{os.path.basename(source)}')
        shutil.copy(source, copy)
        with h5py.File(copy, 'r+') as f:
            plant(f)
        checker.REPORT = False
        failed = checker.check_file(copy, mesh_dir, kind)
        checker.REPORT = True
        caught = any(expected in line for line in failed)
        print(f'{"ok    " if caught else "FAILED"} planted: {what}: '
              + (f'reported by "{expected}" ({len(failed)} checks failed)' if caught else
                 f'not reported by "{expected}" (failed: {failed})'), flush=True)
        if not caught:
            problems.append(what)
    if problems:
        print(f'{len(problems)} problem(s): {problems}')
        sys.exit(1)
    print(f'results_independent_faults: {len(cases)} planted faults reported, 3 clean files pass')


if __name__ == '__main__':
    main(sys.argv)
