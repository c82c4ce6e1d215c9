"""Run the ffrf driver and the C API test program on the same cases and compare.

The driver writes <out>/driver/*.h5; test_capi_run prints what the C API returns and writes
<out>/capi/*.h5 (modal case with an output folder). Checked:
  - frequencies: C API == driver's /bodies/<name>/modes/frequency, bitwise (both call the same
    compute_body_modes; the API's run without an output folder is checked equal in C);
  - the C API's results file of the modal case: frequencies bitwise equal to the driver's;
  - mechanism advanced in chunks: crank angle and speed at the end of every chunk against the
    driver's /time/{crank_angle, crank_speed} at the same t, |difference| <= 1e-10 (issue 11;
    with chunks that are multiples of h the steps are the driver's, so 0 is expected);
  - joint reactions and body positions at t_end against the driver's last rows (1e-10
    relative to the largest value of each quantity).
Usage: compare_driver.py FFRF TEST_CAPI_RUN MODAL_CASE MECHANISM_CASE MESH_DIR OUT_DIR CHUNK
"""
import argparse
import os
import subprocess
import sys

import h5py
import numpy as np


def run(command):
    print('+', ' '.join(command), flush=True)
    done = subprocess.run(command, stdout=subprocess.PIPE, text=True)
    if done.returncode != 0:
        sys.exit(f'{command[0]} failed with exit code {done.returncode}')
    return done.stdout


def output_name(case_file):
    for line in open(case_file):
        if line.strip().startswith('&run') and 'output' in line:
            return line.split("output")[1].split("'")[1]
    return os.path.splitext(os.path.basename(case_file))[0] + '.h5'


def main():
    p = argparse.ArgumentParser()
    for name in ('ffrf', 'test_program', 'modal_case', 'mechanism_case', 'mesh_dir', 'out_dir',
                 'chunk'):
        p.add_argument(name)
    a = p.parse_args()
    driver_dir = os.path.join(a.out_dir, 'driver')
    capi_dir = os.path.join(a.out_dir, 'capi')
    os.makedirs(driver_dir, exist_ok=True)
    os.makedirs(capi_dir, exist_ok=True)
    for case in (a.modal_case, a.mechanism_case):
        run([a.ffrf, case, '--mesh-dir', a.mesh_dir, '--output-dir', driver_dir, '--quiet'])
    lines = run([a.test_program, a.modal_case, a.mechanism_case, a.mesh_dir, capi_dir,
                 a.chunk]).splitlines()
    failures = []

    # frequencies
    modal = h5py.File(os.path.join(driver_dir, output_name(a.modal_case)), 'r')
    modal_capi = h5py.File(os.path.join(capi_dir, output_name(a.modal_case)), 'r')
    api = {}
    for line in lines:
        w = line.split()
        if w[0] == 'frequency':
            api.setdefault(w[1], []).append(float(w[3]))
    for body, hz in api.items():
        driver = modal[f'/bodies/{body}/modes/frequency'][()]
        written = modal_capi[f'/bodies/{body}/modes/frequency'][()]
        diff = np.max(np.abs(np.array(hz) - driver)) if len(hz) == len(driver) else np.inf
        print(f'{body}: {len(hz)} frequencies {hz[0]:.6f} .. {hz[-1]:.6f} Hz, largest '
              f'difference to the driver {diff:.3g} Hz (bitwise expected)')
        if len(hz) != len(driver) or not np.array_equal(np.array(hz), driver):
            failures.append(f'{body}: C API frequencies differ from the driver by {diff}')
        if not np.array_equal(written, driver):
            failures.append(f'{body}: the C API results file differs from the driver\'s')

    # mechanism: crank after every chunk
    mech = h5py.File(os.path.join(driver_dir, output_name(a.mechanism_case)), 'r')
    t_series = mech['/time/t'][()]
    angle_series = mech['/time/crank_angle'][()]
    speed_series = mech['/time/crank_speed'][()]
    worst_angle = worst_speed = 0.0
    chunks = 0
    for line in lines:
        w = line.split()
        if w[0] != 'crank':
            continue
        t, angle, speed = map(float, w[1:4])
        row = int(np.argmin(np.abs(t_series - t)))
        if abs(t_series[row] - t) > 1e-9:
            failures.append(f'no driver step at t = {t}')
            continue
        worst_angle = max(worst_angle, abs(angle - angle_series[row]))
        worst_speed = max(worst_speed, abs(speed - speed_series[row]))
        chunks += 1
    print(f'mechanism: {chunks} states of {a.chunk} s chunks, largest |crank angle difference| '
          f'{worst_angle:.3g} rad, |crank speed difference| {worst_speed:.3g} rad/s '
          f'(driver final: {angle_series[-1]:.9f} rad, {speed_series[-1]:.9f} rad/s)')
    if chunks < 2 or worst_angle > 1e-10 or worst_speed > 1e-10:
        failures.append('chunked crank state differs from the driver by more than 1e-10')

    # reactions and positions at t_end
    for line in lines:
        w = line.split()
        if w[0] == 'reaction':
            api_values = np.array(list(map(float, w[2:14])))
            driver = mech[f'/joints/{w[1]}/reaction'][()][-1]
            scale = max(np.max(np.abs(driver)), 1.0)
            diff = np.max(np.abs(api_values - driver))
            print(f'reaction {w[1]}: largest difference {diff:.3g} (largest value {scale:.4g})')
            if diff > 1e-10 * scale:
                failures.append(f'reaction {w[1]} differs by {diff}')
        elif w[0] == 'position':
            api_values = np.array(list(map(float, w[2:5])))
            driver = mech[f'/bodies/{w[1]}/position'][()][-1]
            diff = np.max(np.abs(api_values - driver))
            if diff > 1e-12:
                failures.append(f'position of {w[1]} differs by {diff}')
    if failures:
        print('FAILED:\n  ' + '\n  '.join(failures))
        return 1
    print('compare_driver: C API equals the driver')
    return 0


if __name__ == '__main__':
    sys.exit(main())
