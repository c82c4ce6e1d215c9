#!/usr/bin/env python3
"""Generated inputs for the input rules of issue 23 (items 4 and 5), several variants per class,
each run through the driver and checked for its exact verdict (docs/input.md "Input rules").

    input_rules.py --driver FFRF --work DIR --class CLASS [--mesh-dir DIR] [--gmsh GMSH]

Classes (one ctest entry each, tests/negative/negative.cmake):
  sparse      a 2 GB sparse .msh (all NUL, or a valid header then NUL padding) refused in < 5 s
              with exit 2 and the file's name, a 2 GB sparse case file with exit 3 (ctest
              TIMEOUT 10 s)
  bounded     peak memory of the worst meshes at most 5x their content, a header with 256 MiB
              of blanks read as its header; declared node/element/entity/name counts larger
              than the file can hold (exit 2, "cannot be right"), in MSH 4.1 and 2.2; case
              files that are no namelist (a mesh, binary bytes, text) named by their first
              bytes (exit 2)
  options     every option with an empty value: exit 1 naming the option
  characters  TAB, 0x01, 0x1b, 0x7f, new line in a --set string, in --output, in a sweep cell and
              in a case-file string: exit 2, "a control character (code N)"
  file_kinds  a FIFO, a folder and /dev/null as the case, a mesh, --sweep, --restart, a
              &pressure table and a &body modes_file: exit 3 naming the argument, within 5 s
              (a FIFO never blocks)
  sweep       a sweep header naming a key twice (3 spellings): exit 2 naming key and column; a
              UTF-8 byte-order mark in a table and in a case skipped (the values arrive), a
              UTF-16 one named
  task        job-array variables of 10, 65, 200 and 5000 characters: exit 2 naming the
              variable (never read as unset); 9 digits accepted
  echo        --print-input of every input/*.nml and of a case with apostrophes, '!' and '"'
              in strings: the echo reads back, and the echo of the echo is identical
  sets        20 000 --set options take linear time: 2 000 and 20 000 timed; the 20 000 run
              under 4 s and at most 10x + 0.5 s the 2 000 run (quadratic: 100x)
  restart     a restart to an earlier t_end: exit 2 naming --restart, the file and t_end
  surfaces    a physical surface spanning two bodies: exit 2 naming the surface, the body and
              the number of triangles off it; two physical names equal up to trailing blanks:
              exit 2; a name with a leading or trailing blank is not the case's plain name:
              exit 2 (gmsh makes the two-box mesh)
Every failing run must print exactly one stderr line starting 'ffrf: error: '. Exit status 1 if
any variant fails; each variant prints its exit code, time and first message.
"""
import argparse
import os
import re
import shutil
import subprocess
import sys
import time

#: a rigid arm on a revolute to the ground (no mesh): a mechanism case that runs in < 1 s
ARM = """&body name = 'arm', type = 'rigid', mass = 1.0, inertia = 0.01, 0.01, 0.01, 0, 0, 0 /
&marker body = 'arm', name = 'hinge', position = 0, 0, 0 /
&marker body = 'ground', name = 'hinge', position = 0, 0, 0 /
&joint name = 'pivot', type = 'revolute', body1 = 'ground', marker1 = 'hinge', body2 = 'arm', marker2 = 'hinge' /
&mechanism gravity = 0, -9.81, 0 /
"""

failures = []


def run(args, command, env=None, timeout=20, stdin=None):
    environment = dict(os.environ, OPENBLAS_NUM_THREADS='1')
    for name in ('SLURM_ARRAY_TASK_ID', 'PBS_ARRAY_INDEX', 'LSB_JOBINDEX'):
        environment.pop(name, None)
    environment.update(env or {})
    start = time.monotonic()
    proc = subprocess.run([args.driver] + command, capture_output=True, env=environment,
                          timeout=timeout, stdin=stdin or subprocess.DEVNULL, cwd=args.work)
    return proc.returncode, proc.stdout.decode('latin-1'), proc.stderr.decode('latin-1'), \
        time.monotonic() - start


