#!/usr/bin/python3
"""An independent peer model of testdata/valvetrain/valvetrain.toml (and valvetrain_lever.toml) at speed, in SciPy.

Written from the documentation (docs/valvetrain.md sections 1-6 and 10, docs/scene-format.md sections 1, 3, 4,
6, 7) and the scene files, not from solve's C++ source, so that a test can check solve's whole-scene result
against a second implementation. Reduced (minimal) coordinates in the plane x-y (the scene is planar):

  state  y_t, y_t'   tappet's reference point (= roller centre) along the bore (+y), x = 0
         phi, phi'   rocker angle about +z through its pivot (0 as drawn; phi < 0 opens the valve)
         y_v, y_v'   valve's centre of mass along its guide (y)
         pushrod chain: x_k, v_k, k = 1..3 (from the tappet's cup along the line to the rocker's ball)
         valve spring chain: x_k, v_k, k = 1..5 (from the spring seat along +y)
  the camshaft is driven: theta(t) = omega t (speed driver, scene-format.md section 3: "the angle starts from
  the initial configuration" = 0; the clock's crank angle is theta, zero_deg = 0).

Element laws, as implemented (doc source in brackets):
  cam profile  `polynomial` [valvetrain.md s.1 "polynomial"]: quintic ramp (0,0,0)->(H,V,0), V = 2H/ramp (rad),
               rise (H,V,0)->(L,0,0), mirror image about nose_angle_deg, base circle elsewhere.
  roller-cam   [valvetrain.md s.2 "Geometry" and "Force"]: roller centre c in the cam frame (rotated by
               -theta); pitch curve P(psi) = rho(psi)[cos psi, sin psi], rho = Rb + Rr + s(-psi); foot psi* by
               Newton on (P - c).P' = 0 from atan2(c_y, c_x), steps <= 0.2 rad; n = [y', -x']/|P'|;
               delta = -n.(c - P); delta' = -n.(v_i - omega x p_i); fn = F(delta)(1 + alpha delta') >= 0,
               F = E* L (delta / (C L^0.1))^(10/9) (Palmgren, s.2 "Line contact"), C = 3.84e-8 * 1e3^-0.8 *
               E*_steel^0.9, alpha = 3 (1 - e)/(2 v_ref), v_ref = 1 m/s; fn n on the tappet at the roller's
               centre (only its y component works: the bore takes x).
  pushrod      `mass-chain` [valvetrain.md s.3 "The model"; scene-format.md s.4 row]: N = 3 masses of 0.1875/3,
               N+1 segments of rate (N+1) k, l0 = free_length/(N+1), free_length = the initial distance
               (0.3 m), h = 0; f_s = k_s (l0 - l_s) - c_s r_s, c_s = 2 zeta k_s / w_1,
               w_1 = 2 sqrt(k_s/m) sin(pi/(2(N+1))); x_k' = v_k - e.v_j, m v_k' = f_{k-1} - f_k; F_i = f_N e on
               the ball, F_j = -f_0 e on the cup; no weight, no e' terms.
  rocker       rigid, Izz = 6.5e-4 about its centre of mass on the pivot (gravity gives no moment);
               `torsional-spring-damper` [scene-format.md s.4]: T = -k (phi - phi0) - d phi', phi0 = 34.38 deg,
               the twist starting at the initial relative angle 0.
  lash         `contact` [scene-format.md s.4 row]: gap = z_j.(p_foot - p_tip) + clearance, z_j = +y (valve tip),
               delta = -gap, fn = k delta^1.5 (1 + alpha delta') >= 0, alpha = 3 (1 - e)/(2 v_ref), v_ref = 1 m/s
               (default: see AMBIGUITIES); fn along +y on the foot, -fn on the valve.
  valve seat   `valve-seat` [valvetrain.md s.4]: closure delta_a = -z_j.(p_face - p_seat), z_j = -y;
               delta_n = cos(beta) delta_a, F_a = cos(beta) P(delta_n) (1 + alpha delta_a') >= 0, P Palmgren on
               L = pi seat_diameter, alpha = 3 (1 - e)/(2 v_ref), v_ref = 1 m/s (axial terms); F_a on the valve
               along z_j (down).
  valve spring `valve-spring` [valvetrain.md s.3 "From wire data", "Dead coils"]: k = G d^4/(8 D^3 n_a),
               m_a = rho (pi d^2/4)(pi D n_a), N = 5 masses of m_a/(N+1), h = n_d d at each end,
               l0 = (free_length - 2h)/(N+1), k_s = (N+1) k, l_solid = n_a d/(N+1), clash k_c = 100 k_s,
               c_s = 2 zeta k_s / w_1. end_mass (35.1 g) NOT added: the scene's valve mass 0.285 kg already
               contains it (0.25 kg valve + retainer + keepers + 0.0351 kg; checked in this file).
  gravity      [0, -9.81, 0] on tappet and valve (the chains' masses carry no weight, s.3).
  gas load     scale 0 in the scene: left out.

THE LEVER SCENE (--scene lever: testdata/valvetrain/valvetrain_lever.toml, valvetrain.md s.10): the tappet is
replaced by a rigid lever (body `follower`) on a revolute joint at ground.follower_pivot (-0.060, 0.0675);
everything from the pushrod up (pushrod chain, rocker and its return spring, lash, valve, seat, valve spring,
gravity, the gas load off) is the tappet scene's, term for term. What differs:
  state        beta, beta' (in place of y_t, y_t'): the lever's angle about +z through its pivot, 0 as drawn
               (the scene's orientation is the identity; solve's bodies/follower/euler_parameters: 2 atan2(e3, e0)).
  geometry     [scene-format.md s.1: "A rigid body's reference point is its centre of mass", marker `at` "body
               axes, from the reference point"]: the centre of mass at (-0.020, 0.0675), markers pivot (-0.040, 0),
               roller (0.010, 0), cup (0.020, 0): from the pivot along the lever at beta, the centre of mass at
               r_cm = 0.040, the roller's centre at r_r = 0.050, the cup at r_c = 0.060 (L_rp, L_pp of s.10's
               table). Roller centre p_r = pivot + r_r [cos beta, sin beta], v_r = beta' r_r [-sin beta, cos beta];
               the cup likewise with r_c.
  inertia      [scene-format.md s.1: `inertia` "about the centre of mass"]: Izz = 2.1e-4 (the scene's value)
               about the centre of mass, about the pivot by parallel axes I_p = 2.1e-4 + 0.391 * 0.040^2 =
               8.356e-4 kg m^2 (see AMBIGUITIES). mass 0.391 kg.
  roller-cam   [valvetrain.md s.2 "Geometry", "Force"; s.2 "The contact point is found on the profile at every
               evaluation ... a pivoting roller lever"; s.10 "needs nothing of its own"]: the tappet's law with
               the lever's cam: lift 0.00805 m, ramp_height 0.000333 m (V = 2H/ramp), the rest as the tappet's
               (Rb 25 mm, Rr 12.5 mm, rise 52, ramp 22, nose 180 deg, width 15 mm, e 0.6); the camshaft's axis
               (its marker `lobe`, identity orientation) at (-0.010, 0.030). c = R(-theta)(p_r - p_axis), the foot
               by the same Newton from atan2(c_y, c_x) (now off the cam's y axis as beta grows: x of the roller
               = -0.060 + 0.050 cos beta); delta' = -n.(v_r - omega z x (p_r - p_axis)). As drawn the roller's
               centre is 37.5 mm = Rb + Rr straight above the axis (gap 0 on the base circle), so the event is
               the tappet's: s(theta - 90 deg) to first order, nose at 270 cam deg.
  lever's EOM  I_p beta'' = z.(r_roller x fn n) + z.(r_cup x F_j) - m g r_cm cos beta, the cam's fn n at the
               roller's centre [valvetrain.md s.2 "fn n acts on the follower at the roller's centre ... the
               follower gets no torque from the contact": about the pivot it is r x F], the pushrod's
               F_j = -f_0 e at the cup [scene-format.md s.4 mass-chain row], the weight at the centre of mass
               [scene gravity (0, -9.81, 0)]; the pivot's reaction does no work (reduced coordinates).
  pushrod      [scene-format.md s.4 mass-chain row]: as for the tappet, but the line runs from the lever's
               moving cup (j) to the rocker's moving ball (i): e = (p_ball - p_cup)/L turns with both ends;
               x_k' = v_k - e.v_cup, v_k absolute along the line, m v_k' = f_{k-1} - f_k, the last segment's rate
               L' = e.(v_ball - v_cup); inertia along the line only (no e' terms). free_length = the initial
               distance: the cup as drawn is where the tappet's was, (0, 0.0675), so 0.3 m as before.
  initial      as drawn (the drawing satisfies the revolute joint and the cam's gap is 0): beta = 0, beta' = 0, the
               rest as the tappet scene's (below).

Initial state (scene-format.md s.1 "Initial positions ... assembles them ... projects the velocities", s.3,
valvetrain.md s.3): the drawing already satisfies the joints, so positions are as drawn: y_t = 0.0375
(roller on the base circle, gap 0), phi = 0, y_v = 0.2675 (face on the seat, gap 0, lash open 0.5 mm); all
velocities 0 except the camshaft's omega (the roller on the base circle needs none); the chains at their static
equilibrium at the initial distance, x_k = h + k (L0 - 2h)/(N+1), v_k = 0. The system is therefore NOT in
equilibrium at t = 0 (pushrod unloaded against the return spring's 6 N m, valve seat unloaded against the
spring's 491 N): both the peer and solve start with the same short transient, which has decayed long before
the event (196..344 cam deg).

Integration: scipy.integrate.solve_ivp, LSODA (default) or Radau, rtol 1e-9 by default, atol scaled per state.
Converged: rtol 1e-10 against 1e-9 (LSODA) differs by <= 1.3e-5 of each channel's range over the first
revolution (the largest in the seat force during the bounces), Radau 1e-9 and DOP853 1e-10 against LSODA 1e-10
by <= 3.5e-6; the located seating speed agrees to 1e-8 m/s.
The lever (975 and 325 cam rpm; the lever's angle's atol is atol / r_c): LSODA rtol 1e-10 against 1e-9 differs
by <= 2.5e-5 (975) and 4.3e-5 (325) of each channel's range over the first revolution, the seat force in the
bounces; over the event (190-320 deg) by <= 1.3e-6. Radau 1e-9 against LSODA 1e-10 by <= 1.3e-5 (975), 2.5e-5
(325), over the event <= 1.8e-6; DOP853 1e-10 against LSODA 1e-10 by <= 6.6e-5 (the cam force), over the event
<= 1.9e-5. The located first seating speed agrees to 1e-6 m/s between all of them.

AMBIGUITIES (where the docs left a point open; resolved from solve's source, read for these points only):
  - `reference_speed` of `contact` (the lash) and of `valve-seat` (the seat): the scene sets neither, and
    scene-format.md s.4 gives no default for either (valvetrain.md s.4's example sets 0.5; s.8 implies 1 m/s
    for the seat). solve/elements/contact_law.cpp (number_or("reference_speed", 1.0)) and valve_seat.cpp: 1 m/s.
    (scene-format.md now states both defaults, restitution 1 and reference_speed 1 m/s; the mass-chain's start
    and the tappet's cam angle below are now stated too: scene-format.md s.4, valvetrain.md s.5.)
  - E*_steel in Palmgren's constant C: valvetrain.md s.2 says "113.7 GPa (207 GPa and 0.3 on both sides)";
    solve/elements/hertz_line.hpp computes it exactly, 207e9 / (2 (1 - 0.09)) = 113.736 GPa (as here; for steel
    on steel it cancels in any case).
  - The lever's inertia (lever scene): valvetrain.md s.10 and the scene's comment give "8.4e-4 kg m^2 about the
    pivot" and derive Izz = 8.4e-4 - 0.391 * 0.040^2 = 2.144e-4 about the centre of mass, but the scene writes
    inertia[2] = 2.1e-4: about the pivot that is 8.356e-4 (0.5 % less than the text). The peer uses the scene's
    value (what solve reads); with 8.4e-4 instead the tight comparison at 975 rpm moves by 1.1e-3 of the cam
    force's range (from 7e-6), so the choice is visible in the test.
  Not ambiguous but easy to misread: the mass-chain "starts at the static equilibrium" of the chain alone, at the
  initial distance; with the default free_length (= the initial distance) the pushrod starts unloaded, so the
  scene's "6 N m at the start: 150 N on the pushrod" holds after the start transient, not at t = 0. The tappet on
  the cam's +y axis sees s(theta - 90 deg) (section 1's convention is a follower on +x): nose at 270 cam deg,
  event 196..344 cam deg.

Usage:  valvetrain_scipy.py --rpm 975 --out FILE.csv [--scene tappet|lever] [--rtol 1e-9] [--method LSODA]
                            [--end-deg 360] [--step-deg 0.25]
Columns of the CSV (one row per cam angle on a uniform grid from 0):
  cam_deg, valve_lift_m (0.2675 - y_v: the KPI report's definition), valve_velocity_mps (y_v', + up),
  cam_force_N, rocker_angle_rad, tappet_lift_m (y_t - 0.0375; the lever: lever_angle_rad, beta),
  pushrod_force_i_N, pushrod_force_j_N, lash_force_N, seat_axial_force_N, spring_force_i_N
The header comment gives the command, the tolerances, scipy's version and the located seating events.
"""
import argparse
import math
import sys
import time

