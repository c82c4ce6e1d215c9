#!/usr/bin/env python3
"""MPI tests of the sequential build's ctest (tests/mpi/mpi.cmake), run against the MPI build
that the fixture mpi_build made (build_mpi.py). Exit 77 (ctest SKIP_RETURN_CODE) with
"skipped: <why>" when that build was skipped (no MPI or no MPI MUMPS on this machine).

  modes:  the sequential driver and `mpirun -np RANKS` MPI driver on the same modal case;
          every body's frequencies must agree to --rtol (relative); the MPI results file must
          hold /timings/peak_memory_mib_per_rank with one value per rank.
  engine: the same for a mechanism case: the crank angle and speed histories must agree to
          --rtol (relative to the largest |value|), and only rank 0 writes files.
  host:   `mpirun -np 3 mpi_host_program CASE MESH_DIR OUT [ENGINE]`: groups of 2 and 1 ranks run
          the case on their own communicators; both groups' frequencies against the sequential
          driver's; with --engine both groups' final time, crank angle and speed of the mechanism
          advanced through the C API in two halves against the driver's last step (--rtol of
          the value).
  ranks:  issue 27, PARPACK: the sequential driver and `mpirun -np RANKS` (--debug) on a modal
          case with the ARPACK eigensolver: the log says PARPACK ran on RANKS ranks with each
          rank's block of rows; frequencies agree to --rtol, mode shapes (up to sign) to
          --shape-rtol of their largest component.
"""
import argparse
import re
import os
import shutil
import subprocess
import sys

SKIP = 77


def mpirun_prefix(a, ranks):
    info = {}
    if a.mpi_build:
        with open(os.path.join(a.mpi_build, 'mpi_build_status.txt')) as f:
            for line in f:
                key, _, value = line.strip().partition('=')
                info[key] = value
    else:   # inside the MPI build's own ctest (tests/mpi/CMakeLists.txt)
        info = dict(status='built', mpirun=a.mpirun, driver=a.mpi_driver,
                    host_program=a.host_program)
    if info.get('status') != 'built':
        print(f"skipped: {info.get('reason', 'the MPI build was not made')}")
        sys.exit(SKIP)
    cmd = [info['mpirun'], '-np', str(ranks), '--oversubscribe']
    if os.geteuid() == 0:
        cmd.append('--allow-run-as-root')
    return cmd, info


def run(cmd, env=None, cwd=None):
    print('+ ' + ' '.join(cmd), flush=True)
    done = subprocess.run(cmd, env=env, cwd=cwd, capture_output=True, text=True)
    sys.stdout.write(done.stdout[-4000:])
    sys.stderr.write(done.stderr[-4000:])
    if done.returncode != 0:
        print(f'FAIL: exit code {done.returncode}')
        sys.exit(1)
    return done


def check_sturm(seq_h5, mpi_h5, failures):
    """The completeness proof (issue 22) holds under MPI too: status 'proven', the same count
    and shift as the sequential run's (the inertia is global: INFOG(12))."""
    import h5py
    with h5py.File(seq_h5, 'r') as f, h5py.File(mpi_h5, 'r') as g:
        for body in f['/bodies']:
            path = f'/bodies/{body}/modes/sturm_check'
            if path not in f:
                continue
            if path not in g:
                failures.append(f'{body}: no sturm_check in the MPI results')
                continue
            seq = (f[path].attrs['status'], int(f[path + '/count'][()]))
            par = (g[path].attrs['status'], int(g[path + '/count'][()]))
            print(f'{body}: Sturm check sequential {seq}, MPI {par}, shifts '
                  f'{f[path + "/shift_hz"][()]:.6f} / {g[path + "/shift_hz"][()]:.6f} Hz')
            if par[0] != b'proven' or par[1] != seq[1]:
                failures.append(f'{body}: Sturm check MPI {par} against sequential {seq}')


def frequencies(h5_file, dataset='frequency'):
    """Each body's modes/<dataset> (frequency, or shape: one row per mode)."""
    import h5py
    out = {}
    with h5py.File(h5_file, 'r') as f:
        for body in f['/bodies']:
            if 'modes' in f[f'/bodies/{body}']:
                out[body] = f[f'/bodies/{body}/modes/{dataset}'][()]
    return out


