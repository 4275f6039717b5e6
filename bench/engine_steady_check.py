#!/usr/bin/python3
"""The engine's periodic steady state against a longer run (issue 15 item 2's verification; docs/engine.md).

    /usr/bin/python3 bench/engine_steady_check.py STEADY.results.h5 LONG.results.h5

STEADY: engine_steady.toml's result (the kept cycle only). LONG: the same scene with `end_cycles = N` in place of
[steady_state] (make it with make_scenes.flexible_scene(..., steady=None, end_cycles=60, outdir=...)); its last
complete 720 deg cycle is compared. For each watched channel: the difference measured as solve's steady-state
measure (scene-format.md section 9), RMS over the cycle of x_long - x_steady over RMS(x_long), the vector's
components together, and the largest difference over the cycle; the samples are matched by crank angle modulo
720 deg (both 24 kHz at the held 2000 rpm: the same phases). Also the mounts' orders 0, 2, 4 (DFT of the cycle).
"""
import sys

import h5py
import numpy as np

CHANNELS = ["forces/mount1_z/force", "forces/mount2_z/force", "forces/mount3_z/force", "forces/mount4_z/force",
            "forces/main3/force"]


def last_cycle(f, n):
    a = f["crank_angle_deg"][:]
    return slice(len(a) - n, len(a)), a[-n:] % 720


def main():
    fs, fl = h5py.File(sys.argv[1], "r"), h5py.File(sys.argv[2], "r")
    n = int(fs["solver/steady_state"].attrs["samples"])
    ss, als = last_cycle(fs, n)
    sl, all_ = last_cycle(fl, n)
    print(f"steady: {fs['solver/steady_state'].attrs['cycles']} cycles, kept from {fs['crank_angle_deg'][0]:.2f} deg; "
          f"long: last cycle from {fl['crank_angle_deg'][sl][0]:.2f} deg")
    assert np.allclose(als, all_, atol=0.01), "phases differ"
    worst = 0.0
    for c in CHANNELS:
        xs, xl = fs[c][ss], fl[c][sl]
        d = xl - xs
        rel = np.sqrt((d ** 2).sum(1).mean()) / np.sqrt((xl ** 2).sum(1).mean())
        worst = max(worst, rel)
        print(f"{c}: RMS difference {np.sqrt((d ** 2).sum(1).mean()):.3g} N = {rel:.2e} of the RMS "
              f"{np.sqrt((xl ** 2).sum(1).mean()):.4g} N; largest {np.abs(d).max():.3g} N")
        if "mount" in c:
            A = [np.abs(np.fft.rfft(x[:, 2]) / n) * np.array([1] + [2] * (n // 2)) for x in (xs, xl)]
            print("   orders 0, 2, 4 (N): steady " + ", ".join(f"{A[0][j]:.2f}" for j in (0, 4, 8)) +
                  "; long " + ", ".join(f"{A[1][j]:.2f}" for j in (0, 4, 8)))
    print(f"largest relative difference {worst:.2e} (tolerance {fs['solver/steady_state'].attrs['tolerance']:g})")


if __name__ == "__main__":
    main()
