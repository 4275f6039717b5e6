#!/usr/bin/env python3
"""Reference frequencies of a uniform cantilever spinning about an axis through its root, normal to it
(hub radius 0): the rotating-beam eigenproblem solved as a boundary-value problem with SciPy's solve_bvp -
an independent solver, not this project's code. Writes rotating_beam_reference.csv beside this script.

Euler-Bernoulli beam, length L, mass per length m, bending stiffness EI, spin Omega. With xi = x/L,
lambda = Omega sqrt(m L^4 / EI) and mu = omega sqrt(m L^4 / EI), the out-of-plane (flapwise) motion w obeys
(Hodges & Rutkowski, AIAA J. 19(11), 1981, eq. 1; Wright, Smith, Thresher & Wang, J. Appl. Mech. 49, 1982)

    w'''' - (lambda^2 / 2) ((1 - xi^2) w')' = mu^2 w,     N(xi) = m Omega^2 L^2 (1 - xi^2) / 2,

    w(0) = w'(0) = 0,  w''(1) = 0,  w'''(1) = 0   (N(1) = 0, so the shear condition is the free end's).

The in-plane (lead-lag) motion v adds the spin softening - m Omega^2 v to the same operator, so for a beam
with equal bending stiffness in both planes mu_lag^2 = mu_flap^2 - lambda^2 exactly. Southwell's
coefficient of mode k is S_k = (mu_k(lambda)^2 - mu_k(0)^2) / lambda^2 in the limit lambda -> 0
(published: S_1 = 1.193, S_2 = 6.48; Bramwell, Helicopter Dynamics, 1976, sec. 5.4).
"""
import csv
import pathlib

import numpy as np
from scipy.integrate import solve_bvp

# Non-rotating clamped-free roots (beta L)^2 as starting guesses: 3.516, 22.03, 61.70.
BETA = [1.8751040687, 4.6940911330, 7.8547574382]


def mode_guess(k, xi):
    b = BETA[k]
    s = (np.sinh(b) - np.sin(b)) / (np.cosh(b) + np.cos(b))
    w = np.cosh(b * xi) - np.cos(b * xi) - s * (np.sinh(b * xi) - np.sin(b * xi))
    d1 = b * (np.sinh(b * xi) + np.sin(b * xi) - s * (np.cosh(b * xi) - np.cos(b * xi)))
    d2 = b**2 * (np.cosh(b * xi) + np.cos(b * xi) - s * (np.sinh(b * xi) + np.sin(b * xi)))
    d3 = b**3 * (np.sinh(b * xi) - np.sin(b * xi) - s * (np.cosh(b * xi) + np.cos(b * xi)))
    y = np.vstack([w, d1, d2, d3])
    return y / w[-1]


def flap_frequency(k, lam, guess=None):
    """mu_k(lambda) of flapwise mode k (0-based)."""
    xi = np.linspace(0.0, 1.0, 401)

    def rhs(x, y, p):
        mu2 = p[0]
        # w'''' = mu^2 w + (lambda^2/2) ((1 - xi^2) w'' - 2 xi w')
        w4 = mu2 * y[0] + 0.5 * lam**2 * ((1 - x**2) * y[2] - 2 * x * y[1])
        return np.vstack([y[1], y[2], y[3], w4])

    def bc(ya, yb, p):
        return np.array([ya[0], ya[1], yb[2], yb[3], yb[0] - 1.0])

    y0 = mode_guess(k, xi)
    p0 = [guess if guess is not None else BETA[k] ** 4]
    sol = solve_bvp(rhs, bc, xi, y0, p=p0, tol=1e-8, bc_tol=1e-10, max_nodes=100000)
    if not sol.success:
        raise RuntimeError(f"solve_bvp: {sol.message}")
    return np.sqrt(sol.p[0])


def main():
    rows = []
    for lam in [0, 0.1, 1, 2, 2.5, 3, 4, 5, 6, 8, 10, 12]:
        mus = []
        for k in range(3):
            guess = None
            if lam > 0:
                guess = (BETA[k] ** 2) ** 2 + (1.193 if k == 0 else 6.48 if k == 1 else 17.0) * lam**2
            mus.append(flap_frequency(k, lam, guess))
        rows.append([lam] + mus)
        print(f"lambda {lam:5.1f}: mu = " + ", ".join(f"{m:.5f}" for m in mus))
    mu0 = rows[0][1:]
    small = rows[1]
    southwell = [(small[1 + k] ** 2 - mu0[k] ** 2) / small[0] ** 2 for k in range(3)]
    print("Southwell coefficients (lambda = 0.1): " + ", ".join(f"{s:.4f}" for s in southwell))
    out = pathlib.Path(__file__).with_name("rotating_beam_reference.csv")
    with open(out, "w", newline="") as f:
        f.write("# Flapwise frequencies mu_k = omega_k sqrt(m L^4 / EI) of a uniform cantilever spinning at\n")
        f.write("# lambda = Omega sqrt(m L^4 / EI) about an axis through its root (hub radius 0);\n")
        f.write("# made by rotating_beam_reference.py (SciPy solve_bvp, tol 1e-8). Lead-lag: mu^2 - lambda^2.\n")
        w = csv.writer(f)
        w.writerow(["lambda", "mu_1", "mu_2", "mu_3"])
        for r in rows:
            w.writerow([f"{r[0]:g}"] + [f"{m:.6f}" for m in r[1:]])
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
