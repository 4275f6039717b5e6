#!/usr/bin/python3
"""Valvetrain fidelity against cost (issue 13 item 6; the paper 001's Table 1 in practice).

    bench/valvetrain_fidelity.py [--build build] [--out out/bench/valvetrain_fidelity] [--cam-rpm 975 1300]

The valvetrain of testdata/valvetrain/valvetrain.toml with one part at a time switched to another level of
detail, each run at the given cam speeds (default 975: rated, 1950 rpm engine, no separation; and 1300: the
2600 rpm overspeed, where the roller leaves the cam), two cam revolutions, KPIs of the second
(pipelines/valvetrain_report.py kpis(): one definition). The levels:

  valve spring   linear: a massless spring-damper at the wire's rate and the installed preload, a third of the
                 active coils' mass on the valve (the textbook one-mass model); chain of 1, 2, 5 (the scene),
                 10, 20 masses (valve-spring, the valve carrying the chain's end mass at each N)
  pushrod        rigid: a `distance` joint, its mass half in the tappet and half in the rocker; chain of 1,
                 3 (the scene), 8 masses (mass-chain, the same EA/L and total mass); the Craig-Bampton beam of
                 pushrod.toml on two spherical joints (valvetrain_flexible_pushrod.toml: it bends as well)
  rocker         rigid (the scene); flexible: the beam superelement of rocker.toml reduced by Guyan (12
                 coordinates) or by Craig-Bampton to 25 kHz (15; valvetrain_flexible_rocker.toml)

The reference is every part at its most detailed level (spring 20 masses, pushrod 8 masses, the Craig-Bampton
rocker); "simplest" is every part at its least (linear spring, rigid pushrod, rigid rocker). For each variant it
prints the KPIs, the CPU time per cam revolution (user + system time of the whole solve process) and each KPI's
change against the reference, relative to a scale: the reference's value, but at least 200 N for the smallest
cam force (it is 0 where the roller leaves the cam), 10 cam deg for the separation, 0.05 mm for the bounce.
It writes OUT/fidelity.csv, OUT/fidelity.txt and OUT/fidelity.png (per speed a map of the changes, one row per
variant, beside its CPU time).
"""
import argparse
import csv
import math
import resource
import subprocess
import sys
from pathlib import Path

import h5py
import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "pipelines"))
import valvetrain_report  # noqa: E402  (the KPI definitions: one place)

TESTDATA = ROOT / "testdata/valvetrain"
PI = math.pi

# The valve spring of the scene (valve-spring keys) and what the valve carries besides the spring.
WIRE_D, MEAN_D, ACTIVE, DEAD, FREE_L, G, RHO = 0.0058, 0.038, 5, 1, 0.072, 79.3e9, 7850.0
VALVE_ALONE = 0.25  # kg: valve, retainer and keepers (valvetrain.toml: 0.285 with the 5-mass chain's end mass)
WIRE_PER_COIL = RHO * PI * WIRE_D ** 2 / 4 * PI * MEAN_D  # kg
RATE = G * WIRE_D ** 4 / (8 * MEAN_D ** 3 * ACTIVE)  # N/m
PUSHROD_INTERNAL = 0.1875  # kg: the chain's masses (3/4 of the pushrod); 1/8 at each end is in tappet and rocker

# KPI, label, unit, smallest scale of its change (see the docstring)
KPIS = [("lift_mm", "lift", "mm", 0.0), ("cam_force_min", "Fcam min", "N", 200.0),
        ("cam_force_max", "Fcam max", "N", 0.0), ("separation_deg", "separated", "deg", 10.0),
        ("seating_speed", "v seat", "m/s", 0.0), ("bounce_mm", "bounce", "mm", 0.05),
        ("pushrod_max", "F pushrod", "N", 0.0), ("pivot_max", "F pivot", "N", 0.0),
        ("torque_max", "T cam", "N m", 0.0), ("spring_max", "F spring", "N", 0.0),
        ("surge_mm", "surge", "mm", 0.0)]