import numpy as np
import scipy
from scipy.integrate import solve_ivp

# ---------------------------------------------------------------------------------------------------------------
# Scene data (testdata/valvetrain/valvetrain.toml)
G_ACC = 9.81
# camshaft / cam profile (the lift and the ramp's height per scene: TAPPET_CAM, LEVER_CAM below)
RB, RR = 0.025, 0.0125
RISE, RAMP = math.radians(52.0), math.radians(22.0)
NOSE = math.radians(180.0)
CAM_WIDTH, CAM_E = 0.015, 0.6
# tappet (valvetrain.toml; the camshaft's axis at the origin)
M_T, YT0, CUP = 0.38, 0.0375, 0.030
# lever (valvetrain_lever.toml): global positions as drawn (beta = 0); the scene's marker `at`s are from the
# centre of mass (-0.020, 0.0675): pivot -0.040, roller +0.010, cup +0.020 along x
LV_PX, LV_PY = -0.060, 0.0675                    # ground.follower_pivot (= follower.pivot as drawn)
LV_CAM_X, LV_CAM_Y = -0.010, 0.030               # ground.cam_axis (the camshaft's position, its lobe marker)
LV_M, LV_ICM = 0.391, 2.1e-4                     # kg; Izz about the centre of mass (the scene's inertia[2])
LV_RCM, LV_RROL, LV_RCUP = 0.040, 0.050, 0.060   # m from the pivot along the lever: centre of mass, roller, cup
LV_IP = LV_ICM + LV_M * LV_RCM ** 2              # about the pivot (parallel axes): 8.356e-4 kg m^2
# rocker
PIV_X, PIV_Y, ARM_B, ARM_F, I_R = 0.040, 0.3675, 0.040, 0.058, 6.5e-4
K_RET, D_RET, PHI0 = 10.0, 0.05, math.radians(34.38)
# valve
M_V, YV0, TIP, FACE, RET = 0.285, 0.2675, 0.100, -0.100, 0.090
SEAT_Y, SPRING_SEAT_Y = 0.1675, 0.2975
# pushrod chain
PR_N, PR_M, PR_K, PR_ZETA = 3, 0.1875, 4.3e7, 0.1
# lash contact
LASH_K, LASH_N, LASH_E, LASH_C = 1.5e10, 1.5, 0.8, 0.0005
# seat
SEAT_D, SEAT_BETA, SEAT_E = 0.050, math.radians(45.0), 0.5
# valve spring
VS_D, VS_DM, VS_NA, VS_ND, VS_FREE, VS_N, VS_ZETA = 0.0058, 0.038, 5.0, 1.0, 0.072, 5, 0.03
VS_G, VS_RHO, VS_CLASH = 79.3e9, 7850.0, 100.0
V_REF = 1.0  # m/s, reference_speed default of roller-cam (valvetrain.md s.2 table), contact and valve-seat