def expect(args, label, command, code, fragments, env=None, max_seconds=None, timeout=20):
    """Run; the exit code must be `code` and the single error line hold every fragment."""
    try:
        got, out, err, seconds = run(args, command, env, timeout)
    except subprocess.TimeoutExpired:
        failures.append('%s: no end within %d s (a blocking read?)' % (label, timeout))
        print('FAIL %-40s timeout' % label)
        return
    problems = []
    if got != code:
        problems.append('exit %d, expected %d' % (got, code))
    if code != 0:
        lines = err.splitlines()
        if len(lines) != 1 or not lines[0].startswith('ffrf: error: '):
            problems.append('stderr is not one "ffrf: error:" line: %r' % err[:400])
        for fragment in fragments:
            if fragment not in err:
                problems.append('message lacks %r' % fragment)
    if max_seconds is not None and seconds > max_seconds:
        problems.append('%.2f s, more than %.1f s' % (seconds, max_seconds))
    status = 'FAIL' if problems else 'ok  '
    print('%s %-40s exit %d in %.2f s: %s' % (status, label, got, seconds,
                                             (err.strip() or out.strip()[:100])[:300]))
    for problem in problems:
        failures.append('%s: %s' % (label, problem))
        print('     ' + problem)


def peak_rss(args, command):
    """Exit code, peak resident memory (bytes, ru_maxrss of the child) and stderr of a run."""
    environment = dict(os.environ, OPENBLAS_NUM_THREADS='1')
    proc = subprocess.Popen([args.driver] + command, stdout=subprocess.DEVNULL,
                            stderr=subprocess.PIPE, stdin=subprocess.DEVNULL, env=environment,
                            cwd=args.work)
    err = proc.stderr.read().decode('latin-1')
    _, status, usage = os.wait4(proc.pid, 0)
    proc.returncode = os.waitstatus_to_exitcode(status)
    return proc.returncode, usage.ru_maxrss * 1024, err


def write(args, name, text, mode='w'):
    path = os.path.join(args.work, name)
    with open(path, mode) as f:
        f.write(text)
    return path


# ================================================================= classes
def class_sparse(args):
    """Item 4: a 2 GB sparse .msh is refused by its first bytes, a valid header padded with
    2 GB of NUL by its content's end, each within seconds (the files live in the build tree
    and are removed after)."""
    gib2 = 2 * 1024**3
    sparse = os.path.join(args.work, 'sparse_2g.msh')
    header = os.path.join(args.work, 'header_padded.msh')
    case = write(args, 'bounded.nml', "&body name = 'b', mesh_file = 'MESH', volumes = 'block' /\n"
                 "&interface body = 'b', name = 'face_a' /\n")
    try:
        with open(sparse, 'wb') as f:
            f.truncate(gib2)
        with open(header, 'wb') as f:
            f.write(b'$MeshFormat\n4.1 0 8\n$EndMeshFormat\n')
            f.truncate(gib2)
        for label, path, fragments in (
                ('sparse 2 GB of NUL', sparse, ['sparse_2g.msh', 'does not start with $MeshFormat']),
                ('valid header + 2 GB NUL', header, ['header_padded.msh', 'NUL padding'])):
            text = open(case).read().replace('MESH', path)
            expect(args, label, [write(args, 'bounded_case.nml', text), '--check'], 2, fragments,
                   max_seconds=5, timeout=30)
        # a 2 GB sparse case file: refused by its size before it is opened
        case_2g = os.path.join(args.work, 'sparse_2g.nml')
        with open(case_2g, 'wb') as f:
            f.truncate(gib2)
        expect(args, 'sparse 2 GB case file', [case_2g, '--check'], 3,
               ['sparse_2g.nml', '2147483648 bytes, more than the 16777216 allowed'],
               max_seconds=5, timeout=30)
    finally:
        for path in (sparse, header, os.path.join(args.work, 'sparse_2g.nml')):
            if os.path.exists(path):
                os.remove(path)


