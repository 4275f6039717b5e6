#!/usr/bin/env python3
"""Reference for Hertz's elliptical point contact (the crowned roller of solve's roller-cam element): an
independent evaluation in SciPy, not this project's code. Writes hertz_ellipse_reference.csv beside this
script; tests/solve/test_hertz_ellipse.cpp asserts its numbers.

Two bodies whose principal planes of curvature coincide, relative radii Rx, Ry (1/Rx = 1/R1x + 1/R2x),
principal relative curvatures A = 1/(2 Rmax) <= B = 1/(2 Rmin), radius ratio r = B / A = Rmax / Rmin >= 1,
sum of curvatures Sigma rho = 1/Rx + 1/Ry = 2 (A + B), contact modulus E*, load P.

Route 1 (Hertz 1881 in its potential form; K. L. Johnson, Contact Mechanics, 1985, eqs. 3.58-3.60 with
4.36): an ellipsoidal pressure p0 sqrt(1 - x^2/a^2 - y^2/b^2), P = 2 pi a b p0 / 3, displaces the surface by
delta - A x^2 - B y^2 inside the ellipse with
    delta = c I0,  A = c I_a,  B = c I_b,  c = 3 P / (4 pi E*),
    I0  = int_0^inf dw / sqrt((a^2 + w)(b^2 + w) w),
    I_a = int_0^inf dw / ((a^2 + w) sqrt((a^2 + w)(b^2 + w) w)),
    I_b = int_0^inf dw / ((b^2 + w) sqrt((a^2 + w)(b^2 + w) w)).
With a = 1 the ratio I_b / I_a depends on b alone: b is found by brentq on I_b / I_a = r (quadrature by
scipy.integrate.quad after w = t^2), then the scale from A. No elliptic integral is used.

Route 2 (Johnson eqs. 4.39-4.41 with scipy.special.ellipk / ellipe, which take the parameter m = e^2): e
solves B/A = ((a/b)^2 E(e) - K(e)) / (K(e) - E(e)), a/b = 1 / sqrt(1 - e^2), then
a^3 = 3 P (K - E) / (2 pi E* e^2 A), b = a sqrt(1 - e^2), delta = p0 b K / E*, p0 = 3 P / (2 pi a b).

The two routes agree to better than 1e-11 (asserted below). Output, in the dimensionless form of
T. A. Harris and M. N. Kotzalas, Rolling Bearing Analysis, 5th ed. 2007, eqs. 6.39-6.41 (the tabulated
a*, b*, delta* against the curvature difference F(rho) = (B - A) / (A + B)):
    a = a* (3 P / (2 Sigma rho E*))^(1/3),  b = b* (...)^(1/3),  delta = delta* (...)^(2/3) Sigma rho / 2,
so a* = b* = delta* = 1 for a sphere (r = 1). Columns: ratio r, F(rho), ellipticity k = a/b, a*, b*, delta*.
"""
import csv
import math
import pathlib

import numpy as np
from scipy.integrate import quad
from scipy.optimize import brentq
from scipy.special import ellipe, ellipk

RATIOS = [1.0, 1.0001, 1.01, 1.1, 1.5, 2.0, 2.5, 3.0, 5.0, 7.5, 10.0, 20.0, 30.0, 50.0, 62.0, 75.0, 100.0,
          150.0, 200.0, 247.0, 300.0, 500.0, 1000.0, 3000.0]


def integrals(b):
    """I0, I_a, I_b of route 1 for a = 1 and minor semi-axis b <= 1 (w = t^2, dw = 2 t dt)."""
    def g(t):
        return 2.0 / math.sqrt((1.0 + t * t) * (b * b + t * t))
    opts = dict(epsabs=0.0, epsrel=1e-13, limit=400)
    # split at t = b and t = 1 where the integrands turn; the tail to infinity on its own
    pieces = [(0.0, b), (b, 1.0), (1.0, np.inf)]
    i0 = sum(quad(g, lo, hi, **opts)[0] for lo, hi in pieces)
    ia = sum(quad(lambda t: g(t) / (1.0 + t * t), lo, hi, **opts)[0] for lo, hi in pieces)
    ib = sum(quad(lambda t: g(t) / (b * b + t * t), lo, hi, **opts)[0] for lo, hi in pieces)
    return i0, ia, ib


