#!/usr/bin/python3
"""Plot the CSV tables of bench_beam_convergence (accuracy against cost) as PNG files.

usage: bench/plot_convergence.py [CSV_DIR] [--out DIR] [--dpi N]

  CSV_DIR   the directory bench_beam_convergence --out wrote (default bench-out)
  --out     where to write the PNG files (default: CSV_DIR)
  --dpi     resolution (default 90; the plots stay below 150 kB)

Writes
  element_convergence.png  |relative error| of bending modes 1-4 against elements (and free DOF), log-log:
                           a) slender cantilever, Euler-Bernoulli element; b) thick simply supported beam,
                           Timoshenko element and Euler-Bernoulli element against the Timoshenko equation
  craig_bampton.png        largest |relative error| of the first 6 elastic modes of the L-frame against the
                           number of fixed-interface modes (Guyan at 0)
  error_vs_time.png        the same errors against the wall time of condense_component

Needs matplotlib (Debian: apt-get install -y python3-matplotlib); uses the Agg backend (no display).
"""
import argparse
import csv
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

MODE_COLORS = ["tab:blue", "tab:orange", "tab:green", "tab:red"]


def read(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def num(text):
    return float(text) if text not in ("", None) else math.nan


def mode_series(rows, model, key):
    """(elements, |error|) of rows of `model` with a value in column `key`."""
    xs, ys = [], []
    for r in rows:
        if r["model"] != model or r[key] == "":
            continue
        xs.append(int(r["elements"]))
        ys.append(max(abs(num(r[key])), 1e-16))
    return xs, ys


def dof_axis(ax):
    # Both beams have 6 free DOF per element (cantilever: N nodes free; simply supported: 6 (N + 1) - 6).
    top = ax.secondary_xaxis("top", functions=(lambda n: 6.0 * n, lambda d: d / 6.0))
    top.set_xlabel("free DOF of the 3D model (6 x elements)")


def slope_guide(ax, x0, y0, order, label):
    xs = [x0, x0 * 4]
    ax.plot(xs, [y0, y0 * 4.0 ** (-order)], color="0.4", lw=1, ls=":")
    ax.annotate(label, (xs[1], y0 * 4.0 ** (-order)), textcoords="offset points", xytext=(4, -2), fontsize=8,
                color="0.3")


def plot_elements(cantilever, thick, out, dpi):
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(11, 4.6), sharey=True)
    for m in range(4):
        xs, ys = mode_series(cantilever, "euler-bernoulli", f"err_{m + 1}")
        ax1.loglog(xs, ys, "o-", color=MODE_COLORS[m], label=f"mode {m + 1}")
    slope_guide(ax1, 8, 3e-9, 4, r"$\propto h^4$")
    ax1.set_title("a) cantilever L = 1 m, d = 10 mm\nEuler-Bernoulli element vs beta_n L", fontsize=10)
    for m in range(4):
        xs, ys = mode_series(thick, "timoshenko", f"err_{m + 1}")
        ax2.loglog(xs, ys, "o-", color=MODE_COLORS[m], label=f"Timoshenko element, mode {m + 1}")
        xs, ys = mode_series(thick, "euler-bernoulli", f"err_{m + 1}")
        ax2.loglog(xs, ys, "s--", color=MODE_COLORS[m], mfc="none", alpha=0.8,
                   label=f"Euler-Bernoulli element, mode {m + 1}")
    slope_guide(ax2, 8, 2e-5, 2, r"$\propto h^2$")
    ax2.set_title("b) simply supported L = 0.6 m, square 0.1 m (L/h = 6)\nagainst the Timoshenko equation",
                  fontsize=10)
    for ax in (ax1, ax2):
        ax.set_xlabel("elements")
        ax.grid(True, which="major", alpha=0.4)
        ax.grid(True, which="minor", alpha=0.1)
        dof_axis(ax)
    ax1.set_ylabel("|f / f_ref - 1| (relative frequency error)")
    ax1.legend(fontsize=8, loc="lower left")
    ax2.legend(fontsize=7, loc="lower left", ncol=2)
    fig.tight_layout()
    path = os.path.join(out, "element_convergence.png")
    fig.savefig(path, dpi=dpi)
    plt.close(fig)
    return path