def class_bounded(args):
    """Item 4: memory bounded by the content; declared counts against the file's bytes."""
    case = write(args, 'bounded.nml', "&body name = 'b', mesh_file = 'MESH', volumes = 'block' /\n"
                 "&interface body = 'b', name = 'face_a' /\n")
    # memory: the content once, arrays bounded by its size (docs/input.md "Input rules": at most 5x
    # the content above the program's own ~16 MB); the worst cases are files of bare nodes or of
    # element lines in the fewest bytes, a million of each
    baseline = peak_rss(args, [write(args, 'tiny.nml', open(case).read().replace(
        'MESH', os.path.join(args.mesh_dir, 'fuzz_block_tet4_msh41.msh'))), '--check'])[1]
    n = 10**6

    def bare_nodes(f):
        f.write('$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$PhysicalNames\n1\n3 2 "block"\n'
                '$EndPhysicalNames\n$Nodes\n%d\n' % n)
        for k in range(0, n - 4, 1000):
            f.write(''.join('%d 0 0 0\n' % (j + 1) for j in range(k, min(k + 1000, n - 4))))
        f.write('%d 1 0 0\n%d 0 1 0\n%d 0 0 1\n%d 0 0 0.5\n$EndNodes\n$Elements\n1\n'
                '1 4 2 2 1 %d %d %d %d\n$EndElements\n'
                % (n - 3, n - 2, n - 1, n, n - 3, n - 2, n - 1, n))

    def element_lines(f):
        f.write('$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n4\n1 1 0 0\n2 0 1 0\n'
                '3 0 0 1\n4 0 0 0\n$EndNodes\n$Elements\n%d\n' % n)
        for k in range(0, n, 1000):
            f.write(''.join('%d 4 0 1 2 3 4\n' % (j + 1) for j in range(k, min(k + 1000, n))))
        f.write('$EndElements\n')

    for label, fill in (('bare nodes', bare_nodes), ('element lines', element_lines)):
        mesh = os.path.join(args.work, 'worst.msh')
        with open(mesh, 'w') as f:
            fill(f)
        size = os.path.getsize(mesh)
        code, rss, err = peak_rss(args, [write(args, 'worst.nml', open(case).read().replace(
            'MESH', mesh)), '--check'])
        ratio = (rss - baseline) / size
        ok = code in (0, 2) and ratio <= 5.0
        print('%s %s: %.1f MB file, peak %.1f MB (baseline %.1f MB): %.2fx the content'
              % ('ok  ' if ok else 'FAIL', label, size / 2**20, rss / 2**20,
                 baseline / 2**20, ratio))
        if not ok:
            failures.append('%s: exit %d, %.2fx the content (at most 5x): %s'
                            % (label, code, ratio, err[:200]))
        os.remove(mesh)
    # a valid header and 256 MiB of blanks (written, not sparse): only the header is read
    padded = os.path.join(args.work, 'blank_padded.msh')
    try:
        with open(padded, 'wb') as f:
            f.write(b'$MeshFormat\n4.1 0 8\n$EndMeshFormat\n')
            block = b' ' * 2**20
            for _ in range(256):
                f.write(block)
        code, rss, err = peak_rss(args, [write(args, 'blank_padded.nml', open(case).read()
                                               .replace('MESH', padded)), '--check'])
        ok = code == 2 and 'no $Nodes' in err and rss - baseline < 32 * 2**20
        print('%s header + 256 MiB of blanks: exit %d, peak %.1f MB: %s'
              % ('ok  ' if ok else 'FAIL', code, rss / 2**20, err.strip()[:200]))
        if not ok:
            failures.append('header + 256 MiB blanks: exit %d, peak %.1f MB, %s'
                            % (code, rss / 2**20, err[:200]))
    finally:
        if os.path.exists(padded):
            os.remove(padded)
    # a case file is checked by its first bytes too: what is no namelist is named at once
    mesh41 = os.path.join(args.mesh_dir, 'fuzz_block_tet4_msh41.msh')
    for k, (label, data, shown) in enumerate((
            ('a mesh given as the case', open(mesh41, 'rb').read(), '$MeshFormat'),
            ('binary bytes as the case', bytes(range(200, 256)) * 100, '????'),
            ('text after blank lines', b'\n\n   hello &run /\n', 'hello &run /'),
            ('a key before any group', b'num_modes = 4\n&modes /\n', 'num_modes = 4'))):
        line = 3 if label.startswith('text after') else 1
        path = write(args, 'not_case_%d.nml' % k, data, 'wb')
        expect(args, label, [path, '--check'], 2,
               ['not_case_%d.nml:%d: not a namelist case: it starts with "%s' % (k, line, shown)])
    # a valid mesh followed by blanks: read (trailing blanks are no content)
    base41 = open(os.path.join(args.mesh_dir, 'fuzz_block_tet4_msh41.msh')).read()
    base22 = open(os.path.join(args.mesh_dir, 'fuzz_block_tet4_msh22.msh')).read()
    good = write(args, 'blank_tail.msh', base41 + ' \n' * 50000)
    expect(args, 'valid mesh + 100 kB of blanks', [write(args, 'blank_tail.nml', open(case).read()
           .replace('MESH', good)), '--check'], 0, [])
    # declared counts larger than the file can hold
    variants = []

    def header_count(text, section, index, value):
        """The section's first line with its field `index` set to value."""
        start = text.index(section + '\n') + len(section) + 1
        end = text.index('\n', start)
        fields = text[start:end].split()
        fields[index] = str(value)
        return text[:start] + ' '.join(fields) + text[end:]

    for value in (10**9, 2**40, 2**62):
        variants.append(('4.1 nodes = %d' % value, header_count(base41, '$Nodes', 1, value),
                         'number of nodes'))
        variants.append(('4.1 elements = %d' % value, header_count(base41, '$Elements', 1, value),
                         'number of elements'))
        variants.append(('4.1 volume entities = %d' % value, header_count(base41, '$Entities', 3,
                                                                          value), 'entities'))
        variants.append(('2.2 nodes = %d' % value if value < 2**31 else '2.2 nodes = 2e9',
                         header_count(base22, '$Nodes', 0, min(value, 2 * 10**9)),
                         'number of nodes'))
    variants.append(('4.1 physical names = 10^8', header_count(base41, '$PhysicalNames', 0, 10**8),
                     'number of physical names'))
    variants.append(('4.1 node blocks = 10^9', header_count(base41, '$Nodes', 0, 10**9),
                     'number of node blocks'))
    for k, (label, text, what) in enumerate(variants):
        mesh = write(args, 'counts_%d.msh' % k, text)
        expect(args, label, [write(args, 'counts_%d.nml' % k, open(case).read()
                                   .replace('MESH', mesh)), '--check'], 2,
               ['counts_%d.msh' % k, what], max_seconds=3)