def route_potential(r):
    """(k, a*, b*, delta*) by route 1."""
    if r == 1.0:
        return 1.0, 1.0, 1.0, 1.0
    # I_b / I_a falls from infinity at b -> 0 to 1 at b = 1
    b = brentq(lambda bb: integrals(bb)[2] / integrals(bb)[1] - r, 1e-6, 1.0 - 1e-15, xtol=1e-16,
               rtol=1e-15, maxiter=500)
    i0, ia, ib = integrals(b)
    # P = E* = 1 and Sigma rho = 1 (A + B = 1/2, A = 1 / (2 (1 + r))). Semi-axes (s, s b) scale the
    # integrals as I0 ~ 1/s, I_a ~ 1/s^3; c = 3 / (4 pi).
    c = 3.0 / (4.0 * math.pi)
    big_a_at_unit = c * ia           # A when a = 1
    a_target = 1.0 / (2.0 * (1.0 + r))
    s = (big_a_at_unit / a_target) ** (1.0 / 3.0)   # the semi-axis a under P = 1
    delta = c * i0 / s
    scale = (3.0 / 2.0) ** (1.0 / 3.0)               # (3 P / (2 Sigma rho E*))^(1/3) with P = Sigma rho = E* = 1
    return 1.0 / b, s / scale, s * b / scale, delta / (scale**2 * 0.5)


def route_elliptic(r):
    """(k, a*, b*, delta*) by route 2."""
    if r == 1.0:
        return 1.0, 1.0, 1.0, 1.0

    def f(m):
        kk, ee = ellipk(m), ellipe(m)
        return (ee / (1.0 - m) - kk) / (kk - ee) - r
    m = brentq(f, 1e-12, 1.0 - 1e-15, xtol=1e-18, rtol=1e-15, maxiter=500)
    kk, ee = ellipk(m), ellipe(m)
    a_curv = 1.0 / (2.0 * (1.0 + r))                  # Sigma rho = 1
    a = (3.0 * (kk - ee) / (2.0 * math.pi * m * a_curv)) ** (1.0 / 3.0)   # P = E* = 1
    b = a * math.sqrt(1.0 - m)
    p0 = 3.0 / (2.0 * math.pi * a * b)
    delta = p0 * b * kk
    scale = (3.0 / 2.0) ** (1.0 / 3.0)
    return a / b, a / scale, b / scale, delta / (scale**2 * 0.5)


def main():
    rows = []
    worst = 0.0
    for r in RATIOS:
        one, two = route_potential(r), route_elliptic(r)
        err = max(abs(x / y - 1.0) for x, y in zip(one, two))
        worst = max(worst, err)
        assert err < 1e-11, (r, one, two)
        rows.append([r, (r - 1.0) / (r + 1.0)] + list(two))
    out = pathlib.Path(__file__).with_name("hertz_ellipse_reference.csv")
    with open(out, "w", newline="") as fh:
        fh.write("# Hertz's elliptical contact, dimensionless (hertz_ellipse_reference.py; "
                 f"routes 1 and 2 agree to {worst:.1e})\n")
        w = csv.writer(fh, lineterminator="\n")
        w.writerow(["ratio", "curvature_difference", "ellipticity", "a_star", "b_star", "delta_star"])
        for row in rows:
            w.writerow([f"{x:.17g}" for x in row])
    print(f"wrote {out} ({len(rows)} rows; the two routes agree to {worst:.2e})")


if __name__ == "__main__":
    main()
