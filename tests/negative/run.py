#!/usr/bin/env python3
"""Run the driver on every input of a generated negative suite and check each verdict.

    run.py --manifest OUT/<class>/manifest.json --driver PATH [--check-flag=--check]
           [--mesh-dir DIR] [--jobs 2] [--timeout 10] [--memory-mb 1024] [--only ID]

Per input, the driver runs as `DRIVER CASE [--mesh-dir DIR] --output-dir TMP [CHECK_FLAG...]` in
a fresh folder (the case's folder is the generated one) and must:
  * exit with one of the codes the manifest expects (a signal, or a code >= 128, is a crash);
  * if it fails, print exactly ONE line on stderr, starting 'ffrf: error: ' and containing every
    string of the manifest's `names` (the mutated file's base name) and, for exit 2, of its
    `key_names` (the group and key of a case-file mutation);
  * print no runtime banner ("Fortran runtime error", "Backtrace", "ERROR STOP",
    "Program received signal", ...) on stdout or stderr;
  * end within --timeout seconds wall (then it is killed: a hang) and peak at most --memory-mb
    resident (ru_maxrss from os.wait4; RLIMIT_AS caps it at 2x that as a safety net).
Prints a summary (tried, passed, crashes, hangs, wrong codes, bad messages, too much memory, max
time, max memory) and the first failures with the command that reproduces each; exit status 1 if
anything failed. --only ID (repeatable) runs the named inputs; --keep leaves the output folders.
"""
import argparse
import concurrent.futures
import json
import os
import resource
import shlex
import shutil
import signal
import subprocess
import sys
import tempfile
import threading
import time

BANNERS = ('Fortran runtime error', 'Backtrace', 'ERROR STOP', 'Program received signal',
           'Error termination', 'Segmentation fault', 'Aborted', 'Floating point exception',
           'At line ', 'HDF5-DIAG', 'malloc(): ', 'double free', 'munmap_chunk')


def limits(memory_bytes):
    def apply():
        resource.setrlimit(resource.RLIMIT_AS, (2 * memory_bytes, 2 * memory_bytes))
        resource.setrlimit(resource.RLIMIT_CORE, (0, 0))
        resource.setrlimit(resource.RLIMIT_FSIZE, (512 * 2**20, 512 * 2**20))
    return apply


