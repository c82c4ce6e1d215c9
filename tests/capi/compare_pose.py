"""The body pose set through the C API against the driver's run with the pose as --set (issue
24, body pose: the API acts exactly as the namelist keys).

Runs the ffrf driver on the pose-free POSE_CASE (tests/capi/pose_pendulum.nml) with
--set body[rod].position/orientation/velocity/angular_velocity=... into OUT_DIR/driver, and
test_capi_pose, which sets the same pose through ffrf_body_set_pose and runs the case to t_end
with the output folder OUT_DIR/api (its own refusal checks first). Checked: every dataset and
attribute of the two results files bitwise equal (tests/regression/bitwise.py digest, wall-clock
figures left out), except the entries that hold the case echo, whose override comment lines
name where the pose came from ("--set ..." against "body_set_pose ..."); and the echoes equal
once those comment lines are dropped.
Usage: compare_pose.py FFRF TEST_CAPI_POSE POSE_CASE MESH_DIR OUT_DIR
"""
import os
import subprocess
import sys

import h5py

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', 'regression'))
import bitwise  # noqa: E402
from compare_driver import output_name  # noqa: E402

# the pose of tests/capi/pose_pendulum_posed.nml (test_capi_pose.c sets the same doubles)
POSE = ['body[rod].position=0.3, 0.0, -0.4',
        'body[rod].orientation=0.6, 0.0, 0.8, 0.0, 1.0, 0.0, -0.8, 0.0, 0.6',
        'body[rod].velocity=-0.8, 0.0, -0.6',
        'body[rod].angular_velocity=0.0, 2.0, 0.0']


def run(command):
    print('+', ' '.join(command), flush=True)
    if subprocess.run(command).returncode != 0:
        sys.exit(f'{command[0]} failed')


def echo_entries(path):
    """Names of the string datasets and attributes that hold the case echo."""
    names = []
    with h5py.File(path, 'r') as f:
        def visit(name, obj):
            for key, value in obj.attrs.items():
                if isinstance(value, (bytes, str)) and 'body_set_pose body[rod]' in str(value):
                    names.append(name + '@' + key)
            if isinstance(obj, h5py.Dataset) and obj.dtype.kind in 'OS':
                text = str(obj[()])
                if 'body_set_pose body[rod]' in text:
                    names.append(name)
        f.visititems(visit)
    return names


def main(ffrf, program, case, mesh_dir, out_dir):
    ffrf, program, case, mesh_dir, out_dir = map(os.path.abspath, (ffrf, program, case,
                                                                   mesh_dir, out_dir))
    driver, api = os.path.join(out_dir, 'driver'), os.path.join(out_dir, 'api')
    for folder in (driver, api):
        os.makedirs(folder, exist_ok=True)
    command = [ffrf, case, '--mesh-dir', mesh_dir, '--output-dir', driver]
    for setting in POSE:
        command += ['--set', setting]
    run(command)
    run([program, case, mesh_dir, api])
    name = output_name(case)
    a = bitwise.digest_h5(os.path.join(driver, name))
    b = bitwise.digest_h5(os.path.join(api, name))
    echoes = echo_entries(os.path.join(api, name))
    problems = []
    for key in sorted(set(a) | set(b)):
        if key not in a or key not in b:
            problems.append(f'{key}: in one file only')
        elif a[key]['sha256'] != b[key]['sha256'] and key not in echoes:
            problems.append(f'{key}: differs')
    if not echoes:
        problems.append('no echo entry names body_set_pose: the API run did not record it')
    for key in echoes:
        texts = []
        for path in (os.path.join(driver, name), os.path.join(api, name)):
            with h5py.File(path, 'r') as f:
                if '@' in key:
                    obj, attr = key.split('@')
                    value = f[obj].attrs[attr] if obj else f.attrs[attr]
                else:
                    value = f[key][()]
                text = value.decode() if isinstance(value, bytes) else str(value)
                texts.append([line for line in text.splitlines()
                              if not line.lstrip().startswith('!')])
        if texts[0] != texts[1]:
            problems.append(f'{key}: the echoes differ beyond the override comments')
    if problems:
        print(f'{len(problems)} of {len(a)} entries differ:')
        for p in problems:
            print('  ' + p)
        return 1
    print(f'pose: {len(a)} entries of {name} bitwise equal (the {len(echoes)} echo entries '
          'equal apart from the override comment lines)')
    return 0


if __name__ == '__main__':
    if len(sys.argv) != 6:
        sys.exit(__doc__)
    sys.exit(main(*sys.argv[1:]))