def frequency_differences(seq_h5, mpi_h5, failures):
    """body -> (sequential frequencies, largest relative difference of the MPI run's); a body
    without the same number of modes in the MPI results is a failure."""
    reference, result = frequencies(seq_h5), frequencies(mpi_h5)
    out = {}
    for body, y in reference.items():
        x = result.get(body)
        if x is None or len(x) != len(y):
            failures.append(f'{body}: no or other modes in the MPI results')
            continue
        out[body] = (y, max(abs(x - y) / abs(y)))
    return out


def available_mb():
    """MemAvailable of /proc/meminfo in MB (the automatic memory limit's source)."""
    with open('/proc/meminfo') as f:
        for line in f:
            if line.startswith('MemAvailable:'):
                return int(line.split()[1]) / 1024.0
    return None


def check_node_share(log, available, ranks, failures):
    """The automatic memory limit of a rank is its resident memory + MemAvailable shared by the
    ranks of the node (all `ranks` here): (limit - resident) / MemAvailable near 1 / ranks, not 1
    (MemAvailable moves with the other tests running: +-40 % of the share accepted)."""
    found = re.search(r'([0-9]+) MB resident .*limit ([0-9]+) MB', log)
    if not found or not available:
        failures.append('no "N MB resident ... limit N MB" line in the MPI log, or no MemAvailable')
        return
    share = (int(found.group(2)) - int(found.group(1))) / available
    print(f'automatic memory limit on {ranks} ranks of one node: {share:.3f} of MemAvailable '
          f'({available:.0f} MB) beside the resident memory (expected {1.0 / ranks:.3f})')
    if not 0.6 / ranks < share < 1.4 / ranks:
        failures.append(f'automatic limit takes {share:.3f} of MemAvailable on each of {ranks} '
                        f'ranks, expected about {1.0 / ranks:.3f}')


def check_parpack_run(a, log, seq_h5, mpi_h5, failures):
    """PARPACK ran on a.ranks ranks (the debug line of rank 0, rows 1..n / ranks), and the
    frequencies and shapes equal the sequential ARPACK run's."""
    found = re.search(r'PARPACK on ([0-9]+) rank\(s\): rows 1\.\.([0-9]+) of ([0-9]+)', log)
    if not found or int(found.group(1)) != a.ranks or \
            int(found.group(2)) != int(found.group(3)) // a.ranks:
        failures.append(f'no "PARPACK on {a.ranks} rank(s): rows 1..n/{a.ranks}" in the log')
    else:
        print(f'PARPACK on {a.ranks} rank(s): rank 0 holds rows 1..{found.group(2)} of '
              f'{found.group(3)}')
    ref_shapes, mpi_shapes = frequencies(seq_h5, 'shape'), frequencies(mpi_h5, 'shape')
    for body, (y, diff) in frequency_differences(seq_h5, mpi_h5, failures).items():
        X, Y = mpi_shapes[body], ref_shapes[body]
        shape_diff = max(min(abs(X[j] - Y[j]).max(), abs(X[j] + Y[j]).max()) / abs(Y[j]).max()
                         for j in range(len(Y)))
        print(f'{body}: {len(y)} modes {y[0]:.6f} .. {y[-1]:.6f} Hz, {a.ranks} ranks against '
              f'the sequential run: frequencies {diff:.3g} (tolerance {a.rtol:g}), shapes '
              f'{shape_diff:.3g} of their largest component (tolerance {a.shape_rtol:g})')
        if diff > a.rtol:
            failures.append(f'{body}: frequencies differ by {diff:.3g} > {a.rtol:g}')
        if shape_diff > a.shape_rtol:
            failures.append(f'{body}: shapes differ by {shape_diff:.3g} > {a.shape_rtol:g}')


