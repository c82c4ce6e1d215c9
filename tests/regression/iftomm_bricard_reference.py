#!/usr/bin/env python3
"""Independent reference for IFToMM A04, Bricard's mechanism (input/iftomm_a04_bricard.nml):
the same five rods and six hinges integrated in joint coordinates, not by ffrf.

Coordinates: the angles q1..q5 of the hinges J1..J5 of the open chain ground-rod1-...-rod5
(product of exponentials: rod i turns about the current axes of J1..Ji; all angles 0 in the
starting pose of the case). Hinge J6 closes the loop: rod5's end at (0, 0, 1) and rod5's x axis
(the J6 axis) normal to y and z, 5 equations of rank 4 on the motion (the mechanism is
over-constrained). Mass matrix from the bodies' Jacobians, velocity terms from their time
derivatives (central differences along q', 1e-6), gravity 9.81 m/s^2 along -y; the multipliers by
least squares on the rank-deficient saddle-point system, Baumgarte terms (alpha = 20 1/s) against
drift; scipy's DOP853 at rtol 1e-10, atol 1e-12. Prints P3 (the corner (1, -1, 0), rod2's end)
every 0.1 s to 10 s, the energy change and the largest closure residual.
Measured: energy kept to 8.7e-10 J, closure to 1.8e-12 m; P3 of rtol 1e-8 and 1e-10 agree to
5.0e-10 m. tests/regression/check_iftomm_bricard.py holds this table (about 8 min on one core).

    iftomm_bricard_reference.py [RTOL]
"""
import math
import sys
import time
import numpy as np
from scipy.integrate import solve_ivp
AXES = np.array([[0,1,0],[0,0,1],[1,0,0],[0,1,0],[0,0,1]], float)
POINTS = np.array([[0,0,0],[1,0,0],[1,-1,0],[1,-1,1],[0,-1,1]], float)
CENTRES = np.array([[0.5,0,0],[1,-0.5,0],[1,-1,0.5],[0.5,-1,1],[0,-0.5,1]], float)
LONG, ACROSS = 0.02/12, 1.01/12
INERTIA = [np.diag(d) for d in ([LONG,ACROSS,ACROSS],[ACROSS,LONG,ACROSS],[ACROSS,ACROSS,LONG],
                                 [LONG,ACROSS,ACROSS],[ACROSS,LONG,ACROSS])]
G = np.array([0.0, -9.81, 0.0])
def rot(a, t):
    K = np.array([[0,-a[2],a[1]],[a[2],0,-a[0]],[-a[1],a[0],0]])
    return np.eye(3) + math.sin(t)*K + (1-math.cos(t))*K@K
def kinematics(q):
    """Rotation R_i and translation d_i (x -> R_i x + d_i) of each rod, current joint axes and points."""
    R = np.eye(3); d = np.zeros(3); Rs=[]; ds=[]; axes=[]; points=[]
    for k in range(5):
        axes.append(R @ AXES[k]); points.append(R @ POINTS[k] + d)
        Rk = rot(AXES[k], q[k])
        d = R @ (POINTS[k] - Rk @ POINTS[k]) + d   # x -> R (Rk (x - c) + c) + d
        R = R @ Rk
        Rs.append(R.copy()); ds.append(d.copy())
    return Rs, ds, np.array(axes), np.array(points)
def jac_point(i, p, axes, points):
    J = np.zeros((3,5))
    for k in range(i+1): J[:,k] = np.cross(axes[k], p - points[k])
    return J
def jac_rot(i, axes):
    J = np.zeros((3,5)); J[:, :i+1] = axes[:i+1].T; return J
def parts(q):
    Rs, ds, axes, points = kinematics(q)
    Jv = [jac_point(i, Rs[i] @ CENTRES[i] + ds[i], axes, points) for i in range(5)]
    Jw = [jac_rot(i, axes) for i in range(5)]
    end = Rs[4] @ np.array([0,0,1.0]) + ds[4]
    xaxis = Rs[4][:,0]
    phi = np.concatenate([end - np.array([0,0,1.0]), xaxis[1:]])
    Jend = jac_point(4, end, axes, points)
    Jx = np.array([np.cross(axes[k], xaxis) for k in range(5)]).T
    Phi_q = np.vstack([Jend, Jx[1:]])
    return Rs, ds, Jv, Jw, phi, Phi_q
EPS = 1e-6
def rhs(t, y, alpha=20.0):
    q, v = y[:5], y[5:]
    Rs, ds, Jv, Jw, phi, Phi_q = parts(q)
    _, _, Jv_p, Jw_p, _, Pq_p = parts(q + EPS*v)
    _, _, Jv_m, Jw_m, _, Pq_m = parts(q - EPS*v)
    M = np.zeros((5,5)); f = np.zeros(5)
    for i in range(5):
        Iw = Rs[i] @ INERTIA[i] @ Rs[i].T
        w = Jw[i] @ v
        acc_v = (Jv_p[i] - Jv_m[i]) @ v / (2*EPS)
        acc_w = (Jw_p[i] - Jw_m[i]) @ v / (2*EPS)
        M += Jv[i].T @ Jv[i] + Jw[i].T @ Iw @ Jw[i]
        f += Jv[i].T @ (G - acc_v) - Jw[i].T @ (Iw @ acc_w + np.cross(w, Iw @ w))
    gamma = -(Pq_p - Pq_m) @ v / (2*EPS) - 2*alpha*(Phi_q @ v) - alpha**2*phi
    K = np.block([[M, Phi_q.T], [Phi_q, np.zeros((5,5))]])
    sol = np.linalg.lstsq(K, np.concatenate([f, gamma]), rcond=1e-12)[0]
    return np.concatenate([v, sol[:5]])
def energy(y):
    q, v = y[:5], y[5:]
    Rs, ds, Jv, Jw, phi, _ = parts(q)
    e = 0.0
    for i in range(5):
        Iw = Rs[i] @ INERTIA[i] @ Rs[i].T
        e += 0.5*np.dot(Jv[i]@v, Jv[i]@v) + 0.5*(Jw[i]@v) @ Iw @ (Jw[i]@v) - G @ (Rs[i]@CENTRES[i]+ds[i])
    return e
def p3(q):
    Rs, ds, *_ = kinematics(q); return Rs[1] @ np.array([1,-1,0.0]) + ds[1]


def main():
    rtol = float(sys.argv[1]) if len(sys.argv) > 1 else 1.0e-10
    start = time.time()
    solution = solve_ivp(rhs, (0.0, 10.0), np.zeros(10), method="DOP853", rtol=rtol,
                         atol=rtol * 1.0e-2, dense_output=True)
    print(f"# status {solution.status}, {solution.nfev} evaluations, "
          f"{time.time() - start:.1f} s, rtol {rtol:g}")
    e0 = energy(np.zeros(10))
    for t in np.arange(0, 101) * 0.1:
        y = solution.sol(t)
        p = p3(y[:5])
        print(f"{t:.1f} {p[0]:.12f} {p[1]:.12f} {p[2]:.12f} {energy(y) - e0:.3e} "
              f"{np.abs(parts(y[:5])[4]).max():.1e}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
