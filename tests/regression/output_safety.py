#!/usr/bin/env python3
"""Results files that survive faults (issue 10, parts 1 and 2): runs the ffrf driver on copies of
the engine and crank cases and checks, with h5py, what it leaves behind.

    output_safety.py TEST FFRF MESH_DIR CASE_DIR WORK_DIR

TEST is one of
  concurrent      two runs on one output: the second stops at once (exit 3, one line naming the
                  file and the other run), the first completes and its file reads back complete;
                  the file of an earlier run stays readable until the new run replaces it;
                  --no-overwrite refuses an existing file
  disk_full       a full disk (a 1 or 2 MiB tmpfs when root may mount one, else RLIMIT_FSIZE)
                  for a modal run and an engine run (noticed at the failing write): exit 3, one stderr line naming the file, no
                  signal, no .part file left, nothing reported written that is not complete
  signals         a modal run of two bodies (factors out of core) stopped by SIGTERM inside
                  the first body's eigen solve (after its factorisation; in the block loop) and
                  after the first body: exit 5, status 'interrupted: SIGTERM', the body stopped
                  left out, no out-of-core file left; a mechanism run: SIGTERM during the modes,
                  early and late in the integration, and SIGINT, SIGHUP, SIGUSR1, SIGXCPU once
                  each: exit 5, status 'interrupted: <signal>', /final_state, the file readable
  restart         a run to t1 continued with --restart to t2 equals a run straight to t2 (crank
                  angle and speed to 1e-12, the same steps); kill -9 during a run then --restart
                  from its checkpoint, likewise; a restart from another mechanism is refused
                  (exit 2)
FFRF_TEST_NO_TMPFS=1 in the environment forces the RLIMIT_FSIZE variant of disk_full.
CASE_DIR holds engine_lc8_rc1.nml and engine_lc8_all_rigid.nml (tests/engine of the build);
the crank modal case is made from them. Every check prints what it found; any failure exits 1.
"""
import os
import re
import resource
import shutil
import signal
import subprocess
import sys
import time

import h5py
import numpy as np

FAILURES = []


def check(condition, what):
    print(('ok     ' if condition else 'FAILED ') + what, flush=True)
    if not condition:
        FAILURES.append(what)


def environment():
    env = dict(os.environ, OPENBLAS_NUM_THREADS='1', GFORTRAN_UNBUFFERED_PRECONNECTED='y')
    return env


class Run:
    """One ffrf run in the background, stdout and stderr to files."""

    def __init__(self, args, work, name, preexec=None, env=None):
        self.out_path = os.path.join(work, name + '.out')
        self.err_path = os.path.join(work, name + '.err')
        self.out = open(self.out_path, 'w')
        self.err = open(self.err_path, 'w')
        self.start = time.time()
        self.process = subprocess.Popen(args, stdout=self.out, stderr=self.err,
                                        env=env or environment(), preexec_fn=preexec)

    def wait(self, timeout=600):
        code = self.process.wait(timeout=timeout)
        self.seconds = time.time() - self.start
        self.out.close()
        self.err.close()
        self.stdout = open(self.out_path).read()
        self.stderr = open(self.err_path).read()
        return code

    def wait_for(self, pattern, timeout=300):
        """Wait until stdout matches `pattern` (regex); False if the run ended first."""
        end = time.time() + timeout
        while time.time() < end:
            if re.search(pattern, open(self.out_path).read()):
                return True
            if self.process.poll() is not None:
                return False
            time.sleep(0.02)
        return False


def one_error_line(stderr, must_contain):
    lines = stderr.splitlines()
    return (len(lines) == 1 and lines[0].startswith('ffrf: error: ') and
            all(text in lines[0] for text in must_contain) and
            'Program received signal' not in stderr and 'Backtrace' not in stderr)


def status_of(path):
    with h5py.File(path, 'r') as f:
        return f.attrs['status'].decode()


def make_case(source, target, replacements):
    text = open(source).read()
    for old, new in replacements:
        if old not in text:
            raise SystemExit(f'{source}: "{old}" not found')
        text = text.replace(old, new, 1)
    with open(target, 'w') as f:
        f.write(text)
    return target


def ffrf_args(ffrf, case, mesh_dir, out_dir, *more):
    return [ffrf, case, '--mesh-dir', mesh_dir, '--output-dir', out_dir, *more]