def replace(text: str, old: str, new: str) -> str:
    """One edit of the scene's text, which must find what it replaces (a changed scene fails loudly)."""
    if text.count(old) != 1:
        raise RuntimeError(f"the scene text has {text.count(old)} copies of {old!r}, expected 1")
    return text.replace(old, new)


def spring_chain(text: str, n: int) -> str:
    end_mass = WIRE_PER_COIL * ACTIVE / (2 * (n + 1)) + WIRE_PER_COIL * DEAD  # mass_chain.cpp, valve-spring
    text = replace(text, "mass = 0.285 ", f"mass = {VALVE_ALONE + end_mass:.6f} ")
    return replace(text, "masses = 5\n", f"masses = {n}\n")


def spring_linear(text: str) -> str:
    m = VALVE_ALONE + WIRE_PER_COIL * (DEAD + ACTIVE / 3.0)
    text = replace(text, "mass = 0.285 ", f"mass = {m:.6f} ")
    start = text.index('type = "valve-spring"')
    end = text.index("damping_ratio = 0.03", start) + len("damping_ratio = 0.03")
    d = 2 * 0.03 * math.sqrt(RATE * m)  # the chain's 3 % of critical, on the valve's mass
    return text[:start] + (f'type = "spring-damper"\ni = "valve.retainer"\nj = "ground.spring_seat"\n'
                           f"k = {RATE:.1f}\nd = {d:.3f}\nfree_length = {FREE_L}") + text[end:]


def pushrod_chain(text: str, n: int) -> str:
    return replace(text, "masses = 3\n", f"masses = {n}\n")


def pushrod_rigid(text: str) -> str:
    start = text.index('name = "pushrod"')
    end = text.index("damping_ratio = 0.1", start) + len("damping_ratio = 0.1")
    text = text[:start] + ('name = "pushrod"\ntype = "distance"\ni = "rocker.ball"\nj = "tappet.cup"') + text[end:]
    text = replace(text, "[[force]]\nname = \"pushrod\"", "[[joint]]\nname = \"pushrod\"")
    half = PUSHROD_INTERNAL / 2
    text = replace(text, "mass = 0.38\n", f"mass = {0.38 + half:.5f}\n")
    # The rigid rocker's Izz about its pivot gains the other half at the ball end (40 mm); Iyy with it (the
    # arm lies along x), which keeps the moments a real body's (Ixx + Iyy >= Izz) and leaves the plane's motion.
    dizz = half * 0.04 ** 2
    return replace(text, "inertia = [1e-4, 6e-4, 6.5e-4]", f"inertia = [1e-4, {6e-4 + dizz:.4e}, {6.5e-4 + dizz:.4e}]")


def rocker_flexible(superelement: str):
    def edit(_: str) -> str:
        text = (TESTDATA / "valvetrain_flexible_rocker.toml").read_text()
        return replace(text, 'superelement = "rocker.h5"', f'superelement = "{superelement}"')
    return edit


def pushrod_beam(superelement: str):
    """The pushrod as the Craig-Bampton beam of pushrod.toml (valvetrain_flexible_pushrod.toml's scene: the tube on
    two spherical joints, the tappet and the rocker without their eighth of it)."""
    def edit(_: str) -> str:
        text = (TESTDATA / "valvetrain_flexible_pushrod.toml").read_text()
        text = replace(text, 'file = "exhaust_valve_gas.csv"', f'file = "{TESTDATA / "exhaust_valve_gas.csv"}"')
        return replace(text, 'superelement = "pushrod.h5"', f'superelement = "{superelement}"')
    return edit


def chain(*edits):
    def edit(text: str) -> str:
        for e in edits:
            text = e(text)
        return text
    return edit


