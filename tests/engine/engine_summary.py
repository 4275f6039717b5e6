#!/usr/bin/python3
"""The engine study's SUMMARY.txt (docs/engine.md "Results"): the files of `make -f Makefile.workflow engine`'s
results folder and their headline numbers, read from postproc's HDF5 outputs and solve's results, and the CPU
and peak memory of every stage (the `/usr/bin/time -v` records the workflow writes beside each output).

    /usr/bin/python3 tests/engine/engine_summary.py OUT/engine --runup RUNUP.results.h5 -o SUMMARY.txt

Nothing here computes a result: it reads and lists them (the checks are tests/engine/test_engine_results.py).
"""
import argparse
import re
from pathlib import Path

import h5py
import numpy as np


def time_record(path):
    """user + system CPU (s), wall (s) and peak RSS (MB) of a /usr/bin/time -v record, or None."""
    p = Path(str(path) + ".time")
    if not p.exists():
        return None
    text = p.read_text()

    def num(key):
        m = re.search(re.escape(key) + r":\s*([0-9.:]+)", text)
        return m.group(1) if m else None
    wall = num("Elapsed (wall clock) time (h:mm:ss or m:ss)")
    seconds = 0.0
    for part in (wall or "0").split(":"):
        seconds = 60 * seconds + float(part)
    return (float(num("User time (seconds)")) + float(num("System time (seconds)")), seconds,
            float(num("Maximum resident set size (kbytes)")) / 1024)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("engine", type=Path, help="the workflow's engine directory (OUT/engine)")
    ap.add_argument("--runup", type=Path, required=True, help="the run-up's results file")
    ap.add_argument("-o", "--output", type=Path, required=True)
    a = ap.parse_args()
    eng, res = a.engine, a.engine / "results"
    steady = eng / "engine_steady.results.h5"
    lines = ["# The engine study's results (docs/engine.md \"Results\"; make -f Makefile.workflow engine)", ""]

    lines += ["## CPU and peak memory per stage (user + system; /usr/bin/time -v, the machine as loaded)", "",
              f"{'stage':<40} {'CPU s':>9} {'wall s':>9} {'peak MB':>9}"]
    stages = [("condense block.h5 (surface exported)", eng / "block.h5"),
              ("solve engine_steady (to steady state)", steady), (f"solve {a.runup.name}", a.runup)]
    stages += [(f"postproc {p.stem}", p) for p in sorted(res.glob("*.h5"))]
    for name, path in stages:
        t = time_record(path)
        lines.append(f"{name:<40} " + (f"{t[0]:9.1f} {t[1]:9.1f} {t[2]:9.0f}" if t else f"{'(no record)':>29}"))
    lines.append("")

    with h5py.File(steady, "r") as f:
        s = f["solver/steady_state"].attrs
        cyc = f["solver/steady_state"].attrs["cycles"]
        ang = f["crank_angle_deg"][()]
        lines += ["## The steady-state run (engine_steady.toml, 2000 rpm)", "",
                  f"{'converged' if s['converged'] else 'NOT converged'} after {int(cyc)} cycles; kept cycle "
                  f"{ang[0]:.1f} .. {ang[-1]:.1f} deg ({len(ang)} samples); "
                  f"{f['solver/statistics'].attrs['steps']} steps", ""]

    with h5py.File(res / "erp.h5", "r") as f:
        g = f["erp/block"]
        nom, erp, vel = g["nominal_hz"][()], g["erp_level_db"][()], g["velocity_level_db"][()]
        lines += ["## ERP and surface velocity levels of the block (erp.h5; kept cycle, with the rigid-body motion)",
                  "",
                  f"{g.attrs['surface_nodes']} surface nodes, {g.attrs['surface_area_m2']:.3f} m^2; overall ERP "
                  f"{float(g['overall_erp_level_db'][()]):.1f} dB re 1 pW ({float(g['overall_erp_w'][()]):.3g} W);"
                  f" {g.attrs['averages']} average(s) of {g.attrs['segment_length']} samples",
                  "(levels per 1/3 octave; Lv: area-mean normal velocity re 5e-8 m/s; regions: ERP dB / share "
                  "of the band's ERP)",
                  f"{'band Hz':>8} {'ERP dB':>8} {'Lv dB':>8}  " +
                  " ".join(f"{r:>16}" for r in g["regions"].keys())]
        for b in range(len(nom)):
            reg = " ".join(f"{r['erp_level_db'][b]:8.1f}/{r['erp_share'][b]:6.1%}" + " " for r in g["regions"].values())
            lines.append(f"{nom[b]:8g} {erp[b]:8.1f} {vel[b]:8.1f}  {reg}")
        lines.append("")

    with h5py.File(res / "tdc4_history.h5", "r") as f, h5py.File(res / "tdc4_spectrum.h5", "r") as sp:
        lines += ["## Cylinder 4, -30..+90 deg about its firing TDC (360 deg) in the kept cycle "
                  "(tdc4_history.h5, tdc4_spectrum.h5)", "",
                  f"{'signal':<18} {'samples':>7} {'from deg':>9} {'to deg':>8} {'peak m/s^2':>11} "
                  f"{'at deg':>7} {'RMS m/s^2':>10} {'spectrum peak':>20}"]
        for name, g in f["history"].items():
            x, c = g["value"][()], g["cycle_angle_deg"][()]
            k = int(np.argmax(np.abs(x)))
            s = sp["spectrum/" + name]
            amp, fr = s["amplitude"][()], s["frequency_hz"][()]
            j = int(np.argmax(amp[1:])) + 1
            lines.append(f"{name:<18} {len(x):7d} {c[0]:9.1f} {c[-1]:8.1f} {x[k]:11.1f} {c[k]:7.1f} "
                         f"{np.sqrt(np.mean(x**2)):10.1f} {amp[j]:9.2f} at {fr[j]:5.0f} Hz")
        lines.append("")

    with h5py.File(res / "pulley_history.h5", "r") as f:
        lines += ["## Crank front end (pulley) accelerations over the kept cycle, global axes (pulley_*.h5)", ""]
        for name, g in f["history"].items():
            x = g["value"][()]
            lines.append(f"{name:<10} RMS {np.sqrt(np.mean(x**2)):9.1f} m/s^2, peak {np.max(np.abs(x)):9.1f} m/s^2")
        lines.append("")

    def order_table(path, title, picks):
        with h5py.File(path, "r") as f:
            lines.extend([title, ""])
            for name, g in f["orders"].items():
                if name == "cut":
                    continue
                order, amp, rpm = g["order"][()], g["amplitude"][()], g["rpm"][()]
                unit = g["amplitude"].attrs["units"]
                unit = unit.decode() if isinstance(unit, bytes) else unit
                for r in picks(rpm):
                    i = int(np.argmin(np.abs(rpm - r)))
                    cells = " ".join(f"{o:g}:{amp[i, np.argmin(np.abs(order - o))]:.3g}" for o in (0.5, 1, 2, 4, 6))
                    lines.append(f"{name:<22} {rpm[i]:6.0f} rpm  {cells}  [{unit}]")
            lines.append("")

    with h5py.File(res / "mount_spectrum_2000rpm.h5", "r") as f:
        lines += ["## Mount forces and accelerations per order at 2000 rpm, kept cycle (mount_spectrum_2000rpm.h5; "
                  "order:peak amplitude)", ""]
        for name, g in f["spectrum"].items():
            order, amp = g["frequency_hz"][()] / (2000.0 / 60.0), g["amplitude"][()]
            unit = g["amplitude"].attrs["units"]
            unit = unit.decode() if isinstance(unit, bytes) else unit
            cells = " ".join(f"{o:g}:{amp[np.argmin(np.abs(order - o))]:.3g}" for o in (0.5, 1, 2, 4, 6))
            lines.append(f"{name:<22}   2000 rpm  {cells}  [{unit}]")
        lines.append("")
    order_table(res / "mount_orders_runup.h5",
                f"## Mount forces and accelerations per order over speed, run-up {a.runup.name} "
                "(mount_orders_runup.h5; per-cycle values near these speeds)",
                lambda rpm: sorted({float(r) for r in np.linspace(rpm.min(), rpm.max(), 5)}))

    lines += ["## Files", ""]
    for p in sorted(res.rglob("*")):
        if p.is_file() and not p.name.endswith(".time") and p.name != a.output.name:
            lines.append(f"{p.relative_to(res)}  ({p.stat().st_size / 1024:.0f} kB)")
    a.output.write_text("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
