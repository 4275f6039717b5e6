#!/usr/bin/python3
"""Valvetrain benchmark (issue 13): CPU time against real time and against accuracy (work-precision).

    bench/valvetrain_bench.py [--build build] [--out out/bench/valvetrain] [--cam-rpm 975] [--quick] [--only NAME..]

For the single-valve scene (testdata/valvetrain/valvetrain.toml), the bridge scene with two valves
(valvetrain_bridge.toml), the bridge scene with the flexible rocker of valvetrain_flexible_rocker.toml
(valvetrain_bridge_flexible_rocker.toml, the issue's benchmark scene; rocker.toml condensed into OUT first) and the single valve with the paper's lever
follower (valvetrain_lever.toml) at a cam speed (default 975 rpm: 1950 rpm engine, a heavy-duty diesel's rated speed),
two cam revolutions each (the KPIs read the second), with the integrator settings below, it prints:
  - CPU seconds per cam revolution (solve's own /solver/statistics wall_s over the revolutions simulated: the
    scenes run 760 cam deg, 2.11 revolutions) and that against real time (one revolution lasts 60 / rpm s): < 1
    is faster than real time (before 2026-12-03 the bench divided by 2, which put every figure 5.6 % high);
  - the error of each KPI against a reference run of the same scene (IDA, rtol 1e-9, atol 1e-12): the largest
    valve lift, the largest and the smallest cam force over the event, the valve's seating velocity;
  - for IDA, the unknown that set most of the steps and its share (solve's /solver/statistics/error_test_steps);
The benchmark scene runs seven times more with the cheap settings at once (CHEAPEST below: the rocker's first 4
modes, the time histories written raw, no contact events; three times with the rocker on the shaft's fixed axis), its
errors against its 15-mode reference. The bench
writes OUT/work_precision.png (CPU per revolution against the largest KPI error, per scene and method)
and OUT/valvetrain_bench.csv. The output rate is 20 kHz for every run (output costs are in the CPU time).
"""
import argparse
import csv
import re
import subprocess
import sys
from pathlib import Path

import h5py

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "pipelines"))
import valvetrain_report  # noqa: E402  (the KPI definitions: one place)

SETTINGS = [  # label, [integrator] table
    ("reference", "rtol = 1e-9\natol = 1e-12\nmax_step = 5e-5\n"),
    ("IDA 1e-6 (scene)", "rtol = 1e-6\natol = 1e-9\nvelocity_atol = 2e-7\nmax_step = 5e-5\n"),
    ("IDA 1e-6, no velocity_atol", "rtol = 1e-6\natol = 1e-9\nmax_step = 5e-5\n"),
    ("IDA 1e-5", "rtol = 1e-5\natol = 1e-8\nvelocity_atol = 2e-6\nmax_step = 5e-5\n"),
    ("IDA 1e-4", "rtol = 1e-4\natol = 1e-7\nvelocity_atol = 2e-5\nmax_step = 5e-5\n"),
    ("IDA 1e-3", "rtol = 1e-3\natol = 1e-6\nvelocity_atol = 2e-4\nmax_step = 5e-5\n"),
    # BDF2 at most: A-stable, so no steps spent where orders 3-5 let a lightly damped mode grow (docs/verification.md,
    # Stability map); the cheapest setting on the flexible rocker
    ("IDA 1e-3, max_order 2", "rtol = 1e-3\natol = 1e-6\nvelocity_atol = 2e-4\nmax_step = 5e-5\nmax_order = 2\n"),
    ("g-alpha 5 us", 'method = "generalized-alpha"\nstep = 5e-6\nrho_inf = 0.8\n'),
    ("g-alpha 10 us", 'method = "generalized-alpha"\nstep = 1e-5\nrho_inf = 0.8\n'),
    ("g-alpha 20 us", 'method = "generalized-alpha"\nstep = 2e-5\nrho_inf = 0.8\n'),
]

