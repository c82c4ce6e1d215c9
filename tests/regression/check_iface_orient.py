#!/usr/bin/env python3
"""A flexible interface's own &marker orientation (issue 24, docs/mechanisms.md "Joint frames").
1. AXIS.h5 ORIENTED.h5: tests/data/frames/flexible_pendulum_iface_oriented.nml is
   tests/regression/frames_pendulum_xz.nml with the joint frames given as the links'
   interfaces' orientation C (the joints' axis frame turned by 90 deg about its z axis) instead
   of by the joints' axis; a revolute joint locks the same motion in either frame.
2. --turned TURNED.h5 ORIENTED.h5 [--plain PLAIN.h5]: tests/data/frames/
   universal_pendulum_iface.nml, a universal joint between two flexible interfaces whose cross
   arms (turned by 45 deg about the shafts) only the interfaces' orientation can give, against
   universal_pendulum_turned.nml, the scene turned as a whole by R = R_x(-45 deg) with the
   elbow's frame from its axis: the turned run's frame origins and orientations turned back by
   R^T and its modal coordinates. --plain: the oriented scene with the interfaces' orientation
   set to the axis frame (arms along y and z): it must move otherwise (by more than
   PLAIN_MIN), so the comparison sees the arms' direction.
Both: every output step, the links swinging, to ANGLE_TOL (rotation matrices, rad) and
POSITION_TOL (m); the runs differ by round-off (inputs to 16 digits, the joint equations
in other frames), amplified through Newton's stopping tolerance.
"""
import argparse
import sys

import h5py
import numpy as np

ANGLE_TOL = 1.0e-12     # rad; measured 1.7e-14 (revolute), 4.9e-14 (universal)
POSITION_TOL = 1.0e-12  # m; measured 1.4e-15, 1.3e-15
MODAL_TOL = 1.0e-13     # absolute (the coordinates reach 3.3e-7); measured 8.8e-16, 8.5e-16
PLAIN_MIN = 1.0e-5      # m; measured 6.7e-5 (the arms' direction acts only at a bent joint)


def rotation(e):
    """A of Euler parameters (rows e0, e1, e2, e3), docs/theory.md 3.1."""
    e0, e1, e2, e3 = e[:, 0], e[:, 1], e[:, 2], e[:, 3]
    return np.stack([
        np.stack([e0**2 + e1**2 - e2**2 - e3**2, 2 * (e1 * e2 - e0 * e3), 2 * (e1 * e3 + e0 * e2)], -1),
        np.stack([2 * (e1 * e2 + e0 * e3), e0**2 - e1**2 + e2**2 - e3**2, 2 * (e2 * e3 - e0 * e1)], -1),
        np.stack([2 * (e1 * e3 - e0 * e2), 2 * (e2 * e3 + e0 * e1), e0**2 - e1**2 - e2**2 + e3**2], -1)],
        1)


def read(path):
    """Times; per link: positions (n, 3), rotation matrices (n, 3, 3), modal coordinates."""
    with h5py.File(path, 'r') as f:
        t = f['time/t'][:]
        x, a, q = [], [], []
        for link in ('link1', 'link2'):
            p = f[f'bodies/{link}/position'][:]
            x.append(p if p.shape[-1] == 3 else p.T)
            e = f[f'bodies/{link}/euler_parameters'][:]
            a.append(rotation(e if e.shape[-1] == 4 else e.T))
            m = f[f'bodies/{link}/modal_coordinates'][:]
            q.append(m if m.shape[0] == len(t) else m.T)
    return t, np.stack(x), np.stack(a), np.stack(q)


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument('reference', help='the axis run (--axis) or the turned run (--turned)')
    parser.add_argument('oriented', help='the run with the interfaces\' orientation')
    parser.add_argument('--turned', action='store_true', help='reference is turned by R_x(-45 deg)')
    parser.add_argument('--plain', help='the oriented scene with the axis frame at the interfaces')
    args = parser.parse_args()
    t_ref, x_ref, a_ref, q_ref = read(args.reference)
    t, x, a, q = read(args.oriented)
    if t.shape != t_ref.shape or np.max(np.abs(t - t_ref)) > 0.0:
        print(f'FAIL: output times differ ({t.shape} against {t_ref.shape})')
        return 1
    if args.turned:
        c = np.sqrt(0.5)
        r = np.array([[1.0, 0.0, 0.0], [0.0, c, c], [0.0, -c, c]])
        x_ref = x_ref @ r            # rows R^T x
        a_ref = np.einsum('ji,ltjk->ltik', r, a_ref)   # R^T A
    swing = np.max(np.abs(x_ref - x_ref[:, :1]))
    d_x = np.max(np.abs(x - x_ref))
    d_a = np.max(np.abs(a - a_ref))
    d_q = np.max(np.abs(q - q_ref))
    print(f'{len(t)} steps to t = {t[-1]:.3f} s; the links travel {swing:.3f} m; interface '
          f'orientation against the reference: positions {d_x:.2e} m (tolerance '
          f'{POSITION_TOL:.0e}), rotations {d_a:.2e} (tolerance {ANGLE_TOL:.0e}), modal '
          f'coordinates {d_q:.2e} (tolerance {MODAL_TOL:.0e}, largest {np.max(np.abs(q_ref)):.1e})')
    failed = False
    if swing < 0.05:
        print('FAIL: the reference pendulum does not swing')
        failed = True
    if not (d_x <= POSITION_TOL and d_a <= ANGLE_TOL and d_q <= MODAL_TOL):
        print('FAIL: the joint frames given at the interfaces move the pendulum otherwise')
        failed = True
    if args.plain:
        _, x_plain, _, _ = read(args.plain)
        d_plain = np.max(np.abs(x_plain - x))
        print(f'the same scene with the axis frame at the interfaces moves {d_plain:.2e} m '
              f'otherwise (at least {PLAIN_MIN:.0e} m)')
        if not d_plain >= PLAIN_MIN:
            print('FAIL: the interfaces\' orientation does not change the motion')
            failed = True
    if failed:
        return 1
    print('PASS')
    return 0


if __name__ == '__main__':
    sys.exit(main())
