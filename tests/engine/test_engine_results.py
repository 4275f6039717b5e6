#!/usr/bin/python3
"""Checks of the engine study's results (`make -f Makefile.workflow engine`, docs/engine.md "Results"), each
against numbers recomputed here in numpy from the files solve and condense wrote, never from postproc's code:

    test_engine_results.py BUILD_DIR ENGINE_DIR      # ENGINE_DIR: the workflow's OUT/engine

Exits 77 (ctest: skipped) when ENGINE_DIR holds no workflow run (block.h5 takes ~3 min and ~4 GB to condense,
the steady state ~2 min to solve: too much for the unit suite; the workflow runs this script itself).

erp. `postproc erp` on the kept cycle of engine_steady (elastic normal velocity, rectangular window, one
segment of the whole cycle) against the definition (docs/postproc.md section 4.5, eq. 1-2; Fahy & Gardonio
2007, ch. 3, radiation efficiency 1): v_n,k(t) = n_k . Phi_k eta'(t) from the superelement's /surface (normal,
shape, area) and the results' /bodies/block/modal_velocities; its DFT amplitude v_hat_k,i = 2 |V_k[i]| / N at
bin i; the band's ERP = 1/2 rho c sum_k A_k sum_i w_i |v_hat_k,i|^2, w_i the fraction of bin i (width df = 1 / T)
inside the 1/3-octave band (IEC 61260-1 base-10 edges, 1000 x 10^(0.1 j +- 0.05) Hz). Tolerance 1e-9 relative
for the 1 kHz and 2.5 kHz bands and the oil-pan region's 1 kHz band.

orders. The order amplitudes of the mounts' vertical forces at constant speed (mount_spectrum_2000rpm.h5: the
kept cycle's amplitude spectrum, one rectangular segment, bin 2 k = order k) against numpy's DFT of the samples (1440 samples over exactly 720 deg at
2000 rpm and 24 kHz; order k is bin 2 k, amplitude 2 |X| / N): orders 0.5 .. 6, to 1e-6 of the largest order
amplitude of that mount.

window. The liner and block accelerations -30..+90 deg about cylinder 4's firing TDC (tdc4_history.h5,
--angle-window 330,450 --angle-period 720): exactly the results' samples whose crank angle, less 720 k of the
kept cycle, lies in [330, 450] deg - counted here (240 or 241 samples at 0.5 deg: the kept cycle's grid lies
5.6e-4 deg before the 0.5 deg marks, so 330 itself is just outside) - and their values unchanged.
"""
import subprocess
import sys
import tempfile
from pathlib import Path

import h5py
import numpy as np

RHO, C = 1.204, 343.2  # postproc erp's default air (docs/postproc.md 3.5)


def third_octave(nominal):
    """IEC 61260-1 base-10 1/3-octave band: exact mid-band 1000 x 10^(j/10) Hz nearest the nominal value."""
    j = round(10 * np.log10(nominal / 1000.0))
    fm = 1000.0 * 10 ** (j / 10)
    return fm * 10 ** -0.05, fm * 10 ** 0.05


def check_erp(build, eng, fails):
    results, se = eng / "engine_steady.results.h5", eng / "block.h5"
    with h5py.File(results, "r") as f:
        eta_dot = f["bodies/block/modal_velocities"][()]
        fs = f.attrs["sample_rate_hz"] if "sample_rate_hz" in f.attrs else 1.0 / np.diff(f["time"][:2])[0]
    n, m = eta_dot.shape
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / "erp.h5"
        subprocess.run([str(build / "postproc" / "postproc"), "erp", str(results), "--superelement", str(se),
                        "--body", "block", "--window", "rectangular", "--segment", str(n), "--fmin", "900",
                        "--fmax", "2600", "--region", "oilpan=-0.21,-0.13,-0.061,0.21,0.13,-0.05", "-o", str(out),
                        "-q"], check=True)
        with h5py.File(out, "r") as f:
            g = f["erp/block"]
            nominal, erp_band = g["nominal_hz"][()], g["erp_band_w"][()]
            oil_band = g["regions/oilpan/erp_band_w"][()]
            df = g.attrs["resolution_hz"]
    with h5py.File(se, "r") as f:
        normal, area, pos = f["surface/normal"][()], f["surface/area"][()], f["surface/position"][()]
        shape = f["surface/shape"][:, :, :m]
    psi = np.einsum("kd,kdj->kj", normal, shape)            # eq. (1): v_n = Psi eta'
    spectrum = np.fft.rfft(eta_dot, axis=0)                   # (bins, modes), one segment, no window
    freq = np.arange(spectrum.shape[0]) * fs / n
    if abs(df - fs / n) > 1e-9 * df:
        fails.append(f"erp: resolution {df} Hz, expected fs / N = {fs / n} Hz")
    oil = (pos[:, 2] >= -0.061) & (pos[:, 2] <= -0.05) & (np.abs(pos[:, 1]) <= 0.13) & (np.abs(pos[:, 0]) <= 0.21)
    for nom in (1000, 2500):
        lo, hi = third_octave(nom)
        b = int(np.argmin(np.abs(nominal - nom)))
        w = np.clip(np.minimum(hi, freq + df / 2) - np.maximum(lo, freq - df / 2), 0, None) / df
        bins = np.nonzero(w > 0)[0]
        v_hat = 2 * np.abs(spectrum[bins] @ psi.T) / n         # (bins, nodes): amplitude of v_n per bin
        per_node = (w[bins, None] * v_hat**2).sum(axis=0)
        for name, got, mask in (("surface", erp_band[b], np.ones(len(area), bool)), ("oilpan", oil_band[b], oil)):
            if name == "oilpan" and nom != 1000:
                continue
            ref = 0.5 * RHO * C * np.sum(area[mask] * per_node[mask])
            rel = abs(got - ref) / ref
            print(f"erp {name} {nom} Hz band: postproc {got:.10e} W, numpy {ref:.10e} W, rel. diff {rel:.2e}")
            if not rel < 1e-9:
                fails.append(f"erp {name} {nom} Hz: {got} W against {ref} W (rel. {rel:.2e} > 1e-9)")