def check_signal_stop(cmd, env, out_dir, failures):
    """SIGUSR1 to mpirun (which forwards it to the ranks; SIGTERM would make mpirun end the job
    itself) once the block eigen loop has started: the ranks stop together between two block
    solves, exit 5 through mpirun, one error line, status 'interrupted: SIGUSR1', the body left
    out of the results file. On the default lc = 6 mm crank: its loop lasts far longer than the
    signal takes to arrive."""
    import signal
    import h5py
    results = os.path.join(out_dir, 'interrupted.h5')
    cmd = cmd + ['--set', 'body[crank].mesh_file=crank.msh', '--output-dir', out_dir,
                 '--output', 'interrupted.h5']
    print('+ ' + ' '.join(cmd) + '   (SIGUSR1 at "block Lanczos: N right-hand sides")', flush=True)
    process = subprocess.Popen(cmd, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                               text=True)
    sent = False
    for line in process.stdout:
        if re.search(r'block Lanczos: [0-9]+ right-hand sides', line):
            process.send_signal(signal.SIGUSR1)
            sent = True
            break
    _, stderr = process.communicate(timeout=600)
    errors = [x for x in stderr.splitlines() if x.startswith('ffrf: error:')]
    print(f'SIGUSR1 in the eigen loop: exit {process.returncode}, error line(s): {errors}')
    if not sent or process.returncode != 5 or len(errors) != 1 or \
            'interrupted by SIGUSR1 in the block eigen loop' not in errors[0]:
        failures.append('SIGUSR1 under mpirun: expected exit 5 and one line "interrupted by '
                        'SIGUSR1 in the block eigen loop"')
        return
    with h5py.File(results, 'r') as f:
        status = f.attrs.get('status', b'').decode()
        bodies = list(f['/bodies']) if '/bodies' in f else []
    print(f'status "{status}", bodies in the file: {bodies}')
    if status != 'interrupted: SIGUSR1' or bodies:
        failures.append(f'SIGUSR1 under mpirun: status "{status}", bodies {bodies}')


