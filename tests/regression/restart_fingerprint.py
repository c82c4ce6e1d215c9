#!/usr/bin/env python3
"""The restart fingerprint (issue 23 item 3, issue 28 item 2; docs/restart.md), entry by entry.

Usage: restart_fingerprint.py FFRF MESH_DIR CASE RESULTS WORK

CASE is a mechanism case and RESULTS the results file of its run (a finished run holds its restart
state). The table of what a restart depends on is the file's own /checkpoint/fingerprint_input:
for every entry of it, one `--set` changes that input alone, and `ffrf CASE --restart RESULTS`
must end with exit 2 and one error line naming the entry's label and both values, before any
modes are computed (no [modes] line in the log). So an input added to the echo is tested without
touching this script; an entry this script cannot change is a failure (the table below grows).
Then the model entries (/checkpoint/fingerprint_model): a mesh with one node moved by 1e-9 m
(same name, same counts: 'node coordinates' named), Young's modulus changed in its 14th digit
(equal in the 12-digit echo: 'modes material: young' named), and the keys that may change
(t_end, outputs, energy watch, progress, checkpoints) all changed at once: the restart runs (exit
0) and the continued file records its origin (/restart_origin: file, time of the restart state,
fingerprint hash).
"""
import os
import re
import shutil
import subprocess
import sys

import h5py

failures = []


def check(condition, what):
    print(('ok   ' if condition else 'FAIL ') + what)
    if not condition:
        failures.append(what)


# A value for each choice, different from the one in the base case and valid for the key; the
# other keys are changed by their type (numbers scaled, logicals negated).
ALTERNATIVE = {
    'mpc': {"'RBE3'": "'RBE2'", "'RBE2'": "'RBE3'"},
    'weighting': {"'uniform'": "'area'", "'area'": "'uniform'"},
    'virtual_node': {"'position'": "'centroid'", "'centroid'": "'position'"},
    'rc': None,  # drop the last dof
    'formulation': {"'multipliers'": "'null_space'", "'null_space'": "'multipliers'"},
    'basis': {"'rc_normal'": "'craig_bampton'", "'craig_bampton'": "'rc_normal'"},
    'jacobian': {"'step'": "'full'", "'full'": "'step'", "'adaptive'": "'step'"},
    'selection': {"'auto'": "'manual'", "'manual'": "'auto'"},
    'type': {"'revolute'": "'spherical'", "'prismatic'": "'revolute'", "'fixed'": "'revolute'",
             "'cylindrical'": "'revolute'",
             "'flexible'": "'rigid'", "'rigid'": "'flexible'", "'drag'": "'torque'",
             "'starter'": "'torque'", "'pressure'": "'force'"},
}


# Keys that name another group's item (and a body's type, which decides whether its interfaces
# exist): changed alone they make an invalid case.
STRUCTURAL = ('body', 'body1', 'body2', 'marker', 'marker1', 'marker2', 'crank', 'volumes')


def structural(label):
    group, key = label.split('[')[0].split('.')[0], label.rsplit('.', 1)[1]
    return key in STRUCTURAL or (group == 'body' and key == 'type')


def changed(key, value):
    """Another valid value of `key` (as echoed), or None when there is no rule."""
    if key in ALTERNATIVE and ALTERNATIVE[key] is not None:
        return ALTERNATIVE[key].get(value)
    if key == 'rc':
        dofs = value.strip("'").split()
        return "'" + ' '.join(dofs[:-1] if dofs else ['Tx']) + "'"
    if key == 'lanczos_vectors' and value == '0':
        return '40'
    if value in ('.true.', '.false.'):
        return '.false.' if value == '.true.' else '.true.'
    if value.startswith("'"):
        inner = value.strip("'")
        if key == 'rc_label':
            return "'another label'"
        if key == 'table_file':
            return 'SKIP'
        # a reference to another body or marker: the first other name of its kind is chosen
        # by the caller
        return ('REFERENCE', inner)
    items = re.split(r'[,\s]+', value.strip())
    try:
        numbers = [float(x) for x in items]
    except ValueError:
        return None
    first = numbers[0]
    if re.fullmatch(r'-?\d+', items[0]):
        new_first = str(int(first) + 1)
    else:
        new_first = repr(first * 1.25 + (0.001 if first == 0 else 0.0))
    return ', '.join([new_first] + items[1:])