# ---------------------------------------------------------------------------------------------------------------
# Derived constants
E_STAR = 1.0 / (2.0 * (1.0 - 0.3 ** 2) / 207e9)  # steel on steel, 113.7 GPa
C_PALM = 3.84e-5 * 1e-3 * 1e3 ** -0.8 * E_STAR ** 0.9  # SI (valvetrain.md s.2)


def palmgren(delta, length):
    """Palmgren's line-contact load for the approach delta > 0 (valvetrain.md s.2)."""
    return E_STAR * length * (delta / (C_PALM * length ** 0.1)) ** (10.0 / 9.0)


ALPHA_CAM = 3.0 * (1.0 - CAM_E) / (2.0 * V_REF)
ALPHA_LASH = 3.0 * (1.0 - LASH_E) / (2.0 * V_REF)
ALPHA_SEAT = 3.0 * (1.0 - SEAT_E) / (2.0 * V_REF)
SEAT_L = math.pi * SEAT_D
COSB = math.cos(SEAT_BETA)

# pushrod: free length = the initial distance between the ball (0, 0.3675) and the cup (0, 0.0675)
PR_L0 = PIV_Y - (YT0 + CUP)
# the lever's cup as drawn is where the tappet's is (0, 0.0675): the same free length
assert math.hypot(PIV_X - ARM_B - (LV_PX + LV_RCUP), PIV_Y - LV_PY) == PR_L0
PR_KS = (PR_N + 1) * PR_K
PR_MK = PR_M / PR_N
PR_SEG0 = PR_L0 / (PR_N + 1)
PR_W1 = 2.0 * math.sqrt(PR_KS / PR_MK) * math.sin(math.pi / (2 * (PR_N + 1)))
PR_CS = 2.0 * PR_ZETA * PR_KS / PR_W1