# The benchmark scene once more with every cheap setting at once (docs/valvetrain.md section 8, "Every lever at
# once"): the rocker's band (modes = 4, what `solve --advise --band 5000` recommends), the cheapest IDA setting or
# generalized-alpha, the time histories written raw, no contact events. Their KPI errors are against the 15-mode
# reference.
# `events = false` (no contact events located: the error test alone resolves the contacts) saves the restarts at
# order 1 that the loose IDA settings pay at each of the scene's ~230 events; at the scene's own tolerance it
# changes little (section 8, "What sets the benchmark scene's steps").
NO_EVENTS = "events = false\n"
# "on shaft": the same rocker on the shaft's fixed axis (valvetrain_bridge_rocker_on_shaft.toml, the superelement
# of rocker_on_shaft.toml: clamped at the pivot, one coordinate for the swing, no revolute joint); with all its
# coordinates it spans the floating rocker's motions (its reference run agrees with the floating one's to 0.2 %),
# so its errors are against the same 15-mode reference. Of its lowest clamped modes (4.8-8.2 kHz) only the third and
# the sixth move in the plane (the others twist the arms or bend them out of it): 8 modes, or those two by number.
ON_SHAFT = "valvetrain_bridge_rocker_on_shaft.toml"
CHEAPEST = [  # label, [integrator] table, rocker modes (0: all 15; a list: mode_numbers), raw output, scene file
    ("4 modes, IDA 1e-3, mo 2, raw", dict(SETTINGS)["IDA 1e-3, max_order 2"], 4, True, None),
    ("15 modes, IDA 1e-3, mo 2, raw, no events", dict(SETTINGS)["IDA 1e-3, max_order 2"] + NO_EVENTS, 0, True, None),
    ("4 modes, IDA 1e-3, mo 2, raw, no events", dict(SETTINGS)["IDA 1e-3, max_order 2"] + NO_EVENTS, 4, True, None),
    ("4 modes, g-alpha 20 us, raw", dict(SETTINGS)["g-alpha 20 us"], 4, True, None),
    ("on shaft, 15 modes, IDA 1e-3, mo 2, raw, no events", dict(SETTINGS)["IDA 1e-3, max_order 2"] + NO_EVENTS, 0,
     True, ON_SHAFT),
    ("on shaft, 8 modes, IDA 1e-3, mo 2, raw, no events", dict(SETTINGS)["IDA 1e-3, max_order 2"] + NO_EVENTS, 8,
     True, ON_SHAFT),
    # its two in-plane modes below 10 kHz only (mode_numbers = [3, 6]: 6.5 and 8.2 kHz; the others below 10 kHz
    # twist the arms or bend them out of the plane, which the planar loads do not excite)
    ("on shaft, modes 3 and 6, IDA 1e-3, mo 2, raw, no events", dict(SETTINGS)["IDA 1e-3, max_order 2"] + NO_EVENTS,
     [3, 6], True, ON_SHAFT),
]

SCENES = {  # name: file, valve body, seat, spring (the cam element is "cam" in all), flexible rocker
    "single valve": ("valvetrain.toml", "valve", "seat", "valve_spring", False),
    "bridge, two valves": ("valvetrain_bridge.toml", "valve1", "seat1", "valve1_spring", False),
    "bridge, flexible rocker": ("valvetrain_bridge_flexible_rocker.toml", "valve1", "seat1", "valve1_spring", True),
    "lever follower": ("valvetrain_lever.toml", "valve", "seat", "valve_spring", False),
}


