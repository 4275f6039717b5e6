#!/usr/bin/python3
"""Tests of the engine scene family (testdata/engine, docs/engine.md), run by ctest:

    test_engine.py bearing_loads BUILD_DIR WORK_DIR   # engine_rigid_throws.toml against the hand calculation
    test_engine.py energy_mounts BUILD_DIR WORK_DIR   # engine_rigid.toml: energy balance and mount forces

bearing_loads. The crank train split at the main bearings (4 rigid throws, each on its own 2 half bearings,
each turned at constant speed) is statically determinate: each half bearing carries half of its throw's
crank-pin force (the lever rule: the pin lies midway between the journals, the throw's centre of mass is on
the axis). The pin force is computed here in closed form (e.g. C. F. Taylor, The Internal-Combustion Engine
in Theory and Practice, vol. 2, MIT Press 1985, ch. 8; Heywood 1988, sec. 2.2), with no use of solve's code:
  piston pin on the cylinder axis at x(theta) = r cos(theta) + sqrt(l^2 - r^2 sin^2(theta)) from the crank
  axis, its acceleration omega^2 x''(theta) with x'' = -r cos(theta) - r^2 cos(2 theta) / s
  - r^4 sin^2(theta) cos^2(theta) / s^3, s = sqrt(l^2 - r^2 sin^2(theta)) (constant omega);
  the conrod as two point masses, m_b = m (l - a) / l at the big end, m_s = m a / l at the small end
  (a: its centre of mass from the big end); the scene's conrod has the inertia m a (l - a) about its
  swing axis that makes this split exact;
  the piston with m_s: (m_p + m_s) x_ddot = -F_gas + S e_z, S the rod's compression along e = (pin -
  crank pin) / l; the force on the crank pin F = -S e + m_b omega^2 c (c: the crank pin's radius vector);
  F_gas = (p - 1 bar) A from cylinder_pressure.csv at the cylinder's crank angle (firing order 1-3-4-2).
  Main bearing k's load on the block is the sum of its halves: F_{k-1}/2 + F_k/2.
The scene's loads are the bushings' forces on the throws, reversed. Compared after the first 30 deg (the
start-up ringing of the throws on their bearings, 3.3 kHz, zeta 0.21, has decayed by then). Tolerance:
1 % of the bearing's peak load, at every sample of the cycle (y and z); the remaining differences are the
bearings' compliance (the pins move 10-20 um) and the throws' small vibration on them.

energy_mounts. The rigid twin of the engine (rigid block on the 4 mounts with the Maxwell element, rigid
crankshaft on bushing mains, gas on pistons and heads, 2000 rpm), 2 cycles, gravity off:
  - the big ends carry no moment across the crank pin beyond the bodies' own out-of-plane inertia (a few N m;
    tolerance 10 N m RMS): the guidance holds each direction once (the former one: up to 7.4 kN m);
  - the energy balance (/energy/balance: kinetic + potential + dissipated - input - its start value) stays
    below 1e-4 of the largest energy put in or taken out by the sources (/energy/input) at every sample;
  - the mounts' total vertical force over the second cycle: its mean times the cycle's duration equals the
    change of the vertical momentum of all bodies over it (impulse and momentum, the only external vertical
    forces being the mounts': the gas acts on the pistons and, reversed, on the heads; the dynamometer gives
    a torque), to 1e-3 of the peak force x T; and, with gravity off, the mean is near zero: below 3 % of the
    peak vertical mount force (what is left is the mounts' start-up transient at ~15 Hz, not yet decayed
    after 2 cycles).
"""
import csv
import math
import shutil
import subprocess
import sys
from pathlib import Path

import h5py
import numpy as np

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent.parent
DATA = ROOT / "testdata" / "engine"
sys.path.insert(0, str(DATA))
import make_scenes as P  # noqa: E402  (the scenes' parameters: the same numbers the scenes were written from)


def run(build, work, scene):
    work.mkdir(parents=True, exist_ok=True)
    for f in [scene, "cylinder_pressure.csv"]:
        shutil.copy(DATA / f, work / f)
    out = work / (Path(scene).stem + ".h5")
    subprocess.run([str(Path(build) / "solve" / "solve"), str(work / scene), "-o", str(out), "-q"], check=True)
    return h5py.File(out, "r")


def pressure_table():
    with open(DATA / "cylinder_pressure.csv") as fh:
        rows = [r for r in csv.reader(l for l in fh if not l.startswith("#"))]
    deg = np.array([float(r[0]) for r in rows[1:]])
    bar = np.array([float(r[1]) for r in rows[1:]])
    return deg, bar


def pin_force(theta, omega, p_bar):
    """Force of conrod + piston on the crank pin (global y, z components), closed form. theta: the throw's
    angle from top dead centre, positive about +x."""
    r, l = P.R, P.L_ROD
    m_s = P.ROD_M * P.ROD_A / l
    m_b = P.ROD_M - m_s
    m_osc = P.PISTON_M + m_s
    s = np.sqrt(l**2 - (r * np.sin(theta))**2)
    x = r * np.cos(theta) + s
    xdd = -r * np.cos(theta) - r**2 * np.cos(2 * theta) / s - r**4 * np.sin(theta)**2 * np.cos(theta)**2 / s**3
    acc = omega**2 * xdd
    cy, cz = -r * np.sin(theta), r * np.cos(theta)      # crank pin: rotation about +x takes z towards -y
    ey, ez = (0 - cy) / l, (x - cz) / l
    f_gas = p_bar * P.GAS_SCALE
    S = (m_osc * acc + f_gas) / ez
    return -S * ey + m_b * omega**2 * cy, -S * ez + m_b * omega**2 * cz


