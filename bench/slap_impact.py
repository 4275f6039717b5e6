"""The slap's impact figures from a results file of the slap family (testdata/slap/, docs/bearing.md section 16).

Definitions (the same in tests/solve/test_slap.cpp):
  side force F(t)  the liner's lateral force on the piston along x (+x the thrust side): the piston-liner
                   element's `side_force` channel, or for the dry level the sum of the contacts' normal forces
                   (anti-thrust points push +x, thrust points -x)
  lift-off         the last sample in 340..400 deg with F > +F_th before F first drops below -F_th (the piston
                   leaves the anti-thrust side); F_th = 10 N
  impact           the first instant after lift-off at which F <= -F_th (the thrust side takes load again: the
                   contact's onset, or the film engaging), interpolated linearly between samples
  impact velocity  the piston's lateral velocity at its pin (its centre of mass in this family) at the impact,
                   interpolated between samples; also the skirt edges' lateral velocities there
  impact energy    1/2 m_p v_pin^2 + 1/2 J_p omega^2 at the impact: the kinetic energy of the lateral motion
                   and the tilt that the film or the contact takes up
Units SI, angles in deg.
"""
import numpy as np

F_TH = 10.0
M_PISTON, J_PISTON = 0.42, 3.2e-4


def side_force(f):
    if "skirt" in f["forces"]:
        return f["forces/skirt/side_force"][:]
    total = 0.0
    for name in f["forces"]:
        if name.startswith("dry_thrust_"):
            total = total - f[f"forces/{name}/normal_force"][:]
        elif name.startswith("dry_anti_"):
            total = total + f[f"forces/{name}/normal_force"][:]
    return total


def impact(f):
    th = f["crank_angle_deg"][:]
    t = f["time"][:]
    F = side_force(f)
    window = np.where((th >= 340) & (th <= 400))[0]
    first_neg = next(k for k in window if F[k] <= -F_TH)
    lift = max(k for k in window if k < first_neg and F[k] > F_TH)
    k = first_neg
    w = (F[k - 1] + F_TH) / (F[k - 1] - F[k]) if F[k - 1] != F[k] else 1.0  # F(k-1) > -F_TH >= F(k)
    lerp = lambda y: y[k - 1] + w * (y[k] - y[k - 1])
    v_pin = lerp(f["markers/piston.pin/velocity"][:, 0])
    v_top = lerp(f["markers/piston.skirt_top/velocity"][:, 0])
    v_bottom = lerp(f["markers/piston.skirt_bottom/velocity"][:, 0])
    omega = (v_top - v_bottom) / 0.040
    x_pin = f["markers/piston.pin/position"][:, 0]
    return {
        "lift_off_deg": th[lift],
        "impact_deg": lerp(th),
        "impact_time": lerp(t),
        "v_pin": v_pin,
        "v_top": v_top,
        "v_bottom": v_bottom,
        "energy": 0.5 * M_PISTON * v_pin**2 + 0.5 * J_PISTON * omega**2,
        "travel": lerp(x_pin) - x_pin[lift],
        "peak_v_pin": float(np.max(f["markers/piston.pin/velocity"][lift:k + 1, 0])),
    }