# ------------------------------------------------------------------------------ concurrent

def test_concurrent(ffrf, mesh_dir, case_dir, work):
    case = make_case(os.path.join(case_dir, 'engine_lc8_all_rigid.nml'),
                     os.path.join(work, 'rigid.nml'),
                     [('t_end = 0.3', 't_end = 2.0'), ('label =', 'progress_interval = 0.01, label =')])
    out = os.path.join(work, 'out')
    os.makedirs(out, exist_ok=True)
    results = os.path.join(out, 'rigid.h5')
    for locking in ('TRUE', 'FALSE'):
        for name in os.listdir(out):
            os.remove(os.path.join(out, name))
        env = dict(environment(), HDF5_USE_FILE_LOCKING=locking)
        first = Run(ffrf_args(ffrf, case, mesh_dir, out), work, 'first', env=env)
        check(first.wait_for(r'\[run\] t = '), f'HDF5_USE_FILE_LOCKING={locking}: first run integrating')
        second = Run(ffrf_args(ffrf, case, mesh_dir, out), work, 'second', env=env)
        code = second.wait(timeout=60)
        first_running = first.process.poll() is None
        check(code == 3, f'second run exits 3 (got {code})')
        check(first_running, f'second run stopped at once, while the first still runs ({second.seconds:.2f} s)')
        check(one_error_line(second.stderr, [results, 'another ffrf run']),
              f'second run: one line naming the file and the other run: {second.stderr.strip()}')
        check('[modes]' not in second.stdout and '[run]' not in second.stdout,
              'second run computed nothing')
        code = first.wait()
        check(code == 0, f'first run exits 0 (got {code}): {first.stderr.strip()}')
        check(status_of(results) == 'complete', 'first run\'s file reads back with status complete')
        with h5py.File(results, 'r') as f:
            t = f['/time/t'][()]
            check(len(t) == 20001 and abs(t[-1] - 2.0) < 1e-9, f'first run\'s file holds its 20001 steps ({len(t)})')
        check(not os.path.exists(results + '.part') and not os.path.exists(results + '.lock'),
              'no .part or .lock file left')

    # An existing complete file stays readable (and unchanged) until the new run replaces it
    before = os.stat(results).st_mtime_ns
    again = Run(ffrf_args(ffrf, case, mesh_dir, out), work, 'again')
    check(again.wait_for(r't = 1\.\d* s'), 'replacing run integrating')
    check(status_of(results) == 'complete' and os.stat(results).st_mtime_ns == before,
          'the earlier file is intact while the new run writes rigid.h5.part')
    code = again.wait()
    check(code == 0 and status_of(results) == 'complete' and os.stat(results).st_mtime_ns != before,
          'replaced by the new run when it finished')

    # --no-overwrite
    refused = Run(ffrf_args(ffrf, case, mesh_dir, out, '--no-overwrite'), work, 'refused')
    code = refused.wait(timeout=60)
    check(code == 3 and one_error_line(refused.stderr, [results, '--no-overwrite']),
          f'--no-overwrite on an existing file: exit 3 with one line ({code}: {refused.stderr.strip()})')
    check(status_of(results) == 'complete', 'the existing file is untouched')


# ------------------------------------------------------------------------------ full disk

def small_disk(work, name, mib):
    """A folder of `mib` MiB: a tmpfs when mount is permitted (mounted = True), else a plain
    folder (the run is then limited by RLIMIT_FSIZE)."""
    folder = os.path.join(work, name)
    os.makedirs(folder, exist_ok=True)
    if os.geteuid() == 0 and not os.environ.get('FFRF_TEST_NO_TMPFS'):
        result = subprocess.run(['mount', '-t', 'tmpfs', '-o', f'size={mib}m', 'tmpfs', folder],
                                capture_output=True)
        if result.returncode == 0:
            return folder, True
    return folder, False


def release_disk(folder, mounted):
    if mounted:
        subprocess.run(['umount', folder], capture_output=True)