def class_options(args):
    """An empty option value is a usage error (exit 1) naming the option."""
    case = write(args, 'options.nml', ARM + "&integrator h = 1e-3, t_end = 0.002 /\n")
    for option in ('--output', '--sweep', '--restart', '--set', '--mesh-dir', '--output-dir',
                   '--task', '--threads'):
        expect(args, 'empty %s' % option, [case, option, '', '--check'], 1,
               [option + " ''", 'empty value'])
    expect(args, 'empty case file name', ['', '--check'], 1, ['empty argument'])


def class_characters(args):
    """Control characters: one rule for case files, --set, sweep cells and --output (exit 2)."""
    case = write(args, 'chars.nml', ARM + "&integrator h = 1e-3, t_end = 0.002 /\n")
    for code in (9, 1, 27, 127, 10):
        c = chr(code)
        expect(args, '--set title with code %d' % code,
               [case, '--set', 'run.title=a%sb' % c, '--check'], 2,
               ['--set run.title', 'control character (code %d)' % code])
        expect(args, '--set quoted label with code %d' % code,
               [case, '--set', "mechanism.label='x%sy'" % c, '--check'], 2,
               ['--set mechanism.label', 'control character (code %d)' % code])
        expect(args, '--output with code %d' % code,
               [case, '--output', 'out%s.h5' % c, '--check'], 2,
               ['--output', 'control character (code %d)' % code])
        if code != 10:
            table = write(args, 'chars_%d.csv' % code, 'run.title,modes.num_modes\n"a%sb",4\n' % c)
            expect(args, 'sweep cell with code %d' % code,
                   [case, '--sweep', table, '--task', '1', '--check'], 2,
                   ['chars_%d.csv:2 run.title' % code, 'control character (code %d)' % code])
            bad = write(args, 'chars_case_%d.nml' % code,
                        ARM + "&run title = 'a%sb' /\n" % c)
            expect(args, 'case-file string with code %d' % code, [bad, '--check'], 2,
                   ['chars_case_%d.nml:6: &run title' % code, 'control character (code %d)' % code])
    # a numeric --set with a control character: the same class (input error)
    expect(args, '--set number with TAB', [case, '--set', 'integrator.t_end=0.002\t', '--check'], 2,
           ['--set integrator.t_end', 'control character (code 9)'])


