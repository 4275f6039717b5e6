#!/usr/bin/python3
"""The valvetrain study's KPIs per point of a sweep (issue 13, docs/valvetrain.md section 6).

    valvetrain_report.py DIR                  # DIR: a sweep folder (plan.json, points/NNN/results.h5)
    valvetrain_report.py DIR --spring-study   # the spring design study: KPIs, constraints, the best design
    valvetrain_report.py DIR --kinematic K1.h5 K2.h5   # with the kinematic model run at two cam speeds

Reads solve's results of every point (the last whole cam revolution: crank_angle_deg is the cam angle)
and writes DIR/kpi.txt (the table), DIR/kpi.csv, DIR/plots/{kpis,lift,cam_force}.png and DIR/SUMMARY.txt.
The KPIs, from the channels of the scene's elements (names as in testdata/valvetrain/valvetrain.toml):
  valve lift          -/bodies/valve/position[y] from its closed position (m -> mm), its largest value
  cam force           /forces/cam/normal_force: the smallest over the main event (valve lift > 10 % of its
                      largest) - it reaches 0 where the roller leaves the cam (separation) - and the largest
  separation          samples of /forces/cam/separated = 1 within the main event, as cam angle deg
  Hertz pressure      /forces/cam/hertz_pressure and /forces/seat/hertz_pressure, largest (MPa)
  seating velocity    /forces/seat/closing_speed at the valve's first landing after the main event (m/s)
  bounce              after that landing: the largest lift until the next opening (mm) and how long the valve
                      is off its seat again (cam deg)
  pushrod, pivot      largest pushrod force (/forces/pushrod/force_i) and rocker pivot reaction
                      (|/bodies/rocker/support_force| of the rotor, or |/joints/rocker_shaft/reaction_force|
                      where a revolute joint holds it: the flexible rocker), N
  follower bearing    the largest reaction of the follower's bearing, N: the lever's pivot
                      (|/bodies/follower/support_force|, valvetrain_lever.toml; or its joint follower_pivot) or
                      the tappet's bore (|/bodies/tappet/support_force|, or the joint tappet_bore: the side force
                      the cam's pressure angle puts on it)
  drive torque        /forces/cam/cam_torque: largest and mean (N m; the mean is the friction-free work)
  spring              largest force (/forces/valve_spring/force_i) and the middle coil's surge: the largest
                      |x_3| (displacement of mass 3 from its quasi-static place, mm; of a chain of N masses,
                      mass (N+1)//2; a massless spring-damper has none: nan)
  (a rigid pushrod, a `distance` joint named pushrod: its force is |/joints/pushrod/reaction_force|)
Spring study (--spring-study; the points differ in wire_diameter d, active_coils n_a, free_length L0,
mean_diameter D; installed length 60 mm and valve lift 14 mm as in the scene), constraints per design:
  shear stress at full lift   tau = K_w 8 F D / (pi d^3) <= 900 MPa, Wahl's factor K_w = (4C - 1)/(4C - 4) +
                              0.615/C, C = D/d (Wahl 1963; Shigley 10th ed. eq. 10-5), F the largest spring force
                              of the run (dynamic); 900 MPa: about half the tensile strength of Cr-Si valve
                              spring wire (EN 10270-2 VDSiCr, ~1900 MPa at 6 mm), a usual fatigue design limit
  coil clash margin           installed length - lift - solid length (n_a + 2) d >= 1 mm
  surge                       the fixed-fixed surge frequency d / (2 pi n_a D^2) sqrt(G / (2 rho)) >= 13 x the cam
                              frequency at the highest speed (a common rule: surge above the cam's 13th harmonic)
  no separation               the smallest cam force over the main event >= 100 N at the speed run (a margin
                              for what the scene leaves out: gas force on the valve, tolerances, wear)
The best design: feasible, with the smallest largest cam force (Hertz pressure, friction and drive torque fall
with it).

Kinematic model (--kinematic, two runs of testdata/valvetrain/valvetrain_kinematic.toml, or of
valvetrain_lever_kinematic.toml for the lever follower, at different speeds):
  kinematic lift      the valve's displacement less the lash (--lash, 0.5 mm) where positive (the paper's kinematic
                      model: "the cold lash is specified as a constant value"); drawn under each dynamic lift
  lift deviation      per speed: the largest |dynamic - kinematic lift| over the main event (mm), column "dlift"
  kinematic separation  a rigid chain's cam force is F(theta) = A(theta) + B(theta) n^2 at constant speed n (the
                      spring, gravity and return spring in A, the inertia in B): two speeds give A and B at every
                      cam angle, and the follower leaves the cam first at n = min sqrt(-A/B) over the angles with
                      B < 0 - the closed form of the issue's verification (kinematic acceleration, moving mass,
                      spring force), to set beside the dynamic model's separation speed

The separation speed is where the smallest cam force over the main event first reaches 0: from the last two
points with contact, as F = A - B n^2 (the quasi-static force falls with the inertia, as the speed squared);
where that fit lies beyond the first separated point, only the bracket of the grid's points is reported.
"""
import argparse
import json
import math
import sys
from pathlib import Path