# valve spring from the wire
VS_K = VS_G * VS_D ** 4 / (8.0 * VS_DM ** 3 * VS_NA)
VS_MA = VS_RHO * (math.pi * VS_D ** 2 / 4.0) * (math.pi * VS_DM * VS_NA)
VS_MK = VS_MA / (VS_N + 1)
VS_H = VS_ND * VS_D
VS_KS = (VS_N + 1) * VS_K
VS_SEG0 = (VS_FREE - 2.0 * VS_H) / (VS_N + 1)
VS_SOLID = VS_NA * VS_D / (VS_N + 1)
VS_KC = VS_CLASH * VS_KS
VS_W1 = 2.0 * math.sqrt(VS_KS / VS_MK) * math.sin(math.pi / (2 * (VS_N + 1)))
VS_CS = 2.0 * VS_ZETA * VS_KS / VS_W1
VS_END_MASS = VS_MA / (2 * (VS_N + 1)) + VS_RHO * (math.pi * VS_D ** 2 / 4.0) * math.pi * VS_DM * VS_ND
# The scene's valve mass 0.285 kg = 0.25 kg (valve, retainer, keepers) + the spring's end mass: not added again.
assert abs(0.25 + VS_END_MASS - M_V) < 1e-3, VS_END_MASS


# ---------------------------------------------------------------------------------------------------------------
# Cam profile (valvetrain.md s.1)
def _quintic(p0, v0, a0, p1, v1, a1):
    dp = p1 - p0
    c3 = 10 * dp - 6 * v0 - 4 * v1 - (3 * a0 - a1) / 2
    c4 = -15 * dp + 8 * v0 + 7 * v1 + (3 * a0 - 2 * a1) / 2
    c5 = 6 * dp - 3 * v0 - 3 * v1 - (a0 - a1) / 2
    return (p0, v0, a0 / 2, c3, c4, c5)