def scene_text(path: Path, cam_rpm: float, integrator: str, rocker: Path = None, modes: int = 0,
               raw: bool = False) -> str:
    text = path.read_text()
    if rocker is not None:  # the flexible rocker's superelement, condensed into the bench's folder
        # its first `modes` coordinates only, or a list of mode numbers (`mode_numbers`)
        modes_key = (f"\nmode_numbers = {list(modes)}" if isinstance(modes, (list, tuple))
                     else f"\nmodes = {modes}" if modes > 0 else "")
        text = text.replace('superelement = "rocker.h5"', f'superelement = "{rocker}"{modes_key}')
        on_shaft = rocker.with_name("rocker_on_shaft.h5")  # the rocker clamped at its pivot (ON_SHAFT)
        text = text.replace('superelement = "rocker_on_shaft.h5"', f'superelement = "{on_shaft}"{modes_key}')
    # Files the scene names, found from where the bench writes it (the gas table of valvetrain.toml).
    text = text.replace('file = "exhaust_valve_gas.csv"', f'file = "{path.resolve().parent / "exhaust_valve_gas.csv"}"')
    text = re.sub(r"^rpm = [0-9.]+ ", f"rpm = {cam_rpm} ", text, flags=re.M)
    text = text[:text.index("[integrator]")] + "[integrator]\n" + integrator + "\n[output]\nsample_rate_hz = 20000\n"
    if raw:  # the time histories without deflate (scene-format.md section 8)
        text += "compression = 0\n"
    return text