def run(ffrf, case, mesh_dir, out_dir, *more):
    os.makedirs(out_dir, exist_ok=True)
    return subprocess.run([ffrf, case, '--mesh-dir', mesh_dir, '--output-dir', out_dir, *more],
                          capture_output=True, text=True, timeout=600)


def main():
    if len(sys.argv) != 6:
        raise SystemExit(__doc__)
    ffrf, mesh_dir, case, results, work = (os.path.abspath(a) for a in sys.argv[1:])
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    with h5py.File(results, 'r') as f:
        inputs = [x.decode() for x in f['/checkpoint/fingerprint_input'][()]]
        model = [x.decode() for x in f['/checkpoint/fingerprint_model'][()]]
    check(len(inputs) > 100, f'{len(inputs)} input entries in the restart fingerprint')
    check(not any(re.match(r'(integrator\.t_end|run\.output|run\.title)=', e) for e in inputs),
          'the keys that may change (t_end, output, title) are not in it')
    # the fingerprint holds every key of the echo but those docs/restart.md says may change
    echo = subprocess.run([ffrf, case, '--print-input'], capture_output=True, text=True).stdout
    may_change = documented_may_change()
    expected = set()
    for line in echo.splitlines():
        m = re.match(r'&(\w+) (.*)/\s*$', line)
        if not m:
            continue
        group = m.group(1)
        for key in re.findall(r"(?:^|, )(\w+) = ", m.group(2)):
            if key != 'name' and f'{group}.{key}' not in may_change:
                expected.add(f'{group}.{key}')
    found = {re.sub(r'\[[^\]]*\]', '', e.split('=', 1)[0]) for e in inputs}
    check(found == expected, f'fingerprint keys = echo keys but the {len(may_change)} documented '
          f'ones ({len(found)} keys); missing {sorted(expected - found)}, extra {sorted(found - expected)}')
    names = {}
    for entry in inputs:
        m = re.match(r'(\w+)\[([^\]#]+)\]\.', entry)
        if m:
            names.setdefault(m.group(1), []).append(m.group(2))
    tried = 0
    for k, entry in enumerate(inputs):
        label, value = entry.split('=', 1)
        if '#' in label:
            # a second instance of one name (markers of two bodies): --set cannot address it
            continue
        key = label.rsplit('.', 1)[1]
        new = changed(key, value)
        if isinstance(new, tuple):
            group_of_reference = {'body': 'body', 'body1': 'body', 'body2': 'body',
                                  'marker': 'marker', 'marker1': 'marker', 'marker2': 'marker',
                                  'crank': 'body', 'volumes': None}.get(key)
            candidates = sorted(set(names.get(group_of_reference, [])) - {new[1]}) \
                if group_of_reference else []
            new = "'" + (candidates[0] if candidates else new[1] + 'x') + "'"
        if new == 'SKIP':
            # a pressure table needs a file of its own; its name is compared, not its content
            print(f'skip {label}: not changed alone here (a table file of its own)')
            continue
        check(new is not None, f'{label}: a changed value ({value})')
        if new is None:
            continue
        tried += 1
        out = run(ffrf, case, mesh_dir, os.path.join(work, f'entry{k}'), '--set', f'{label}={new}',
                  '--restart', results)
        lines = [l for l in out.stderr.splitlines() if l.strip()]
        refused = (out.returncode == 2 and len(lines) == 1 and '[modes]' not in out.stdout)
        if structural(label):
            # a reference changed alone is not a valid case: the case check refuses it first,
            # naming the new reference (the restart would refuse it too)
            instance = re.search(r'\[(.*)\]', label)
            ok = refused and (f'{label} = ' in lines[0] or new.strip("'") in lines[0] or
                              (instance is not None and f'"{instance.group(1)}"' in lines[0]))
        else:
            ok = refused and 'not a run of this model' in lines[0] and f'{label} = ' in lines[0]
        check(ok, f'{label} = {new} (was {value}): exit {out.returncode}, '
              f'{lines[-1] if lines else "no message"}')
    check(tried >= 0.9 * len(inputs), f'{tried} of {len(inputs)} entries changed one by one')

    # model entries: the mesh moved by 1e-9 m at one node, under the same name
    bodies = sorted({m.group(1) for m in (re.match(r'body\[(\w+)\]\.modes mesh', e) for e in model) if m})
    check(len(bodies) >= 1, f'model entries of the flexible bodies {bodies}')
    with open(case) as f:
        text = f.read()
    body = bodies[0]
    mesh_name = re.search(r"name\s*=\s*'" + body + r"'[^/]*?mesh_file\s*=\s*'([^']+)'", text).group(1)
    moved_dir = os.path.join(work, 'moved_mesh')
    os.makedirs(moved_dir)
    for name in os.listdir(mesh_dir):
        if name.endswith('.msh'):
            shutil.copy(os.path.join(mesh_dir, name), moved_dir)
    moved = move_one_node(os.path.join(moved_dir, mesh_name))
    out = run(ffrf, case, moved_dir, os.path.join(work, 'moved'), '--restart', results)
    check(out.returncode == 2 and f'body[{body}].modes mesh: node coordinates = hash' in out.stderr,
          f'{mesh_name} with node {moved} moved by 1e-9 m: exit {out.returncode}, {out.stderr.strip()}')
    young = re.search(r"body\[" + body + r"\]\.young=(\S+)", '\n'.join(inputs)).group(1)
    nudged = repr(float(young) * (1 + 3e-14))
    out = run(ffrf, case, mesh_dir, os.path.join(work, 'young'), '--set', f'body[{body}].young={nudged}',
              '--restart', results)
    check(out.returncode == 2 and f'body[{body}].modes material: young = ' in out.stderr,
          f'young {young} -> {nudged} (equal in the echo): exit {out.returncode}, {out.stderr.strip()}')

    # what may change, all at once: the restart runs and records its origin
    with h5py.File(results, 'r') as f:
        t_end = float(f['/time/t'][-1])
    out = run(ffrf, case, mesh_dir, os.path.join(work, 'may_change'),
              '--set', f'integrator.t_end={t_end + 0.002!r}', '--set', "run.title='another title'",
              '--set', "run.output='continued.h5'", '--set', "integrator.energy_watch='off'",
              '--set', 'mechanism.progress_interval=0.5', '--set', 'integrator.checkpoint_steps=7',
              '--set', "run.log_level='debug'", '--set', 'integrator.energy_watch_tolerance=1e-3',
              '--restart', results)
    check(out.returncode == 0, f'restart with t_end, title, output, watch and its tolerance, '
          f'progress, checkpoints, log level changed: exit {out.returncode} {out.stderr.strip()}')
    continued = os.path.join(work, 'may_change', 'continued.h5')
    if os.path.exists(continued):
        with h5py.File(continued, 'r') as f, h5py.File(results, 'r') as source:
            origin_file = [x.decode() for x in f['/restart_origin/file'][()]]
            origin_time = f['/restart_origin/time'][()]
            origin_hash = [x.decode() for x in f['/restart_origin/fingerprint'][()]]
            n = int(source['/checkpoint/num_steps'][()][0])
            state_time = float(source['/time/t'][n - 1])
        check(origin_file == [results], f'/restart_origin/file {origin_file}')
        check(len(origin_time) == 1 and origin_time[0] == state_time,
              f'/restart_origin/time {origin_time} = the restart state\'s time {state_time}')
        check(len(origin_hash) == 1 and re.fullmatch(r'[0-9a-f]{16}', origin_hash[0]) is not None,
              f'/restart_origin/fingerprint {origin_hash}')
    if failures:
        print(f'{len(failures)} failure(s)')
        sys.exit(1)


