#!/usr/bin/env python3
"""Signals, output paths and allocation failure (issue 23, items 1, 2 and 6): runs the ffrf
driver on small cases and checks exit codes, messages and what is left on disk.

    faults_io.py TEST FFRF MESH_DIR CASE_DIR WORK_DIR

TEST is one of
  signal_stages  2 or 3 signals sent by the run itself at exact stages (FFRF_TEST_SIGNALS, the
                 test points of src/core/posix.c): before, during and after the METIS ordering
                 (whose own handlers used to leave ffrf's one-shot), the MUMPS factorisation
                 (during: from a thread while MUMPS runs) and the Lanczos loop of a modal run
                 (two cranks, lc 10 mm) and of a mechanism run (engine, crank lc 10 mm, 5 ms),
                 and the mechanism's integration: exit 5, one stderr line "interrupted by
                 SIGTERM", status "interrupted: SIGTERM", the file readable, /final_state and
                 the restart state (mechanism); a signal after the last step lets the run
                 complete (exit 0). SIGINT twice in the Lanczos loop ends the run at once (by
                 SIGINT, as documented); twice while METIS runs (held) it counts once: exit 5.
  output_paths   stale temporaries and a final name that are symbolic links (the link targets
                 stay byte for byte and mtime, the outputs are regular files); outputs naming the
                 case file, a mesh, the --sweep table, the --restart file, and two outputs naming
                 one file (directly and through a link): exit 2, one line naming both roles, the
                 input untouched
  memory_limit   a modal run under an address-space limit (ulimit -v) that fails at different
                 depths: exit 3 or 4, one "ffrf: error:" line about memory, no signal, within
                 the ctest TIMEOUT (the OpenBLAS buffer retry used to spin forever)
CASE_DIR holds engine_lc8_rc1.nml (tests/engine of the build). Any failed check exits 1.
"""
import os
import re
import shutil
import subprocess
import sys
import time

import h5py

FAILURES = []


def check(condition, what):
    print(('ok     ' if condition else 'FAILED ') + what, flush=True)
    if not condition:
        FAILURES.append(what)


def run(args, env_more=None, shell_prefix=None, timeout=120):
    env = dict(os.environ, OPENBLAS_NUM_THREADS='1')
    env.update(env_more or {})
    start = time.time()
    if shell_prefix:
        args = ['/bin/sh', '-c', shell_prefix + ' && exec "$@"', 'sh', *args]
    p = subprocess.run(args, capture_output=True, text=True, env=env, timeout=timeout)
    return p.returncode, p.stdout, p.stderr, time.time() - start


def one_error_line(stderr, fragments):
    lines = stderr.splitlines()
    return (len(lines) == 1 and lines[0].startswith('ffrf: error: ') and
            all(f in lines[0] for f in fragments))


def status_of(path):
    with h5py.File(path, 'r') as f:
        return f.attrs['status'].decode()


def two_crank_case(path, num_modes=4, mesh='crank_lc10.msh'):
    with open(path, 'w') as f:
        f.write(f"&run title = 'two cranks' /\n&modes num_modes = {num_modes} /\n")
        for body in ('crank_a', 'crank_b'):
            f.write(f"&body name = '{body}', mesh_file = '{mesh}', volumes = 'crank',\n"
                    "      young = 210.0e9, poisson = 0.3, density = 7850.0 /\n"
                    f"&interface body = '{body}', name = 'B1', mpc = 'RBE3', rc = 'Tx Ty Tz' /\n"
                    f"&interface body = '{body}', name = 'B2', mpc = 'RBE3', rc = '' /\n"
                    f"&interface body = '{body}', name = 'B3', mpc = 'RBE3', "
                    "rc = 'Tx Ty Tz Rz' /\n")
    return path


def one_crank_case(path, num_modes=4):
    with open(path, 'w') as f:
        f.write(f"&run title = 'crank' /\n&modes num_modes = {num_modes} /\n"
                "&body name = 'crank', mesh_file = 'crank_lc10.msh', volumes = 'crank',\n"
                "      young = 210.0e9, poisson = 0.3, density = 7850.0 /\n"
                "&interface body = 'crank', name = 'B1', mpc = 'RBE3', rc = 'Tx Ty Tz' /\n"
                "&interface body = 'crank', name = 'B2', mpc = 'RBE3', rc = '' /\n"
                "&interface body = 'crank', name = 'B3', mpc = 'RBE3', rc = 'Tx Ty Tz Rz' /\n")
    return path


# the engine with the coarser crank mesh and 4 modes a body: the stages are the same, the runs
# shorter
SMALL_ENGINE = ['--set', "body[crank].mesh_file='crank_lc10.msh'", '--set',
                'body[crank].num_modes=4', '--set', 'body[conrod].num_modes=4']


