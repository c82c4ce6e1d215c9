#!/usr/bin/env python3
"""The Slurm array script postprocess/slurm_array.sh without Slurm (issue 12 part 5): a fake
array task (SLURM_ARRAY_TASK_ID, SLURM_ARRAY_JOB_ID, SLURM_JOB_ID) with stub `scontrol` and
`sbatch` on PATH that record their arguments.

    slurm_array.py FFRF SCRIPT MESH_DIR CASE_DIR WORK_DIR

1. The lc 8 mm engine (engine_lc8_rc1.nml of CASE_DIR) of the sweep table's row 1 (0.4 s),
   run straight by ffrf: the reference.
2. The script as task 1: once ffrf integrates, SIGUSR1 goes to the batch shell (what
   `#SBATCH --signal=B:USR1@120` does); the script passes it on, ffrf exits 5 with status
   'interrupted: SIGUSR1', and the script asks `scontrol requeue 4242_1` and exits 0.
3. The requeued task (the same script again, SLURM_RESTART_COUNT=1): ffrf continues with
   --restart and completes; no further requeue.
4. Its results equal the reference bit for bit: the time series (t, crank angle and speed,
   pressure), every body's and joint's series and /final_state, and the number of steps.
5. With `scontrol` refusing (exit 1), the interrupted task submits itself again:
   `sbatch --array=1 --export=ALL SCRIPT`.
Any failure exits 1.
"""
import os
import re
import signal
import stat
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


def write_stub(folder, name, log):
    """A scheduler command that records its arguments; exits 1 when STUB_REFUSE names it."""
    path = os.path.join(folder, name)
    with open(path, 'w') as f:
        f.write(f'#!/bin/sh\necho "{name} $*" >> "{log}"\n'
                f'[ "${{STUB_REFUSE:-}}" = "{name}" ] && exit 1\nexit 0\n')
    os.chmod(path, os.stat(path).st_mode | stat.S_IXUSR | stat.S_IXGRP | stat.S_IXOTH)


def series(path):
    """Every dataset of the time history and final state, by path."""
    found = {}
    with h5py.File(path, 'r') as f:
        def visit(name, obj):
            if isinstance(obj, h5py.Dataset) and (
                    name.startswith(('time/', 'energy/', 'final_state/', 'joints/')) or
                    re.match(r'bodies/[^/]+/(position|euler_parameters|modal_coordinates)$', name)):
                found[name] = obj[()]
        f.visititems(visit)
        status = f.attrs['status'].decode()
    return found, status