def full_disk_run(ffrf, case, mesh_dir, work, name, results_name, mib, failing_name=None):
    """Run `case` on a disk of `mib` MiB; `failing_name`: the file the error names (default
    the results file), which must not be left in place."""
    folder, mounted = small_disk(work, name, mib)
    how = f'a {mib} MiB tmpfs' if mounted else f'RLIMIT_FSIZE = {mib} MiB'

    def limit_file_size():
        resource.setrlimit(resource.RLIMIT_FSIZE, (mib << 20, resource.RLIM_INFINITY))

    try:
        run = Run(ffrf_args(ffrf, case, mesh_dir, folder), work, name,
                  preexec=None if mounted else limit_file_size)
        code = run.wait()
        results = os.path.join(folder, results_name)
        check(code == 3, f'{name} ({how}): exit 3 (got {code}, a signal if negative)')
        failing = os.path.join(folder, failing_name or results_name)
        check(one_error_line(run.stderr, [failing]),
              f'{name}: one stderr line naming {failing}: {run.stderr.strip()}')
        check('results written' not in run.stdout, f'{name}: no results reported written')
        for line in run.stdout.splitlines():
            m = re.search(r'written: (\S+)$', line)
            if m:
                check(os.path.exists(m.group(1)), f'{name}: reported {m.group(1)} exists')
        left = [f for f in os.listdir(folder) if f.endswith('.part')]
        check(not left, f'{name}: no .part file left ({left})')
        if failing_name:
            check(not os.path.exists(failing), f'{name}: no cut-short {failing_name} in place')
        if os.path.exists(results):
            status = status_of(results)
            check(status.startswith('error: '), f'{name}: the file left reads back with status error ({status[:60]})')
    finally:
        release_disk(folder, mounted)


def test_disk_full(ffrf, mesh_dir, case_dir, work):
    modal = os.path.join(work, 'crank_modal.nml')
    with open(modal, 'w') as f:
        f.write("&run title = 'crank lc8, full disk' /\n"
                "&body name = 'crank', mesh_file = 'crank_lc8.msh', volumes = 'crank',\n"
                "      young = 210.0e9, poisson = 0.3, density = 7850.0 /\n"
                "&interface body = 'crank', name = 'B1', mpc = 'RBE3', rc = 'Tx Ty Tz' /\n"
                "&interface body = 'crank', name = 'B2', mpc = 'RBE3', rc = '' /\n"
                "&interface body = 'crank', name = 'B3', mpc = 'RBE3', rc = 'Tx Ty Tz Rz' /\n"
                "&modes num_modes = 12 /\n")
    full_disk_run(ffrf, modal, mesh_dir, work, 'modal_full', 'crank_modal.h5', 1)
    # room for the HDF5 file (2.9 MB), not for the Gmsh mode file (9.1 MB): its chunked stream
    # writes report ENOSPC / EFBIG; the size check behind them stays for short writes
    full_disk_run(ffrf, modal, mesh_dir, work, 'modal_msh_full', 'crank_modal.h5', 4,
                  'crank_modal_modes.msh')
    engine = make_case(os.path.join(case_dir, 'engine_lc8_rc1.nml'), os.path.join(work, 'engine.nml'),
                       [('t_end = 0.1', 't_end = 0.4')])
    # past the free-space check before the integration (it would refuse this run at once,
    # regression_output_rate_free_space): the disk must fill during the run
    with open(engine, 'a') as f:
        f.write('&output ignore_free_space = .true. /\n')
    # 4 MiB: the file starts with the bodies' mode shapes (2.8 MB, for &body modes_file) and
    # grows by about 1.2 kB per step (7.7 MB at 4000 steps): full about a quarter into the run
    full_disk_run(ffrf, engine, mesh_dir, work, 'engine_full', 'engine.h5', 4)
    # noticed when it happens, not at the end of the integration
    out = open(os.path.join(work, 'engine_full.out')).read()
    steps = [int(s) for s in re.findall(r'\[run\] (\d+) steps,', out)]
    check(bool(steps) and steps[0] < 4000, f'engine_full: stopped at the failing write (step {steps[:1]} of 4000)')


# ------------------------------------------------------------------------------ signals

def interrupted_file(path, name, signal_name):
    status = status_of(path)
    check(status == 'interrupted: ' + signal_name, f'{name}: status "{status}"')
    with h5py.File(path, 'r') as f:
        check('/final_state/t' in f and '/final_state/q' in f, f'{name}: /final_state present')
        t = f['/time/t'][()]
        check(abs(f['/final_state/t'][()][0] - t[-1]) < 1e-12, f'{name}: file readable, last step t = {t[-1]:.4f} s = final_state t')
        return t[-1]


