#!/usr/bin/python3
"""Write the cylinder-pressure table of the engine scenes (cylinder_pressure.csv) and print its
plausibility figures. Run from anywhere: /usr/bin/python3 make_tables.py (writes next to itself).

Engine class: a naturally aspirated 2.0 l four-cylinder in-line spark-ignition (gasoline) passenger-car
engine at full load, 2000 rpm. Geometry from the components: bore 86 mm (testdata/engine_block.geo),
stroke 86 mm (crank radius 43 mm, testdata/crankshaft.toml), conrod 145 mm (testdata/conrod.toml);
swept volume 4 x 0.4996 l = 1.998 l.

The pressure is an engineering estimate from a single-zone heat-release model (J. B. Heywood, Internal
Combustion Engine Fundamentals, McGraw-Hill 1988, sec. 9.2: the first law for the closed cylinder with a
Wiebe burn-rate function, eq. 9.23/9.24), not a measurement:
  dp/dtheta = (gamma - 1) / V dQ/dtheta - gamma p / V dV/dtheta,
  Q(theta) = Q_tot (1 - exp(-a ((theta - theta_s) / dtheta)^(m + 1))),  a = 5, m = 2 (Heywood's
  typical values), start of combustion theta_s = -20 deg, burn duration dtheta = 45 deg (50 % burned
  at 3 deg ATDC, peak pressure at 12 deg ATDC: near MBT timing, whose peak lies 12-16 deg ATDC,
  Heywood sec. 9.2.1);
  gamma = 1.30 (burned/unburned mixture average), compression ratio 10.5 (typical NA gasoline),
  intake-valve closing at 40 deg ABDC (crank angle -140 deg) with 0.95 bar in the cylinder (WOT, NA),
  Q_tot chosen so that the peak is 60 bar absolute (the brief's gasoline figure; NA gasoline peaks at
  full load are 50-70 bar: Heywood fig. 9-2, van Basshuysen & Schaefer, Internal Combustion Engine
  Handbook, SAE 2004, sec. 7);
  exhaust-valve opening at 40 deg BBDC (140 deg): blowdown as an exponential approach to the exhaust
  back-pressure 1.10 bar with a 20 deg time constant; exhaust stroke at 1.10 bar, intake stroke at
  0.95 bar (gas-exchange pumping losses of a throttle wide open).
The table's crank angle: 0 deg = firing top dead centre of this cylinder, 0..720 deg (one 4-stroke cycle).
The value is the gauge pressure p - 1.0 bar (the crankcase's pressure acts under the piston), in bar:
the force on the piston crown is (p - 1 bar) x A, A = pi 0.086^2 / 4 = 5.809e-3 m^2 (the scenes' `scale`
= 1e5 Pa/bar x A = 580.88 N/bar).
Result (printed, and in the CSV header): peak 60.0 bar at 12.0 deg ATDC, motored peak 18.2 bar, heat
released 1090 J per cylinder and cycle (about 2/3 of the fuel energy of a stoichiometric 0.5 l charge,
~1.6 kJ: the rest is heat loss and incomplete combustion, which this model lumps into Q_tot), IMEP 10.5 bar,
indicated torque 168 N m (a 2.0 l NA engine's brake torque at 2000 rpm, full load, is ~170-190 N m at a BMEP
of 11-12 bar: this curve is on the low side of full load, as a 60 bar peak implies).
Checks printed: peak pressure and its angle, the motored (no combustion) peak, IMEP = (loop work) / V_d,
the indicated torque of 4 cylinders, IMEP x V_total / (4 pi), and the indicated power at 2000 rpm.
"""
import math
from pathlib import Path

HERE = Path(__file__).resolve().parent
BORE, R, L = 0.086, 0.043, 0.145           # m
AREA = math.pi / 4 * BORE**2               # m^2
VD = AREA * 2 * R                          # m^3 swept per cylinder
CR = 10.5
VC = VD / (CR - 1)
GAMMA = 1.30
P_IVC, P_EXH, P_INT, P_CASE = 0.95e5, 1.10e5, 0.95e5, 1.0e5   # Pa
THETA_IVC, THETA_EVO = -140.0, 140.0       # deg
THETA_S, DTHETA, A_W, M_W = -20.0, 45.0, 5.0, 2.0
P_PEAK_TARGET = 60e5                       # Pa absolute