import h5py
import numpy as np

COLUMNS = [  # key, header, unit, format
    ("engine_rpm", "engine", "rpm", "{:.0f}"), ("lift_mm", "lift", "mm", "{:.3f}"),
    ("cam_force_min", "Fcam min", "N", "{:.1f}"), ("cam_force_max", "Fcam max", "N", "{:.0f}"),
    ("separation_deg", "separated", "deg", "{:.1f}"), ("hertz_cam", "p cam", "MPa", "{:.0f}"),
    ("hertz_seat", "p seat", "MPa", "{:.0f}"), ("seating_speed", "v seat", "m/s", "{:.3f}"),
    ("bounce_mm", "bounce", "mm", "{:.3f}"), ("bounce_deg", "bounce", "deg", "{:.1f}"),
    ("pushrod_max", "F pushrod", "N", "{:.0f}"), ("pivot_max", "F pivot", "N", "{:.0f}"),
    ("follower_max", "F follower", "N", "{:.0f}"),
    ("torque_max", "T cam max", "N m", "{:.1f}"), ("torque_mean", "T cam mean", "N m", "{:.2f}"),
    ("spring_max", "F spring", "N", "{:.0f}"), ("surge_mm", "surge x3", "mm", "{:.3f}"),
]
KINEMATIC_COLUMN = ("lift_dev_mm", "dlift", "mm", "{:.3f}")


def last_revolution(r) -> tuple:
    """The samples of the last whole cam revolution [360 k - 360, 360 k) and their angles from its start."""
    angle = r["crank_angle_deg"][:]
    stop = 360.0 * math.floor(angle[-1] / 360.0 + 1e-9)
    last = (angle >= stop - 360.0) & (angle < stop)
    return last, angle[last] - (stop - 360.0)


def revolutions_simulated(r) -> float:
    """Cam revolutions a results file spans (its cam angle's range / 360): the benches' CPU per revolution."""
    angle = r["crank_angle_deg"]
    return float(angle[-1] - angle[0]) / 360.0


def kinematic(files: list, lash: float) -> dict:
    """The kinematic model from runs at two speeds (module docstring): lift against cam angle, the separation
    speed of the rigid chain (engine rpm) and the cam angle where it starts."""
    runs = []
    for f in files:
        with h5py.File(f, "r") as r:
            if r.attrs.get("status") != "complete":
                raise RuntimeError(f"{f}: status {r.attrs.get('status')}")
            last, a = last_revolution(r)
            t, angle = r["time"][:], r["crank_angle_deg"][:]
            cam_rpm = (angle[-1] - angle[0]) / (t[-1] - t[0]) / 6.0
            y = r["bodies/valve/position"][:, 1]
            disp = (y[0] - y)[last]
            # The cam's force on the follower, signed: + pushes. A lift driver's reaction lies along the tappet's
            # bore (y); a cam joint's along the pitch curve's normal, whose y component is positive wherever the
            # follower stands above the cam (valvetrain_lever_kinematic.toml): |F| with the sign of F_y.
            f = r["joints/cam/reaction_force"][:][last]
            force = np.sign(f[:, 1]) * np.linalg.norm(f, axis=1)
            runs.append((cam_rpm, a, disp, force))
    (n1, a1, d1, f1), (n2, a2, _, f2) = sorted(runs)[:2]
    if abs(n2 - n1) < 1e-6 * n2:
        raise RuntimeError("--kinematic needs runs at two different speeds")
    f2 = np.interp(a1, a2, f2)
    b = (f2 - f1) / (n2 ** 2 - n1 ** 2)
    a = f1 - b * n1 ** 2
    lift = np.maximum(0.0, d1 - lash)
    pulls = (b < 0) & (lift > 0)
    n_sep = np.where(pulls, np.sqrt(np.maximum(0.0, -a / np.where(pulls, b, -1.0))), np.inf)
    k = int(np.argmin(n_sep))
    return {"angle": a1, "lift": lift, "separation_rpm": 2.0 * n_sep[k], "separation_deg": a1[k],
            "lift_max_mm": 1e3 * lift.max()}