def class_file_kinds(args):
    """FIFOs, folders and devices as any file argument: exit 3 naming it, never blocking."""
    fifo = os.path.join(args.work, 'kinds.fifo')
    if not os.path.exists(fifo):
        os.mkfifo(fifo)
    folder = os.path.join(args.work, 'kinds_folder')
    os.makedirs(folder, exist_ok=True)
    case = write(args, 'kinds.nml', ARM + "&integrator h = 1e-3, t_end = 0.002 /\n")
    for name, path in (('FIFO', fifo), ('folder', folder), ('device', '/dev/null')):
        kind = {'FIFO': 'a FIFO', 'folder': 'a folder', 'device': 'a device'}[name]
        expect(args, 'case is a %s' % name, [path, '--check'], 3, ['case file', kind],
               max_seconds=5, timeout=15)
        expect(args, '--sweep is a %s' % name, [case, '--sweep', path, '--task', '1', '--check'],
               3, ['--sweep table', kind], max_seconds=5, timeout=15)
        expect(args, '--restart is a %s' % name,
               [case, '--restart', path, '--output-dir', args.work, '--quiet'], 3,
               ['--restart file', kind], max_seconds=5, timeout=15)
        mesh_case = write(args, 'kinds_mesh_%s.nml' % name,
                          "&body name = 'b', mesh_file = '%s', volumes = 'block' /\n" % path)
        expect(args, 'mesh is a %s' % name, [mesh_case, '--check'], 3, ['mesh file', kind],
               max_seconds=5, timeout=15)
        table_case = write(args, 'kinds_table_%s.nml' % name, ARM.replace(
            "&mechanism gravity = 0, -9.81, 0 /", "&mechanism crank = 'arm' /") +
            "&load name = 'gas', type = 'pressure', body = 'arm', marker = 'hinge' /\n"
            "&pressure table_file = '%s' /\n" % path)
        expect(args, 'pressure table is a %s' % name, [table_case, '--output-dir', args.work,
                                                       '--quiet'], 3,
               ['table_file', kind], max_seconds=5, timeout=15)
        modes_case = write(args, 'kinds_modes_%s.nml' % name, (
            "&body name = 'block', mesh_file = '%s', volumes = 'block', modes_file = '%s' /\n"
            "&interface body = 'block', name = 'face_a', rc = '' /\n"
            "&marker body = 'ground', name = 'g', position = 0, 0, 0 /\n"
            "&joint name = 'pin', type = 'revolute', body1 = 'ground', marker1 = 'g', "
            "body2 = 'block', marker2 = 'face_a' /\n")
            % (os.path.join(args.mesh_dir, 'fuzz_block_tet4_msh41.msh'), path))
        expect(args, 'modes_file is a %s' % name, [modes_case, '--check'], 3,
               ['modes_file', kind], max_seconds=5, timeout=15)


