#!/usr/bin/python3
"""The slap study (docs/bearing.md section 16): runs the three fidelity levels of testdata/slap/, the film
grid study and generalized-alpha on the film scene, and prints the figures - CPU per 720 deg cycle, the
impact (bench/slap_impact.py's definitions), the integrator statistics of /solver/statistics. Not a test.

  /usr/bin/python3 bench/slap_study.py [--solve build/solve/solve] [--out bench-out/slap]
                                      [--grids 16x12,24x18,32x24,48x36] [--skip-grids] [--skip-alpha]
                                      [--flexible] [--levels-only]

--flexible-piston adds level (e), slap_flexible_piston.toml (the flexible piston's skirt in the film) at several
mode counts (--piston-modes, default 6,16,30,all), on other condensations of the piston (--piston-residual H5,
e.g. with residual vectors of the skirt points), and its rigid twin slap_piston_rigid.toml; it needs
testdata/slap/piston_skirt.h5 (make_flexible_piston.py says how: condense, about 15 s) and writes
OUT/slap_piston.png.

--flexible adds level (d), slap_flexible.toml: the film on cylinder 4's liner of the flexible block. It needs
testdata/slap/block.h5 (testdata/slap/make_flexible.py says how to make it: condense, about 1 min CPU and 3.9 GB)
and takes a few minutes of CPU per cycle; it also prints the liner's deformation under the slap.

Writes OUT/*.h5, OUT/slap_levels.png (lateral motion, tilt, minimum film or gap, side force over crank angle)
and OUT/slap_grid.png (impact velocity against CPU). CPU: the solve process's user + system time (one
cycle per run), so a loaded machine shows it less than the wall time.
"""
import argparse
import os
import pathlib
import re
import resource
import subprocess
import sys
import time

import h5py
import numpy as np

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
import slap_impact  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parent.parent
SLAP = ROOT / "testdata" / "slap"
LEVELS = [("a: dry contacts", "slap_dry"), ("b: film, 8 um oil layer", "slap_film"),
          ("c: film, starved 3 um oil layer", "slap_film_starved")]


def run(solve, scene_text, name, out):
    scene = SLAP / f".bench_{name}.toml"  # beside the pressure table it names
    scene.write_text(scene_text)
    h5 = out / f"{name}.h5"
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.time()
    try:
        p = subprocess.run([solve, str(scene), "-o", str(h5)], capture_output=True, text=True)
    finally:
        scene.unlink()
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if p.returncode != 0:
        print(f"{name}: solve failed ({p.returncode}): {p.stderr.strip()[-400:]}")
        return None
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    f = h5py.File(h5, "r")
    stats = dict(f["solver/statistics"].attrs)
    return {"name": name, "h5": f, "cpu": cpu, "wall": time.time() - t0, "stats": stats,
            "impact": slap_impact.impact(f)}


def describe_liner(f):
    """Level (d): the liner's largest radial displacement under the skirt (the element's liner_displacement) over
    the cycle and over the slap (360 - 380 deg), and the largest radial load on the liner markers."""
    th = f["crank_angle_deg"][:]
    u = f["forces/skirt/liner_displacement"][:]
    load = f["forces/skirt/liner_force"][:]
    m = (th >= 360) & (th <= 380)
    k = np.argmax(np.where(m, u, -1))
    print(f"{'':34s} liner: largest |u| under the skirt {1e6 * u.max():.3f} um over the cycle, {1e6 * u[k]:.3f} um "
          f"at {th[k]:.2f} deg in 360 - 380 deg; largest radial load on the liner markers {np.abs(load).max():.0f} N; "
          f"uncovered share up to {f['forces/skirt/liner_uncovered'][:].max():.3f}")


def describe_piston(f):
    """Level (e): the peak thrust-side force 360 - 380 deg, the minimum film 365 - 375 deg, the skirt's largest
    radial deformation (skirt_displacement), the film's loss per cycle."""
    th = f["crank_angle_deg"][:]
    side = slap_impact.side_force(f)
    m, m2 = (th >= 360) & (th <= 380), (th >= 365) & (th <= 375)
    k = np.argmin(np.where(m, side, np.inf))
    text = (f"peak thrust-side force {-side[k] / 1e3:.2f} kN at {th[k]:.2f} deg, min film "
            f"{1e6 * f['forces/skirt/min_film'][:][m2].min():.2f} um (365 - 375 deg), film loss "
            f"{np.trapz(f['forces/skirt/power_loss'][:], f['time'][:]):.3f} J per cycle")
    if "skirt_displacement" in f["forces/skirt"]:
        u = f["forces/skirt/skirt_displacement"][:]
        j = np.argmax(u)
        text += f"; skirt deformation up to {1e6 * u[j]:.1f} um at {th[j]:.1f} deg"
    print(f"{'':34s} {text}")