def main(argv):
    if len(argv) != 6:
        print(__doc__)
        return 1
    ffrf, script, mesh_dir, case_dir, work = [os.path.abspath(a) for a in argv[1:]]
    os.makedirs(work, exist_ok=True)
    stubs = os.path.join(work, 'bin')
    os.makedirs(stubs, exist_ok=True)
    log = os.path.join(work, 'scheduler.log')
    if os.path.exists(log):
        os.remove(log)
    for name in ('scontrol', 'sbatch'):
        write_stub(stubs, name, log)
    out = os.path.join(work, 'out')
    os.makedirs(os.path.join(out, 'sweep'), exist_ok=True)
    for name in os.listdir(os.path.join(out, 'sweep')):
        os.remove(os.path.join(out, 'sweep', name))
    case = os.path.join(case_dir, 'engine_lc8_rc1.nml')
    table = os.path.join(work, 'table.csv')
    with open(table, 'w') as f:
        f.write('integrator.t_end,mechanism.progress_interval,mechanism.animation_frames\n'
                '0.4,0.01,0\n')
    env = dict(os.environ, OPENBLAS_NUM_THREADS='1', GFORTRAN_UNBUFFERED_PRECONNECTED='y')

    # 1. the reference, straight
    reference = os.path.join(out, 'reference.h5')
    result = subprocess.run([ffrf, case, '--sweep', table, '--task', '1', '--output', 'reference.h5',
                             '--output-dir', out, '--mesh-dir', mesh_dir, '--quiet'],
                            env=env, capture_output=True, text=True, timeout=600)
    check(result.returncode == 0, f'reference run (exit {result.returncode}) {result.stderr.strip()}')

    task_env = dict(env, PATH=stubs + os.pathsep + env['PATH'], SLURM_ARRAY_TASK_ID='1',
                    SLURM_ARRAY_JOB_ID='4242', SLURM_JOB_ID='4243', SLURM_CPUS_PER_TASK='1',
                    FFRF=ffrf, CASE=case, TABLE=table, OUTPUT_DIR=out, MESH_DIR=mesh_dir,
                    FFRF_OPTIONS='')
    task_env.pop('SLURM_RESTART_COUNT', None)
    results = os.path.join(out, 'sweep', 'engine_lc8_rc1_1.h5')

    # 2. the task, signalled mid-run
    code, stderr = signalled_task(script, task_env, work)
    check(code == 0, f'interrupted task: the script exits 0 after asking for a requeue (got {code})')
    check(re.search(r'ffrf: error: .*interrupted by SIGUSR1', stderr) is not None,
          'ffrf reports the interruption by SIGUSR1')
    check(re.search(r'task 1 interrupted \(exit 5\); requeueing 4242_1', stderr) is not None,
          f'the script turns exit 5 into a requeue: {stderr.strip().splitlines()[-1:]}')
    calls = open(log).read().splitlines() if os.path.exists(log) else []
    check(calls == ['scontrol requeue 4242_1'], f'scheduler calls: {calls}')
    with h5py.File(results, 'r') as f:
        status = f.attrs['status'].decode()
        t_stop = f['/final_state/t'][0]
    check(status == 'interrupted: SIGUSR1' and 0.05 <= t_stop < 0.4,
          f'results file: status "{status}", stopped at t = {t_stop:.4f} s')

    # 3. the requeued task
    requeued = dict(task_env, SLURM_RESTART_COUNT='1')
    result = subprocess.run(['bash', script], env=requeued, capture_output=True, text=True,
                            timeout=600)
    check(result.returncode == 0, f'requeued task completes (exit {result.returncode}) '
          f'{result.stderr.strip()}')
    check(re.search(r'\[restart\] .*continuing from t = ', result.stdout) is not None,
          'the requeued task continues with --restart')
    calls = open(log).read().splitlines()
    check(len(calls) == 1, f'no further scheduler call ({calls})')
    check(not os.path.exists(results + '.requeued'), 'the requeue mark is removed')

    # 4. bitwise equal to the uninterrupted run
    got, status = series(results)
    want, _ = series(reference)
    check(status == 'complete', f'final status "{status}"')
    check(len(want.get('time/t', [])) > 4000, f'reference has {len(want.get("time/t", []))} steps')
    differ = [k for k in want if k not in got or got[k].shape != want[k].shape or
              not np.array_equal(got[k], want[k])]
    check(set(got) == set(want) and not differ,
          f'{len(want)} series and final-state datasets bitwise equal to the uninterrupted run'
          + (f'; differ: {differ[:6]}' if differ else ''))

    # 5. a cluster that refuses requeues: the script submits the task again with sbatch
    os.remove(results)
    os.remove(log)
    code, stderr = signalled_task(script, dict(task_env, STUB_REFUSE='scontrol'), work)
    calls = open(log).read().splitlines() if os.path.exists(log) else []
    check(code == 0 and calls == ['scontrol requeue 4242_1', f'sbatch --array=1 --export=ALL {script}'],
          f'requeue refused: the task is submitted again (exit {code}, calls {calls})')
    print(f'{len(FAILURES)} failure(s)')
    return 1 if FAILURES else 0


def signalled_task(script, task_env, work):
    """Run the script as a task and send SIGUSR1 to its shell once ffrf integrates."""
    stdout_path = os.path.join(work, 'task.out')
    stderr_path = os.path.join(work, 'task.err')
    with open(stdout_path, 'w') as so, open(stderr_path, 'w') as se:
        task = subprocess.Popen(['bash', script], stdout=so, stderr=se, env=task_env)
        started = False
        end = time.time() + 300
        while time.time() < end and task.poll() is None:
            if re.search(r'\[run\] t = 0\.0[5-9]', open(stdout_path).read()):
                started = True
                break
            time.sleep(0.01)
        check(started, 'the task integrates (progress line at t = 0.05 s)')
        task.send_signal(signal.SIGUSR1)
        code = task.wait(timeout=300)
    return code, open(stderr_path).read()


if __name__ == '__main__':
    sys.exit(main(sys.argv))
