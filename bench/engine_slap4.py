#!/usr/bin/python3
"""Cylinder 4's slap in the engine (testdata/engine/engine_film4.toml, docs/engine.md) and its effect on the
block's 1/3-octave acceleration levels against the prismatic piston 4 (engine_steady.toml).

    /usr/bin/python3 bench/engine_slap4.py FILM4.results.h5 [--octave FILM4.octave.h5 REF.octave.h5] [--plot PNG]

Definitions as docs/bearing.md section 16.3 (bench/slap_impact.py), with the engine's axes: the thrust side is
+y (the crank turns about +x), the side force F is the film's `side_force` along the liner frame's x (= +y) on
the piston; cylinder 4 fires at 360 deg (crank angle 0 = firing TDC of cylinder 1):
  lift-off  the last sample in 340..400 deg (of the cycle) with F > 10 N before F first reaches -10 N
  impact    the first instant after it with F <= -10 N, interpolated linearly between samples (0.5 deg apart here: 24 kHz at 2000 rpm)
  v_pin     the piston pin's lateral velocity relative to the liner point (block.liner4) at the impact
  energy    1/2 m_p v_pin^2 (the lateral part only: no skirt-edge markers, so no tilt rate in the output)
  travel    the pin's lateral displacement relative to the liner point from lift-off to impact
"""
import argparse

import h5py
import numpy as np

F_TH = 10.0
M_PISTON = 0.465   # testdata/engine/make_scenes.py PISTON_M


def cycles_in(path):
    """The complete 720 deg cycles (0-based, counted from crank angle 0) of a results file."""
    with h5py.File(path, "r") as f:
        a = f["crank_angle_deg"][:]
    return list(range(int(np.ceil(a[0] / 720 - 1e-3)), int(np.floor(a[-1] / 720 + 1e-3))))


def slap(path, cycle=None):
    """cycle: the 720 deg cycle K (samples with crank angle in [720 K, 720 (K + 1)), a history file) or None
    (the whole file: a steady-state result holds the kept cycle only)."""
    with h5py.File(path, "r") as f:
        a = f["crank_angle_deg"][:]
        sel = slice(None) if cycle is None else np.where((a >= 720 * cycle - 0.5) & (a < 720 * (cycle + 1) - 0.5))[0]
        rd = lambda name, col=None: f[name][sel] if col is None else f[name][sel, col]
        th = a[sel] % 720.0
        F = rd("forces/skirt4/side_force")
        hmin = rd("forces/skirt4/min_film")
        asp = rd("forces/skirt4/asperity_force")
        v = rd("markers/piston4.pin/velocity", 1) - rd("markers/block.liner4/velocity", 1)
        x = rd("markers/piston4.pin/position", 1) - rd("markers/block.liner4/position", 1)
    order = np.argsort(th)
    th, F, hmin, asp, v, x = th[order], F[order], hmin[order], asp[order], v[order], x[order]
    window = np.where((th >= 340) & (th <= 400))[0]
    first_neg = next(k for k in window if F[k] <= -F_TH)
    lift = max(k for k in window if k < first_neg and F[k] > F_TH)
    k = first_neg
    w = (F[k - 1] + F_TH) / (F[k - 1] - F[k]) if F[k - 1] != F[k] else 1.0
    lerp = lambda y: y[k - 1] + w * (y[k] - y[k - 1])
    after = (th >= lerp(th)) & (th <= 420)
    r = dict(lift_off_deg=th[lift], impact_deg=lerp(th), v_pin=lerp(v), energy=0.5 * M_PISTON * lerp(v) ** 2,
             travel=lerp(x) - x[lift], peak_side_force=float(np.max(np.abs(F[(th >= 355) & (th <= 420)]))),
             min_film_after=float(np.min(hmin[after])), max_asperity=float(np.max(asp)),
             min_film_cycle=float(np.min(hmin)), sign_changes=[float(a) for a in th[1:][np.diff(np.sign(F)) != 0]])
    return r, (th, F, hmin, v)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("results")
    ap.add_argument("--octave", nargs=2, metavar=("FILM4", "REF"))
    ap.add_argument("--plot")
    ap.add_argument("--cycle", type=int, help="analyse this 720 deg cycle of a history (0-based); default the "
                    "whole file (a steady-state result)")
    ap.add_argument("--last", type=int, default=0, help="also list the slap of the last N complete cycles")
    a = ap.parse_args()
    if a.last:
        for c in cycles_in(a.results)[-a.last:]:
            r, _ = slap(a.results, c)
            print(f"cycle {c}: lift-off {r['lift_off_deg']:.2f}, impact {r['impact_deg']:.2f} deg, "
                  f"v_pin {r['v_pin']:.3f} m/s, peak |F| {r['peak_side_force']:.0f} N, "
                  f"min film after {r['min_film_after'] * 1e6:.1f} um")
    r, (th, F, hmin, v) = slap(a.results, a.cycle)
    print(f"lift-off {r['lift_off_deg']:.2f} deg, impact {r['impact_deg']:.2f} deg, v_pin {r['v_pin']:.3f} m/s, "
          f"energy {r['energy'] * 1e3:.1f} mJ, travel {r['travel'] * 1e6:.1f} um, peak |F| 355-420 deg "
          f"{r['peak_side_force']:.0f} N, min film after the impact (to 420 deg) {r['min_film_after'] * 1e6:.1f} um, "
          f"min film over the cycle {r['min_film_cycle'] * 1e6:.1f} um, largest asperity force {r['max_asperity']:.1f} N")
    print("side force sign changes (deg):", ", ".join(f"{s:.0f}" for s in r["sign_changes"]))
    if a.octave:
        with h5py.File(a.octave[0], "r") as f1, h5py.File(a.octave[1], "r") as f0:
            for p in f1["octave"]:
                nom = f1[f"octave/{p}/nominal_hz"][:]
                d = f1[f"octave/{p}/level_db"][:] - f0[f"octave/{p}/level_db"][:]
                o = f1[f"octave/{p}/overall_level_db"][()] - f0[f"octave/{p}/overall_level_db"][()]
                print(f"{p}: overall {o:+.2f} dB; per band " +
                      " ".join(f"{n:.0f}:{x:+.1f}" for n, x in zip(nom, d)))
    if a.plot:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, ax = plt.subplots(3, 1, figsize=(9, 8), sharex=True)
        ax[0].plot(th, F)
        ax[0].set_ylabel("side force on piston 4 (N)\n(-: the thrust side +y carries it)")
        ax[1].plot(th, hmin * 1e6)
        ax[1].set_ylabel("min film (um)")
        ax[2].plot(th, v)
        ax[2].set_ylabel("pin lateral velocity\nrel. liner (m/s)")
        ax[2].set_xlabel("crank angle (deg; cylinder 4 fires at 360)")
        for x in ax:
            x.axvline(r["impact_deg"], color="r", lw=0.8, ls="--")
            x.grid(True, alpha=0.3)
        ax[0].set_title(f"engine_film4: cylinder 4, steady cycle; impact {r['impact_deg']:.1f} deg (red)")
        fig.tight_layout()
        fig.savefig(a.plot, dpi=100)
        print("plot:", a.plot)


if __name__ == "__main__":
    main()