def engine_case(case_dir, path, t_end='0.005', more=''):
    text = open(os.path.join(case_dir, 'engine_lc8_rc1.nml')).read()
    assert 't_end = 0.1' in text
    text = text.replace('t_end = 0.1', f't_end = {t_end}{more}', 1)
    with open(path, 'w') as f:
        f.write(text)
    return path


# ------------------------------------------------------------------------------ signals

def test_signal_stages(ffrf, mesh_dir, case_dir, work):
    modal = two_crank_case(os.path.join(work, 'modal.nml'))
    mech = engine_case(case_dir, os.path.join(work, 'mech.nml'))
    out = os.path.join(work, 'out')
    os.makedirs(out)
    # (case, stage, count, signal, async, expected exit, bodies kept (modal))
    trials = [(modal, 'ordering:before', 2), (modal, 'ordering:during', 3),
              (modal, 'ordering:end', 2), (modal, 'ordering:after', 3),
              (modal, 'factorisation:before', 2), (modal, 'factorisation:during', 3),
              (modal, 'factorisation:after', 2), (modal, 'lanczos:before', 3),
              (modal, 'lanczos:during', 2), (modal, 'lanczos:after', 3),
              (mech, 'ordering:before', 3), (mech, 'ordering:during', 2),
              (mech, 'ordering:after', 3), (mech, 'factorisation:before', 2),
              (mech, 'factorisation:during', 3), (mech, 'factorisation:after', 2),
              (mech, 'lanczos:before', 3), (mech, 'lanczos:during', 2),
              (mech, 'lanczos:after', 3), (mech, 'integration:before', 2),
              (mech, 'integration:during', 3), (mech, 'integration:after', 2)]
    for case, stage, count in trials:
        kind = 'modal' if case == modal else 'mechanism'
        name = f'{kind} {stage} x{count}'
        spec = f'{stage}:{count}:TERM' + (':async' if stage == 'factorisation:during' else '')
        results = os.path.join(out, os.path.basename(case)[:-4] + '.h5')
        if os.path.exists(results):
            os.remove(results)
        code, stdout, stderr, seconds = run([ffrf, case, '--mesh-dir', mesh_dir,
                                             '--output-dir', out,
                                             *(SMALL_ENGINE if kind == 'mechanism' else [])],
                                            {'FFRF_TEST_SIGNALS': spec})
        if stage == 'integration:after':
            # every step done when the signals come: the run completes
            check(code == 0 and status_of(results) == 'complete',
                  f'{name}: after the last step the run completes (exit {code}, {stderr.strip()})')
            continue
        check(code == 5, f'{name}: exit 5 (got {code}, {seconds:.1f} s)')
        check(one_error_line(stderr, ['interrupted by SIGTERM', results]),
              f'{name}: one stderr line: {stderr.strip()[:160]}')
        if not os.path.exists(results):
            check(False, f'{name}: results file {results} exists')
            continue
        check(status_of(results) == 'interrupted: SIGTERM', f'{name}: status interrupted: SIGTERM')
        with h5py.File(results, 'r') as f:
            if kind == 'modal':
                # stopped inside crank_a (a check follows its Lanczos loop): no body written
                bodies = sorted(f['/bodies'].keys()) if '/bodies' in f else []
                check(bodies == [] and 'body "crank_a"' in stderr,
                      f'{name}: stopped in crank_a, no body written ({bodies})')
            else:
                t = f['/time/t'][()]
                check('/final_state/t' in f and '/checkpoint/num_steps' in f and
                      abs(f['/final_state/t'][()][0] - t[-1]) < 1e-12,
                      f'{name}: /final_state and the restart state at t = {t[-1]:.4f} s')
                # the modes are finished first, then the run stops after its first step
                # (docs/faults.md "Faults")
                found = re.search(r'\(step (\d+)\)', stderr)
                steps = int(found.group(1)) if found else -1
                expected = 10 if stage == 'integration:during' else 1
                check(steps == expected and len(t) == steps + 1,
                      f'{name}: stopped after step {steps} (expected {expected}), {len(t)} states')

    # SIGINT rules (docs/faults.md "Faults"): twice in the Lanczos loop ends the run at once; twice
    # while METIS runs the signals are held and merge into one: a clean end
    code, _, stderr, _ = run([ffrf, modal, '--mesh-dir', mesh_dir, '--output-dir', out],
                             {'FFRF_TEST_SIGNALS': 'lanczos:during:2:INT'})
    check(code == -2, f'SIGINT twice in the Lanczos loop: ended by SIGINT at once (got {code})')
    code, _, stderr, _ = run([ffrf, modal, '--mesh-dir', mesh_dir, '--output-dir', out],
                             {'FFRF_TEST_SIGNALS': 'ordering:during:2:INT'})
    check(code == 5 and one_error_line(stderr, ['interrupted by SIGINT']),
          f'SIGINT twice while METIS runs: one clean end, exit 5 '
          f'(got {code}: {stderr.strip()[:100]})')