# name, part (for the chart's colour), edits applied to valvetrain.toml's text (a rocker edit goes first: it
# starts from the flexible scene's text)
VARIANTS = [
    ("reference: spring 20, pushrod 8, rocker CB", "reference",
     chain(rocker_flexible("rocker_cb.h5"), lambda t: spring_chain(t, 20), lambda t: pushrod_chain(t, 8))),
    ("scene: spring 5, pushrod 3, rocker rigid", "scene", chain()),
    ("spring linear (1/3 mass on valve)", "spring", spring_linear),
    ("spring 1 mass", "spring", lambda t: spring_chain(t, 1)),
    ("spring 2 masses", "spring", lambda t: spring_chain(t, 2)),
    ("spring 10 masses", "spring", lambda t: spring_chain(t, 10)),
    ("spring 20 masses", "spring", lambda t: spring_chain(t, 20)),
    ("pushrod rigid", "pushrod", pushrod_rigid),
    ("pushrod 1 mass", "pushrod", lambda t: pushrod_chain(t, 1)),
    ("pushrod 8 masses", "pushrod", lambda t: pushrod_chain(t, 8)),
    ("pushrod beam, CB 15 kHz (bends)", "pushrod", pushrod_beam("pushrod_cb.h5")),
    ("rocker flexible, Guyan", "rocker", rocker_flexible("rocker_guyan.h5")),
    ("rocker flexible, CB 25 kHz", "rocker", rocker_flexible("rocker_cb.h5")),
    ("simplest: spring linear, pushrod rigid, rocker rigid", "simplest", chain(spring_linear, pushrod_rigid)),
]


def condense_rockers(build: Path, out: Path) -> None:
    """The superelements beside the scenes: the rocker's Craig-Bampton to 25 kHz (rocker.toml) and Guyan, the
    pushrod's Craig-Bampton to 15 kHz (pushrod.toml)."""
    condense = build / "condense/condense"
    text = (TESTDATA / "rocker.toml").read_text()
    guyan = replace(text, 'method = "craig-bampton"', 'method = "guyan"')
    pushrod = (TESTDATA / "pushrod.toml").read_text()
    for name, component in (("rocker_cb", text), ("rocker_guyan", guyan), ("pushrod_cb", pushrod)):
        (out / f"{name}.toml").write_text(component)
        subprocess.run([str(condense), str(out / f"{name}.toml"), "-o", str(out / f"{name}.h5"), "-q"],
                       check=True)