def plot_craig_bampton(frame, out, dpi):
    fig, ax = plt.subplots(figsize=(7, 4.6))
    cb = [r for r in frame if r["method"] == "craig-bampton"]
    xs = [int(r["fixed_interface_modes"]) for r in cb]
    for m in range(6):
        ax.semilogy(xs, [abs(num(r[f"err_{m + 1}"])) for r in cb], "-", lw=0.8, alpha=0.5,
                    label=f"mode {m + 1}")
    ax.semilogy(xs, [num(r["max_err"]) for r in cb], "ko-", lw=2, label="Craig-Bampton, max over modes 1-6")
    for r in frame:
        if r["method"] == "guyan":
            ax.semilogy([0], [num(r["max_err"])], "rs", ms=8, label="Guyan (12 interface DOF), max")
    for r, x in zip(cb, xs):
        if r["cutoff_ratio"] and x in (8, 16, 32, 48):
            ax.annotate(f"{num(r['cutoff_ratio']):.1f}x", (x, num(r["max_err"])), textcoords="offset points",
                        xytext=(3, 6), fontsize=8)
    ax.set_xlabel("fixed-interface modes (annotated: highest fixed-interface / 6th elastic frequency)")
    ax.set_ylabel("|f / f_unreduced - 1| (relative frequency error)")
    ax.set_title("c) Craig-Bampton, free L-frame (198 DOF, 2 interfaces), first 6 elastic modes", fontsize=10)
    ax.grid(True, which="major", alpha=0.4)
    ax.legend(fontsize=8, loc="upper right", ncol=2)
    fig.tight_layout()
    path = os.path.join(out, "craig_bampton.png")
    fig.savefig(path, dpi=dpi)
    plt.close(fig)
    return path


def plot_error_time(cantilever, thick, frame, out, dpi):
    fig, ax = plt.subplots(figsize=(8, 5))

    def worst(r, keys):
        vals = [abs(num(r[k])) for k in keys if r[k] != ""]
        return max(vals) if vals else math.nan

    keys = [f"err_{m}" for m in range(1, 5)]
    series = [
        ("a) cantilever, E-B element, max modes 1-4", [r for r in cantilever], "o-", "tab:blue"),
        ("b) thick beam, Timoshenko element, max modes 1-4",
         [r for r in thick if r["model"] == "timoshenko"], "o-", "tab:green"),
        ("b) thick beam, E-B element vs Timoshenko",
         [r for r in thick if r["model"] == "euler-bernoulli"], "s--", "tab:red"),
    ]
    for label, rows, style, color in series:
        rows = [r for r in rows if r["err_4"] != ""]  # only meshes that have all 4 modes
        ax.loglog([num(r["t_min_ms"]) for r in rows], [worst(r, keys) for r in rows], style, color=color,
                  label=label + " (2..64 elements)")
    cb = [r for r in frame if r["method"] == "craig-bampton"]
    ax.loglog([num(r["t_min_ms"]) for r in cb], [num(r["max_err"]) for r in cb], "D-", color="tab:purple",
              label="c) L-frame, Craig-Bampton 1..48 modes, max modes 1-6")
    for r in frame:
        if r["method"] == "guyan":
            ax.loglog([num(r["t_min_ms"])], [num(r["max_err"])], "rs", ms=8, label="c) L-frame, Guyan")
        if r["method"] == "modal":
            ax.loglog([num(r["t_min_ms"])], [max(num(r["max_err"]), 1e-16)], "k*", ms=10,
                      label="c) L-frame, full modal (= the reference up to round-off)")
    ax.set_xlabel("wall time of condense_component [ms] (minimum over repeats)")
    ax.set_ylabel("largest |relative frequency error|")
    ax.set_title("Accuracy against cost", fontsize=10)
    ax.grid(True, which="major", alpha=0.4)
    ax.grid(True, which="minor", alpha=0.1)
    ax.legend(fontsize=8, loc="lower left")
    fig.tight_layout()
    path = os.path.join(out, "error_vs_time.png")
    fig.savefig(path, dpi=dpi)
    plt.close(fig)
    return path


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("csv_dir", nargs="?", default="bench-out")
    parser.add_argument("--out", default=None)
    parser.add_argument("--dpi", type=int, default=90)
    args = parser.parse_args()
    out = args.out or args.csv_dir
    os.makedirs(out, exist_ok=True)
    try:
        cantilever = read(os.path.join(args.csv_dir, "cantilever_euler_bernoulli.csv"))
        thick = read(os.path.join(args.csv_dir, "thick_beam_timoshenko.csv"))
        frame = read(os.path.join(args.csv_dir, "craig_bampton_frame.csv"))
    except OSError as e:
        sys.exit(f"plot_convergence.py: {e}; run bench_beam_convergence --out {args.csv_dir} first")
    for path in (plot_elements(cantilever, thick, out, args.dpi), plot_craig_bampton(frame, out, args.dpi),
                 plot_error_time(cantilever, thick, frame, out, args.dpi)):
        print(f"wrote {path} ({os.path.getsize(path) / 1024:.0f} kB)")


if __name__ == "__main__":
    main()