# ------------------------------------------------------------------------------ output paths

def snapshot(path):
    return open(path, 'rb').read(), os.stat(path).st_mtime_ns


def test_output_paths(ffrf, mesh_dir, case_dir, work):
    case = one_crank_case(os.path.join(work, 'm.nml'))
    out = os.path.join(work, 'out')
    os.makedirs(out)
    victims = {}
    for name in ('results_part', 'msh_part', 'lock', 'final', 'opt_part'):
        path = os.path.join(work, 'victim_' + name)
        with open(path, 'w') as f:
            f.write(f'the file {name} a stale link points to\n')
        os.utime(path, ns=(1_000_000_000, 1_000_000_000))
        victims[name] = path
    os.symlink(victims['results_part'], os.path.join(out, 'm.h5.part'))
    os.symlink(victims['msh_part'], os.path.join(out, 'm_modes.msh.part'))
    os.symlink(victims['opt_part'], os.path.join(out, 'm_modes.msh.opt.part'))
    os.symlink(victims['lock'], os.path.join(out, 'm.h5.lock'))
    os.symlink(victims['final'], os.path.join(out, 'm.h5'))
    before = {k: snapshot(v) for k, v in victims.items()}
    code, _, stderr, _ = run([ffrf, case, '--mesh-dir', mesh_dir, '--output-dir', out])
    check(code == 0, f'modal run over stale links: exit 0 (got {code}: {stderr.strip()[:120]})')
    for k, v in victims.items():
        check(snapshot(v) == before[k], f'link target of {k} untouched (bytes and mtime)')
    for name in ('m.h5', 'm_modes.msh', 'm_modes.msh.opt'):
        path = os.path.join(out, name)
        check(os.path.isfile(path) and not os.path.islink(path), f'{name} is a regular file')
    check(status_of(os.path.join(out, 'm.h5')) == 'complete', 'm.h5 complete')
    left = sorted(n for n in os.listdir(out) if n.endswith('.part') or n.endswith('.lock'))
    check(left == [], f'no temporary or lock left ({left})')

    # the checkpoint's temporary of a mechanism run
    mech = engine_case(case_dir, os.path.join(work, 'e.nml'), more=', checkpoint_steps = 10')
    victim = os.path.join(work, 'victim_checkpoint')
    with open(victim, 'w') as f:
        f.write('checkpoint victim\n')
    os.utime(victim, ns=(1_000_000_000, 1_000_000_000))
    mech_out = os.path.join(work, 'mech_out')
    os.makedirs(mech_out)
    os.symlink(victim, os.path.join(mech_out, 'e.h5.checkpoint.part'))
    os.symlink(victim, os.path.join(mech_out, 'e_crank_animation.msh.part'))
    keep = snapshot(victim)
    code, _, stderr, _ = run([ffrf, mech, '--mesh-dir', mesh_dir, '--output-dir', mech_out,
                              *SMALL_ENGINE])
    check(code == 0 and snapshot(victim) == keep,
          f'mechanism run with checkpoints over stale links: exit 0, target untouched ({code})')

    # outputs naming an input or another output: exit 2 before any work
    meshes = os.path.join(work, 'meshes')
    shutil.copytree(mesh_dir, meshes, ignore=shutil.ignore_patterns('test_*'))
    table = os.path.join(work, 'table.csv')
    with open(table, 'w') as f:
        f.write('modes.num_modes\n4\n')
    os.symlink(work, os.path.join(work, 'work_link'))
    os.symlink('m2.h5', os.path.join(out, 'b.msh'))
    refusals = [
        ('--output naming the case file', ['--output-dir', work, '--output', 'm.nml'],
         case, ['the results file', 'the case file']),
        ('--output naming the case file through a linked folder',
         ['--output-dir', os.path.join(work, 'work_link'), '--output', 'm.nml'],
         case, ['the results file', 'the case file']),
        ('--output naming the mesh', ['--mesh-dir', meshes, '--output-dir', meshes, '--output',
                                     'crank_lc10.msh'],
         os.path.join(meshes, 'crank_lc10.msh'), ['the results file', 'the mesh of body "crank"']),
        ('--output naming the --sweep table', ['--output-dir', work, '--sweep', table, '--task',
                                               '1', '--output', 'table.csv'],
         table, ['the results file', 'the --sweep table']),
        ('mode_shapes_msh naming the results file',
         ['--output-dir', out, '--output', 'm.h5', '--set', 'run.mode_shapes_msh=m.h5'],
         os.path.join(out, 'm.h5'), ['the results file', 'the mode shapes file']),
        ('mode_shapes_msh a link to the results file (not yet there)',
         ['--output-dir', out, '--output', 'm2.h5', '--set', 'run.mode_shapes_msh=b.msh'],
         None, ['the results file', 'the mode shapes file']),
        ('--output naming the mesh through the mode shapes file',
         ['--mesh-dir', meshes, '--output-dir', meshes, '--set',
          'run.mode_shapes_msh=crank_lc10.msh'],
         os.path.join(meshes, 'crank_lc10.msh'), ['the mode shapes file', 'the mesh of body']),
    ]
    for what, args, guarded, roles in refusals:
        keep = snapshot(guarded) if guarded else None
        args = [a if a != '--mesh-dir' else a for a in args]
        if '--mesh-dir' not in args:
            args = ['--mesh-dir', mesh_dir] + args
        code, stdout, stderr, _ = run([ffrf, case, *args])
        check(code == 2 and one_error_line(stderr, ['output path refused', *roles]),
              f'{what}: exit 2, one line naming both roles ({code}: {stderr.strip()[:200]})')
        check('[modes]' not in stdout, f'{what}: nothing computed')
        if guarded:
            check(snapshot(guarded) == keep, f'{what}: the input untouched')

    # a mechanism's animation over its --restart file (restart in place stays allowed)
    previous = os.path.join(mech_out, 'e_crank_animation.msh')
    keep = snapshot(previous)
    code, _, stderr, _ = run([ffrf, mech, '--mesh-dir', mesh_dir, '--output-dir', mech_out,
                              '--restart', previous, *SMALL_ENGINE])
    check(code == 2 and one_error_line(stderr, ['output path refused',
                                                'the animation of body "crank"',
                                                'the --restart file'])
          and snapshot(previous) == keep,
          f'animation naming the --restart file: exit 2 ({code}: {stderr.strip()[:200]})')
    longer = engine_case(case_dir, os.path.join(work, 'e.nml'), t_end='0.006',
                         more=', checkpoint_steps = 10')
    code, _, stderr, _ = run([ffrf, longer, '--mesh-dir', mesh_dir, '--output-dir', mech_out,
                              '--restart', os.path.join(mech_out, 'e.h5'), *SMALL_ENGINE])
    check(code == 0, 'restart in place (--restart the run\'s own results file) still runs '
          f'({code}: {stderr.strip()[:120]})')


