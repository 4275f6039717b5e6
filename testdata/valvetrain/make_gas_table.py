#!/usr/bin/python3
"""Write the exhaust valve's gas load of the valvetrain scenes (exhaust_valve_gas.csv): the pressure difference
across the valve head, cylinder less exhaust port, against the scene's clock (the cam angle). Run from anywhere:
python3 make_gas_table.py (writes next to itself). Every number is explained here; the CSV carries a header
comment saying it was made by this script.

The engine: a generic heavy-duty turbocharged diesel cylinder at rated speed and full load (the valvetrain's
exhaust valve, head 55 mm, belongs to a ~150 mm bore; docs/valvetrain.md section 5): bore 150 mm, stroke 180 mm
(3.18 l), conrod 360 mm, compression ratio 16.5. Crank angle 0 = firing top dead centre.

Cylinder pressure, a single-zone model (J. B. Heywood, Internal Combustion Engine Fundamentals, 1988, sec. 9.2,
the heat-release form of the first law, eq. 9.25: dp/dth = ((g - 1) dQ/dth - g p dV/dth) / V) with a Wiebe
heat release (Heywood eq. 9.23: x_b = 1 - exp(-a ((th - th0) / dth)^(m + 1)), a = 5, m = 1.5, start 10 deg
before top dead centre, duration 50 deg), g = 1.33, no wall heat loss; inlet valve closing (IVC) at 560 deg
(20 deg after bottom dead centre) at the boost pressure 2.8 bar; fuel energy released to the gas Q = 14.5 kJ per cycle (BMEP about 20 bar at a brake efficiency of 0.42 - a modern heavy-duty rating - and
90 % of the fuel's energy released as heat in the gas). Printed by this script: peak pressure 176 bar at
13 deg after top dead centre (heavy-duty diesels at rated: 160-220 bar), 9.5 bar at EVO.
After the exhaust valve opens (EVO, 150 deg: the end of the opening ramp of the scene's cam), blowdown: the
pressure falls to the exhaust's p_e = 2.3 bar (pre-turbine pressure at rated) as p_e + (p_EVO - p_e)
exp(-(th - 150) / 25 deg); the exhaust stroke then stays at p_e, the intake stroke (inlet valve open from 350
deg to IVC) at the boost, 2.8 bar.

The valve's load: (p_cylinder - p_e) on the seat's area (mean seat diameter 50 mm: 1.963e-3 m^2), pushing the
valve onto its seat (against opening): the scene's [[load]] has scale = 196.35 N/bar (1e5 Pa/bar x 1.963e-3
m^2) in its gas variant, 0 in the motored runs. A simplification said once: the pressure across an open valve
is taken as that difference on the same area (the flow forces on an open valve are not modelled; by then
blowdown has equalized the pressures to within a bar).

Cam angle: the scene's clock turns with the camshaft; the cam angle c and the crank angle th are tied by
th = 2 c - 286 deg, so the opening ramp's start (cam 196 deg, lift angle 106 deg + the roller's 90 deg) falls at
106 deg crank, the main lift starts at 150 deg (EVO), the nose (cam 270) at 254 deg crank and the closing
ramp ends at 402 deg crank (EVC 42 deg after the gas-exchange top dead centre, with the ramp: 358 deg).
"""
import math
from pathlib import Path

HERE = Path(__file__).resolve().parent
BORE, STROKE, ROD, CR = 0.150, 0.180, 0.360, 16.5
R = STROKE / 2
AREA = math.pi / 4 * BORE ** 2
VS = AREA * STROKE
VC = VS / (CR - 1)
GAMMA, P_BOOST, P_EXH = 1.33, 2.8e5, 2.3e5
Q_TOTAL, TH0, DTH, A_W, M_W = 14.5e3, 710.0, 50.0, 5.0, 1.5  # TH0: 10 deg before firing TDC (720 = 0)
IVC, EVO, TAU_BLOWDOWN, IVO = 560.0, 150.0, 25.0, 350.0


def volume(th_deg: float) -> float:
    th = math.radians(th_deg)
    s = R * (1 - math.cos(th)) + ROD - math.sqrt(ROD ** 2 - (R * math.sin(th)) ** 2)
    return VC + AREA * s


def burned(th: float) -> float:
    if th <= TH0:
        return 0.0
    return 1 - math.exp(-A_W * ((th - TH0) / DTH) ** (M_W + 1))


def cylinder_pressure() -> dict:
    """p (Pa) at every 0.25 deg of the cycle [0, 720), integrated from IVC (560) through 720 + EVO."""
    step = 0.25
    p = {}
    th, pc = IVC, P_BOOST
    while th < 720 + EVO - 1e-9:
        p[round(th % 720, 2)] = pc
        # Heywood eq. 9.25 with dQ from the Wiebe function; RK2 (midpoint) in the angle.
        def rate(t, pp):
            dv = (volume(t + 1e-3) - volume(t - 1e-3)) / 2e-3
            dq = Q_TOTAL * (burned(t + 1e-3) - burned(t - 1e-3)) / 2e-3
            return ((GAMMA - 1) * dq - GAMMA * pp * dv) / volume(t)
        k1 = rate(th, pc)
        pc = pc + step * rate(th + step / 2, pc + step / 2 * k1)
        th += step
    p_evo = pc
    th = EVO
    while th < IVO - 1e-9:
        p[round(th, 2)] = P_EXH + (p_evo - P_EXH) * math.exp(-(th - EVO) / TAU_BLOWDOWN)
        th += step
    th = IVO
    while th < IVC - 1e-9:
        p[round(th, 2)] = P_BOOST
        th += step
    return p


def main() -> None:
    p = cylinder_pressure()
    peak = max(p, key=p.get)
    print(f"peak pressure {p[peak] / 1e5:.1f} bar at {peak:.1f} deg; at EVO (150 deg) {p[150.0] / 1e5:.2f} bar")
    rows = []
    for cam10 in range(0, 3600, 5):  # every 0.5 cam deg
        cam = cam10 / 10
        crank = (2 * cam - 286) % 720
        key = round(round(crank * 4) / 4, 2) % 720
        rows.append((cam, crank, (p[key] - P_EXH) / 1e5))
    with open(HERE / "exhaust_valve_gas.csv", "w") as f:
        f.write("# made by make_gas_table.py: the pressure across the exhaust valve's head (cylinder - port, bar)\n")
        f.write("# against the scene's cam angle (crank = 2 cam - 286 deg, 0 = firing top dead centre)\n")
        f.write("cam_deg,crank_deg,dp_bar\n")
        for cam, crank, dp in rows:
            f.write(f"{cam:.1f},{crank:.1f},{dp:.4f}\n")


if __name__ == "__main__":
    main()