def volume(deg):
    t = math.radians(deg)
    x = R * math.cos(t) + math.sqrt(L**2 - (R * math.sin(t))**2)
    return VC + AREA * (R + L - x)


def burned(deg):
    if deg <= THETA_S:
        return 0.0
    return 1.0 - math.exp(-A_W * ((deg - THETA_S) / DTHETA) ** (M_W + 1))


def closed_cycle(q_tot, h=0.01):
    """p (Pa) from IVC to EVO on a grid of h deg, RK4 on the first-law ODE."""
    def rhs(deg, p):
        v = volume(deg)
        dv = (volume(deg + 1e-4) - volume(deg - 1e-4)) / 2e-4
        dq = q_tot * (burned(deg + 1e-4) - burned(deg - 1e-4)) / 2e-4
        return (GAMMA - 1) / v * dq - GAMMA * p / v * dv
    n = int(round((THETA_EVO - THETA_IVC) / h))
    degs, ps = [THETA_IVC], [P_IVC]
    p, d = P_IVC, THETA_IVC
    for _ in range(n):
        k1 = rhs(d, p)
        k2 = rhs(d + h / 2, p + h / 2 * k1)
        k3 = rhs(d + h / 2, p + h / 2 * k2)
        k4 = rhs(d + h, p + h * k3)
        p += h / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
        d += h
        degs.append(d)
        ps.append(p)
    return degs, ps


def pressure_function(q_tot):
    degs, ps = closed_cycle(q_tot)
    h = degs[1] - degs[0]
    p_evo = ps[-1]

    def p(deg):  # deg in [-360, 360)
        if THETA_IVC <= deg <= THETA_EVO:
            i = min(int((deg - THETA_IVC) / h), len(ps) - 2)
            f = (deg - degs[i]) / h
            return ps[i] + f * (ps[i + 1] - ps[i])
        if THETA_EVO < deg <= 360.0:     # blowdown, then the exhaust stroke
            return P_EXH + (p_evo - P_EXH) * math.exp(-(deg - THETA_EVO) / 20.0)
        if deg < -180.0:                 # -360..-180: the intake stroke (and the valve overlap at -360)
            return P_INT + (P_EXH - P_INT) * math.exp(-(deg + 360.0) / 20.0)
        return P_INT                     # -180..-140: the intake valve still open
    return p, max(ps), degs[ps.index(max(ps))]


def main():
    lo, hi = 0.0, 3000.0                 # J per cylinder per cycle: bisect for the peak pressure
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        if pressure_function(mid)[1] < P_PEAK_TARGET:
            lo = mid
        else:
            hi = mid
    q_tot = 0.5 * (lo + hi)
    p, peak, peak_deg = pressure_function(q_tot)
    _, motored_peak, _ = pressure_function(0.0)
    table = []
    for d in range(0, 721):
        deg = d if d < 360 else d - 720  # table angle 0..720 -> cycle angle -360..360
        table.append((d, (p(float(deg)) - P_CASE) / 1e5))
    table[-1] = (720, table[0][1])
    # loop work (J) = closed integral p dV, on 0.01 deg steps
    work, steps = 0.0, 72000
    for k in range(steps):
        a = -360.0 + 720.0 * k / steps
        b = a + 720.0 / steps
        work += 0.5 * (p(a) + p(min(b, 359.9999))) * (volume(b) - volume(a))
    imep = work / VD
    torque = imep * 4 * VD / (4 * math.pi)
    power = torque * 2000 * 2 * math.pi / 60
    figures = (f"peak {peak / 1e5:.1f} bar abs at {peak_deg:.1f} deg ATDC (motored peak {motored_peak / 1e5:.1f} "
               f"bar); heat released {q_tot:.0f} J/cylinder/cycle; IMEP {imep / 1e5:.2f} bar; indicated "
               f"torque {torque:.1f} N m, power {power / 1e3:.1f} kW at 2000 rpm")
    with open(HERE / "cylinder_pressure.csv", "w") as f:
        f.write("# Cylinder gauge pressure p - 1 bar (bar) against crank angle (deg, 0 = firing TDC), made by make_tables.py:\n")
        f.write(f"# NA 2.0 l gasoline, full load; {figures}\n")
        f.write("crank_deg,p_bar\n")
        for d, v in table:
            f.write(f"{d},{v:.5f}\n")
    print(figures)


if __name__ == "__main__":
    main()