def kpis(results: Path, valve: str = "valve", seat: str = "seat", spring: str = "valve_spring") -> dict:
    """The KPIs of one results file over its last cam revolution. valve, seat, spring: the names of the valve
    body and its seat and spring elements (valvetrain_bridge.toml: valve1, seat1, valve1_spring)."""
    with h5py.File(results, "r") as r:
        if r.attrs.get("status") != "complete":
            raise RuntimeError(f"{results}: status {r.attrs.get('status')}")
        angle = r["crank_angle_deg"][:]
        t = r["time"][:]
        last, a = last_revolution(r)  # the last whole revolution
        y = r[f"bodies/{valve}/position"][:, 1]
        lift = (y[0] - y)[last]
        g = lambda name: r[name][:][last]
        fcam, sep = g("forces/cam/normal_force"), g("forces/cam/separated")
        seat_gap, closing = g(f"forces/{seat}/gap"), g(f"forces/{seat}/closing_speed")
        event = lift > 0.1 * lift.max()
        k = {"engine_rpm": 2.0 * (angle[-1] - angle[0]) / (t[-1] - t[0]) / 6.0, "lift_mm": 1e3 * lift.max(),
             "cam_force_min": fcam[event].min(), "cam_force_max": fcam.max(),
             "separation_deg": float(np.sum(sep[event] > 0) * (a[1] - a[0])),
             "hertz_cam": 1e-6 * g("forces/cam/hertz_pressure").max(),
             "hertz_seat": 1e-6 * g(f"forces/{seat}/hertz_pressure").max()}
        # The first landing after the main event: the seat gap crosses 0 downwards after the last event sample.
        end = np.nonzero(event)[0][-1]
        land = next((i for i in range(end, len(a) - 1) if seat_gap[i] > 0 >= seat_gap[i + 1]), None)
        k["seating_speed"] = closing[land] if land is not None else math.nan
        if land is not None:
            after = seat_gap[land + 1:]
            off = after > 1e-6  # 1 um: off the seat again
            k["bounce_mm"] = 1e3 * max(0.0, after.max())
            k["bounce_deg"] = float(np.sum(off) * (a[1] - a[0]))
        else:
            k["bounce_mm"] = k["bounce_deg"] = math.nan
        # The pushrod as a chain (its force) or rigid (a distance joint: its reaction's magnitude).
        if "forces/pushrod/force_i" in r:
            k["pushrod_max"] = g("forces/pushrod/force_i").max()
        else:
            k["pushrod_max"] = np.linalg.norm(r["joints/pushrod/reaction_force"][:][last], axis=1).max()
        # A bearing's reaction: its joint's, or the support of a rotor or slider (a body on its fixed axis).
        def bearing(joint, body):
            path = next((p for p in (f"joints/{joint}/reaction_force", f"bodies/{body}/support_force") if p in r),
                        None)
            return np.linalg.norm(r[path][:][last], axis=1).max() if path else math.nan
        k["pivot_max"] = bearing("rocker_shaft", "rocker")
        k["follower_max"] = next((v for v in (bearing("follower_pivot", "follower"), bearing("tappet_bore", "tappet"))
                                  if not math.isnan(v)), math.nan)
        torque = g("forces/cam/cam_torque")
        k["torque_max"], k["torque_mean"] = np.abs(torque).max(), torque.mean()
        # The spring as a chain of N masses (its force at the retainer; surge: the middle mass, x_3 of 5) or
        # as a massless spring-damper (its compression; no surge).
        if f"forces/{spring}/force_i" in r:
            k["spring_max"] = g(f"forces/{spring}/force_i").max()
            n = sum(1 for name in r[f"forces/{spring}"] if name.startswith("x_"))
            k["surge_mm"] = 1e3 * np.abs(g(f"forces/{spring}/x_{(n + 1) // 2}")).max()
        else:
            k["spring_max"], k["surge_mm"] = -g(f"forces/{spring}/tension").min(), math.nan
        k["_angle"], k["_lift"], k["_fcam"] = a, lift, fcam
    return k