def class_sweep(args):
    case = write(args, 'sweep.nml', ARM + "&integrator h = 1e-3, t_end = 0.002 /\n")
    for k, header in enumerate(('run.title,run.title', 'integrator.t_end,run.title,Integrator.T_END',
                                'run.title,mechanism.label,run.title')):
        values = ','.join(['0.002' if 't_end' in key.lower() else 'x'
                           for key in header.split(',')])
        table = write(args, 'dup_%d.csv' % k, header + '\n' + values + '\n')
        second = header.split(',')[2 if k > 0 else 1]
        column = header.split(',').index(second, 1) + 1
        expect(args, 'duplicate header key %d' % k, [case, '--sweep', table, '--task', '1',
                                                     '--check'], 2,
               ['dup_%d.csv' % k, 'column %d "%s"' % (column, second), 'again'])
    # UTF-8 byte-order marks: skipped; the value must arrive
    bom = '\ufeff'.encode('utf-8')
    table = write(args, 'bom.csv', bom + b'run.title\nswept\n', 'wb')
    got, out, err, _ = run(args, [case, '--sweep', table, '--task', '1', '--print-input'])
    ok = got == 0 and "title = 'swept'" in out
    print('%s sweep table with a UTF-8 BOM: exit %d %s' % ('ok  ' if ok else 'FAIL', got,
                                                           err.strip()))
    if not ok:
        failures.append('sweep table with a BOM: exit %d, %s' % (got, err))
    bom_case = write(args, 'bom_case.nml', bom + (ARM + "&run title = 'bom' /\n").encode(), 'wb')
    got, out, err, _ = run(args, [bom_case, '--print-input'])
    ok = got == 0 and "title = 'bom'" in out
    print('%s case with a UTF-8 BOM: exit %d %s' % ('ok  ' if ok else 'FAIL', got, err.strip()))
    if not ok:
        failures.append('case with a BOM: exit %d, %s' % (got, err))
    utf16 = write(args, 'utf16_case.nml', b'\xff\xfe' + ARM.encode('utf-16-le'), 'wb')
    expect(args, 'case in UTF-16', [utf16, '--check'], 2, ['utf16_case.nml:1', 'UTF-16'])


def class_task(args):
    case = write(args, 'task.nml', ARM + "&integrator h = 1e-3, t_end = 0.002 /\n")
    table = write(args, 'task.csv', 'run.title\nfirst\n')
    for variable in ('SLURM_ARRAY_TASK_ID', 'PBS_ARRAY_INDEX', 'LSB_JOBINDEX'):
        for length in (10, 65, 200, 5000):
            expect(args, '%s of %d digits' % (variable, length),
                   [case, '--sweep', table, '--check'], 2,
                   [variable, '(%d characters)' % length, 'not a task index'],
                   env={variable: '1' * length})
    got, out, err, _ = run(args, [case, '--sweep', table, '--print-input'],
                           env={'SLURM_ARRAY_TASK_ID': '000000001'})
    ok = got == 0 and "title = 'first'" in out
    print('%s SLURM_ARRAY_TASK_ID = 000000001: exit %d %s' % ('ok  ' if ok else 'FAIL', got,
                                                             err.strip()))
    if not ok:
        failures.append('9-digit task index: exit %d %s' % (got, err))


def class_echo(args):
    """The echo is input: read back, its own echo is identical (the resolved input is)."""
    cases = sorted(os.path.join(args.input_dir, n) for n in os.listdir(args.input_dir)
                   if n.endswith('.nml') and n != 'study.nml')
    tricky = write(args, 'tricky.nml', ARM.replace("name = 'pivot'", "name = 'it''s a \"pin\"'")
                   + "&run title = 'it''s ''quoted'' ! not a comment, a / and \"double\"' /\n")
    cases.append(tricky)
    for case in cases:
        name = os.path.basename(case)
        got, first, err, _ = run(args, [case, '--print-input'])
        if got != 0:
            failures.append('%s: --print-input exit %d: %s' % (name, got, err))
            print('FAIL echo %s: exit %d %s' % (name, got, err.strip()))
            continue
        echo = write(args, 'echo_' + name, first)
        got, second, err, _ = run(args, [echo, '--print-input'])
        same = got == 0 and second == first
        print('%s echo of %s reads back%s' % ('ok  ' if same else 'FAIL', name,
                                              '' if same else ': exit %d %s' % (got, err.strip())))
        if not same:
            failures.append('%s: the echo does not read back to itself (exit %d, %s)' %
                            (name, got, err.strip()))
    got, out, err, _ = run(args, [tricky, '--print-input'])
    if "title = 'it''s ''quoted'' ! not a comment, a / and \"double\"'" not in out:
        failures.append('tricky title not echoed with doubled quotes: %s' % out[:300])