class Cam:
    """One scene's polynomial event: its lift L and ramp height H (rise, ramp, nose and radii are common)."""

    def __init__(self, lift_m, ramp_height):
        v_ramp = 2.0 * ramp_height / RAMP  # m/rad, the default ramp velocity
        self.ramp_q = _quintic(0.0, 0.0, 0.0, ramp_height, v_ramp * RAMP, 0.0)
        self.rise_q = _quintic(ramp_height, v_ramp * RISE, 0.0, lift_m, 0.0, 0.0)


TAPPET_CAM = Cam(0.00966, 0.0004)   # valvetrain.toml, m at the tappet
LEVER_CAM = Cam(0.00805, 0.000333)  # valvetrain_lever.toml, m at the roller


def _qeval(c, x):
    g = c[0] + x * (c[1] + x * (c[2] + x * (c[3] + x * (c[4] + x * c[5]))))
    g1 = c[1] + x * (2 * c[2] + x * (3 * c[3] + x * (4 * c[4] + x * 5 * c[5])))
    g2 = 2 * c[2] + x * (6 * c[3] + x * (12 * c[4] + x * 20 * c[5]))
    g3 = 6 * c[3] + x * (24 * c[4] + x * 60 * c[5])
    return g, g1, g2, g3


def lift(u, cam):
    """s, s', s'', s''' (m, m/rad^k) of the polynomial event at the profile angle u (rad)."""
    d = math.remainder(u - NOSE, 2.0 * math.pi)  # in [-pi, pi]
    a = abs(d)
    if a >= RISE + RAMP:
        return 0.0, 0.0, 0.0, 0.0
    if a >= RISE:
        w, x, c = RAMP, (RISE + RAMP - a) / RAMP, cam.ramp_q
    else:
        w, x, c = RISE, (RISE - a) / RISE, cam.rise_q
    g, g1, g2, g3 = _qeval(c, x)
    sg = 1.0 if d < 0 else -1.0  # opening side: x grows with u; closing side: the mirror image
    return g, sg * g1 / w, g2 / (w * w), sg * g3 / (w * w * w)


def pitch(psi, cam):
    """P, P', P'' of the pitch curve at psi (cam frame)."""
    s, s1, s2, _ = lift(-psi, cam)
    rho, r1, r2 = RB + RR + s, -s1, s2
    c, sn = math.cos(psi), math.sin(psi)
    px, py = rho * c, rho * sn
    p1x, p1y = r1 * c - rho * sn, r1 * sn + rho * c
    p2x, p2y = (r2 - rho) * c - 2 * r1 * sn, (r2 - rho) * sn + 2 * r1 * c
    return px, py, p1x, p1y, p2x, p2y


def cam_contact(theta, x_g, y_g, cam):
    """Gap g and the outward unit normal (global axes) of the roller centre (x_g, y_g) (global axes, from the
    cam's axis) on the cam at angle theta; also the profile angle of the contact point."""
    ct, st = math.cos(theta), math.sin(theta)
    cx, cy = ct * x_g + st * y_g, ct * y_g - st * x_g  # R(-theta) [x_g, y_g]
    psi = math.atan2(cy, cx)
    for _ in range(50):
        px, py, p1x, p1y, p2x, p2y = pitch(psi, cam)
        dx, dy = px - cx, py - cy
        f = dx * p1x + dy * p1y
        fp = p1x * p1x + p1y * p1y + dx * p2x + dy * p2y
        step = -f / fp
        step = max(-0.2, min(0.2, step))
        psi += step
        if abs(step) < 1e-15:
            break
    px, py, p1x, p1y, _, _ = pitch(psi, cam)
    nrm = math.hypot(p1x, p1y)
    nx, ny = p1y / nrm, -p1x / nrm
    g = nx * (cx - px) + ny * (cy - py)
    ngx, ngy = ct * nx - st * ny, st * nx + ct * ny  # R(theta) n
    return g, ngx, ngy, psi