def kpis(results: Path, valve: str, seat: str, spring: str) -> dict:
    """The report's KPIs (pipelines/valvetrain_report.py) that the bench compares, and solve's own cost."""
    k = valvetrain_report.kpis(results, valve, seat, spring)
    with h5py.File(results, "r") as r:
        st = r["solver/statistics"].attrs
        # The unknown that set most of IDA's steps (/solver/statistics/error_test_steps; none for g-alpha).
        held = ""
        if "error_test_steps" in r["solver/statistics"]:
            counts = r["solver/statistics/error_test_steps"][:]
            k_top = int(counts.argmax())
            name = r["checkpoint/state_names"][k_top]
            held = f"{name.decode() if isinstance(name, bytes) else name} {100 * counts[k_top] / max(1, counts.sum()):.0f} %"
        return {"lift_mm": k["lift_mm"], "fcam_max": k["cam_force_max"], "fcam_min": k["cam_force_min"],
                "v_seat": k["seating_speed"], "cpu": float(st["wall_s"]), "steps": int(st["steps"]),
                "revolutions": valvetrain_report.revolutions_simulated(r),
                "steps_set_by": held}


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--build", type=Path, default=ROOT / "build")
    ap.add_argument("--out", type=Path, default=ROOT / "out/bench/valvetrain")
    ap.add_argument("--cam-rpm", type=float, default=975.0)
    ap.add_argument("--quick", action="store_true", help="the single-valve scene only")
    ap.add_argument("--only", nargs="*", help="the scenes whose name contains one of these (e.g. lever)")
    args = ap.parse_args()
    solve = args.build / "solve/solve"
    args.out.mkdir(parents=True, exist_ok=True)
    rev_s = 60.0 / args.cam_rpm
    rows = []
    rocker = args.out / "rocker.h5"
    if not args.quick and (not args.only or any(o in "bridge, flexible rocker" for o in args.only)):
        # the flexible rocker's superelement (docs/valvetrain.md section 5)
        for component, se in (("rocker.toml", rocker), ("rocker_on_shaft.toml", rocker.with_name("rocker_on_shaft.h5"))):
            subprocess.run([str(args.build / "condense/condense"), str(ROOT / "testdata/valvetrain" / component), "-o",
                            str(se), "-q"], check=True)
    for scene, (file, valve, seat, spring, flexible) in SCENES.items():
        if args.quick and scene != "single valve":
            continue
        if args.only and not any(o in scene for o in args.only):
            continue
        ref = None
        print(f"\n{scene} ({file}) at {args.cam_rpm:.0f} cam rpm ({2 * args.cam_rpm:.0f} engine rpm); one cam "
              f"revolution lasts {1e3 * rev_s:.1f} ms")
        print(f"{'setting':42s} {'steps':>7s} {'CPU/rev':>9s} {'x real':>7s} {'lift':>8s} {'Fcam max':>9s} "
              f"{'Fcam min':>9s} {'v seat':>7s} {'max err':>8s}  steps set by (most)")
        print(f"{'':42s} {'':>7s} {'[s]':>9s} {'time':>7s} {'[mm]':>8s} {'[N]':>9s} {'[N]':>9s} {'[m/s]':>7s} "
              f"{'[%]':>8s}")
        runs = [(label, integ, 0, False, None) for label, integ in SETTINGS] + (CHEAPEST if flexible else [])
        for label, integ, modes, raw, other in runs:
            toml = args.out / f"{(other or file)[:-5]}_{len(rows)}.toml"
            toml.write_text(scene_text(ROOT / "testdata/valvetrain" / (other or file), args.cam_rpm, integ,
                                       rocker if flexible else None, modes, raw))
            h5 = toml.with_suffix(".h5")
            p = subprocess.run([str(solve), str(toml), "-o", str(h5), "-q"], capture_output=True, text=True)
            if p.returncode != 0:
                print(f"{label:42s} failed: {p.stderr.strip().splitlines()[-1] if p.stderr.strip() else p.returncode}")
                continue
            k = kpis(h5, valve, seat, spring)
            if ref is None:
                ref = k
            err = max(abs(k[q] - ref[q]) / abs(ref[q]) for q in ("lift_mm", "fcam_max", "fcam_min", "v_seat"))
            cpu_rev = k["cpu"] / k["revolutions"]
            rows.append({"scene": scene, "setting": label, "steps": k["steps"], "cpu_per_rev_s": cpu_rev,
                         "real_time_ratio": cpu_rev / rev_s, "max_kpi_error": err, **k})
            print(f"{label:42s} {k['steps']:7d} {cpu_rev:9.3f} {cpu_rev / rev_s:7.1f} {k['lift_mm']:8.3f} "
                  f"{k['fcam_max']:9.1f} {k['fcam_min']:9.1f} {k['v_seat']:7.3f} {100 * err:8.3f}  {k['steps_set_by']}")
    with open(args.out / "valvetrain_bench.csv", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        w.writeheader()
        w.writerows(rows)
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, ax = plt.subplots(figsize=(10.5, 5.5))
        for scene, marker in zip(SCENES, "os^D"):
            for method, color in (("IDA", "C0"), ("g-alpha", "C1")):
                pts = [(r["max_kpi_error"], r["cpu_per_rev_s"], r["setting"]) for r in rows
                       if r["scene"] == scene and r["setting"].startswith(method) and r["max_kpi_error"] > 0]
                if pts:
                    ax.loglog([p[0] * 100 for p in pts], [p[1] for p in pts], marker + "-", color=color,
                              label=f"{scene}: {method}")
                    for e, c, lab in pts:
                        ax.annotate(lab.replace(method, "").strip(), (e * 100, c), fontsize=6)
        cheap = [r for r in rows if r["setting"] in [c[0] for c in CHEAPEST] and r["max_kpi_error"] > 0]
        if cheap:
            ax.loglog([r["max_kpi_error"] * 100 for r in cheap], [r["cpu_per_rev_s"] for r in cheap], "*", ms=10,
                      color="C2", label="bridge, flexible rocker: every cheap setting")
            for r in cheap:
                ax.annotate(r["setting"], (r["max_kpi_error"] * 100, r["cpu_per_rev_s"]), fontsize=6)
        ax.axhline(rev_s, color="k", lw=0.8, ls="--")
        ax.text(ax.get_xlim()[0], rev_s * 1.05, " real time", fontsize=8)
        ax.set_xlabel("largest KPI error against the reference [%] (lift, cam force max/min, seating velocity)")
        ax.set_ylabel("CPU per cam revolution [s] (one core)")
        ax.set_title(f"valvetrain work-precision, {args.cam_rpm:.0f} cam rpm")
        ax.grid(True, which="both", lw=0.3)
        ax.legend(fontsize=7, loc="center left", bbox_to_anchor=(1.01, 0.5))  # outside: no point hidden
        fig.tight_layout()
        fig.savefig(args.out / "work_precision.png", dpi=110)
        print(f"\nwrote {args.out / 'work_precision.png'}, {args.out / 'valvetrain_bench.csv'}")
    except ImportError:
        print("(no matplotlib: no chart)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