def class_sets(args):
    """--set options parse in linear time: 2 000 and 20 000 timed (docs/batch.md "Batch runs")."""
    case = write(args, 'sets.nml', ARM + "&integrator h = 1e-3, t_end = 0.002 /\n")
    times = {}
    for count in (2000, 20000):
        command = [case, '--print-input']
        for k in range(count):
            command += ['--set', 'run.title=title_%d' % k]
        got, out, err, seconds = run(args, command, timeout=60)
        times[count] = seconds
        ok = got == 0 and "title = 'title_%d'" % (count - 1) in out
        print('%s %d --set options: exit %d in %.3f s' % ('ok  ' if ok else 'FAIL', count, got,
                                                         seconds))
        if not ok:
            failures.append('%d --set: exit %d %s' % (count, got, err[:300]))
    if times[20000] > 4.0 or times[20000] > 10 * times[2000] + 0.5:
        failures.append('20 000 --set took %.2f s, 2 000 took %.2f s: not linear'
                        % (times[20000], times[2000]))


def class_restart(args):
    case = write(args, 'restart_long.nml', ARM + "&integrator h = 1e-3, t_end = 0.02 /\n"
                 "&run output = 'restart_long.h5' /\n")
    got, out, err, _ = run(args, [case, '--output-dir', args.work, '--quiet'], timeout=60)
    if got != 0:
        failures.append('restart: the first run failed: exit %d %s' % (got, err))
        return
    results = os.path.join(args.work, 'restart_long.h5')
    # a finished run keeps the state before its last step (t = 0.019 s) as its restart state
    for t_end in ('0.01', '0.005', '0.0185'):
        short = write(args, 'restart_short.nml', ARM + "&integrator h = 1e-3, t_end = %s /\n"
                      "&run output = 'restart_short.h5' /\n" % t_end)
        expect(args, 'restart to t_end = %s' % t_end,
               [short, '--restart', results, '--output-dir', args.work, '--quiet'], 2,
               ['--restart "%s"' % results, 't = 0.019 s', 't_end = %s s' % t_end])
    # the control: a later t_end continues
    longer = write(args, 'restart_longer.nml', ARM + "&integrator h = 1e-3, t_end = 0.03 /\n"
                   "&run output = 'restart_longer.h5' /\n")
    expect(args, 'restart to t_end = 0.03 (control)',
           [longer, '--restart', results, '--output-dir', args.work, '--quiet'], 0, [])


GEO = """SetFactory("OpenCASCADE");
Box(1) = {0, 0, 0, 0.02, 0.01, 0.01};
Box(2) = {0.02, 0, 0, 0.02, 0.01, 0.01};
Coherence;
e = 1e-6;
tops() = Surface In BoundingBox{-e, -e, 0.01 - e, 0.04 + e, 0.01 + e, 0.01 + e};
left() = Surface In BoundingBox{-e, -e, -e, e, 0.01 + e, 0.01 + e};
right() = Surface In BoundingBox{0.04 - e, -e, -e, 0.04 + e, 0.01 + e, 0.01 + e};
bottoms() = Surface In BoundingBox{-e, -e, -e, 0.04 + e, 0.01 + e, e};
Physical Volume("a", 1) = {1};
Physical Volume("b", 2) = {2};
Physical Surface("tops", 1) = {tops()};
Physical Surface("left", 2) = {left()};
Physical Surface("right", 3) = {right()};
Physical Surface("a_and_right", 4) = {left(), right()};
Physical Surface("bottoms", 5) = {bottoms()};
Mesh.CharacteristicLengthMax = 0.005;
"""


