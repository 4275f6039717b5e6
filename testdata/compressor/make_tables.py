#!/usr/bin/python3
"""Write the load tables of the compressor scene: the gas force on the piston against crank angle and the
induction motor's torque-speed curves. Run from anywhere: python3 make_tables.py (writes next to itself).
Every number is explained here; the CSV files carry a header comment saying they were made by this script.

Gas force (cylinder_force.csv). An ideal single-stage cycle with polytropic compression and re-expansion
(e.g. W. Soedel, Sound and Vibrations of Positive Displacement Compressors, CRC 2007, ch. 2), for R134a at
the ASHRAE low-back-pressure rating point of domestic refrigerators (evaporating -23.3 C, condensing
54.4 C): saturation pressures 1.15 bar and 14.7 bar. The suction and discharge valves are idealized as
opening at 0.9 x suction and 1.1 x discharge pressure (their pressure drops). The piston's back faces the
shell, which is at suction pressure, so the force on the piston is (p_cylinder - p_suction) x bore area.
Geometry (the scene): bore 21 mm, crank radius 8.5 mm (stroke 17 mm, 5.9 cm^3 swept: about 170 kcal/h at
50 Hz, the paper's compressor), conrod 35 mm, clearance volume 3.5 % of the swept volume, polytropic
exponent 1.10 (R134a, cooled cylinder). Crank angle 0 = top dead centre, the piston furthest from the
shaft.

Motor (motor_<f>hz.csv). A 2-pole induction motor: synchronous speed 60 f rpm. Torque against slip from
Kloss' formula T = 2 T_b / (s / s_b + s_b / s) (e.g. A. Hughes, Electric Motors and Drives, 3rd ed., ch. 7),
breakdown slip s_b = 0.15 at 50 Hz, T_b such that the mean gas torque is delivered at 2% slip (2940 rpm,
308 rad/s: the paper's "about 308 rad/sec"). Supplied at constant V/f (a variable-speed compressor: the
paper, sec. 2), the curve keeps its shape against the slip speed 60 f - n.
"""
import math
from pathlib import Path

HERE = Path(__file__).resolve().parent
BORE, R, L = 0.021, 0.0085, 0.035          # m
AREA = math.pi / 4 * BORE**2               # m^2
SWEPT = AREA * 2 * R
CLEAR = 0.035 * SWEPT
P_SUC, P_DIS = 1.15e5, 14.7e5              # Pa, saturation at -23.3 C and 54.4 C (R134a)
P_IN, P_OUT = 0.9 * P_SUC, 1.1 * P_DIS     # valve opening pressures in the cylinder
N_POLY = 1.10


def volume(theta):
    """Cylinder volume at crank angle theta (rad from TDC): slider-crank piston position."""
    x = R * math.cos(theta) + math.sqrt(L**2 - (R * math.sin(theta))**2)  # from the shaft axis
    return CLEAR + AREA * (R + L - x)


def pressure(theta):
    v, v_tdc, v_bdc = volume(theta), volume(0.0), volume(math.pi)
    if theta <= math.pi:  # re-expansion of the clearance gas, then suction
        return max(P_OUT * (v_tdc / v) ** N_POLY, P_IN)
    return min(P_IN * (v_bdc / v) ** N_POLY, P_OUT)  # compression, then discharge


def main():
    degs = list(range(0, 361))
    force = [(pressure(math.radians(d % 360 if d < 360 else 0)) - P_SUC) * AREA for d in degs]
    force[-1] = force[0]
    # Work per cycle (J) = integral of the gas force over the piston travel: mean torque = W / (2 pi).
    work = 0.0
    for d in range(360):
        a, b = math.radians(d), math.radians(d + 1)
        work += 0.5 * (force[d] + force[d + 1]) * (volume(b) - volume(a)) / AREA
    t_mean = -work / (2 * math.pi) if work < 0 else work / (2 * math.pi)
    with open(HERE / "cylinder_force.csv", "w") as f:
        f.write("# Gas force on the piston (N) against crank angle (deg, 0 = TDC), made by make_tables.py:\n")
        f.write(f"# R134a, suction {P_SUC/1e5} bar, discharge {P_DIS/1e5} bar, bore {BORE*1e3} mm, "
                f"stroke {2*R*1e3} mm; work per cycle {abs(work):.3f} J, mean torque {t_mean:.4f} N m\n")
        f.write("crank_angle_deg,force_n\n")
        for d, F in zip(degs, force):
            f.write(f"{d},{F:.3f}\n")
    s_b, s_op = 0.15, 0.02
    t_b = t_mean * (s_op / s_b + s_b / s_op) / 2
    for f_hz in (40, 45, 50, 55, 60):
        n_sync = 60.0 * f_hz
        with open(HERE / f"motor_{f_hz}hz.csv", "w") as f:
            f.write(f"# 2-pole induction motor at {f_hz} Hz (V/f constant), Kloss curve, made by make_tables.py:\n")
            f.write(f"# breakdown torque {t_b:.4f} N m at slip speed {s_b*3000:.0f} rpm; synchronous {n_sync:.0f} rpm\n")
            f.write("rpm,torque_nm\n")
            for k in range(0, 101):
                n = n_sync * k / 100.0
                ds = (n_sync - n) / 3000.0  # slip referred to 50 Hz (constant V/f)
                t = 0.0 if ds <= 0 else 2 * t_b / (ds / s_b + s_b / ds)
                f.write(f"{n:.1f},{t:.5f}\n")
            f.write(f"{n_sync + 300:.1f},{-2 * t_b / (0.1 / s_b + s_b / 0.1):.5f}\n")  # generating side
    print(f"peak gas force {max(force):.1f} N, work per cycle {abs(work):.3f} J, mean torque {t_mean:.4f} N m, "
          f"breakdown torque {t_b:.4f} N m")


if __name__ == "__main__":
    main()