def two_crank_case(path, ooc_folder, mesh='crank_lc8.msh'):
    """A modal case of two bodies (the same crank mesh twice), factors out of core."""
    with open(path, 'w') as f:
        f.write("&run title = 'two cranks' /\n&modes num_modes = 12, out_of_core = .true., "
                f"ooc_tmpdir = '{ooc_folder}' /\n")
        for body in ('crank_a', 'crank_b'):
            f.write(f"&body name = '{body}', mesh_file = '{mesh}', volumes = 'crank',\n"
                    "      young = 210.0e9, poisson = 0.3, density = 7850.0 /\n"
                    f"&interface body = '{body}', name = 'B1', mpc = 'RBE3', rc = 'Tx Ty Tz' /\n"
                    f"&interface body = '{body}', name = 'B2', mpc = 'RBE3', rc = '' /\n"
                    f"&interface body = '{body}', name = 'B3', mpc = 'RBE3', rc = 'Tx Ty Tz Rz' /\n")
    return path


def modal_signal_run(ffrf, mesh_dir, work, name, pattern, more=(),
                     must_say=('interrupted by SIGTERM', 'is left out'), mesh='crank_lc8.msh'):
    """The two-crank modal case, SIGTERM at the first log line matching pattern: exit 5, one
    stderr line saying must_say and naming the file, status 'interrupted: SIGTERM', no
    out-of-core file left; returns the bodies in the results file."""
    ooc = os.path.join(work, name + '_ooc')
    os.makedirs(ooc, exist_ok=True)
    modal = two_crank_case(os.path.join(work, name + '.nml'), ooc, mesh)
    out = os.path.join(work, name + '_out')
    os.makedirs(out, exist_ok=True)
    results = os.path.join(out, name + '.h5')
    run = Run(ffrf_args(ffrf, modal, mesh_dir, out, *more), work, name)
    check(run.wait_for(pattern), f'{name}: reached {pattern}')
    run.process.send_signal(signal.SIGTERM)
    code = run.wait()
    check(code == 5, f'{name}: exit 5 (got {code})')
    check(one_error_line(run.stderr, list(must_say) + [results]),
          f'{name}: one stderr line: {run.stderr.strip()}')
    check(status_of(results) == 'interrupted: SIGTERM', f'{name}: status interrupted: SIGTERM')
    check(os.listdir(ooc) == [], f'{name}: no out-of-core file left: {os.listdir(ooc)}')
    with h5py.File(results, 'r') as f:
        return sorted(f['/bodies'].keys()) if '/bodies' in f else []


