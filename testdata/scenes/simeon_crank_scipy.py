#!/usr/bin/python3
"""Simeon's flexible slider crank integrated by SciPy from the published equations: the independent check.

The equations are those of the Test Set for IVP Solvers' crank.f, subroutine RESMBS (as shipped in the R
package deTestSet, rforge/bvpsolve, pkg/deTestSet/src/Ex_crank.f), written here anew in NumPy:
M(p, q) w = f(p, v, q, v_q) - G^T lambda with the constraints g(p, q) = (L1 sin phi1 + (L2 + q4) sin phi2,
x3 - L1 cos phi1 - (L2 + q4) cos phi2, phi1 - omega t) = 0. The index is reduced to 1 (the constraints'
second derivatives, RESMBS's ALC): each right-hand side solves [M G^T; G 0] [w; lambda] = [f; -gamma], and
solve_ivp (Radau, rtol = atol = 1e-13 by default) integrates (p, q, v) from the test set's initial values
(ini = 1) to t = 0.1 s. Options: --stiff (the nonlinear stiffness term, IPAR(1) = 1), --damp (the 0.5 %
damping, IPAR(2) = 1), --consistent (the initial values completed to consistency, as the scene does).

Prints the 24 components at t = 0.1 (phi1, phi2, x3, q1..q4, their rates, accelerations, lambda1..3) and
their differences to the reference (cranksoln) and the largest position-constraint violation.
  /usr/bin/python3 simeon_crank_scipy.py [--rtol 1e-13] [--stiff] [--damp]
"""

import argparse
import math

import numpy as np
from scipy.integrate import solve_ivp

M1, M2, M3 = 0.36, 0.151104, 0.075552
L1, L2 = 0.15, 0.30
J1, J2 = 0.002727, 0.0045339259
EE, BB, HH, RHO, GRAV, OMEGA = 0.20e12, 0.0080, 0.0080, 7870.0, 0.0, 150.0
PI = 3.1415927  # as RESMBS (its PARAMETER PI = 3.1415927D0)

# cranksoln: MEBDFI, rtol = atol = 1e-14, t = 0.1 (deTestSet's reference("crank")).
REFERENCE = np.array([
    0.1500000000000104e+002, -0.3311734988256260e+000, 0.1697373328427860e+000, 0.1893192899613509e-003,
    0.2375751249879174e-004, -0.5323896770569702e-005, -0.8363313279112129e-005, 0.1500000000000000e+003,
    0.6025346755138369e+002, -0.8753116326670527e+001, -0.3005541400289738e-001, -0.5500431812571696e-002,
    0.4974111734266989e-003, 0.1105560003626645e-002, 0.0, 0.6488737541276957e+004,
    0.2167938629509884e+004, 0.3391137060286523e+002, 0.1715134772216488e+000, -0.1422449408912512e+001,
    0.1003946428124810e+001, -0.6232935833287916e+002, -0.1637920993367306e+003, 0.2529857947066878e+002])

Y0 = np.array([0, 0, 0.450016933, 0, 0, 0.103339863e-4, 0.169327969e-4, 0.150000000e3, -0.749957670e2,
               -0.268938672e-5, 0.444896105, 0.463434311e-2, -0.178591076e-5, -0.268938672e-5])


