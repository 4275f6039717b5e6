#!/usr/bin/env python3
"""Accuracy against cost of a reduction: the estimated receptance error at the interfaces in a band
(condense [reduction] band, docs/component-format.md section 5.3) against the cut-off and the number of
coordinates, for Craig-Bampton, modal with residual modes and modal without, on the testdata crankshaft
(9 interfaces, band 3 kHz). Also the cut-off condense chooses from the band alone.

usage: bench/frf_error_cutoff.py CONDENSE [--band HZ] [--component FILE] [--out PNG]
Prints one line per run (method, cut-off, coordinates, estimated error, wall time) and writes the chart
(default docs/img/frf_error_cutoff.png).
"""
import argparse
import os
import subprocess
import sys
import tempfile
import time

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)


def run(condense, component, out, band, method, fmax=None, residual=None):
    """One condense run; returns (cut-off Hz, coordinates, max error, seconds, passes)."""
    args = [condense, component, "-o", out, "-q", "--band", str(band), "--method", method]
    if fmax is not None:
        args += ["--fmax", str(fmax)]
    # residual_modes cannot be overridden on the command line, nor fmax removed: a copy of the file.
    with open(component) as f:
        lines = f.read().splitlines()
    if fmax is None:
        lines = [l for l in lines if not l.strip().startswith(("fmax", "modes"))]
    text = "\n".join(lines) + "\n"
    if residual is not None:
        text = text.replace("[reduction]", "[reduction]\nresidual_modes = %s" % ("true" if residual else "false"), 1)
    copy = out + ".toml"
    with open(copy, "w") as f:
        f.write(text)
    args[1] = copy
    start = time.perf_counter()
    subprocess.run(args, check=True)
    seconds = time.perf_counter() - start
    with h5py.File(out) as f:
        g = f["reduction_error"]
        n = f["reduced/mass"].shape[0]
        passes = list(g.attrs["pass_cutoff_hz"]) if "pass_cutoff_hz" in g.attrs else []
        return g.attrs["cutoff_hz"], n, g.attrs["max_error"], seconds, passes


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("condense")
    parser.add_argument("--band", type=float, default=3000.0)
    parser.add_argument("--component", default=os.path.join(ROOT, "testdata", "crankshaft.toml"))
    parser.add_argument("--out", default=os.path.join(ROOT, "docs", "img", "frf_error_cutoff.png"))
    a = parser.parse_args()
    factors = [1.5, 2, 3, 4.5, 6.7, 10, 15]
    series = {
        "craig-bampton": ("craig-bampton", None),
        "modal + residual modes": ("modal", True),
        "modal": ("modal", False),
    }
    results = {}
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "se.h5")
        print("%-24s %10s %6s %12s %8s" % ("method", "cut-off", "coords", "est. error", "time s"))
        for label, (method, residual) in series.items():
            rows = []
            for k in factors:
                cutoff, n, err, sec, _ = run(a.condense, a.component, out, a.band, method, k * a.band, residual)
                rows.append((cutoff, n, err, sec))
                print("%-24s %10.0f %6d %12.3e %8.2f" % (label, cutoff, n, err, sec))
            results[label] = rows
        chosen = {}
        for label, (method, residual) in list(series.items())[:2]:
            cutoff, n, err, sec, passes = run(a.condense, a.component, out, a.band, method, None, residual)
            chosen[label] = (cutoff, n, err, sec)
            print("%-24s %10.0f %6d %12.3e %8.2f  chosen from the band (passes at %s Hz)"
                  % (label, cutoff, n, err, sec, ", ".join("%.0f" % p for p in passes)))

    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(11, 4.2))
    for label, rows in results.items():
        ax1.loglog([r[0] / a.band for r in rows], [r[2] for r in rows], "o-", label=label)
        ax2.loglog([r[1] for r in rows], [r[2] for r in rows], "o-", label=label)
    for label, (cutoff, n, err, _) in chosen.items():
        ax1.loglog([cutoff / a.band], [err], "k*", ms=12)
        ax2.loglog([n], [err], "k*", ms=12)
    for ax in (ax1, ax2):
        ax.axhline(0.01, color="gray", ls="--", lw=1)
        ax.grid(True, which="both", alpha=0.3)
        ax.set_ylabel("estimated receptance error in 0 .. %.0f Hz" % a.band)
    ax1.set_xlabel("cut-off / band")
    ax2.set_xlabel("coordinates of the reduced model")
    ax1.legend(fontsize=8)
    ax1.set_title("%s: error against cut-off" % os.path.basename(a.component), fontsize=9)
    ax2.set_title("error against size (stars: cut-off chosen for 1 %)", fontsize=9)
    fig.tight_layout()
    fig.savefig(a.out, dpi=110)
    print("wrote", a.out)


if __name__ == "__main__":
    sys.exit(main())