# ---------------------------------------------------------------------------------------------------------------
# State layout (the follower's coordinate: the tappet's y_t, or the lever's angle beta)
I_YT, I_VT, I_PHI, I_W, I_YV, I_VV = range(6)
I_BETA, I_WB = I_YT, I_VT
I_PX = 6
I_PV = I_PX + PR_N
I_SX = I_PV + PR_N
I_SV = I_SX + VS_N
NSTATE = I_SV + VS_N


def initial_state(lever=False):
    y = np.zeros(NSTATE)
    y[I_YT], y[I_PHI], y[I_YV] = (0.0 if lever else YT0), 0.0, YV0
    for k in range(1, PR_N + 1):
        y[I_PX + k - 1] = k * PR_L0 / (PR_N + 1)
    l_vs = YV0 + RET - SPRING_SEAT_Y
    for k in range(1, VS_N + 1):
        y[I_SX + k - 1] = VS_H + k * (l_vs - 2 * VS_H) / (VS_N + 1)
    return y


def chain_forces(xs, vs, L, Ld, uj, h, n, seg0, ks, cs, solid, kc):
    """Segment forces f_0..f_N of a chain (valvetrain.md s.3), compression positive."""
    nodes = [h] + list(xs) + [L - h]
    rates = [0.0] + [v - uj for v in vs] + [Ld]
    f = []
    for s in range(n + 1):
        ls = nodes[s + 1] - nodes[s]
        rs = rates[s + 1] - rates[s]
        fs = ks * (seg0 - ls) - cs * rs
        if kc > 0.0 and ls < solid:
            fs += kc * (solid - ls)
        f.append(fs)
    return f


