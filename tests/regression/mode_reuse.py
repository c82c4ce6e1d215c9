#!/usr/bin/env python3
"""Mode reuse (&body modes_file, issue 12 part 4): runs the ffrf driver on the lc = 8 mm engine
(flexible crank RC set 1 and conrod, 10 modes each, h = 1e-4 s, 20 ms) and checks with h5py.

    mode_reuse.py TEST FFRF MESH_DIR CASE_DIR WORK_DIR

TEST is one of
  bitwise   the engine with both bodies' modes taken from the results file of a computed run
            gives that run's results bit for bit (every dataset and attribute except the
            timings, library versions, wall times and the input echo; the Gmsh animations byte
            for byte), and computes no modes; likewise with the crank's modes from a modal run
            of the crank alone (same interfaces, 10 modes) and the conrod's computed
  errors    bad uses, each exit 2 (input) or 3 (file) with one stderr line matching a regex:
            a missing file, a file that is not HDF5, a truncated one, a file without the
            body's modes, and a
            file whose modes were computed for another mesh, material, interface RC or number
            of modes; modes_file in a modal run and on a rigid body
  check     `ffrf --check` on the same cases: with the computed run's file for both bodies
            (and the modal run's for the crank) exit 0, the fingerprints matching; every
            refusal of `errors` with the run's exit code and message (the run's own check,
            check_stored_modes), the stderr line of --check equal to the run's for the mesh,
            material and interface cases
  fields    every entry of the crank's modes fingerprint (read from the source file, so a new
            entry without a change listed in FIELD_CHANGES fails) changed alone: exit 2 with
            one line naming the component and the entry ('the material differs (poisson ...')
CASE_DIR holds engine_lc8_rc1.nml (tests/engine of the build). Any failure exits 1.
"""
import os
import re
import shutil
import subprocess
import sys

import h5py
import numpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from bitwise import digest_h5  # noqa: E402

FAILURES = []
# what a reused run may change: wall-clock figures (as bitwise.py) and the input echo, which
# names the modes_file (and the --set lines that gave it)
IGNORED = ('input/namelist',)


def check(condition, what):
    print(('ok     ' if condition else 'FAILED ') + what, flush=True)
    if not condition:
        FAILURES.append(what)


def run(ffrf, case, mesh_dir, out_dir, *more):
    env = dict(os.environ, OPENBLAS_NUM_THREADS='1')
    result = subprocess.run([ffrf, case, '--mesh-dir', mesh_dir, '--output-dir', out_dir, *more],
                            capture_output=True, text=True, env=env, timeout=600)
    return result.returncode, result.stdout, result.stderr


def make_case(source, target, replacements):
    text = open(source).read()
    for old, new in replacements:
        if old not in text:
            raise SystemExit(f'{source}: "{old}" not found')
        text = text.replace(old, new, 1)
    with open(target, 'w') as f:
        f.write(text)
    return target


def engine_case(case_dir, work):
    """The lc 8 mm engine, 20 ms (200 steps of 1e-4 s), no animation frames change."""
    return make_case(os.path.join(case_dir, 'engine_lc8_rc1.nml'), os.path.join(work, 'engine.nml'),
                     [('t_end = 0.1', 't_end = 0.02')])


def crank_modal_case(engine, work):
    """A modal case of the engine's crank alone: its &body (mesh, material) and &interface
    groups, 10 modes."""
    text = open(engine).read()
    body = re.search(r"&body name = 'crank'.*?/\n", text, re.S).group(0)
    body = body.replace(" type = 'flexible', num_modes = 10,", '')
    body = re.sub(r",\s*coarse_meshes = [^/]*", ' ', body)
    interfaces = re.findall(r"&interface body = 'crank'.*?/\n", text, re.S)
    target = os.path.join(work, 'crank_modal.nml')
    with open(target, 'w') as f:
        f.write("&run title = 'engine crank alone', mode_shapes_msh = 'none' /\n" + body +
                ''.join(interfaces) + '&modes num_modes = 10 /\n')
    return target


def compare_runs(reference, other, label):
    a = digest_h5(reference)
    b = digest_h5(other)
    keys = [k for k in a if k not in IGNORED]
    differ = [k for k in keys if k not in b or b[k]['sha256'] != a[k]['sha256']]
    extra = [k for k in b if k not in a and k not in IGNORED]
    check(not differ and not extra,
          f'{label}: {len(keys)} datasets and attributes bitwise equal to the computed run'
          + (f'; differ: {differ[:8]}' if differ else '') + (f'; extra: {extra[:8]}' if extra else ''))