def run_one(entry, args, case_dir):
    work = tempfile.mkdtemp(prefix='neg_%s_' % entry['id'], dir=args.work_dir)
    out_dir = os.path.join(work, 'out')
    os.mkdir(out_dir)
    command = [args.driver, os.path.join(case_dir, entry['case'])]
    if entry.get('mesh_dir') and args.mesh_dir:
        command += ['--mesh-dir', args.mesh_dir]
    command += ['--output-dir', out_dir] + args.check_flag
    env = dict(os.environ, OPENBLAS_NUM_THREADS='1', OMP_NUM_THREADS='1')
    with open(os.path.join(work, 'stdout'), 'wb') as so, \
            open(os.path.join(work, 'stderr'), 'wb') as se:
        start = time.monotonic()
        proc = subprocess.Popen(command, cwd=work, stdin=subprocess.DEVNULL, stdout=so, stderr=se,
                                env=env, start_new_session=True,
                                preexec_fn=limits(args.memory_mb * 2**20))
        timed_out = threading.Event()

        def kill():
            timed_out.set()
            try:
                os.killpg(proc.pid, signal.SIGKILL)
            except ProcessLookupError:
                pass
        timer = threading.Timer(args.timeout, kill)
        timer.start()
        _, status, usage = os.wait4(proc.pid, 0)
        timer.cancel()
        elapsed = time.monotonic() - start
        proc.returncode = os.waitstatus_to_exitcode(status)
        try:                                  # children the driver may have left behind
            os.killpg(proc.pid, signal.SIGKILL)
        except (ProcessLookupError, PermissionError):
            pass
    with open(os.path.join(work, 'stdout'), 'rb') as f:
        stdout = f.read(1 << 20).decode('utf-8', 'replace')
    with open(os.path.join(work, 'stderr'), 'rb') as f:
        stderr = f.read(1 << 20).decode('utf-8', 'replace')
    if not args.keep:
        shutil.rmtree(work, ignore_errors=True)
    code = proc.returncode
    problems = []
    kind = None
    if timed_out.is_set():
        kind = 'hang'
        problems.append('killed after %.1f s (limit %g s)' % (elapsed, args.timeout))
    elif code < 0 or code >= 128:
        kind = 'crash'
        sig = -code if code < 0 else code - 128
        try:
            problems.append('signal %s' % signal.Signals(sig).name)
        except ValueError:
            problems.append('exit %d' % code)
    elif code not in entry['expected']:
        kind = 'wrong code'
        problems.append('exit %d, expected %s' % (code, '/'.join(map(str, entry['expected']))))
    banner = [b for b in BANNERS if b in stdout or b in stderr]
    if banner and kind is None:
        kind = 'banner'
    if banner:
        problems.append('runtime banner %r' % banner[0])
    lines = stderr.rstrip('\n').split('\n') if stderr else []   # '\n' ends a line, nothing else
    if code != 0 and kind not in ('hang', 'crash'):
        bad = []
        if len(lines) != 1:
            bad.append('%d stderr lines' % len(lines))
        if not lines or not lines[0].startswith('ffrf: error: '):
            bad.append("stderr does not start 'ffrf: error: '")
        line = lines[0] if lines else ''
        missing = [n for n in entry['names'] if n not in line]
        if code == 2:                 # the key outside the file name (which may spell it too)
            bare = line.replace(entry['case'], '').replace(entry['target'], '')
            missing += [n for n in entry.get('key_names', []) if n not in bare]
        if missing:
            bad.append('message does not name %s' % ', '.join(repr(n) for n in missing))
        if bad:
            kind = kind or 'bad message'
            problems += bad
    maxrss_mb = usage.ru_maxrss / 1024.0
    if maxrss_mb > args.memory_mb:
        kind = kind or 'memory'
        problems.append('peak %.0f MB resident (limit %d MB)' % (maxrss_mb, args.memory_mb))
    return dict(entry=entry, code=code, kind=kind, problems=problems, elapsed=elapsed,
                maxrss_mb=maxrss_mb, stderr=stderr.strip()[:600], command=command)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    parser.add_argument('--manifest', required=True)
    parser.add_argument('--driver', required=True)
    parser.add_argument('--check-flag', action='append', default=[],
                        help='extra driver flag (repeatable), e.g. --check-flag=--check')
    parser.add_argument('--mesh-dir', help='--mesh-dir of the cases that need one (namelists)')
    parser.add_argument('--jobs', type=int, default=2)
    parser.add_argument('--timeout', type=float, default=10.0)
    parser.add_argument('--memory-mb', type=int, default=1024)
    parser.add_argument('--only', action='append', help='run only this input id (repeatable)')
    parser.add_argument('--list-failures', type=int, default=15)
    parser.add_argument('--work-dir', help='where the per-run folders go (default: a temp dir)')
    parser.add_argument('--keep', action='store_true', help='keep the per-run folders')
    parser.add_argument('--json', help='write every result to this file')
    args = parser.parse_args()
    args.driver = os.path.abspath(args.driver)
    if not os.access(args.driver, os.X_OK):
        sys.exit('run.py: the driver %s is not an executable file' % args.driver)
    if args.mesh_dir:
        args.mesh_dir = os.path.abspath(args.mesh_dir)
    case_dir = os.path.dirname(os.path.abspath(args.manifest))
    with open(args.manifest) as f:
        entries = json.load(f)
    if args.only:
        entries = [e for e in entries if e['id'] in args.only]
    own_work = args.work_dir is None
    if own_work:
        args.work_dir = tempfile.mkdtemp(prefix='ffrf_negative_')
    os.makedirs(args.work_dir, exist_ok=True)
    start = time.monotonic()
    with concurrent.futures.ThreadPoolExecutor(max_workers=args.jobs) as pool:
        results = list(pool.map(lambda e: run_one(e, args, case_dir), entries))
    wall = time.monotonic() - start
    if own_work and not args.keep:
        shutil.rmtree(args.work_dir, ignore_errors=True)

    order = ['crash', 'hang', 'banner', 'memory', 'bad message', 'wrong code']
    failed = sorted((r for r in results if r['kind']), key=lambda r: order.index(r['kind']))
    count = lambda kind: sum(1 for r in failed if r['kind'] == kind)
    name = os.path.basename(case_dir)
    slowest = max(results, key=lambda r: r['elapsed']) if results else None
    biggest = max(results, key=lambda r: r['maxrss_mb']) if results else None
    print('negative %s: %d tried, %d passed, %d crashes, %d hangs, %d wrong codes, '
          '%d bad messages, %d runtime banners, %d over memory; max time %.2f s (%s), '
          'max memory %.0f MB (%s); wall %.1f s' % (
              name, len(results), len(results) - len(failed), count('crash'), count('hang'),
              count('wrong code'), count('bad message'), count('banner'), count('memory'),
              slowest['elapsed'] if slowest else 0, slowest['entry']['id'] if slowest else '-',
              biggest['maxrss_mb'] if biggest else 0, biggest['entry']['id'] if biggest else '-',
              wall))
    codes = {}
    for r in results:
        codes[r['code']] = codes.get(r['code'], 0) + 1
    print('exit codes: ' + ', '.join('%s: %d' % (c, n) for c, n in sorted(codes.items())))
    for r in failed[:args.list_failures]:
        e = r['entry']
        print('FAIL %s [%s] %s: %s' % (e['id'], r['kind'], e['mutation'], '; '.join(r['problems'])))
        if r['stderr']:
            print('  stderr: ' + r['stderr'].replace('\n', '\n          ')[:400])
        print('  reproduce: ' + ' '.join(
            '/tmp/out' if c.startswith(args.work_dir) else shlex.quote(c) for c in r['command']))
    if args.check_flag and results and all(r['code'] == 1 for r in results):
        print('note: every run exited 1: does this driver know %s?' % ' '.join(args.check_flag))
    if len(failed) > args.list_failures:
        print('... and %d more failures' % (len(failed) - args.list_failures))
    if args.json:
        with open(args.json, 'w') as f:
            json.dump([dict(id=r['entry']['id'], mutation=r['entry']['mutation'],
                            expected=r['entry']['expected'], code=r['code'], kind=r['kind'],
                            problems=r['problems'], elapsed=round(r['elapsed'], 3),
                            maxrss_mb=round(r['maxrss_mb'], 1), stderr=r['stderr'],
                            command=r['command']) for r in results], f, indent=1)
    return 1 if failed else 0


if __name__ == '__main__':
    sys.exit(main())