def evaluate(t, y, omega, lever=False):
    """The derivative and every output quantity at (t, y); `lever`: valvetrain_lever.toml's follower."""
    theta = omega * t
    yt, vt, phi, w, yv, vv = y[I_YT], y[I_VT], y[I_PHI], y[I_W], y[I_YV], y[I_VV]
    cphi, sphi = math.cos(phi), math.sin(phi)
    out = {}
    # --- roller on cam: the roller's centre (rx, ry) from the cam's axis and its velocity (vrx, vry)
    if lever:
        beta, wb = yt, vt
        cb, sb = math.cos(beta), math.sin(beta)
        rx, ry = LV_PX + LV_RROL * cb - LV_CAM_X, LV_PY + LV_RROL * sb - LV_CAM_Y
        vrx, vry = -LV_RROL * sb * wb, LV_RROL * cb * wb
        g, nx, ny, psi = cam_contact(theta, rx, ry, LEVER_CAM)
    else:
        rx, ry, vrx, vry = 0.0, yt, 0.0, vt
        g, nx, ny, psi = cam_contact(theta, rx, ry, TAPPET_CAM)
    delta = -g
    fcam = 0.0
    if delta > 0.0:
        if lever:  # v_i - omega x (p_i - p_j), omega x r = omega (-r_y, r_x): (vrx + omega ry, vry - omega rx)
            ddelta = -(nx * (vrx + omega * ry) + ny * (vry - omega * rx))
        else:  # the same at (rx, ry) = (0, yt), written as first (the tappet's CSVs to the last bit)
            ddelta = -(nx * omega * yt + ny * vt)
        fcam = max(0.0, palmgren(delta, CAM_WIDTH) * (1.0 + ALPHA_CAM * ddelta))
    out["cam_force"], out["cam_gap"] = fcam, g
    # --- pushrod chain between rocker.ball (i) and the follower's cup (j): cup (cux, cuy), its velocity (cvx, cvy)
    bx, by = PIV_X - ARM_B * cphi, PIV_Y - ARM_B * sphi
    bvx, bvy = ARM_B * sphi * w, -ARM_B * cphi * w
    if lever:
        cux, cuy = LV_PX + LV_RCUP * cb, LV_PY + LV_RCUP * sb
        cvx, cvy = -LV_RCUP * sb * wb, LV_RCUP * cb * wb
    else:
        cux, cuy, cvx, cvy = 0.0, yt + CUP, 0.0, vt
    dx, dy = bx - cux, by - cuy
    L = math.hypot(dx, dy)
    ex, ey = dx / L, dy / L
    uj = ex * cvx + ey * cvy  # e . v_j
    Ld = ex * (bvx - cvx) + ey * (bvy - cvy)
    pxs = y[I_PX:I_PX + PR_N]
    pvs = y[I_PV:I_PV + PR_N]
    fp = chain_forces(pxs, pvs, L, Ld, uj, 0.0, PR_N, PR_SEG0, PR_KS, PR_CS, 0.0, 0.0)
    out["pushrod_force_i"], out["pushrod_force_j"] = fp[-1], fp[0]
    # --- lash contact rocker.foot (i) on valve.tip (j), z_j = +y
    foot_y = PIV_Y + ARM_F * sphi
    foot_vy = ARM_F * cphi * w
    gap_l = (foot_y - (yv + TIP)) + LASH_C
    flash = 0.0
    if gap_l < 0.0:
        dl = -gap_l
        dld = -(foot_vy - vv)
        flash = max(0.0, LASH_K * dl ** LASH_N * (1.0 + ALPHA_LASH * dld))
    out["lash_force"], out["lash_gap"] = flash, gap_l
    # --- seat: valve.face (i) on ground.valve_seat (j), z_j = -y
    gap_s = -((yv + FACE) - SEAT_Y)
    fseat = 0.0
    if gap_s < 0.0:
        da = -gap_s
        dad = vv  # -d(gap)/dt
        fseat = max(0.0, COSB * palmgren(COSB * da, SEAT_L) * (1.0 + ALPHA_SEAT * dad))
    out["seat_force"], out["seat_gap"] = fseat, gap_s
    # --- valve spring: valve.retainer (i) over ground.spring_seat (j), along +y
    Ls = yv + RET - SPRING_SEAT_Y
    sxs = y[I_SX:I_SX + VS_N]
    svs = y[I_SV:I_SV + VS_N]
    fs = chain_forces(sxs, svs, Ls, vv, 0.0, VS_H, VS_N, VS_SEG0, VS_KS, VS_CS, VS_SOLID, VS_KC)
    out["spring_force_i"] = fs[-1]
    # --- equations of motion
    dy = np.empty(NSTATE)
    dy[I_YT] = vt
    if lever:
        # about the pivot: the cam's fn n at the roller's centre, F_j = -f_0 e at the cup, the weight at the centre
        # of mass (all r from the pivot along the lever at beta)
        t_cam = LV_RROL * (cb * fcam * ny - sb * fcam * nx)
        t_rod = LV_RCUP * (cb * (-fp[0] * ey) - sb * (-fp[0] * ex))
        t_grav = -LV_RCM * cb * LV_M * G_ACC
        dy[I_VT] = (t_cam + t_rod + t_grav) / LV_IP
    else:
        dy[I_VT] = (fcam * ny - fp[0] * ey) / M_T - G_ACC
    # rocker: ball force F_i = f_N e at r_b = (-ARM_B cphi, -ARM_B sphi); foot force (0, flash) at r_f
    rbx, rby = -ARM_B * cphi, -ARM_B * sphi
    fix, fiy = fp[-1] * ex, fp[-1] * ey
    torque = rbx * fiy - rby * fix + ARM_F * cphi * flash - K_RET * (phi - PHI0) - D_RET * w
    dy[I_PHI] = w
    dy[I_W] = torque / I_R
    dy[I_YV] = vv
    dy[I_VV] = (-flash - fseat + fs[-1]) / M_V - G_ACC
    for k in range(PR_N):
        dy[I_PX + k] = pvs[k] - uj
        dy[I_PV + k] = (fp[k] - fp[k + 1]) / PR_MK
    for k in range(VS_N):
        dy[I_SX + k] = svs[k]
        dy[I_SV + k] = (fs[k] - fs[k + 1]) / VS_MK
    out["rocker_angle"] = phi
    if lever:
        out["lever_angle"] = yt
    else:
        out["tappet_lift"] = yt - YT0
    out["valve_lift"], out["valve_velocity"], out["valve_acc"] = YV0 - yv, vv, dy[I_VV]
    return dy, out


def atol_vector(atol, lever=False):
    """Absolute tolerances per state: positions atol, velocities atol * 1e3 (m/s vs m over ~1 ms); angles over
    their arm (the rocker's foot, the lever's cup)."""
    a = np.full(NSTATE, atol)
    for i in (I_VT, I_W, I_VV):
        a[i] = atol * 1e3
    a[I_PV:I_PV + PR_N] = atol * 1e3
    a[I_SV:I_SV + VS_N] = atol * 1e3
    a[I_W] = atol * 1e3 / ARM_F  # rad/s
    a[I_PHI] = atol / ARM_F
    if lever:
        a[I_WB] = atol * 1e3 / LV_RCUP
        a[I_BETA] = atol / LV_RCUP
    return a