def matrices(damp):
    facm, fack, facb = RHO * BB * HH * L2, EE * BB * HH / L2, BB * HH * L2
    mq = facm * np.array([[0.5, 0, 0, 0], [0, 0.5, 0, 0], [0, 0, 8, 1], [0, 0, 1, 2]])
    kq = np.zeros((4, 4))
    kq[0, 0] = fack * PI**4 / 24 * (HH / L2) ** 2
    kq[1, 1] = fack * PI**4 * 2 / 3 * (HH / L2) ** 2
    kq[2:, 2:] = fack * np.array([[16 / 3, -8 / 3], [-8 / 3, 7 / 3]])
    bq = np.zeros((4, 4))
    bq[0, 2], bq[0, 3], bq[1, 3] = -16 / PI**3, 8 / PI**3 - 1 / PI, 0.5 / PI
    bq = facb * (bq - bq.T)
    c1 = facb * np.array([0, 0, 2 / 3, 1 / 6])
    c2 = facb * np.array([2 / PI, 0, 0, 0])
    c12 = L2 * facb * np.array([0, 0, 1 / 3, 1 / 6])
    c21 = L2 * facb * np.array([1 / PI, -0.5 / PI, 0, 0])
    dq = np.zeros((4, 4))
    if damp:
        dq[0, 0], dq[1, 1] = 5.0, 25.0
        dq[2:, 2:] = 0.5 * np.array([[2.308375455264791e2, -2.62688487992052e2],
                                     [-2.626884879920526e2, 4.217421837156818e2]])
    return mq, kq, bq, c1, c2, c12, c21, dq


def system(y, stiff, mats):
    """M, G, f and gamma (G w + gamma = 0: the constraints' second derivatives) at the state y (14)."""
    mq, kq, bq, c1, c2, c12, c21, dq = mats
    p1, p2 = y[0], y[1]
    q, v, qd = y[3:7], y[7:9], y[10:14]
    c_1, s_1, c_2, s_2 = math.cos(p1), math.sin(p1), math.cos(p2), math.sin(p2)
    c12_, s12_ = math.cos(p1 - p2), math.sin(p1 - p2)
    am = np.zeros((7, 7))
    am[0, 0] = J1 + M2 * L1 * L1
    am[0, 1] = 0.5 * L1 * L2 * M2 * c12_ + RHO * L1 * (s12_ * c2 @ q + c12_ * c1 @ q)
    am[1, 1] = J2 + q @ mq @ q + 2 * RHO * c12 @ q
    am[2, 2] = M3
    am[0, 3:] = RHO * L1 * (-s12_ * c1 + c12_ * c2)
    am[1, 3:] = RHO * c21 + RHO * (q @ bq)
    am[3:, 3:] = mq
    am = np.triu(am) + np.triu(am, 1).T
    gp = np.zeros((3, 7))
    qku, qdku = q[3], qd[3]
    gp[0, :3] = [L1 * c_1, (L2 + qku) * c_2, 0]
    gp[1, :3] = [L1 * s_1, (L2 + qku) * s_2, 1]
    gp[2, 0] = 1
    gp[0, 6], gp[1, 6] = s_2, -c_2
    f = np.zeros(7)
    f[0] = (-0.5 * L1 * GRAV * (M1 + 2 * M2) * c_1 - 0.5 * L1 * L2 * M2 * v[1] ** 2 * s12_
            + RHO * L1 * v[1] ** 2 * (-s12_ * c1 @ q + c12_ * c2 @ q)
            - 2 * RHO * L1 * v[1] * (c12_ * c1 @ qd + s12_ * c2 @ qd))
    f[1] = (-0.5 * L2 * GRAV * M2 * c_2 + 0.5 * L1 * L2 * M2 * v[0] ** 2 * s12_
            + RHO * L1 * v[0] ** 2 * (s12_ * c1 @ q - c12_ * c2 @ q)
            - 2 * RHO * v[1] * c12 @ qd - 2 * v[1] * qd @ mq @ q - RHO * qd @ bq @ qd
            - RHO * GRAV * (c_2 * c1 @ q - s_2 * c2 @ q))
    f[3:] = (v[1] ** 2 * mq @ q + RHO * (v[1] ** 2 * c12 + L1 * v[0] ** 2 * (c12_ * c1 + s12_ * c2)
                                        + 2 * v[1] * bq @ qd)
             - RHO * GRAV * (s_2 * c1 + c_2 * c2) - kq @ q - dq @ qd)
    if stiff:
        fk, fb = 0.5 * EE * BB * HH / L2**2 * PI**2, 80 / (PI**2 * 9)
        f[3] -= fk * (q[0] * q[3] - fb * q[1] * (-4 * q[2] + 2 * q[3]))
        f[4] -= fk * (4 * q[1] * q[3] - fb * q[0] * (-4 * q[2] + 2 * q[3]))
        f[5] -= fk * 4 * fb * q[0] * q[1]
        f[6] -= fk * (0.5 * q[0] ** 2 + 2 * q[1] ** 2 - 2 * fb * q[0] * q[1])
    gamma = np.array([-L1 * s_1 * v[0] ** 2 - (L2 + qku) * s_2 * v[1] ** 2 + 2 * v[1] * c_2 * qdku,
                      L1 * c_1 * v[0] ** 2 + (L2 + qku) * c_2 * v[1] ** 2 + 2 * v[1] * s_2 * qdku, 0.0])
    return am, gp, f, gamma


