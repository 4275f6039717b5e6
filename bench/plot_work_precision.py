#!/usr/bin/python3
"""Work-precision chart: error against CPU time for each CSV of bench_solve_work_precision."""
import argparse, csv, os
import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt

ap = argparse.ArgumentParser()
ap.add_argument("csv", nargs="+")
ap.add_argument("-o", "--output", required=True)
a = ap.parse_args()
fig, axes = plt.subplots(1, len(a.csv), figsize=(6 * len(a.csv), 4.5), squeeze=False)
for ax, path in zip(axes[0], a.csv):
    rows = list(csv.DictReader(open(path)))
    for method, marker in (("ida", "o-"), ("generalized-alpha", "s-"), ("split", "^-"),
                           ("ida no-events", "o:"), ("generalized-alpha no-events", "s:"),
                           ("split no-events", "^:")):
        pts = [(float(r["cpu_s"]), float(r["error"]), r["setting"]) for r in rows
               if r["method"] == method and r["error"] not in ("nan", "")]
        if not pts:
            continue
        ax.loglog([p[0] for p in pts], [p[1] for p in pts], marker, label=method)
        for x, y, s in pts:
            label = "tol " if method.startswith("ida") else "H " if method.startswith("split") else "h "
            ax.annotate(label + s, (x, y), fontsize=7)
    ax.set_xlabel("CPU time [s]")
    ax.set_ylabel("max error / signal range [-]")
    ax.set_title(os.path.splitext(os.path.basename(path))[0])
    ax.grid(True, which="both", alpha=0.3)
    ax.legend()
fig.tight_layout()
fig.savefig(a.output, dpi=110)
