#!/usr/bin/python3
"""Compare solve before and after issue 12 from the runs of bench/run_solve_speedup.sh.

    /usr/bin/python3 bench/compare_solve_speedup.py OUT

Prints (markdown) the CPU time of each run (the least of the repeats), the speed-up, the solver statistics,
the first-order spring-top accelerations of the compressor (amplitude and phase of 12 channels, new against
old) and the journal orbits of the crankshaft on 5 bearings (distance between the runs in units of the
radial clearance over the second cycle). Exit status 0 when the issue's bars hold (compressor >= 5x,
amplitudes within 0.5 %, phases within 0.5 deg; finite bearings >= 5x, orbits within 1 % of the clearance),
1 otherwise: the figures are printed either way.
"""
import sys
from collections import defaultdict
from pathlib import Path

import h5py
import numpy as np

CLEARANCE = 30e-6  # m, testdata/scenes/bearing_crankshaft.toml
BEARINGS = 5


def times(out):
    best = defaultdict(lambda: float("inf"))
    for line in (out / "times.txt").read_text().split("\n"):
        if line.strip():
            label, cpu = line.split()
            key = label.rsplit("_", 1)[0] if label.startswith("compressor") else label
            best[key] = min(best[key], float(cpu))
    return best


def statistics(path):
    with h5py.File(path, "r") as f:
        a = f["solver/statistics"].attrs
        return {k: a[k] for k in ("steps", "rejected_steps", "jacobian_evaluations", "residual_evaluations")
                if k in a}


def main():
    out = Path(sys.argv[1])
    t = times(out)
    ok = True
    print("## solve before and after issue 12 (bench/run_solve_speedup.sh)\n")
    print("| run | before: CPU s | after: CPU s | speed-up | steps before / after | Jacobians before / after |")
    print("|---|---|---|---|---|---|")
    rows = [("compressor demo (30 rev, whole run)", "compressor_old", "compressor_new",
             out / "compressor/old.results.h5", out / "compressor/new.results.h5", 1.0)]
    for model in ("short", "finite"):
        new = out / f"bearing/{model}_new.results.h5"
        with h5py.File(new, "r") as f:
            revolutions = (f["crank_angle_deg"][-1] - f["crank_angle_deg"][0]) / 360.0
        rows.append((f"crankshaft, 5 {model} bearings (per revolution, {revolutions:.0f} run)", f"bearing_{model}_old",
                     f"bearing_{model}_new", out / f"bearing/{model}_old.results.h5", new, revolutions))
    speedups = {}
    for name, old, new, fo, fn, revs in rows:
        so, sn = statistics(fo), statistics(fn)
        speedups[old] = t[old] / t[new]
        print(f"| {name} | {t[old] / revs:.3f} | {t[new] / revs:.3f} | {speedups[old]:.2f}x | "
              f"{so['steps']} / {sn['steps']} | {so['jacobian_evaluations']} / {sn['jacobian_evaluations']} |")
    ok &= speedups["compressor_old"] >= 5.0 and speedups["bearing_finite_old"] >= 5.0

    print("\n### Compressor: first order of the spring-top accelerations (postproc stats --harmonics 1)\n")
    print("| channel | before: m/s^2 | after: m/s^2 | relative difference | phase difference deg |")
    print("|---|---|---|---|---|")
    worst_a = worst_p = 0.0
    with h5py.File(out / "compressor/old.harmonics.h5", "r") as a, \
            h5py.File(out / "compressor/new.harmonics.h5", "r") as b:
        for ch in sorted(a["stats"].keys()):
            xa = a["stats"][ch]["harmonic_amplitude"][0]
            xb = b["stats"][ch]["harmonic_amplitude"][0]
            pa = a["stats"][ch]["harmonic_phase_deg"][0]
            pb = b["stats"][ch]["harmonic_phase_deg"][0]
            da = abs(xb / xa - 1)
            dp = (pb - pa + 180) % 360 - 180
            worst_a, worst_p = max(worst_a, da), max(worst_p, abs(dp))
            print(f"| {ch} | {xa:.5f} | {xb:.5f} | {da:.2e} | {dp:+.4f} |")
    print(f"\nworst: amplitude {100 * worst_a:.3f} % (bar 0.5 %), phase {worst_p:.3f} deg (bar 0.5 deg)")
    ok &= worst_a <= 5e-3 and worst_p <= 0.5

    print("\n### Crankshaft on 5 bearings: journal orbits after against before, second cycle\n")
    print("| bearings | largest distance / c | RMS distance / c | peak eccentricity before / after |")
    print("|---|---|---|---|")
    for model in ("short", "finite"):
        with h5py.File(out / f"bearing/{model}_old.results.h5", "r") as a, \
                h5py.File(out / f"bearing/{model}_new.results.h5", "r") as b:
            n = min(len(a["time"]), len(b["time"]))
            first = n // 2
            d, ea, eb = [], 0.0, 0.0
            for k in range(1, BEARINGS + 1):
                oa = a[f"markers/crank.main{k}/position"][first:n, :2]
                ob = b[f"markers/crank.main{k}/position"][first:n, :2]
                d.append(np.linalg.norm(oa - ob, axis=1) / CLEARANCE)
                ea = max(ea, np.max(np.linalg.norm(oa, axis=1)) / CLEARANCE)
                eb = max(eb, np.max(np.linalg.norm(ob, axis=1)) / CLEARANCE)
            d = np.concatenate(d)
            print(f"| {model} | {d.max():.2e} | {np.sqrt(np.mean(d ** 2)):.2e} | {ea:.4f} / {eb:.4f} |")
            if model == "finite":
                ok &= d.max() <= 0.01
    print("\nbars (compressor and finite bearings >= 5x, accuracy as above):", "met" if ok else "NOT met")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