def same_bytes(a, b):
    with open(a, 'rb') as f, open(b, 'rb') as g:
        return f.read() == g.read()


def test_bitwise(ffrf, mesh_dir, case_dir, work):
    case = engine_case(case_dir, work)
    code, out, err = run(ffrf, case, mesh_dir, work, '--output', 'computed.h5')
    check(code == 0, f'computed run (exit {code}) {err.strip()}')
    computed = os.path.join(work, 'computed.h5')
    source = os.path.join(work, 'modes_source.h5')
    os.replace(computed, source)
    # the computed run again under the name the comparison uses (its own animations)
    code, out, err = run(ffrf, case, mesh_dir, work, '--output', 'computed.h5')
    check(code == 0, f'computed run again (exit {code})')

    code, out, err = run(ffrf, case, mesh_dir, work, '--output', 'reused.h5',
                         '--set', f'body[crank].modes_file={source}',
                         '--set', f'body[conrod].modes_file={source}')
    check(code == 0, f'run with both bodies\' modes_file (exit {code}) {err.strip()}')
    check(len(re.findall(r'\[modes\] \w+: .* 10 modes from modes_file .* matches\)', out)) == 2,
          'both bodies take 10 modes from the file, fingerprints matching')
    # the [threads] line names the solvers each stage may use, not work done
    work_lines = '\n'.join(line for line in out.splitlines() if '[threads]' not in line)
    check('eigen' not in work_lines and 'MUMPS' not in work_lines and '[rc]' not in work_lines,
          'no eigen-solve, no factorisation in the reused run')
    compare_runs(computed, os.path.join(work, 'reused.h5'), 'both bodies reused')
    for body in ('crank', 'conrod'):
        check(same_bytes(os.path.join(work, f'computed_{body}_animation.msh'),
                         os.path.join(work, f'reused_{body}_animation.msh')),
              f'{body} animation byte for byte equal')

    # the crank's modes from a modal run of the crank alone
    modal = crank_modal_case(case, work)
    code, out, err = run(ffrf, modal, mesh_dir, work)
    check(code == 0, f'modal run of the engine crank (exit {code}) {err.strip()}')
    code, out, err = run(ffrf, case, mesh_dir, work, '--output', 'from_modal.h5',
                         '--set', f'body[crank].modes_file={os.path.join(work, "crank_modal.h5")}')
    check(code == 0, f'crank modes from the modal results (exit {code}) {err.strip()}')
    compare_runs(computed, os.path.join(work, 'from_modal.h5'), 'crank from a modal run')