def main():
    p = argparse.ArgumentParser()
    p.add_argument('kind', choices=['modes', 'engine', 'host', 'ranks'])
    p.add_argument('--mpi-build', help='the MPI build made by build_mpi.py')
    p.add_argument('--mpirun', help='without --mpi-build: mpirun')
    p.add_argument('--mpi-driver', help='without --mpi-build: the MPI ffrf')
    p.add_argument('--host-program', help='without --mpi-build: mpi_host_program')
    p.add_argument('--driver', required=True,
                   help='the reference ffrf: the sequential build (or the MPI one, one process)')
    p.add_argument('--case', required=True)
    p.add_argument('--mesh-dir', required=True)
    p.add_argument('--out', required=True)
    p.add_argument('--ranks', type=int, default=2)
    p.add_argument('--rtol', type=float, default=1e-9)
    p.add_argument('--shape-rtol', type=float, default=1e-8,
                   help='ranks: mode shapes, of their largest component')
    p.add_argument('--set', action='append', default=[])
    p.add_argument('--engine', help='host: also this mechanism case')
    p.add_argument('--compare-num-modes', type=int, default=0,
                   help='modes: also the MPI run with modes.num_modes = N; its first modes '
                        'must equal this run\'s to --rtol (issue 22: 1..3 modes of a free body '
                        'as with 12)')
    p.add_argument('--signal-check', action='store_true',
                   help='modes with the block eigensolver: also SIGUSR1 inside its eigen loop')
    a = p.parse_args()
    mpirun, info = mpirun_prefix(a, a.ranks)
    env = dict(os.environ, OPENBLAS_NUM_THREADS='1', OMP_NUM_THREADS='1')
    if os.geteuid() == 0:
        env.update(OMPI_ALLOW_RUN_AS_ROOT='1', OMPI_ALLOW_RUN_AS_ROOT_CONFIRM='1')
    shutil.rmtree(a.out, ignore_errors=True)
    seq_dir, mpi_dir = os.path.join(a.out, 'sequential'), os.path.join(a.out, 'mpi')
    os.makedirs(seq_dir)
    os.makedirs(mpi_dir)
    sets = []
    for s in a.set:
        sets += ['--set', s]
    common = [a.case, '--mesh-dir', a.mesh_dir, '--output', 'result.h5'] + sets
    run([a.driver] + common + ['--output-dir', seq_dir], env=env)
    failures = []
    if a.kind == 'ranks':
        done = run(mpirun + [info['driver']] + common + ['--output-dir', mpi_dir, '--debug'],
                   env=env)
        check_parpack_run(a, done.stdout, os.path.join(seq_dir, 'result.h5'),
                          os.path.join(mpi_dir, 'result.h5'), failures)
    elif a.kind == 'host':
        engine = [a.engine] if a.engine else []
        run(mpirun + [info['host_program'], a.case, a.mesh_dir, mpi_dir] + engine, env=env)
        if a.engine:
            import h5py
            run([a.driver, a.engine, '--mesh-dir', a.mesh_dir, '--output', 'engine.h5',
                 '--output-dir', seq_dir, '--quiet'], env=env)
            with h5py.File(os.path.join(seq_dir, 'engine.h5'), 'r') as f:
                ref_state = [f['/time/t'][-1], f['/time/crank_angle'][-1],
                             f['/time/crank_speed'][-1]]
            for group in ('group0_engine.txt', 'group1_engine.txt'):
                with open(os.path.join(mpi_dir, group)) as f:
                    state = [float(x) for x in f.read().split()]
                diff = max(abs(x - y) / abs(y) for x, y in zip(state, ref_state))
                print(f'{group}: t, crank angle, speed {state}, largest relative difference '
                      f'from the driver {diff:.3g} (tolerance {a.rtol:g})')
                if diff > a.rtol:
                    failures.append(f'{group}: final state differs by {diff:.3g}')
        reference = frequencies(os.path.join(seq_dir, 'result.h5'))
        ref = [x for body in reference for x in reference[body]]
        for group, ranks in (('group0.txt', 2), ('group1.txt', a.ranks - 2)):
            with open(os.path.join(mpi_dir, group)) as f:
                lines = f.read().split('\n')
            values = [float(x) for x in lines[1:] if x.strip()]
            if lines[0] != f'# ranks {ranks}' or len(values) != len(ref):
                failures.append(f'{group}: header {lines[0]!r}, {len(values)} frequencies, '
                                f'expected ranks {ranks} and {len(ref)}')
                continue
            diff = max(abs(x - y) / abs(y) for x, y in zip(values, ref))
            print(f'{group} ({ranks} ranks): {len(values)} frequencies, largest relative '
                  f'difference from the sequential driver {diff:.3g} (tolerance {a.rtol:g})')
            if diff > a.rtol:
                failures.append(f'{group}: frequencies differ by {diff:.3g}')
    else:
        available = available_mb()
        done = run(mpirun + [info['driver']] + common + ['--output-dir', mpi_dir], env=env)
        if a.kind == 'modes':
            check_node_share(done.stdout, available, a.ranks, failures)
        import h5py
        written = sorted(os.listdir(mpi_dir))
        expected = sorted(os.listdir(seq_dir))
        if written != expected:
            failures.append(f'files written by the MPI run {written}, sequential {expected}: '
                            'results must be written once, by rank 0')
        seq_h5, mpi_h5 = os.path.join(seq_dir, 'result.h5'), os.path.join(mpi_dir, 'result.h5')
        reference, result = frequencies(seq_h5), frequencies(mpi_h5)
        for body, (y, diff) in frequency_differences(seq_h5, mpi_h5, failures).items():
            print(f'{body}: {len(y)} frequencies {y[0]:.6f} .. {y[-1]:.6f} Hz, largest relative '
                  f'difference MPI ({a.ranks} ranks) - sequential {diff:.3g} '
                  f'(tolerance {a.rtol:g})')
            if a.kind == 'modes' and diff > a.rtol:
                failures.append(f'{body}: frequencies differ by {diff:.3g} > {a.rtol:g}')
        if a.kind == 'modes':
            check_sturm(seq_h5, mpi_h5, failures)
        if a.kind == 'modes' and a.compare_num_modes:
            more_dir = os.path.join(a.out, f'mpi_{a.compare_num_modes}')
            os.makedirs(more_dir)
            run(mpirun + [info['driver']] + common +
                ['--set', f'modes.num_modes={a.compare_num_modes}', '--output-dir', more_dir],
                env=env)
            more = frequencies(os.path.join(more_dir, 'result.h5'))
            for body in result:
                x, y = result[body], more[body][:len(result[body])]
                diff = max(abs(x - y) / abs(y))
                print(f'{body}: the {len(x)} modes of this MPI run against the first of '
                      f'{a.compare_num_modes} (MPI): largest relative difference {diff:.3g} '
                      f'(tolerance {a.rtol:g})')
                if diff > a.rtol:
                    failures.append(f'{body}: {len(x)} modes differ from the first of '
                                    f'{a.compare_num_modes} by {diff:.3g}')
        with h5py.File(mpi_h5, 'r') as f:
            status = f.attrs.get('status', b'')
            if a.kind == 'modes':
                peaks = f['/timings/peak_memory_mib_per_rank'][()]
                print(f'peak memory per rank (MiB): {", ".join(f"{x:.1f}" for x in peaks)}')
                if len(peaks) != a.ranks or min(peaks) <= 0:
                    failures.append(f'/timings/peak_memory_mib_per_rank = {peaks}')
                # MUMPS's analysis estimates, which the memory check uses, on the MPI path too
                with h5py.File(seq_h5, 'r') as g:
                    for body in reference:
                        solver = f'/bodies/{body}/modes/solver'
                        entries = f[solver + '/estimated_factor_entries'][()]
                        memory = f[solver + '/estimated_memory_incore_mb'][()]
                        print(f'{body}: MUMPS estimates on {a.ranks} ranks: {entries} factor '
                              f'entries (sequential {g[solver + "/estimated_factor_entries"][()]})'
                              f', {memory} MB in core on the largest rank')
                        if entries <= 0 or memory <= 0:
                            failures.append(f'{body}: no MUMPS estimates in the MPI results')
            else:
                with h5py.File(seq_h5, 'r') as g:
                    for name in ('crank_angle', 'crank_speed'):
                        x, y = f[f'/time/{name}'][()], g[f'/time/{name}'][()]
                        if len(x) != len(y):
                            failures.append(f'{name}: {len(x)} steps, sequential {len(y)}')
                            continue
                        diff = max(abs(x - y)) / max(abs(y))
                        print(f'{name}: {len(y)} steps, largest difference MPI - sequential '
                              f'{diff:.3g} of the largest |value| (tolerance {a.rtol:g})')
                        if diff > a.rtol:
                            failures.append(f'{name} differs by {diff:.3g} > {a.rtol:g}')
            if a.kind == 'modes':
                # a memory limit no run fits: refused before the factorisation on every rank, with
                # the analysis's figure, exit 4 (numerical/resource failure), one error line
                cmd = mpirun + [info['driver']] + common + ['--output-dir', mpi_dir, '--output',
                                                            'refused.h5', '--set',
                                                            'modes.memory_limit_mb=1']
                print('+ ' + ' '.join(cmd), flush=True)
                done = subprocess.run(cmd, env=env, capture_output=True, text=True)
                errors = [x for x in done.stderr.splitlines() if x.startswith('ffrf: error:')]
                print(f'memory_limit_mb = 1: exit {done.returncode}, {len(errors)} error line(s): '
                      f'{errors[0][:300] if errors else done.stderr[-300:]}')
                if done.returncode != 4 or len(errors) != 1 or not re.search(
                        r'would not fit: predicted [0-9]+ MB \(MUMPS analysis: [1-9][0-9]* MB',
                        errors[0]):
                    failures.append('memory_limit_mb = 1 under MPI: expected exit 4 and one line '
                                    'with the predicted figure')
                if a.signal_check:
                    check_signal_stop(mpirun + [info['driver']] + common, env, mpi_dir, failures)
    for f in failures:
        print('FAIL: ' + f)
    sys.exit(1 if failures else 0)


if __name__ == '__main__':
    main()
