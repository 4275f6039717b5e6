#!/usr/bin/env python3
"""Reference for the spin-up of a flexible beam (Kane, Ryan & Banerjee, "Dynamics of a cantilever beam
attached to a moving base", J. Guidance 10(2), 1987, section VI; repeated by Simo & Vu-Quoc, J. Appl. Mech.
53, 1986, and by most floating-frame papers since): an independent assumed-modes model in SciPy, not this
project's code. Writes kane_spinup_reference.csv (t s, tip deflection m) beside this script.

The beam: L = 10 m, E = 7e10 Pa, A = 4e-4 m^2, I = 2e-7 m^4, rho = 3000 kg/m^3 (m = rho A = 1.2 kg/m,
EI = 14000 N m^2; first bending frequency 3.80 rad/s), clamped to a hub of radius 0 that turns about an
axis normal to the beam in the plane of bending, with the prescribed spin-up
    Omega(t) = (Omega_s / T) (t - (T / 2 pi) sin(2 pi t / T))   for t < T,   Omega_s after,
Omega_s = 6 rad/s, T = 15 s - above the first bending frequency, so that a floating frame without the
geometric stiffness buckles (lead-lag omega^2 = omega_1^2 - Omega^2 < 0), Kane et al.'s point.

In-plane deflection v(x, t) = sum_i phi_i(x) q_i(t), phi_i the clamped-free Euler-Bernoulli modes
(Blevins, Formulas for Natural Frequency and Mode Shape, table 8-1), linearised in q in the frame that
turns with the hub:
    M q'' + (K + Omega^2 (K_G - M)) q = -Omega' p,
    M_ij = int m phi_i phi_j dx,  K_ij = int EI phi_i'' phi_j'' dx,
    K_G,ij = int N1(x) phi_i' phi_j' dx,  N1(x) = m (L^2 - x^2) / 2   (the centrifugal axial force per Omega^2),
    p_i = int m x phi_i dx                                         (the hub's angular acceleration's load),
the -Omega^2 M term the spin softening and Omega^2 K_G the stiffening (Kane et al.'s eqs. 80-81 reduced
to planar bending; the Coriolis coupling to axial motion is of second order and left out, as in the
floating frame with bending modes only). Integrated with solve_ivp (DOP853, rtol 1e-11).
"""
import csv
import pathlib

import numpy as np
from scipy.integrate import solve_ivp

L, E, A, I, RHO = 10.0, 7e10, 4e-4, 2e-7, 3000.0
OMEGA_S, T_UP, T_END = 6.0, 15.0, 20.0
M_PER_L, EI = RHO * A, E * I
BETA_L = [1.8751040687, 4.6940911330, 7.8547574382, 10.9955407349, 14.1371683910]


def modes(x):
    """phi, phi', phi'' of the clamped-free modes at x (n_modes x len(x))."""
    out = []
    for bl in BETA_L:
        b = bl / L
        s = (np.sinh(bl) - np.sin(bl)) / (np.cosh(bl) + np.cos(bl))
        bx = b * x
        phi = np.cosh(bx) - np.cos(bx) - s * (np.sinh(bx) - np.sin(bx))
        d1 = b * (np.sinh(bx) + np.sin(bx) - s * (np.cosh(bx) - np.cos(bx)))
        d2 = b**2 * (np.cosh(bx) + np.cos(bx) - s * (np.sinh(bx) + np.sin(bx)))
        out.append((phi, d1, d2))
    return out


def spin(t):
    if t < T_UP:
        w = OMEGA_S / T_UP * (t - T_UP / (2 * np.pi) * np.sin(2 * np.pi * t / T_UP))
        a = OMEGA_S / T_UP * (1 - np.cos(2 * np.pi * t / T_UP))
        return w, a
    return OMEGA_S, 0.0


def main():
    # Gauss-Legendre on 40 panels: the integrands are smooth, exact to round-off.
    g, gw = np.polynomial.legendre.leggauss(12)
    edges = np.linspace(0, L, 41)
    x = np.concatenate([(a + b) / 2 + (b - a) / 2 * g for a, b in zip(edges[:-1], edges[1:])])
    w = np.concatenate([(b - a) / 2 * gw for a, b in zip(edges[:-1], edges[1:])])
    ms = modes(x)
    n = len(ms)
    phi = np.array([m[0] for m in ms])
    d1 = np.array([m[1] for m in ms])
    d2 = np.array([m[2] for m in ms])
    M = (phi * w * M_PER_L) @ phi.T
    K = (d2 * w * EI) @ d2.T
    KG = (d1 * w * M_PER_L * (L**2 - x**2) / 2) @ d1.T
    p = (phi * w * M_PER_L * x).sum(axis=1)
    tip = np.array([m[0] for m in modes(np.array([L]))])[:, 0]
    Minv = np.linalg.inv(M)

    def rhs(t, y):
        q, qd = y[:n], y[n:]
        om, al = spin(t)
        qdd = Minv @ (-(K + om**2 * (KG - M)) @ q - al * p)
        return np.concatenate([qd, qdd])

    times = np.linspace(0, T_END, 401)
    # Integrate piecewise so the kink of Omega' at T_UP is a step boundary.
    y0 = np.zeros(2 * n)
    t_all, v_all = [], []
    for t0, t1 in ((0.0, T_UP), (T_UP, T_END)):
        sel = times[(times >= t0) & (times <= t1)]
        if t0 > 0:
            sel = sel[sel > t0]
        sol = solve_ivp(rhs, (t0, t1), y0, method="DOP853", rtol=1e-11, atol=1e-13, t_eval=sel, dense_output=True)
        y0 = sol.sol(t1)
        t_all.extend(sol.t)
        v_all.extend(tip @ sol.y[:n])
    out = pathlib.Path(__file__).with_name("kane_spinup_reference.csv")
    with out.open("w", newline="") as f:
        wr = csv.writer(f)
        wr.writerow(["t_s", "tip_deflection_m"])
        for t, v in zip(t_all, v_all):
            wr.writerow([f"{t:.4f}", f"{v:.10e}"])
    print(f"wrote {out}: {len(t_all)} rows, min {min(v_all):.6f} m, max {max(v_all):.6f} m")


if __name__ == "__main__":
    main()