def simulate(rpm, end_deg=360.0, rtol=1e-9, atol=1e-12, method="LSODA", max_step_deg=None, lever=False):
    """Integrate from cam angle 0 to end_deg; returns the solve_ivp solution and omega."""
    omega = rpm * 2.0 * math.pi / 60.0
    t_end = math.radians(end_deg) / omega
    y0 = initial_state(lever)
    kw = {}
    if max_step_deg:
        kw["max_step"] = math.radians(max_step_deg) / omega

    def seat_event(t, y):  # the seat's gap, for the seating speed
        return -((y[I_YV] + FACE) - SEAT_Y)
    seat_event.direction = -1.0

    sol = solve_ivp(lambda t, y: evaluate(t, y, omega, lever)[0], (0.0, t_end), y0, method=method, rtol=rtol,
                    atol=atol_vector(atol, lever), dense_output=True, events=[seat_event], **kw)
    if not sol.success:
        raise RuntimeError(sol.message)
    return sol, omega


def outputs(sol, omega, t, lever=False):
    keys = ["valve_lift", "valve_velocity", "cam_force", "rocker_angle", "lever_angle" if lever else "tappet_lift",
            "pushrod_force_i",
            "pushrod_force_j", "lash_force", "seat_force", "spring_force_i", "cam_gap", "seat_gap", "lash_gap",
            "valve_acc"]
    ys = sol.sol(t)
    res = {k: np.empty(len(t)) for k in keys}
    for n in range(len(t)):
        _, o = evaluate(t[n], ys[:, n], omega, lever)
        for k in keys:
            res[k][n] = o[k]
    res["cam_deg"] = np.degrees(omega * t)
    res["time"] = t
    return res


def seatings(sol, omega):
    """(cam deg, closing speed m/s) of every landing of the valve on its seat (gap crossing 0 downwards)."""
    return [(math.degrees(omega * t), y[I_VV]) for t, y in zip(sol.t_events[0], sol.y_events[0]) if t > 0.0]


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--rpm", type=float, required=True, help="cam rpm (the scene's driver rpm)")
    ap.add_argument("--out", required=True, help="CSV file")
    ap.add_argument("--rtol", type=float, default=1e-9)
    ap.add_argument("--atol", type=float, default=1e-12, help="m (positions); velocities 1e3 x")
    ap.add_argument("--method", default="LSODA", choices=["LSODA", "Radau", "BDF", "DOP853"])
    ap.add_argument("--end-deg", type=float, default=360.0)
    ap.add_argument("--step-deg", type=float, default=0.25)
    ap.add_argument("--scene", default="tappet", choices=["tappet", "lever"],
                    help="valvetrain.toml (tappet) or valvetrain_lever.toml (lever)")
    a = ap.parse_args(argv)
    lever = a.scene == "lever"
    t0 = time.process_time()
    sol, omega = simulate(a.rpm, a.end_deg, a.rtol, a.atol, a.method, lever=lever)
    cpu = time.process_time() - t0
    n = int(round(a.end_deg / a.step_deg))
    t = np.radians(np.arange(n + 1) * a.step_deg) / omega
    r = outputs(sol, omega, t, lever)
    cols = [("cam_deg", "cam_deg", "%.4f"), ("valve_lift_m", "valve_lift", "%.9e"),
            ("valve_velocity_mps", "valve_velocity", "%.6e"), ("cam_force_N", "cam_force", "%.6f"),
            ("rocker_angle_rad", "rocker_angle", "%.9e"),
            ("lever_angle_rad", "lever_angle", "%.9e") if lever else ("tappet_lift_m", "tappet_lift", "%.9e"),
            ("pushrod_force_i_N", "pushrod_force_i", "%.6f"), ("pushrod_force_j_N", "pushrod_force_j", "%.6f"),
            ("lash_force_N", "lash_force", "%.6f"), ("seat_axial_force_N", "seat_force", "%.6f"),
            ("spring_force_i_N", "spring_force_i", "%.6f")]
    cmd = "valvetrain_scipy.py " + " ".join(sys.argv[1:] if argv is None else argv)
    lands = seatings(sol, omega)
    land = (f"{len(lands)}; the first: " + ", ".join(f"{d:.4f} deg {v:+.6f} m/s" for d, v in lands[:3])
            if lands else "none")
    with open(a.out, "w") as f:
        f.write(f"# {cmd}\n# method {a.method}, rtol {a.rtol:g}, atol {a.atol:g} m (velocities x1e3), "
                f"scipy {scipy.__version__}, numpy {np.__version__}; {sol.nfev} rhs evaluations, "
                f"{cpu:.1f} s CPU\n# seat landings (located events: cam deg, valve velocity, + up = closing): {land}\n")
        f.write(",".join(c[0] for c in cols) + "\n")
        for i in range(len(t)):
            f.write(",".join(fmt % r[key][i] for _, key, fmt in cols) + "\n")
    print(f"{a.out}: {len(t)} rows, {sol.nfev} rhs, {cpu:.1f} s CPU; landings: {land}")


if __name__ == "__main__":
    main()