def test_signals(ffrf, mesh_dir, case_dir, work):
    # A modal run stops inside a body's eigen solve (after its factorisation, between the
    # solves) and leaves that body out; the bodies done before stay in the file.
    bodies = modal_signal_run(ffrf, mesh_dir, work, 'modal_first', r'\[modes\] crank_a: ')
    check(bodies == [], f'modal run stopped in the first body: no body in the file ({bodies})')
    # (between the bodies or in crank_b's eigen solve, whichever check comes first)
    bodies = modal_signal_run(ffrf, mesh_dir, work, 'modal_second',
                              r'\[modes\] crank_a: mode, frequency',
                              must_say=['interrupted by SIGTERM', 'holds the bodies done'])
    check(bodies == ['crank_a'], f'modal run stopped after the first body: crank_a alone ({bodies})')
    # the signal comes after the factorisation's check: the block loop stops between solves
    # (the default lc = 6 mm crank: its loop lasts about a second, far longer than the signal)
    bodies = modal_signal_run(ffrf, mesh_dir, work, 'modal_block', r'block Lanczos: \d+ right',
                              ['--set', "modes.eigensolver='block'"],
                              ['interrupted by SIGTERM in the block eigen loop', 'is left out'],
                              mesh='crank.msh')
    check(bodies == [], f'modal run stopped in the block eigen loop: no body ({bodies})')

    rigid = make_case(os.path.join(case_dir, 'engine_lc8_all_rigid.nml'), os.path.join(work, 'rigid.nml'),
                      [('t_end = 0.3', 't_end = 2.0'), ('label =', 'progress_interval = 0.01, label =')])
    flexible = make_case(os.path.join(case_dir, 'engine_lc8_rc1.nml'), os.path.join(work, 'flexible.nml'),
                         [('t_end = 0.1', 't_end = 0.5')])
    out = os.path.join(work, 'out')
    os.makedirs(out, exist_ok=True)
    moments = [('SIGTERM', flexible, r'\[modes\]', 'during the modes'),
               ('SIGTERM', rigid, r'\[run\] t = ', 'early in the integration'),
               ('SIGTERM', rigid, r'\[run\] t = 1\.[6-9]', 'late in the integration'),
               ('SIGINT', rigid, r'\[run\] t = 0\.5', 'mid-run'),
               ('SIGHUP', rigid, r'\[run\] t = 0\.5', 'mid-run'),
               ('SIGUSR1', rigid, r'\[run\] t = 0\.5', 'mid-run'),
               ('SIGXCPU', rigid, r'\[run\] t = 0\.5', 'mid-run')]
    for k, (signal_name, case, pattern, when) in enumerate(moments):
        name = f'{signal_name} {when}'
        stem = os.path.splitext(os.path.basename(case))[0]
        results = os.path.join(out, stem + '.h5')
        if os.path.exists(results):
            os.remove(results)
        run = Run(ffrf_args(ffrf, case, mesh_dir, out), work, f'signal{k}')
        check(run.wait_for(pattern), f'{name}: run reached the moment')
        run.process.send_signal(getattr(signal, signal_name))
        code = run.wait()
        check(code == 5, f'{name}: exit 5 (got {code})')
        check(one_error_line(run.stderr, ['interrupted by ' + signal_name, results]),
              f'{name}: one stderr line: {run.stderr.strip()}')
        t = interrupted_file(results, name, signal_name)
        if when == 'during the modes':
            check(t < 0.01, f'{name}: stopped after the first step')
        if when == 'late in the integration':
            check(1.5 < t < 2.0, f'{name}: stopped late ({t:.3f} s)')

    # Ctrl-C pressed twice while the modes are computed (the first waits for the end of a
    # step): the second ends the run at once, by SIGINT; a repeated SIGTERM never does.
    run = Run(ffrf_args(ffrf, flexible, mesh_dir, out), work, 'sigint_twice')
    check(run.wait_for(r'\[mesh\]'), 'SIGINT twice: run reading its meshes')
    run.process.send_signal(signal.SIGINT)
    time.sleep(0.05)
    run.process.send_signal(signal.SIGINT)
    code = run.wait()
    check(code == -signal.SIGINT, f'SIGINT twice: ended by SIGINT at once (got {code})')


# ------------------------------------------------------------------------------ restart

def crank(path):
    with h5py.File(path, 'r') as f:
        return (f['/time/t'][()], f['/time/crank_angle'][()], f['/time/crank_speed'][()],
                f['/integrator/counters'][()], f.attrs['status'].decode())


def same_run(reference, continued, name):
    t0, a0, w0, c0, s0 = crank(reference)
    t1, a1, w1, c1, s1 = crank(continued)
    check(s1 == 'complete', f'{name}: status {s1}')
    check(len(t0) == len(t1), f'{name}: the whole history, {len(t1)} steps recorded ({len(t0)} straight)')
    if len(t0) != len(t1):
        return
    check(np.array_equal(t0, t1), f'{name}: same step sequence (times)')
    check(c0[0] == c1[0], f'{name}: same steps count ({int(c1[0])} vs {int(c0[0])})')
    da = abs(a1[-1] - a0[-1]) / abs(a0[-1])
    dw = abs(w1[-1] - w0[-1]) / abs(w0[-1])
    check(da <= 1e-12 and dw <= 1e-12, f'{name}: crank angle and speed at t_end to 1e-12 '
          f'(relative differences {da:.1e}, {dw:.1e})')
    check(np.max(np.abs(a1 - a0)) <= 1e-12 * np.max(np.abs(a0)), f'{name}: whole crank angle history to 1e-12')