def piston_study(a, out):
    """Level (e) at each mode count against the rigid twin; the chart of the pin's lateral motion, the side
    force and the minimum film over the slap."""
    runs = [("rigid twin", "slap_piston_rigid", None)]
    for m in a.piston_modes.split(","):
        runs.append((f"flexible, {m} modes", "slap_flexible_piston", None if m == "all" else int(m)))
    for path in a.piston_residual or []:
        runs.append((f"flexible, {pathlib.Path(path).name}", "slap_flexible_piston", path))
    results = []
    print("== level (e): the flexible piston (piston_skirt.h5) against its rigid twin")
    for label, name, modes in runs:
        text = (SLAP / f"{name}.toml").read_text()
        if isinstance(modes, int):
            text = text.replace('superelement = "piston_skirt.h5"', f'superelement = "piston_skirt.h5"\nmodes = {modes}')
        elif modes is not None:  # another condensation of the piston (residual vectors), all its coordinates
            text = text.replace('superelement = "piston_skirt.h5"', f'superelement = "{pathlib.Path(modes).resolve()}"')
        tag = modes if isinstance(modes, int) else pathlib.Path(modes).stem if modes else "all"
        r = run(a.solve, text, f"{name}_{tag}", out)
        if r is None:
            return None
        describe(label, r)
        describe_piston(r["h5"])
        results.append((label, r))
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(3, 1, figsize=(8, 9), sharex=True)
    for label, r in results:
        th, xp, tilt, film, side = channels(r["h5"])
        m = (th >= 340) & (th <= 420)
        ax[0].plot(th[m], 1e6 * xp[m], label=f"{label} ({r['cpu']:.0f} s/cycle)")
        ax[1].plot(th[m], side[m] / 1e3)
        ax[2].plot(th[m], 1e6 * film[m])
    ax[0].set_ylabel("pin lateral x (um)")
    ax[1].set_ylabel("side force (kN)")
    ax[2].set_ylabel("min film (um)")
    ax[2].set_xlabel("crank angle (deg, firing TDC 360)")
    for x in ax:
        x.grid(True, alpha=0.3)
    ax[0].legend(fontsize=8)
    fig.suptitle("Piston slap: the flexible piston's skirt in the film (level (e)) against its rigid twin")
    fig.tight_layout()
    fig.savefig(out / "slap_piston.png", dpi=110)
    print(f"wrote {out / 'slap_piston.png'}")
    return results


def describe(label, r):
    i, s = r["impact"], r["stats"]
    print(f"{label:34s} CPU {r['cpu']:7.2f} s/cycle (wall {r['wall']:6.2f}); impact {i['impact_deg']:7.2f} deg "
          f"(lift-off {i['lift_off_deg']:.2f}), v_pin {i['v_pin']:.4f} m/s, energy {1e3 * i['energy']:.2f} mJ; "
          f"steps {int(s['steps'])}, rejected {int(s['rejected_steps'])}, Newton {int(s['newton_iterations'])}, "
          f"Jacobians {int(s['jacobian_evaluations'])}, failures {int(s['nonlinear_failures'])}")


def channels(f):
    th = f["crank_angle_deg"][:]
    xt = f["markers/piston.skirt_top/position"][:, 0]
    xb = f["markers/piston.skirt_bottom/position"][:, 0]
    xp = f["markers/piston.pin/position"][:, 0]
    if "skirt" in f["forces"]:
        film = f["forces/skirt/min_film"][:]
    else:
        film = np.min([f[f"forces/{n}/gap"][:] for n in f["forces"] if n.startswith("dry_")], axis=0)
    return th, xp, (xt - xb) / 0.040, film, slap_impact.side_force(f)


def plot_levels(levels, results, png):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(4, 2, figsize=(12, 10), sharex="col")
    for (label, _), r in zip(levels, results):
        th, xp, tilt, film, side = channels(r["h5"])
        for col, (lo, hi) in enumerate(((0, 720), (340, 420))):
            m = (th >= lo) & (th <= hi)
            ax[0, col].plot(th[m], 1e6 * xp[m], label=label)
            ax[1, col].plot(th[m], 1e3 * tilt[m])
            ax[2, col].plot(th[m], 1e6 * film[m])
            ax[3, col].plot(th[m], side[m])
    for col in range(2):
        ax[0, col].set_ylabel("pin lateral x (um)")
        ax[1, col].set_ylabel("tilt (mrad)")
        ax[2, col].set_ylabel("min film / gap (um)")
        ax[3, col].set_ylabel("side force (N)")
        ax[3, col].set_xlabel("crank angle (deg, firing TDC 360)")
        ax[2, col].set_ylim(-2, 70)
        for a in ax[:, col]:
            a.grid(True, alpha=0.3)
    ax[0, 0].legend(fontsize=8)
    fig.suptitle("Piston slap, 86 x 86 mm gasoline cylinder, 2000 rpm full load (testdata/slap)")
    fig.tight_layout()
    fig.savefig(png, dpi=110)