def accelerations(y, stiff, mats):
    am, gp, f, gamma = system(y, stiff, mats)
    a = np.block([[am, gp.T], [gp, np.zeros((3, 3))]])
    sol = np.linalg.solve(a, np.concatenate([f, -gamma]))
    return sol[:7], sol[7:]


def consistent(y0):
    """The published initial values completed to consistency: x3 = L1 + L2 + q4, phi2' = -L1 omega / (L2 + q4)
    (the published x3 and phi2' are their 9-digit roundings: g2 = 2.03e-10 m, g1' = 1.19e-8 m/s)."""
    y = y0.copy()
    y[2] = L1 + L2 + y[6]
    y[8] = -L1 * y[7] / (L2 + y[6])
    return y


def integrate(rtol, stiff=False, damp=False, t_end=0.1, y0=Y0):
    mats = matrices(damp)
    rhs = lambda t, y: np.concatenate([y[7:], accelerations(y, stiff, mats)[0]])
    sol = solve_ivp(rhs, (0.0, t_end), y0, method="Radau", rtol=rtol, atol=rtol, dense_output=False)
    y = sol.y[:, -1]
    w, lam = accelerations(y, stiff, mats)
    drift = 0.0
    for k in range(sol.y.shape[1]):
        yk, tk = sol.y[:, k], sol.t[k]
        g = [L1 * math.sin(yk[0]) + (L2 + yk[6]) * math.sin(yk[1]),
             yk[2] - L1 * math.cos(yk[0]) - (L2 + yk[6]) * math.cos(yk[1]), yk[0] - OMEGA * tk]
        drift = max(drift, max(abs(x) for x in g))
    return np.concatenate([y, w, lam]), drift, sol


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--rtol", type=float, default=1e-13)
    p.add_argument("--stiff", action="store_true")
    p.add_argument("--damp", action="store_true")
    p.add_argument("--consistent", action="store_true",
                   help="start from the published initial values completed to consistency (as the scene)")
    args = p.parse_args()
    y, drift, sol = integrate(args.rtol, args.stiff, args.damp, y0=consistent(Y0) if args.consistent else Y0)
    names = ["phi1", "phi2", "x3", "q1", "q2", "q3", "q4"]
    names = names + ["v" + n for n in names] + ["a" + n for n in names] + ["lambda1", "lambda2", "lambda3"]
    print(f"# Radau rtol = atol = {args.rtol:g}, stiff = {args.stiff}, damp = {args.damp}: "
          f"consistent = {args.consistent}: {sol.t.size - 1} steps, {sol.nfev} f evaluations; "
          f"max |g| = {drift:.2e}")
    print(f"# {'name':8s} {'scipy':>24s} {'reference':>24s} {'difference':>10s} {'relative':>10s}")
    for k in range(24):
        d = y[k] - REFERENCE[k]
        rel = abs(d) / abs(REFERENCE[k]) if REFERENCE[k] != 0 else float("nan")
        print(f"{names[k]:10s} {y[k]:24.16e} {REFERENCE[k]:24.16e} {d:10.2e} {rel:10.2e}")


if __name__ == "__main__":
    main()
