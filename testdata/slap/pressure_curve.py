#!/usr/bin/python3
"""The cylinder-pressure curve of the slap scenes (testdata/slap/cylinder_pressure.csv): a single-zone
(first law) model of a naturally aspirated gasoline cylinder at 2000 rpm, full load - a measured-style curve,
not a measurement. Engineering estimates, SI except the pressure column (bar, absolute and gauge):

  bore 0.086 m, stroke 0.086 m, conrod 0.143 m, compression ratio 10.5 (a square 2.0 L four-cylinder engine)
  intake 0.95 bar (full load, throttle open; intake stroke), exhaust 1.10 bar (exhaust stroke)
  compression and expansion polytropic: dp = -n p dV / V + (n - 1) dQ / V, n = 1.32 (Heywood 1988, sec. 9.2:
    1.3 +- 0.05 for the compression and expansion of gasoline engines); compression starts at intake BDC
  heat release: Wiebe x_b = 1 - exp(-a ((theta - theta_0) / dtheta)^(m + 1)), a = 5, m = 2 (Heywood 1988,
    eq. 9.23 and Fig. 9-13), start theta_0 = 20 deg before firing TDC, duration 50 deg; released heat 1150 J
    per cycle (0.5 L at volumetric efficiency 0.9: 0.53 g air, 36 mg fuel at lambda 1, lower heating value
    43 MJ/kg: 1.55 kJ, of which about 75 % is the net (apparent) heat release after wall heat losses and
    incomplete combustion)
  exhaust valve opening 130 deg after firing TDC: blow-down to 1.10 bar by 180 deg (cosine blend)

Crank angle in the file: 0 = gas-exchange TDC, 360 = firing TDC (720 deg per cycle). The gauge column is
p - 1.0 bar (the crankcase at 1 bar): times the piston area 5.809e-3 m^2 and 1e5 Pa/bar it is the gas force.
Prints the peak pressure and its angle (62.1 bar at 13.6 deg after firing TDC, 35.5 kN). Run: /usr/bin/python3 pressure_curve.py > cylinder_pressure.csv
"""
import math
import sys

BORE, STROKE, ROD, CR = 0.086, 0.086, 0.143, 10.5
N_POLY, A_W, M_W, THETA0, DURATION, Q_TOTAL = 1.32, 5.0, 2.0, -20.0, 50.0, 1150.0
P_INTAKE, P_EXHAUST, EVO = 0.95e5, 1.10e5, 130.0

area = math.pi * BORE**2 / 4
r = STROKE / 2
v_d = area * STROKE
v_c = v_d / (CR - 1)


def volume(theta_deg):  # theta from firing TDC
    t = math.radians(theta_deg)
    s = r * math.cos(t) + math.sqrt(ROD**2 - (r * math.sin(t))**2)  # pin above crank centre
    return v_c + area * (ROD + r - s)


def burned(theta):
    if theta <= THETA0:
        return 0.0
    return 1 - math.exp(-A_W * ((theta - THETA0) / DURATION) ** (M_W + 1))


# integrate the closed part from intake BDC (-180) to EVO in 0.01 deg steps (RK2 on theta)
step = 0.01
closed = {}
theta, p = -180.0, P_INTAKE
while theta < EVO + 1e-9:
    closed[round(theta, 2)] = p

    def dp(th, pp):
        dv = (volume(th + 1e-4) - volume(th - 1e-4)) / 2e-4
        dq = Q_TOTAL * (burned(th + 1e-4) - burned(th - 1e-4)) / 2e-4
        return -N_POLY * pp * dv / volume(th) + (N_POLY - 1) * dq / volume(th)

    k1 = dp(theta, p)
    k2 = dp(theta + step, p + step * k1)
    p += 0.5 * step * (k1 + k2)
    theta = round(theta + step, 2)
p_evo = closed[round(EVO, 2)]


def pressure(theta):  # theta from firing TDC in [-360, 360)
    if -180 <= theta <= EVO:
        return closed[round(round(theta / step) * step, 2)]
    if EVO < theta <= 180:
        w = 0.5 * (1 - math.cos(math.pi * (theta - EVO) / (180 - EVO)))
        return p_evo + w * (P_EXHAUST - p_evo)
    if theta > 180 or theta < -360 + 1e-9:
        return P_EXHAUST  # exhaust stroke
    # intake stroke (-360 .. -180): exhaust pressure blending to the intake's over the first 20 deg
    w = min(1.0, (theta + 360) / 20.0)
    return P_EXHAUST + w * (P_INTAKE - P_EXHAUST)


# the table: 1 deg from 300 to 480 deg (firing TDC at 360), 10 deg elsewhere
angles = sorted(set([a for a in range(0, 721, 10)] + list(range(300, 481))))
best_p, best_a = 0.0, 0.0
for k in range(-6000, 6001):
    a = k / 100.0
    if pressure(a) > best_p:
        best_p, best_a = pressure(a), a
print("crank_deg,p_bar,p_gauge_bar")
for a in angles:
    pa = pressure(a - 360.0)
    print(f"{a},{pa / 1e5:.4f},{pa / 1e5 - 1.0:.4f}")
print(f"peak {best_p / 1e5:.2f} bar at {best_a:.2f} deg after firing TDC; gas force {(best_p - 1e5) * area:.0f} N",
      file=sys.stderr)
