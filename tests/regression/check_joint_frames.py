#!/usr/bin/env python3
"""Joint frames given at both ends (issue 24, docs/mechanisms.md "Joint frames"): a revolute
joint whose two &marker orientations agree in the starting pose to about 1e-10 (rounded to 10
decimals) runs as before. The rigid pendulum of tests/data/frames/rigid_pendulum_oriented.nml
(reference: the pivot's frame alone gives the joint its frame) turned as a whole by
R = R_z(30 deg) R_x(40 deg) (the pivot's frame, the rod's pose, gravity), with the rod further
turned by Q = R_x(25 deg) about its own axis (its inertia is symmetric about it) and its end
marker given the orientation Q^T P (P the unturned pivot frame): the rod's frame origin, turned
back by R^T, follows the reference run's to POSITION_TOL at every output step.
Usage: check_joint_frames.py REFERENCE.h5 TURNED.h5
"""
import sys

import h5py
import numpy as np

POSITION_TOL = 1.0e-10  # m; measured 1.1e-11 (the inputs are rounded to 1e-10)


def rotation():
    def rx(a):
        c, s = np.cos(a), np.sin(a)
        return np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])
    c, s = np.cos(np.radians(30.0)), np.sin(np.radians(30.0))
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]]) @ rx(np.radians(40.0))


def main():
    with h5py.File(sys.argv[1], 'r') as f:
        t_ref = f['time/t'][:]
        x_ref = f['bodies/rod/position'][:]
    with h5py.File(sys.argv[2], 'r') as f:
        t = f['time/t'][:]
        x = f['bodies/rod/position'][:]
    if t.shape != t_ref.shape or np.max(np.abs(t - t_ref)) > 0.0:
        print(f'FAIL: output times differ ({t.shape} against {t_ref.shape})')
        return 1
    if x.shape[-1] != 3:
        x, x_ref = x.T, x_ref.T
    back = x @ rotation()          # rows R^T x
    err = np.max(np.abs(back - x_ref))
    travel = np.max(np.abs(x_ref - x_ref[0]))
    print(f'{len(t)} steps to t = {t[-1]:.3f} s; the rod swings {travel:.3f} m; turned run '
          f'turned back differs by {err:.2e} m (tolerance {POSITION_TOL:.0e} m)')
    if travel < 0.1:
        print('FAIL: the reference pendulum does not swing')
        return 1
    if not err <= POSITION_TOL:
        print('FAIL: the turned scene with two agreeing joint frames moves otherwise')
        return 1
    print('PASS')
    return 0


if __name__ == '__main__':
    sys.exit(main())
