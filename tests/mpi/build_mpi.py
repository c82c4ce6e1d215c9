#!/usr/bin/env python3
"""Fixture mpi_build of the sequential build's ctest (tests/mpi/mpi.cmake): configure and build
the MPI variant (-DFFRF_MPI=ON) of this source tree into BUILD: the library, the driver and the
MPI host program only (no LTO, no sequential test tree). Writes BUILD/mpi_build_status.txt:
status=built with the paths of mpirun, the MPI driver and the host program, or status=skipped
with the reason (no mpicc/mpif90/mpirun, no MPI MUMPS or PARPACK: `.ci/install-deps --mpi`); the MPI tests
then exit 77 (skipped). A failing configure or build where everything is installed fails."""
import argparse
import os
import shutil
import subprocess
import sys


def write_status(build, **fields):
    with open(os.path.join(build, 'mpi_build_status.txt'), 'w') as f:
        for k, v in fields.items():
            f.write(f'{k}={v}\n')


def main():
    p = argparse.ArgumentParser()
    p.add_argument('--source', required=True)
    p.add_argument('--build', required=True)
    p.add_argument('--cmake', default='cmake')
    p.add_argument('--jobs', default='2')
    a = p.parse_args()
    os.makedirs(a.build, exist_ok=True)
    missing = [tool for tool in ('mpicc', 'mpif90', 'mpirun') if shutil.which(tool) is None]
    if not os.path.exists('/usr/include/dmumps_struc.h') or not any(
            os.path.exists(os.path.join(d, 'libdmumps.so'))
            for d in ('/usr/lib/x86_64-linux-gnu', '/usr/lib64', '/usr/lib')):
        missing.append('MPI MUMPS (libmumps-dev)')
    if not any(os.path.exists(os.path.join(d, 'libparpack.so'))
               for d in ('/usr/lib/x86_64-linux-gnu', '/usr/lib64', '/usr/lib')):
        missing.append('PARPACK (libparpack2-dev)')
    if missing:
        reason = ('not installed: ' + ', '.join(missing) +
                  '; install with .ci/install-deps --mpi')
        write_status(a.build, status='skipped', reason=reason)
        print(f'skipped: {reason}')
        return 0
    configure = [a.cmake, '-S', a.source, '-B', a.build, '-G', 'Ninja',
                 '-DCMAKE_BUILD_TYPE=Release', '-DFFRF_MPI=ON', '-DFFRF_LTO=OFF']
    build = [a.cmake, '--build', a.build, '-j', a.jobs, '--target', 'ffrf', 'mpi_host_program']
    for cmd in (configure, build):
        print('+ ' + ' '.join(cmd), flush=True)
        done = subprocess.run(cmd, capture_output=True, text=True)
        if done.returncode != 0:
            sys.stdout.write(done.stdout[-6000:])
            sys.stderr.write(done.stderr[-6000:])
            write_status(a.build, status='failed', reason='the MPI build failed (see mpi_build)')
            return 1
    write_status(a.build, status='built', mpirun=shutil.which('mpirun'),
                 driver=os.path.join(a.build, 'driver', 'ffrf'),
                 host_program=os.path.join(a.build, 'tests', 'mpi', 'mpi_host_program'))
    print(f'MPI build ready in {a.build}')
    return 0


if __name__ == '__main__':
    sys.exit(main())