# ------------------------------------------------------------------------------ memory limit

def test_memory_limit(ffrf, mesh_dir, case_dir, work):
    case = two_crank_case(os.path.join(work, 'modal.nml'), num_modes=12, mesh='crank_lc8.msh')
    out = os.path.join(work, 'out')
    os.makedirs(out)
    for limit_kib in LIMITS_KIB:
        for threads in ('1', '2'):
            code, stdout, stderr, seconds = run(
                [ffrf, case, '--mesh-dir', mesh_dir, '--output-dir', out],
                {'OPENBLAS_NUM_THREADS': threads}, shell_prefix=f'ulimit -v {limit_kib}',
                timeout=60)
            name = f'ulimit -v {limit_kib}, {threads} BLAS thread(s)'
            check(code in (3, 4), f'{name}: exit 3 or 4 (got {code}, {seconds:.1f} s)')
            lines = stderr.splitlines()
            check(bool(lines) and lines[-1].startswith('ffrf: error: ') and 'memory' in lines[-1]
                  and len(lines) <= 2 and 'Backtrace' not in stderr,
                  f'{name}: an "ffrf: error:" line about memory last: {stderr.strip()[:240]}')
            check(seconds < 30, f'{name}: ended within 30 s ({seconds:.1f} s)')


# Measured (crank lc 8 mm twice, 12 modes): 200 MB leaves no room for OpenBLAS's buffer
# (the reservation at the start), 300 MB fails in a Fortran allocation (the runtime's line),
# 450 MB in the MUMPS factorisation (INFOG(1) = -13); 560 MB completes.
LIMITS_KIB = [200000, 300000, 450000]


def main():
    if len(sys.argv) != 6:
        raise SystemExit(__doc__)
    test, ffrf, mesh_dir, case_dir, work = sys.argv[1:]
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    {'signal_stages': test_signal_stages, 'output_paths': test_output_paths,
     'memory_limit': test_memory_limit}[test](os.path.abspath(ffrf), os.path.abspath(mesh_dir),
                                              os.path.abspath(case_dir), os.path.abspath(work))
    if FAILURES:
        print(f'{len(FAILURES)} check(s) failed', flush=True)
        sys.exit(1)


if __name__ == '__main__':
    main()