def separation_speed(rows: list) -> tuple:
    """The engine speed where the smallest event cam force first reaches 0, and the grid's bracket around it
    (the last point in contact, the first separated), or nans. The force is clamped at 0 once the roller leaves
    the cam, so the onset is found from the last two points with contact: the quasi-static force falls with the
    inertia, as F = A - B n^2 in the speed n; fitted through those two points. The dynamic force falls faster
    than that (the spring's surge, the chain's ringing grow with speed), so a fit beyond the first separated
    point is not an estimate: then the onset is only known to lie within the bracket (returned as nan, lo, hi)."""
    rows = sorted(rows, key=lambda k: k["engine_rpm"])
    for i in range(len(rows)):
        if rows[i]["cam_force_min"] <= 0:
            hi = rows[i]["engine_rpm"]
            lo = rows[i - 1]["engine_rpm"] if i > 0 else math.nan
            if i < 2:
                return (hi if i == 0 else math.nan), lo, hi
            (n1, f1), (n2, f2) = [(k["engine_rpm"], k["cam_force_min"]) for k in rows[i - 2:i]]
            b = (f1 - f2) / (n2 * n2 - n1 * n1)
            fit = math.sqrt((f2 + b * n2 * n2) / b) if b > 0 else hi
            return (fit if fit <= hi else math.nan), lo, hi
    return math.nan, math.nan, math.nan


INSTALLED, LIFT, G, RHO, TAU_MAX, CLASH_MIN, SURGE_HARMONIC, FORCE_MARGIN = 0.060, 0.014, 79.3e9, 7850.0, 900e6, 1e-3, 13, 100.0


def spring_constraints(p: dict, k: dict) -> dict:
    """The design constraints of one spring (module docstring)."""
    d, n, d_mean = p["wire_diameter"], p["active_coils"], p["mean_diameter"]
    c = d_mean / d
    wahl = (4 * c - 1) / (4 * c - 4) + 0.615 / c
    tau = wahl * 8 * k["spring_max"] * d_mean / (math.pi * d ** 3)
    clash = INSTALLED - LIFT - (n + 2) * d
    surge = d / (2 * math.pi * n * d_mean ** 2) * math.sqrt(G / (2 * RHO))
    cam_hz = k["engine_rpm"] / 2 / 60
    rate = G * d ** 4 / (8 * d_mean ** 3 * n)
    return {"rate": rate, "preload": rate * (p["free_length"] - INSTALLED), "tau": tau, "clash": clash,
            "surge": surge, "surge_ratio": surge / cam_hz,
            "feasible": tau <= TAU_MAX and clash >= CLASH_MIN and surge / cam_hz >= SURGE_HARMONIC and
            k["cam_force_min"] >= FORCE_MARGIN}