def class_surfaces(args):
    geo = write(args, 'two_boxes.geo', GEO)
    mesh = os.path.join(args.work, 'two_boxes.msh')
    subprocess.run([args.gmsh, '-3', '-format', 'msh41', '-o', mesh, geo], check=True,
                   capture_output=True, timeout=120)
    text = open(mesh).read()
    for k, surface in enumerate(('tops', 'a_and_right', 'bottoms')):
        case = write(args, 'span_%d.nml' % k,
                     "&body name = 'left_box', mesh_file = 'two_boxes.msh', volumes = 'a' /\n"
                     "&interface body = 'left_box', name = 'left' /\n"
                     "&interface body = 'left_box', name = '%s', rc = '' /\n" % surface)
        expect(args, 'surface %s spans two bodies' % surface, [case, '--check'], 2,
               ["physical surface '%s'" % surface, "'a'", 'triangles are not faces',
                'two_boxes.msh'])
    # the control: each box's own surfaces pass
    case = write(args, 'span_ok.nml',
                 "&body name = 'left_box', mesh_file = 'two_boxes.msh', volumes = 'a' /\n"
                 "&interface body = 'left_box', name = 'left' /\n"
                 "&body name = 'right_box', mesh_file = 'two_boxes.msh', volumes = 'b' /\n"
                 "&interface body = 'right_box', name = 'right' /\n")
    expect(args, 'surfaces on their bodies (control)', [case, '--check'], 0, [])
    # physical names equal up to trailing blanks: a duplicate
    for k, (old, new) in enumerate((('"right"', '"left "'), ('"right"', '"left   "'),
                                    ('"b"', '"a "'))):
        dup = write(args, 'dup_names_%d.msh' % k, text.replace(old, new, 1))
        case = write(args, 'dup_names_%d.nml' % k,
                     "&body name = 'box', mesh_file = 'dup_names_%d.msh', volumes = 'a' /\n"
                     "&interface body = 'box', name = 'left' /\n" % k)
        expect(args, 'names %s and %s' % (old, new), [case, '--check'], 2,
               ['dup_names_%d.msh' % k, "'%s' and '%s', equal up to trailing blanks"
                % (new.strip('"').rstrip(), new.strip('"'))])
    # names compared exactly: a group named "left " (one blank) is not the case's 'left'
    for k, padded in enumerate(('"left "', '"left  "', '" left"')):
        mesh = write(args, 'padded_%d.msh' % k, text.replace('"left"', padded, 1))
        case = write(args, 'padded_%d.nml' % k,
                     "&body name = 'box', mesh_file = 'padded_%d.msh', volumes = 'a' /\n"
                     "&interface body = 'box', name = 'left' /\n" % k)
        expect(args, 'only %s in the mesh, the case names left' % padded, [case, '--check'], 2,
               ['padded_%d.msh' % k, "'left'", padded.strip('"')])


def main():
    parser = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    parser.add_argument('--driver', required=True)
    parser.add_argument('--work', required=True)
    parser.add_argument('--class', dest='klass', required=True)
    parser.add_argument('--mesh-dir', default='')
    parser.add_argument('--input-dir', default='')
    parser.add_argument('--gmsh', default='gmsh')
    args = parser.parse_args()
    args.work = os.path.abspath(os.path.join(args.work, args.klass))
    args.driver = os.path.abspath(args.driver)
    args.mesh_dir = os.path.abspath(args.mesh_dir) if args.mesh_dir else ''
    args.input_dir = os.path.abspath(args.input_dir) if args.input_dir else ''
    shutil.rmtree(args.work, ignore_errors=True)
    os.makedirs(args.work)
    globals()['class_' + args.klass](args)
    if failures:
        print('\n%d failure(s):' % len(failures))
        for failure in failures:
            print('  ' + failure)
        return 1
    print('all variants passed')
    return 0


if __name__ == '__main__':
    sys.exit(main())