# (what, --set overrides, exit code, regex of the one stderr line)
def error_cases(work):
    source = os.path.join(work, 'modes_source.h5')
    not_hdf5 = os.path.join(work, 'not_hdf5.h5')
    with open(not_hdf5, 'w') as f:
        f.write('this is not an HDF5 file\n')
    crank_only = os.path.join(work, 'crank_modal.h5')
    newer_schema = os.path.join(work, 'newer_schema.h5')
    shutil.copyfile(source, newer_schema)
    with h5py.File(newer_schema, 'r+') as f:
        f.attrs['schema_version'] = numpy.bytes_('99.0')  # fixed-length, as ffrf writes it
    truncated = os.path.join(work, 'truncated.h5')
    with open(source, 'rb') as f, open(truncated, 'wb') as g:
        g.write(f.read()[:os.path.getsize(source) // 2])
    return [
        ('missing file', [f'body[crank].modes_file={work}/missing.h5'], 3,
         r'&body "crank": modes_file ".*missing\.h5" does not exist$'),
        ('not HDF5', [f'body[crank].modes_file={not_hdf5}'], 3,
         r'&body "crank": modes_file ".*not_hdf5\.h5": not readable as HDF5 .*give the results '
         r'file \(\.h5\) of an earlier run'),
        ('truncated file', [f'body[crank].modes_file={truncated}'], 3,
         r'&body "crank": modes_file ".*truncated\.h5": not readable as HDF5'),
        ('newer results schema', [f'body[crank].modes_file={newer_schema}'], 2,
         r'&body "crank": modes_file ".*newer_schema\.h5": results schema "99\.0", this ffrf '
         r'reads up to 1\.x; use the ffrf that wrote the file'),
        ('no modes of the body', [f'body[conrod].modes_file={crank_only}'], 2,
         r'&body "conrod": modes_file ".*crank_modal\.h5": no mode shapes of body "conrod" in it '
         r'\(it holds the modes of "crank"\)'),
        ('mesh', [f'body[crank].modes_file={source}', 'body[crank].mesh_file=crank_lc10.msh'], 2,
         r'modes_file ".*modes_source\.h5": the mesh differs \(nodes \'4832\' here, \'8498\' in '
         r'the file\); its modes of body "crank" were computed for another model'),
        ('material', [f'body[crank].modes_file={source}', 'body[crank].young=200e9'], 2,
         r'the material differs \(young \'2E\+11 Pa\' here, \'2\.1E\+11 Pa\' in the file\)'),
        ('interface RC', [f'body[crank].modes_file={source}', 'interface[B2].rc=Tx Ty'], 2,
         r'the interfaces differ \(B2: rc \'Tx Ty\' here, \'none\' in the file\)'),
        ('number of modes', [f'body[conrod].modes_file={source}', 'body[conrod].num_modes=8'], 2,
         r'&body "conrod": modes_file ".*": the modes specification differs \(num_modes \'8\' '
         r'here, \'10\' in the file\)'),
        ('rigid body', [f'body[piston].modes_file={source}'], 2,
         r'--set body\[piston\]\.modes_file = .*: "piston": a rigid body has no modes; '
         r'modes_file is for flexible bodies$'),
    ]


def source_runs(ffrf, mesh_dir, case_dir, work):
    """The engine case and the crank's modal case, each run once: modes_source.h5 and
    crank_modal.h5 in work, the files the error cases name."""
    case = engine_case(case_dir, work)
    code, out, err = run(ffrf, case, mesh_dir, work, '--output', 'modes_source.h5', '--quiet')
    check(code == 0, f'source run (exit {code}) {err.strip()}')
    modal = crank_modal_case(case, work)
    code, out, err = run(ffrf, modal, mesh_dir, work, '--quiet')
    check(code == 0, f'modal source run (exit {code}) {err.strip()}')
    return case, modal


def refused(code, err, expected, pattern):
    """Exit `expected` with one stderr line 'ffrf: error: ...' matching `pattern`."""
    lines = err.splitlines()
    return (code == expected and len(lines) == 1 and lines[0].startswith('ffrf: error: ') and
            re.search(pattern, lines[0]) is not None)


def test_errors(ffrf, mesh_dir, case_dir, work):
    case, modal = source_runs(ffrf, mesh_dir, case_dir, work)
    for what, sets, expected, pattern in error_cases(work):
        args = [a for s in sets for a in ('--set', s)]
        code, out, err = run(ffrf, case, mesh_dir, work, '--output', 'refused.h5', '--quiet', *args)
        check(refused(code, err, expected, pattern),
              f'{what}: exit {code} (expected {expected}): {err.strip()}')
        check(not os.path.exists(os.path.join(work, 'refused.h5')), f'{what}: no results file')
    # modes_file in a modal run
    code, out, err = run(ffrf, modal, mesh_dir, work, '--output', 'refused.h5', '--quiet',
                         '--set', f'body[crank].modes_file={work}/modes_source.h5')
    lines = err.splitlines()
    check(code == 2 and len(lines) == 1 and re.search(
        r'"crank": a modal run computes the modes; modes_file takes them from an earlier run in '
        r'a mechanism run', lines[0]) is not None, f'modes_file in a modal run: exit {code}: {err.strip()}')


def test_check(ffrf, mesh_dir, case_dir, work):
    case, modal = source_runs(ffrf, mesh_dir, case_dir, work)
    source = os.path.join(work, 'modes_source.h5')
    code, out, err = run(ffrf, case, mesh_dir, work, '--check',
                         '--set', f'body[crank].modes_file={source}',
                         '--set', f'body[conrod].modes_file={source}')
    check(code == 0 and err == '', f'--check, both bodies\' modes_file matching: exit {code} '
          f'{err.strip()}')
    check(len(re.findall(r'\[check\] \w+: 10 modes in modes_file ".*modes_source\.h5", '
                         r'fingerprint [0-9a-f]{16} matches', out)) == 2,
          '--check names both bodies\' modes files as matching')
    code, out, err = run(ffrf, case, mesh_dir, work, '--check', '--set',
                         f'body[crank].modes_file={os.path.join(work, "crank_modal.h5")}')
    check(code == 0 and re.search(r'\[check\] crank: 10 modes in modes_file ".*crank_modal\.h5"'
                                  r', fingerprint [0-9a-f]{16} matches', out) is not None,
          f'--check, crank modes from the modal run matching: exit {code} {err.strip()}')
    for what, sets, expected, pattern in error_cases(work):
        args = [a for s in sets for a in ('--set', s)]
        code, out, err = run(ffrf, case, mesh_dir, work, '--check', '--quiet', *args)
        check(refused(code, err, expected, pattern),
              f'--check, {what}: exit {code} (expected {expected}): {err.strip()}')
        if what in ('mesh', 'material', 'interface RC'):
            run_code, _, run_err = run(ffrf, case, mesh_dir, work, '--output', 'refused.h5',
                                       '--quiet', *args)
            check(run_code == code and run_err == err,
                  f'--check, {what}: the run\'s exit code and message')


# Every entry of the modes fingerprint (src/modes/fingerprint.f90) and how to change that input
# alone in the engine case (issue 28 item 2): --set overrides, or a mesh edit. The labels come from
# the source file, so an entry added to the fingerprint without a row here fails the test.
# Entries no input changes alone name the entry that is seen first instead (`named`).
FIELD_CHANGES = {
    'nodes': {'sets': ['body[crank].mesh_file=crank_lc10.msh']},
    'elements': {'sets': ['body[crank].mesh_file=crank_lc10.msh'], 'named': 'nodes'},
    'node coordinates': {'mesh': 'move_node'},
    'connectivity': {'mesh': 'rotate_tet'},
    'young': {'sets': ['body[crank].young=2.2e11']},
    'poisson': {'sets': ['body[crank].poisson=0.29']},
    'density': {'sets': ['body[crank].density=7800']},
    'order': {'case': 'swap_interfaces'},
    'mpc': {'sets': ['interface[{i}].mpc=RBE2']},
    'weighting': {'sets': ['interface[{i}].weighting=area']},
    'rc': {'sets': ['interface[{i}].rc={rc}']},
    'virtual node': {'sets': ['interface[{i}].position={moved}']},
    # the node set and its weights follow from the mesh and the surface: changed with the mesh,
    # the mesh entries are named first
    'nodes@interface': {'sets': ['body[crank].mesh_file=crank_lc10.msh'], 'named': 'nodes'},
    'node set': {'sets': ['body[crank].mesh_file=crank_lc10.msh'], 'named': 'nodes'},
    'weights': {'sets': ['interface[{i}].weighting=area'], 'named': '{i}: weighting'},
    'num_modes': {'sets': ['body[crank].num_modes=8']},
    'basis': {'sets': ["modes.basis=craig_bampton"]},
    'formulation': {'sets': ['modes.formulation=null_space']},
    'shift_hz': {'sets': ['modes.shift_hz=100']},
    'tolerance': {'sets': ['modes.tolerance=1e-10']},
    'lanczos_vectors': {'sets': ['modes.lanczos_vectors=40']},
}


def mesh_lines(mesh_dir, work, name, mesh_name):
    """A copy of the mesh folder for an edited mesh; the lines of mesh `mesh_name`."""
    edited = os.path.join(work, name)
    os.makedirs(edited, exist_ok=True)
    for f in os.listdir(mesh_dir):
        if f.endswith('.msh'):
            with open(os.path.join(mesh_dir, f), 'rb') as src, \
                    open(os.path.join(edited, f), 'wb') as dst:
                dst.write(src.read())
    with open(os.path.join(edited, mesh_name)) as f:
        return edited, f.read().split('\n')


def edited_mesh(mesh_dir, work, how, mesh_name):
    """The crank's mesh (Gmsh 4.1 ASCII) with its first node moved by 1e-9 m in x, or with its first
    Tet10 listed from another corner (corners 0 1 2 3 -> 1 2 0 3, an even permutation: same
    element, same orientation, mid-edge nodes following their edges)."""
    folder, lines = mesh_lines(mesh_dir, work, how, mesh_name)
    if how == 'move_node':
        k = lines.index('$Nodes') + 2
        first = k + 1 + int(lines[k].split()[3])
        x, y, z = (float(v) for v in lines[first].split()[:3])
        lines[first] = f'{x + 1e-9!r} {y!r} {z!r}'
    else:
        k = lines.index('$Elements') + 2
        while int(lines[k].split()[2]) != 11:          # element type 11: Tet10
            k += 1 + int(lines[k].split()[3])
        tag, *nodes = lines[k + 1].split()
        order = [1, 2, 0, 3, 5, 6, 4, 9, 7, 8]          # Gmsh edges 01 12 20 30 32 31
        lines[k + 1] = ' '.join([tag] + [nodes[j] for j in order])
    with open(os.path.join(folder, mesh_name), 'w') as f:
        f.write('\n'.join(lines))
    return folder


def test_fields(ffrf, mesh_dir, case_dir, work):
    case, _ = source_runs(ffrf, mesh_dir, case_dir, work)
    source = os.path.join(work, 'modes_source.h5')
    import h5py
    with h5py.File(source, 'r') as f:
        group = f['/bodies/crank/modes/fingerprint']
        entries = [(c, x.decode()) for c in ('mesh', 'material', 'interfaces', 'modes')
                   for x in group[c][()]]
    check(len(entries) >= 20, f'{len(entries)} entries in the crank\'s modes fingerprint')
    # both ways: every input of the table is in the fingerprint (none forgotten by the code) ...
    present = set()
    for _, entry in entries:
        interface, _, field = entry.split('=', 1)[0].rpartition(': ')
        present.add(field + ('@interface' if interface and field == 'nodes' else ''))
    for key in FIELD_CHANGES:
        check(key in present, f'the fingerprint has the entry {key!r} (an input of the modes)')
    text = open(case).read()
    for component, entry in entries:
        label = entry.split('=', 1)[0]
        interface, _, field = label.rpartition(': ')
        key = field + ('@interface' if interface and field == 'nodes' else '')
        change = FIELD_CHANGES.get(key)
        # ... and every entry has its change here (none forgotten by this test)
        check(change is not None, f'{label}: a change of that input alone is listed')
        if change is None:
            continue
        mesh = mesh_dir
        sets = [f'body[crank].modes_file={source}']
        this_case = case
        value = entry.split('=', 1)[1]
        if 'mesh' in change:
            crank_mesh = re.search(r"name = 'crank'[^/]*?mesh_file = '([^']+)'", text).group(1)
            mesh = edited_mesh(mesh_dir, work, change['mesh'], crank_mesh)
        if change.get('case') == 'swap_interfaces':
            groups = re.findall(r"&interface body = 'crank'.*?/\n", text, re.S)
            swapped = text.replace(groups[0], '@@FIRST@@', 1).replace(groups[-1], groups[0], 1)
            this_case = os.path.join(work, 'swapped.nml')
            with open(this_case, 'w') as f:
                f.write(swapped.replace('@@FIRST@@', groups[-1], 1))
        if field == 'rc':
            dofs = value.split() if value != 'none' else []
            rc = ' '.join(dofs[:-1]) if dofs else 'Tx'
        else:
            rc = ''
        moved = ''
        if field == 'virtual node':
            xyz = [float(v) for v in re.findall(r'-?[\d.eE+-]+', value)[:3]]
            moved = f'{xyz[0]} {xyz[1] + 1e-3} {xyz[2]}'
        for s_ in change.get('sets', []):
            sets.append(s_.format(i=interface, rc=rc, moved=moved))
        named = change.get('named', label).format(i=interface)
        args = [a for s_ in sets for a in ('--set', s_)]
        code, out, err = run(ffrf, this_case, mesh, work, '--output', 'refused.h5', '--quiet', *args)
        words = {'mesh': 'the mesh differs', 'material': 'the material differs',
                 'interfaces': 'the interfaces differ', 'modes': 'the modes specification differs'}
        expected_component = 'mesh' if change.get('named') == 'nodes' else component
        pattern = re.escape(words[expected_component]) + r' \(' + re.escape(named) + " '"
        check(refused(code, err, 2, pattern),
              f'{label} changed alone ({" ".join(sets[1:]) or change}): exit {code}, '
              f'{err.strip()}')


def main(argv):
    if len(argv) != 6 or argv[1] not in ('bitwise', 'errors', 'check', 'fields'):
        print(__doc__)
        return 1
    test, ffrf, mesh_dir, case_dir, work = argv[1:]
    os.makedirs(work, exist_ok=True)
    {'bitwise': test_bitwise, 'errors': test_errors, 'check': test_check,
     'fields': test_fields}[test](
        os.path.abspath(ffrf), os.path.abspath(mesh_dir), os.path.abspath(case_dir),
        os.path.abspath(work))
    print(f'{len(FAILURES)} failure(s)')
    return 1 if FAILURES else 0


if __name__ == '__main__':
    sys.exit(main(sys.argv))
