#!/usr/bin/env python3
"""Benchmark of the C API (not a test): prints a CSV and writes it to --csv.

(a) modal: the same modal case run by the driver (results written to --work) and by a C program
    through the C API (examples/c_modal, nothing written), alternated, --runs times each; the
    median wall time of each and their ratio (target: the C API within 2 % of the driver).
(b) engine: the same engine integrated through the C API in one call to t_end with its own
    `drag` load, and advanced in 1 ms chunks with the host applying that torque itself at the
    crank (the case without its drag load, written to --work), alternated, --runs times each;
    medians of the integration time (after the modes and start: wall and process CPU time) and
    of the whole run, their ratio (target: chunks within 1.3x of the uninterrupted
    integration), and the difference of the crank angle and speed at t_end.
"""
import argparse
import csv
import os
import re
import statistics
import subprocess
import sys
import time


def wall(command):
    """Wall time (s) of a command; its standard output."""
    start = time.perf_counter()
    done = subprocess.run(command, check=True, capture_output=True, text=True)
    return time.perf_counter() - start, done.stdout


def summary(name, case, variant, times, reference=None):
    median = statistics.median(times)
    return {'benchmark': name, 'case': os.path.basename(case), 'variant': variant,
            'runs': len(times), 'median_s': f'{median:.4f}', 'min_s': f'{min(times):.4f}',
            'max_s': f'{max(times):.4f}',
            'ratio': f'{median / statistics.median(reference):.4f}' if reference else '1'}


def modal(args):
    os.makedirs(os.path.join(args.work, 'modal'), exist_ok=True)
    driver, api = [], []
    for _ in range(args.runs):
        driver.append(wall([args.driver, args.modal_case, '--mesh-dir', args.mesh_dir,
                            '--output-dir', os.path.join(args.work, 'modal'), '--quiet'])[0])
        api.append(wall([args.modal_program, args.modal_case, args.mesh_dir])[0])
    return [summary('modal', args.modal_case, 'driver (whole run)', driver),
            summary('modal', args.modal_case, 'C API (whole run)', api, driver)]


def without_drag(case, path):
    """The case without its &load group of type 'drag' (the host applies that torque)."""
    with open(case) as f:
        text = f.read()
    groups = re.findall(r"&load\b[^/]*type\s*=\s*'drag'[^/]*/", text)
    if len(groups) != 1:
        sys.exit(f'{case}: expected one &load of type drag, found {len(groups)}')
    coefficient = float(re.search(r'coefficient\s*=\s*([0-9.eEdD+-]+)', groups[0]).group(1)
                        .replace('d', 'e').replace('D', 'e'))
    with open(path, 'w') as f:
        f.write(text.replace(groups[0], '! (drag load applied by the host)'))
    return coefficient


def engine(args):
    os.makedirs(args.work, exist_ok=True)
    host_case = os.path.join(args.work, 'engine_host_torque.nml')
    coefficient = without_drag(args.engine_case, host_case)
    # the case's relative mesh paths are looked up in --mesh-dir, so the copy reads the same meshes
    runs = {'full': [], 'chunks': []}
    for _ in range(args.runs):
        for mode, case in (('full', args.engine_case), ('chunks', host_case)):
            seconds, out = wall([args.engine_program, case, args.mesh_dir, mode,
                                 str(args.chunk), repr(coefficient), str(args.body),
                                 str(args.marker)])
            fields = out.strip().splitlines()[-1].split(',')
            runs[mode].append({'whole': seconds, 'prepare': float(fields[2]),
                               'integrate': float(fields[3]), 'angle': float(fields[5]),
                               'speed': float(fields[6]), 'integrate CPU': float(fields[7])})
    rows = []
    for what in ('integrate', 'integrate CPU', 'whole'):
        full = [r[what] for r in runs['full']]
        chunks = [r[what] for r in runs['chunks']]
        rows.append(summary('engine', args.engine_case, f'C API one call ({what})', full))
        rows.append(summary('engine', args.engine_case,
                            f'C API {args.chunk * 1e3:g} ms chunks + host torque ({what})',
                            chunks, full))
    full, chunks = runs['full'][-1], runs['chunks'][-1]
    print(f'# engine at t_end: crank angle {full["angle"]:.10f} rad (one call) vs '
          f'{chunks["angle"]:.10f} rad (chunks), difference {chunks["angle"] - full["angle"]:.3e} '
          f'rad; speed {full["speed"]:.8f} vs {chunks["speed"]:.8f} rad/s, difference '
          f'{chunks["speed"] - full["speed"]:.3e} rad/s')
    return rows


def main():
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument('--driver', required=True, help='the ffrf driver')
    parser.add_argument('--modal-program', help='C API modal program (examples/c_modal)')
    parser.add_argument('--modal-case', help='modal case (.nml)')
    parser.add_argument('--engine-program', help='benchmark_api_engine')
    parser.add_argument('--engine-case', help="engine case (.nml) with one &load of type 'drag'")
    parser.add_argument('--body', type=int, default=0, help='crank body index (0-based)')
    parser.add_argument('--marker', type=int, default=2, help="crank marker of the drag load")
    parser.add_argument('--chunk', type=float, default=1e-3, help='chunk length (s)')
    parser.add_argument('--mesh-dir', required=True)
    parser.add_argument('--runs', type=int, default=5)
    parser.add_argument('--work', required=True, help='folder for results and the host case')
    parser.add_argument('--csv', help='CSV file to write')
    args = parser.parse_args()
    rows = []
    if args.modal_program and args.modal_case:
        rows += modal(args)
    if args.engine_program and args.engine_case:
        rows += engine(args)
    fields = ['benchmark', 'case', 'variant', 'runs', 'median_s', 'min_s', 'max_s', 'ratio']
    writer = csv.DictWriter(sys.stdout, fieldnames=fields, lineterminator='\n')
    writer.writeheader()
    writer.writerows(rows)
    if args.csv:
        os.makedirs(os.path.dirname(os.path.abspath(args.csv)), exist_ok=True)
        with open(args.csv, 'w', newline='') as f:
            writer = csv.DictWriter(f, fieldnames=fields, lineterminator='\n')
            writer.writeheader()
            writer.writerows(rows)


if __name__ == '__main__':
    main()