def check_orders(eng, fails):
    with h5py.File(eng / "engine_steady.results.h5", "r") as f, \
            h5py.File(eng / "results" / "mount_spectrum_2000rpm.h5", "r") as o:
        angle = f["crank_angle_deg"][()]
        for k in range(1, 5):
            x = f[f"forces/mount{k}_z/force"][:, 2]
            # the kept cycle: 1440 samples 0.5 deg apart from a 720 deg boundary
            if len(x) < 1440 or abs(angle[1439] - angle[0] - 719.5) > 1e-3 or \
                    abs(angle[0] / 720 - round(angle[0] / 720)) > 1e-6:
                fails.append(f"orders: the kept cycle of mount{k}_z does not start with 1440 samples over 720 deg")
                continue
            X = np.fft.rfft(x[:1440])
            g = o[f"spectrum/mount{k}_z"]
            order, amp = g["frequency_hz"][()] / (2000.0 / 60.0), g["amplitude"][()]
            ref = {q: (1 if q == 0 else 2) * abs(X[int(round(2 * q))]) / 1440 for q in np.arange(0, 6.01, 0.5)}
            scale = max(ref[q] for q in ref if q > 0)
            worst = max(abs(amp[int(np.argmin(np.abs(order - q)))] - r) for q, r in ref.items() if q > 0)
            print(f"orders mount{k}_z: order 2 {ref[2.0]:.4f} N (DFT), largest difference over orders 0.5-6 "
                  f"{worst:.2e} N ({worst / scale:.1e} of the largest)")
            if not worst < 1e-6 * scale:
                fails.append(f"orders mount{k}_z: differs from the DFT by {worst} N (> 1e-6 x {scale} N)")


def check_window(eng, fails):
    with h5py.File(eng / "engine_steady.results.h5", "r") as f, \
            h5py.File(eng / "results" / "tdc4_history.h5", "r") as h:
        angle = f["crank_angle_deg"][()]
        k = np.floor((angle[-1] - 450 + 1e-6) / 720)
        inside = np.nonzero((angle >= 330 + 720 * k - 1e-6) & (angle <= 450 + 720 * k + 1e-6))[0]
        g = h["history/liner4_y"]
        x, c = g["value"][()], g["cycle_angle_deg"][()]
        ref = f["markers/block.liner4/acceleration"][inside, 1]
        print(f"window: {len(x)} samples {c[0]:.1f}..{c[-1]:.1f} deg; counted {len(inside)} "
              f"({angle[inside[0]] - 720 * k:.1f}..{angle[inside[-1]] - 720 * k:.1f} deg)")
        if len(inside) not in (240, 241) or len(x) != len(inside) or not np.array_equal(x, ref) \
                or c[0] < 330 - 1e-6 or c[-1] > 450 + 1e-6 or c[0] > 330.5 + 1e-6 or c[-1] < 449.5 - 1e-6:
            fails.append(f"window: {len(x)} samples from {c[0]} to {c[-1]} deg, expected the {len(inside)} "
                         f"samples of the results within 330..450 deg")


def main():
    build, eng = Path(sys.argv[1]), Path(sys.argv[2])
    needed = [eng / "block.h5", eng / "engine_steady.results.h5", eng / "results" / "mount_spectrum_2000rpm.h5",
              eng / "results" / "tdc4_history.h5"]
    if not all(p.exists() for p in needed):
        print(f"skipped: no workflow run in {eng} (make -f Makefile.workflow engine)")
        sys.exit(77)
    fails = []
    check_window(eng, fails)
    check_orders(eng, fails)
    check_erp(build, eng, fails)
    for f in fails:
        print("FAIL:", f)
    sys.exit(1 if fails else 0)


if __name__ == "__main__":
    main()