def test_restart(ffrf, mesh_dir, case_dir, work):
    source = os.path.join(case_dir, 'engine_lc8_rc1.nml')
    straight_dir, split_dir, kill_dir = (os.path.join(work, d) for d in ('straight', 'split', 'kill'))
    for d in (straight_dir, split_dir, kill_dir):
        os.makedirs(d, exist_ok=True)
    t2 = make_case(source, os.path.join(straight_dir, 'engine.nml'), [('t_end = 0.1', 't_end = 0.2')])
    t1 = make_case(source, os.path.join(split_dir, 'engine.nml'), [('t_end = 0.1', 't_end = 0.1')])
    t2_split = make_case(source, os.path.join(work, 'engine.nml'), [('t_end = 0.1', 't_end = 0.2')])
    run = Run(ffrf_args(ffrf, t2, mesh_dir, straight_dir), work, 'straight')
    check(run.wait() == 0, 'straight run to t2 = 0.2 s')
    straight = os.path.join(straight_dir, 'engine.h5')

    run = Run(ffrf_args(ffrf, t1, mesh_dir, split_dir), work, 'to_t1')
    check(run.wait() == 0, 'run to t1 = 0.1 s')
    run = Run(ffrf_args(ffrf, t2_split, mesh_dir, split_dir, '--restart', os.path.join(split_dir, 'engine.h5')),
              work, 'restart_t2')
    code = run.wait()
    check(code == 0, f'--restart of the finished run to t2 (exit {code}): {run.stderr.strip()}')
    check(re.search(r'\[restart\].*continuing from t = 0\.0999', run.stdout) is not None,
          'continued from the state before the last step of the first run')
    same_run(straight, os.path.join(split_dir, 'engine.h5'), 'finished run continued')

    # kill -9, then --restart from the checkpoint
    killed = make_case(source, os.path.join(kill_dir, 'engine.nml'),
                       [('t_end = 0.1', 't_end = 0.2'), ('&integrator ', '&integrator checkpoint_steps = 100, '),
                        ('label =', 'progress_interval = 0.01, label =')])
    results = os.path.join(kill_dir, 'engine.h5')
    run = Run(ffrf_args(ffrf, killed, mesh_dir, kill_dir), work, 'killed')
    check(run.wait_for(r'\[run\] t = 0\.1[2-9]'), 'killed run got past t = 0.12 s')
    run.process.send_signal(signal.SIGKILL)
    code = run.wait()
    check(code == -signal.SIGKILL, f'killed by SIGKILL ({code})')
    checkpoint = results + '.checkpoint'
    check(os.path.exists(checkpoint) and not os.path.exists(results),
          'a checkpoint and no results file (never renamed into place)')
    with h5py.File(checkpoint, 'r') as f:
        steps = int(f['/checkpoint/num_steps'][()][0])
        check(steps >= 1000, f'the checkpoint holds {steps} steps (checkpoint_steps = 100)')
    run = Run(ffrf_args(ffrf, killed, mesh_dir, kill_dir, '--restart', checkpoint), work, 'after_kill')
    code = run.wait()
    check(code == 0, f'--restart from the checkpoint (exit {code}): {run.stderr.strip()}')
    same_run(straight, results, 'killed run continued from its checkpoint')
    check(not os.path.exists(checkpoint), 'checkpoint removed once the results file is in place')

    # restart from the results of another mechanism: refused
    rigid = make_case(os.path.join(case_dir, 'engine_lc8_all_rigid.nml'), os.path.join(work, 'rigid.nml'),
                      [('t_end = 0.3', 't_end = 0.01')])
    run = Run(ffrf_args(ffrf, rigid, mesh_dir, work), work, 'rigid')
    check(run.wait() == 0, 'rigid engine run')
    run = Run(ffrf_args(ffrf, t2, mesh_dir, work, '--restart', os.path.join(work, 'rigid.h5')), work, 'mismatch')
    code = run.wait()
    check(code == 2 and one_error_line(run.stderr, ['rigid.h5', 'not a run of this model']),
          f'restart from another mechanism: exit 2, one line ({code}: {run.stderr.strip()})')


def main():
    if len(sys.argv) != 6:
        raise SystemExit(__doc__)
    test, ffrf, mesh_dir, case_dir, work = sys.argv[1:]
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    {'concurrent': test_concurrent, 'disk_full': test_disk_full, 'signals': test_signals,
     'restart': test_restart}[test](os.path.abspath(ffrf), os.path.abspath(mesh_dir),
                                    os.path.abspath(case_dir), os.path.abspath(work))
    if FAILURES:
        print(f'{len(FAILURES)} check(s) failed', flush=True)
        sys.exit(1)


if __name__ == '__main__':
    main()
