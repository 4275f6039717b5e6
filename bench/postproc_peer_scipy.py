#!/usr/bin/python3
"""The SciPy peer of bench/postproc_bench.py: the same three analyses on the same signal file, written the way
a SciPy user would (whole signal in memory, scipy.signal / numpy), with the same algorithms and parameters:

  spectrum  scipy.signal.welch: Hann, 65536-sample segments (0.78 Hz), 50 % overlap, no detrending, RMS
  octave    1/3-octave bands 20 Hz - 10 kHz: per band butter(3, [f1, f2], 'bandpass', output='sos') run by
            sosfilt at the rate fs / 2^k >= 5 f_m, reached by the same order-8 Butterworth low-pass at 0.2 of the
            rate and [::2] (the same multirate bank as postproc's)
  orders    resampling to 1024 points per 720 deg cycle by the same Kaiser-windowed sinc (half-width 16,
            beta 8), times from np.interp of the inverse angle, then numpy rfft of each cycle

usage: postproc_peer_scipy.py SIGNAL.h5 OUT.npz STAGE   (STAGE: spectrum, octave or orders)
Prints "seconds <wall> cpu <user+system>" for reading and analysis (the interpreter's start and imports excluded).
"""
import resource
import sys
import time

import h5py
import numpy as np
import scipy.signal as sig

G = 10 ** 0.3


def bands_third_octave(fmin=20.0, fmax=10000.0):
    out = []
    for x in range(-20, 14):
        fm = 1000.0 * G ** (x / 3)
        if fmin / G ** (1 / 12) <= fm <= fmax * G ** (1 / 12):
            out.append((fm, fm * G ** (-1 / 6), fm * G ** (1 / 6)))
    return out


def spectrum(x, fs):
    f, p = sig.welch(x, fs, window="hann", nperseg=65536, noverlap=32768, detrend=False, scaling="spectrum")
    return {"frequency_hz": f, "rms": np.sqrt(p)}


def octave(x, fs):
    bands = bands_third_octave()
    stage_of = []
    for fm, _, _ in bands:
        k = 0
        while fs / 2 ** (k + 1) >= 5 * fm:
            k += 1
        stage_of.append(k)
    ms = np.zeros(len(bands))
    current, rate = x, fs
    for k in range(max(stage_of) + 1):
        for b, (fm, f1, f2) in enumerate(bands):
            if stage_of[b] == k:
                y = sig.sosfilt(sig.butter(3, [f1, f2], btype="bandpass", fs=rate, output="sos"), current)
                ms[b] = np.mean(y * y)
        if k < max(stage_of):
            lp = sig.butter(8, 0.2 * rate, fs=rate, output="sos")
            current = sig.sosfilt(lp, current)[::2]
            rate /= 2
    return {"center_hz": np.array([b[0] for b in bands]), "mean_square": ms}


def kaiser_sinc(u, half_width=16, beta=8.0):
    r = np.clip(u / half_width, -1, 1)
    return np.sinc(u) * np.i0(beta * np.sqrt(1 - r * r)) / np.i0(beta) * (np.abs(u) < half_width)


def orders(x, angle_deg, fs, m=1024, cycle=720.0, max_order=20.0):
    # Targets: whole cycles from the first multiple of 720 deg reachable by the kernel to the last complete one.
    first = np.ceil(angle_deg[131] / cycle) * cycle
    last = np.floor(angle_deg[-20] / cycle) * cycle
    cycles = int((last - first) / cycle)
    targets = first + np.arange(cycles * m) * (cycle / m)
    position = np.interp(targets, angle_deg, np.arange(len(angle_deg), dtype=float))  # fractional sample index
    speed = np.gradient(angle_deg) * fs  # deg/s
    beta = np.clip(np.interp(position, np.arange(len(x)), speed) * m / cycle / fs, 1 / 8, 1.0)
    out = np.empty(len(targets))
    chunk = 1 << 14
    for start in range(0, len(targets), chunk):
        p = position[start:start + chunk]
        b = beta[start:start + chunk]
        reach = int(np.ceil(16 / b.min()))  # taps the kernel reaches at the chunk's lowest cut-off
        t = np.arange(-reach + 1, reach + 1)
        idx = np.floor(p).astype(np.int64)[:, None] + t[None, :]
        np.clip(idx, 0, len(x) - 1, out=idx)
        u = (p[:, None] - idx) * b[:, None]
        out[start:start + len(p)] = b * np.sum(x[idx] * kaiser_sinc(u), axis=1)
    spectra = np.fft.rfft(out.reshape(cycles, m), axis=1)
    k_max = int(max_order * cycle / 360)
    amp = np.abs(spectra[:, :k_max + 1]) * 2 / m
    amp[:, 0] /= 2
    return {"order": np.arange(k_max + 1) * 360 / cycle, "amplitude": amp}


def main():
    path, out, stage = sys.argv[1], sys.argv[2], sys.argv[3]
    start = time.perf_counter()
    usage = resource.getrusage(resource.RUSAGE_SELF)
    with h5py.File(path, "r") as f:
        fs = float(f.attrs["sample_rate_hz"])
        x = f["signal"][()]
        angle = f["crank_angle_deg"][()] if stage == "orders" else None
    if stage == "spectrum":
        result = spectrum(x, fs)
    elif stage == "octave":
        result = octave(x, fs)
    else:
        result = orders(x, angle, fs)
    end = resource.getrusage(resource.RUSAGE_SELF)
    cpu = end.ru_utime - usage.ru_utime + end.ru_stime - usage.ru_stime
    print(f"seconds {time.perf_counter() - start:.3f} cpu {cpu:.3f}")
    np.savez(out, **result)


if __name__ == "__main__":
    main()