def spring_study(out: Path, plan: dict, rows: list) -> str:
    for k in rows:
        k["_c"] = spring_constraints(k["_params"], k)
    base = min(rows, key=lambda k: abs(k["_params"]["wire_diameter"] - 0.0058) + abs(k["_params"]["active_coils"] - 5)
               + abs(k["_params"]["free_length"] - 0.072) + abs(k["_params"]["mean_diameter"] - 0.038))
    ok = [k for k in rows if k["_c"]["feasible"]]
    lines = [f"Valve spring study ({plan['name']}): {len(rows)} designs at {rows[0]['engine_rpm']:.0f} rpm engine speed; "
             f"{len(ok)} feasible (smallest cam force >= {FORCE_MARGIN:.0f} N, tau <= {TAU_MAX / 1e6:.0f} MPa, clash margin >= "
             f"{CLASH_MIN * 1e3:.0f} mm, surge >= {SURGE_HARMONIC} x cam frequency)", "",
             "     d      n_a    L0      D   |  rate preload  tau  clash  surge/cam | Fcam min Fcam max  p cam  v seat "
             "bounce | feasible",
             "   [mm]          [mm]   [mm]  | [N/mm]  [N]  [MPa] [mm]     [1]    |   [N]      [N]    [MPa]  [m/s]  "
             "[mm]  |"]

    def row(k, tag=""):
        p, c = k["_params"], k["_c"]
        return (f"{p['wire_diameter'] * 1e3:6.2f} {p['active_coils']:5.1f} {p['free_length'] * 1e3:6.1f} "
                f"{p['mean_diameter'] * 1e3:6.1f} | {c['rate'] / 1e3:5.1f} {c['preload']:5.0f} {c['tau'] / 1e6:5.0f} "
                f"{c['clash'] * 1e3:5.1f} {c['surge_ratio']:8.1f}   | {k['cam_force_min']:7.1f} {k['cam_force_max']:8.0f} "
                f"{k['hertz_cam']:6.0f} {k['seating_speed']:6.3f} {k['bounce_mm']:6.3f} | "
                f"{'yes' if c['feasible'] else 'no'}{tag}")
    for k in sorted(rows, key=lambda k: (not k["_c"]["feasible"], k["cam_force_max"])):
        lines.append(row(k, "  <- nearest the baseline" if k is base else ""))
    lines.append("")
    if ok:
        best = min(ok, key=lambda k: k["cam_force_max"])
        lines += ["nearest the baseline (5.8 mm, 5, 72 mm, 38 mm) in the grid: " + row(base),
                  "best design:                                           " + row(best)]
    else:
        lines.append("no feasible design in this grid")
    return "\n".join(lines) + "\n"


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("dir", type=Path)
    ap.add_argument("--spring-study", action="store_true", help="the spring design study's constraints and choice")
    ap.add_argument("--kinematic", nargs=2, type=Path, metavar="K.h5",
                    help="results of valvetrain_kinematic.toml (or _lever_kinematic) at two cam speeds: kinematic lift, the lift's "
                         "deviation per speed and the rigid chain's separation speed")
    ap.add_argument("--lash", type=float, default=0.0005, help="valve lash (m) for the kinematic lift (0.0005)")
    args = ap.parse_args()
    out = args.dir
    plan = json.loads((out / "plan.json").read_text())
    rows, failed = [], []
    for i, params in enumerate(plan["points"]):
        res = out / "points" / f"{i:03d}" / "results.h5"
        try:
            k = kpis(res)
        except (OSError, KeyError, RuntimeError) as e:
            failed.append(f"point {i} ({params}): {e}")
            continue
        k["_point"], k["_params"] = i, params
        rows.append(k)
    if not rows:
        print("valvetrain_report: no point could be read:\n  " + "\n  ".join(failed), file=sys.stderr)
        return 1
    if args.spring_study:
        text = spring_study(out, plan, rows) + "".join(f"FAILED: {f}\n" for f in failed)
        (out / "study.txt").write_text(text)
        (out / "SUMMARY.txt").write_text(text)
        print(text, end="")
        return 1 if failed else 0
    rows.sort(key=lambda k: k["engine_rpm"])
    kin, columns = None, list(COLUMNS)
    if args.kinematic:
        kin = kinematic(args.kinematic, args.lash)
        columns.append(KINEMATIC_COLUMN)
        for k in rows:
            event = k["_lift"] > 0.1 * k["_lift"].max()
            k["_kin_lift"] = np.interp(k["_angle"], kin["angle"], kin["lift"])
            k["lift_dev_mm"] = 1e3 * np.abs(k["_lift"] - k["_kin_lift"])[event].max()
    head = "".join(f"{h:>11s}" for _, h, _, _ in columns)
    units = "".join(f"{'[' + u + ']':>11s}" for _, _, u, _ in columns)
    lines = [f"Valvetrain KPIs per point ({plan['name']}, last cam revolution; docs/valvetrain.md section 6)",
             head, units]
    for k in rows:
        lines.append("".join(f"{fmt.format(k[key]):>11s}" for key, _, _, fmt in columns))
    sep, sep_lo, sep_hi = separation_speed(rows)
    lines.append("")
    bracket = (f" (in contact at {sep_lo:.0f}, separated at {sep_hi:.0f} rpm)" if math.isfinite(sep_lo) else "")
    if math.isfinite(sep):
        onset = f"at {sep:.0f} rpm engine speed{bracket}"
    elif math.isfinite(sep_hi):
        onset = (f"between {sep_lo:.0f} and {sep_hi:.0f} rpm engine speed (no quasi-static fit inside that bracket: "
                 f"a finer grid there gives the onset)")
    else:
        onset = f"none up to {rows[-1]['engine_rpm']:.0f} rpm"
    lines.append("separation (the smallest cam force over the main event reaches 0): " + onset)
    if kin:
        lines.append(f"kinematic model (rigid chain): largest lift {kin['lift_max_mm']:.3f} mm; "
                     f"the follower would leave the cam at {kin['separation_rpm']:.0f} rpm engine speed "
                     f"(cam angle {kin['separation_deg']:.1f} deg)")
    lines += [f"FAILED: {f}" for f in failed]
    text = "\n".join(lines) + "\n"
    (out / "kpi.txt").write_text(text)
    with open(out / "kpi.csv", "w") as f:
        f.write(",".join(["point"] + [f"{key} [{u}]" for key, _, u, _ in columns]) + "\n")
        for k in rows:
            f.write(",".join([str(k["_point"])] + [f"{k[key]:.6g}" for key, _, _, _ in columns]) + "\n")
    plots = out / "plots"
    plots.mkdir(exist_ok=True)
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        rpm = [k["engine_rpm"] for k in rows]
        fig, ax = plt.subplots(2, 2, figsize=(11, 7))
        for a_, keys, title in ((ax[0, 0], ["cam_force_min"], "smallest cam force in the event [N]"),
                                (ax[0, 1], ["seating_speed"], "seating velocity [m/s]"),
                                (ax[1, 0], ["bounce_mm"], "valve bounce [mm]"),
                                (ax[1, 1], ["hertz_cam", "hertz_seat"], "largest Hertz pressure [MPa]")):
            for key in keys:
                a_.plot(rpm, [k[key] for k in rows], "o-", label=key)
            a_.set_title(title)
            a_.set_xlabel("engine speed [rpm]")
            a_.grid(True)
            if len(keys) > 1:
                a_.legend()
        ax[0, 0].axhline(0, color="k", lw=0.8)
        fig.tight_layout()
        fig.savefig(plots / "kpis.png", dpi=110)
        for key, name, label in (("_lift", "lift", "valve lift [mm]"), ("_fcam", "cam_force", "cam force [N]")):
            fig, a_ = plt.subplots(figsize=(10, 5))
            for k in rows:
                scale = 1e3 if key == "_lift" else 1.0
                a_.plot(k["_angle"], scale * k[key], lw=0.8, label=f"{k['engine_rpm']:.0f} rpm")
            if key == "_lift" and kin:
                a_.plot(kin["angle"], 1e3 * kin["lift"], "k--", lw=1.2, label="kinematic")
            a_.set_xlabel("cam angle [deg] (last revolution)")
            a_.set_ylabel(label)
            a_.grid(True)
            a_.legend(fontsize=7)
            fig.tight_layout()
            fig.savefig(plots / f"{name}.png", dpi=110)
        if kin:
            fig, a_ = plt.subplots(figsize=(10, 5))
            for k in rows:
                a_.plot(k["_angle"], 1e3 * (k["_lift"] - k["_kin_lift"]), lw=0.8, label=f"{k['engine_rpm']:.0f} rpm")
            a_.set_xlabel("cam angle [deg] (last revolution)")
            a_.set_ylabel("dynamic - kinematic valve lift [mm]")
            a_.grid(True)
            a_.legend(fontsize=7)
            fig.tight_layout()
            fig.savefig(plots / "lift_deviation.png", dpi=110)
        plt.close("all")
    except ImportError:
        lines.append("(no matplotlib: no plots)")
    (out / "SUMMARY.txt").write_text(text + f"files: {out / 'kpi.txt'}, {out / 'kpi.csv'}, {plots}/*.png\n")
    print(text, end="")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