def run(solve: Path, scene: Path, results: Path) -> float:
    """Runs solve; returns its CPU time (user + system) in seconds."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    p = subprocess.run([str(solve), str(scene), "-o", str(results), "-q"], capture_output=True, text=True)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if p.returncode != 0:
        raise RuntimeError(f"{scene}: solve failed: {p.stderr.strip()}")
    return (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)


def change(k: dict, ref: dict, key: str, floor: float) -> float:
    a, b = k[key], ref[key]
    if math.isnan(a) or math.isnan(b):
        return math.nan
    return (a - b) / max(abs(b), floor)


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--build", type=Path, default=ROOT / "build")
    ap.add_argument("--out", type=Path, default=ROOT / "out/bench/valvetrain_fidelity")
    ap.add_argument("--cam-rpm", type=float, nargs="+", default=[975.0, 1300.0])
    args = ap.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)
    condense_rockers(args.build, args.out)
    base = replace((TESTDATA / "valvetrain.toml").read_text(), 'file = "exhaust_valve_gas.csv"',
                   f'file = "{TESTDATA / "exhaust_valve_gas.csv"}"')  # found from where the bench writes scenes
    rows, lines = [], []

    def say(line: str = "") -> None:
        print(line, flush=True)
        lines.append(line)

    for rpm in args.cam_rpm:
        rev_s = 60.0 / rpm
        say(f"\n{rpm:.0f} cam rpm ({2 * rpm:.0f} rpm engine); CPU per cam revolution (one lasts {1e3 * rev_s:.1f} ms)"
            f"; changes against the reference in % of the scale (docstring)")
        say(f"{'variant':52s} {'CPU/rev':>7s} " + " ".join(f"{label:>9s}" for _, label, _, _ in KPIS))
        say(f"{'':52s} {'[s]':>7s} " + " ".join(f"{'[' + unit + ']':>9s}" for _, _, unit, _ in KPIS))
        ref = None
        for i, (name, part, edit) in enumerate(VARIANTS):
            scene = args.out / f"fidelity_{int(rpm)}_{i:02d}.toml"
            text = edit(base)
            text = replace(text, "rpm = 650 ", f"rpm = {rpm} ")
            scene.write_text(text)
            results = scene.with_suffix(".h5")
            cpu = run(args.build / "solve/solve", scene, results)
            k = valvetrain_report.kpis(results)
            ref = ref or k
            with h5py.File(results, "r") as r:  # the scenes run 760 cam deg
                revolutions = valvetrain_report.revolutions_simulated(r)
            row = {"cam_rpm": rpm, "variant": name, "part": part, "cpu_per_rev_s": cpu / revolutions,
                   **{key: k[key] for key, _, _, _ in KPIS},
                   **{"d_" + key: change(k, ref, key, floor) for key, _, _, floor in KPIS}}
            rows.append(row)
            say(f"{name:52s} {cpu / revolutions:7.3f} " + " ".join(
                f"{k[key]:9.4g}" for key, _, _, _ in KPIS))
            if k is not ref:
                say(f"{'':52s} {'':7s} " + " ".join(
                    f"{100 * row['d_' + key]:8.1f}%" if not math.isnan(row["d_" + key]) else f"{'-':>9s}"
                    for key, _, _, _ in KPIS))
    (args.out / "fidelity.txt").write_text("\n".join(lines) + "\n")
    with open(args.out / "fidelity.csv", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        w.writeheader()
        w.writerows(rows)
    chart(rows, args.cam_rpm, args.out / "fidelity.png")
    print(f"\nwrote {args.out / 'fidelity.txt'}, fidelity.csv, fidelity.png")
    return 0


def chart(rows: list, speeds: list, path: Path) -> None:
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        from matplotlib.colors import LogNorm
    except ImportError:
        print("(no matplotlib: no chart)")
        return
    names = [v[0] for v in VARIANTS[1:]]
    fig, axes = plt.subplots(1, 2 * len(speeds), figsize=(7.5 * len(speeds), 5.8),
                             gridspec_kw={"width_ratios": [4, 1] * len(speeds)})
    for s, rpm in enumerate(speeds):
        sel = [r for r in rows if r["cam_rpm"] == rpm and not r["part"] == "reference"]
        ref = next(r for r in rows if r["cam_rpm"] == rpm and r["part"] == "reference")
        m = np.array([[abs(100 * r["d_" + key]) for key, _, _, _ in KPIS] for r in sel])
        ax = axes[2 * s]
        shown = np.where(np.isnan(m), np.nan, np.maximum(m, 0.01))
        im = ax.imshow(shown, cmap="viridis_r", norm=LogNorm(vmin=0.01, vmax=100), aspect="auto")
        for (a, b), v in np.ndenumerate(m):
            ax.text(b, a, "-" if math.isnan(v) else (f"{v:.2g}" if v < 10 else f"{v:.0f}"), ha="center",
                    va="center", fontsize=6, color="w" if not math.isnan(v) and v > 3 else "k")
        ax.set_xticks(range(len(KPIS)), [label for _, label, _, _ in KPIS], rotation=60, fontsize=7)
        ax.set_yticks(range(len(sel)), names if s == 0 else [""] * len(sel), fontsize=7)
        ax.set_title(f"{rpm:.0f} cam rpm: |KPI change| against the reference [%]", fontsize=8)
        cpu = axes[2 * s + 1]
        cpu.barh(range(len(sel)), [r["cpu_per_rev_s"] for r in sel], color="C0")
        cpu.axvline(ref["cpu_per_rev_s"], color="C3", lw=0.8, ls="--")
        cpu.axvline(60.0 / rpm, color="k", lw=0.8, ls=":")
        cpu.set_ylim(len(sel) - 0.5, -0.5)
        cpu.set_yticks([])
        cpu.set_xlabel("CPU per cam rev [s]\n(dashed: reference; dotted: real time)", fontsize=7)
        cpu.tick_params(labelsize=7)
    fig.colorbar(im, ax=axes, shrink=0.6, label="|change| [%] (at least 0.01)")
    fig.suptitle("valvetrain: what each level of detail changes, and what it costs (reference: spring 20 masses, "
                 "pushrod 8 masses, Craig-Bampton rocker)", fontsize=9)
    fig.savefig(path, dpi=120, bbox_inches="tight")


if __name__ == "__main__":
    sys.exit(main())