def bearing_loads(build, work):
    f = run(build, work, "engine_rigid_throws.toml")
    t = f["time"][:]
    omega = P.OMEGA
    crank_deg = np.degrees(omega * t)
    deg, bar = pressure_table()
    keep = crank_deg >= 30.0
    pins = []
    for k in range(4):
        theta = omega * t + (0.0 if P.THROW_UP[k] else math.pi)
        p = np.interp(np.mod(crank_deg - P.FIRING_OFFSET[k], 720.0), deg, bar)
        pins.append(np.array(pin_force(theta, omega, p)).T)
    worst = 0.0
    for b in range(5):
        expected = np.zeros((len(t), 2))
        measured = np.zeros((len(t), 2))
        if b > 0:
            expected += 0.5 * pins[b - 1]
            measured -= f[f"forces/throw{b}_rear/force"][:, 1:3]
        if b < 4:
            expected += 0.5 * pins[b]
            measured -= f[f"forces/throw{b + 1}_front/force"][:, 1:3]
        peak = np.abs(expected[keep]).max()
        err = np.abs(measured[keep] - expected[keep]).max() / peak
        worst = max(worst, err)
        print(f"main bearing {b + 1}: peak load {peak:.0f} N (hand calculation), largest difference "
              f"{err * 100:.3f} % of it (y, z)")
    assert worst < 0.01, f"main-bearing loads differ from the hand calculation by {worst * 100:.2f} % > 1 %"
    # The check can fail: without the gas forces the loads are 5-10x smaller (the hand calculation's gas term
    # is what dominates bearing 1's peak).
    print(f"PASS bearing_loads: worst {worst * 100:.3f} % (tolerance 1 %)")


def energy_mounts(build, work):
    f = run(build, work, "engine_rigid.toml")
    # The crank train's joints hold each direction once (docs/engine.md, "Piston guidance"), so the moments
    # across the crank pin (about y and z) at the big ends are only what turns the conrod and piston out of
    # their plane: I alpha with I ~ 3e-3 kg m^2 and the rigid block's rocking on its mounts, alpha well below
    # 1e3 rad/s^2, a few N m. The former prismatic guidance closed a loop block -> piston -> pin -> conrod ->
    # crank pin whose reactions split arbitrarily: 0.4 N m to 7.4 kN m RMS in this scene.
    for k in range(1, 5):
        m = f[f"joints/big_end{k}/reaction_torque"][:, 1:3]
        rms = np.sqrt((m**2).mean(axis=0))
        print(f"big end {k}: moment across the pin, RMS about y {rms[0]:.2f} N m, about z {rms[1]:.2f} N m")
        assert rms.max() < 10.0, f"big end {k} carries {rms.max():.1f} N m RMS across the pin: an over-constraint"
    t = f["time"][:]
    balance = np.abs(f["energy/balance"][:]).max()
    scale = np.abs(f["energy/input"][:]).max()
    print(f"energy: largest |balance| {balance:.3e} J, largest |input| {scale:.3e} J, ratio {balance / scale:.2e}")
    assert scale > 10.0, "the sources put in next to no energy: the scene is not the engine's"
    assert balance < 1e-4 * scale, "the energy balance does not close to 1e-4"

    fz = np.zeros_like(t)
    for m in range(1, 5):
        fz += f[f"forces/mount{m}/force"][:, 2] + f[f"forces/mount{m}_z/force"][:, 2]
    fz += f["forces/mount1_hydro/force"][:, 2]
    T = 4 * math.pi / P.OMEGA
    sel = t >= t[-1] - T - 1e-12
    ts, fs = t[sel], fz[sel]
    impulse = np.trapz(fs, ts)
    momentum = np.zeros_like(t)
    for name, body in f["bodies"].items():
        if "velocity" in body:
            mass = {"block": P.BLOCK_M, "crank": P.CRANK_M}.get(name)
            if mass is None:
                mass = P.ROD_M if name.startswith("conrod") else P.PISTON_M
            momentum += mass * body["velocity"][:, 2]
    dp = momentum[sel][-1] - momentum[sel][0]
    peak = np.abs(fs).max()
    mean = impulse / (ts[-1] - ts[0])
    print(f"mounts: peak vertical force {peak:.1f} N; mean over cycle 2 {mean:.3f} N ({abs(mean) / peak * 100:.2f} % "
          f"of the peak); impulse {impulse:.5f} N s, change of vertical momentum {dp:.5f} N s")
    assert abs(impulse - dp) < 1e-3 * peak * T, "the mounts' impulse differs from the change of momentum"
    assert abs(mean) < 0.03 * peak, "the mean vertical mount force is not near zero (gravity off)"
    print("PASS energy_mounts")


if __name__ == "__main__":
    what, build, work = sys.argv[1], sys.argv[2], Path(sys.argv[3])
    {"bearing_loads": bearing_loads, "energy_mounts": energy_mounts}[what](build, work / what)