def documented_may_change():
    """GROUP.KEY of the keys docs/restart.md says may change (its table, first column: `a.b`,
    then keys of the same group as `c`)."""
    doc = os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', '..', 'docs', 'restart.md')
    keys = set()
    with open(doc) as f:
        for line in f:
            if not line.startswith('| `'):
                continue
            group = None
            for item in re.findall(r'`([\w.]+)`', line.split('|')[1]):
                if '.' in item:
                    group, key = item.split('.')
                else:
                    key = item
                keys.add(f'{group}.{key}')
    return keys


def move_one_node(path):
    """Move the first node of the mesh's $Nodes block (Gmsh 4.1 ASCII) by 1e-9 m in x."""
    with open(path) as f:
        lines = f.read().split('\n')
    start = lines.index('$Nodes')
    k = start + 2                                  # first entity block header
    num_in_block = int(lines[k].split()[3])
    tag_line = k + 1
    coordinate_line = k + 1 + num_in_block         # coordinates of the block's first node
    x, y, z = (float(v) for v in lines[coordinate_line].split()[:3])
    lines[coordinate_line] = f'{x + 1e-9!r} {y!r} {z!r}'
    with open(path, 'w') as f:
        f.write('\n'.join(lines))
    return lines[tag_line].strip()


if __name__ == '__main__':
    main()