def plot_grid(rows, png):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(6, 4))
    ax.plot([r[1] for r in rows], [r[2] for r in rows], "o-")
    for g, cpu, v in rows:
        ax.annotate(g, (cpu, v), textcoords="offset points", xytext=(4, 4), fontsize=8)
    ax.set_xscale("log")
    ax.set_xlabel("CPU per 720 deg cycle (s)")
    ax.set_ylabel("impact velocity at the pin (m/s)")
    ax.set_title("slap_film.toml: film grid (cells per panel) against cost")
    ax.grid(True, alpha=0.3)
    fig.tight_layout()
    fig.savefig(png, dpi=110)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--solve", default=str(ROOT / "build" / "solve" / "solve"))
    ap.add_argument("--out", default="bench-out/slap")
    ap.add_argument("--grids", default="16x12,24x18,32x24,48x36")
    ap.add_argument("--skip-grids", action="store_true")
    ap.add_argument("--skip-alpha", action="store_true")
    ap.add_argument("--flexible", action="store_true", help="add level (d), the film on the flexible block")
    ap.add_argument("--levels-only", action="store_true", help="only the fidelity levels")
    ap.add_argument("--flexible-piston", action="store_true",
                    help="add level (e), the flexible piston, at several mode counts, and its rigid twin")
    ap.add_argument("--piston-modes", default="6,16,30,all", help="level (e)'s mode counts (with --flexible-piston)")
    ap.add_argument("--piston-only", action="store_true", help="only level (e) and its twin")
    ap.add_argument("--piston-residual", action="append", metavar="H5",
                    help="also run level (e) on this condensation of piston_skirt.toml (e.g. with residual_vectors), "
                         "all its coordinates; repeatable")
    a = ap.parse_args()
    levels = LEVELS + ([("d: film on the flexible block", "slap_flexible")] if a.flexible else [])
    out = pathlib.Path(a.out)
    out.mkdir(parents=True, exist_ok=True)
    print(f"load average {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores")
    if a.flexible_piston or a.piston_only:
        if piston_study(a, out) is None:
            return 1
        if a.piston_only:
            return 0
    print("== fidelity levels (one 720 deg cycle each)")
    results = []
    for label, name in levels:
        r = run(a.solve, (SLAP / f"{name}.toml").read_text(), name, out)
        if r is None:
            return 1
        describe(label, r)
        if name == "slap_flexible":
            describe_liner(r["h5"])
        results.append(r)
    plot_levels(levels, results, out / "slap_levels.png")
    print(f"wrote {out / 'slap_levels.png'}")
    film = (SLAP / "slap_film.toml").read_text()
    if a.levels_only:
        return 0
    if not a.skip_alpha:
        print("== slap_film.toml with generalized-alpha (rho_inf 0.8, adaptive)")
        for step in ("1e-5", "5e-6"):
            text = re.sub(r"\[integrator\][^\[]*", f"[integrator]\nmethod = \"generalized-alpha\"\nstep = {step}\n"
                          "rtol = 1e-7\natol = 1e-9\nvelocity_atol = 1e-6\n\n", film)
            r = run(a.solve, text, f"slap_film_alpha_{step}", out)
            if r is not None:
                describe(f"generalized-alpha, step {step} s", r)
    if not a.skip_grids:
        print("== film grid (cells axial x around, per panel)")
        rows = []
        for g in a.grids.split(","):
            nx, nz = g.split("x")
            text = film.replace("cells_axial = 16", f"cells_axial = {nx}").replace(
                "cells_around = 12", f"cells_around = {nz}")
            r = run(a.solve, text, f"slap_film_{g}", out)
            if r is None:
                continue
            describe(f"grid {g}", r)
            rows.append((g, r["cpu"], r["impact"]["v_pin"]))
        if rows:
            finest = rows[-1][2]
            for g, cpu, v in rows:
                print(f"  {g:6s} CPU {cpu:7.2f} s  v_pin {v:.4f} m/s  change against {rows[-1][0]}: "
                      f"{100 * (v / finest - 1):+.2f} %")
            plot_grid(rows, out / "slap_grid.png")
            print(f"wrote {out / 'slap_grid.png'}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
