#!/usr/bin/python3
"""postproc against SciPy on a long signal: time and peak memory of spectrum, 1/3-octave filter bank and order
analysis, each run as its own process on the same HDF5 file, side by side, with the ratio.

    /usr/bin/python3 bench/postproc_bench.py [--build BUILD_DIR] [--minutes 10] [--work DIR] [--keep]

The signal (written once, uncompressed, chunked): 10 minutes at 51.2 kHz (30.72 M samples) of a 4-stroke
run-up from 1000 to 6000 rpm: orders 0.5, 1, 2, 4 and 6 with speed-dependent amplitudes, a 1234 Hz tone and
white noise, with its crank angle (deg, unwrapped) beside it. postproc streams it in blocks of 2^20 samples;
the SciPy peer (bench/postproc_peer_scipy.py) reads it whole, as SciPy users do. Peak memory is the maximum
resident set size of each process (GNU time). The results are compared as a check that both
did the same work.
"""
import argparse
import os
import shutil
import subprocess
import sys
import tempfile
import time

import h5py
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
FS = 51200.0


def write_signal(path, minutes):
    n = int(minutes * 60 * FS)
    duration = n / FS
    f0, f1 = 1000 / 60, 6000 / 60  # rev/s
    rng = np.random.default_rng(1)
    with h5py.File(path, "w") as f:
        f.attrs["sample_rate_hz"] = FS
        x = f.create_dataset("signal", (n,), dtype="f8", chunks=(1 << 16,))
        x.attrs["unit"] = "m/s^2"
        a = f.create_dataset("crank_angle_deg", (n,), dtype="f8", chunks=(1 << 16,))
        for start in range(0, n, 1 << 20):
            t = np.arange(start, min(n, start + (1 << 20))) / FS
            theta = 2 * np.pi * (f0 * t + (f1 - f0) * t * t / (2 * duration))
            speed = (f0 + (f1 - f0) * t / duration) / f1
            v = np.zeros_like(t)
            for order, amp in ((0.5, 0.3), (1, 0.5), (2, 2.0), (4, 1.0), (6, 0.4)):
                v += amp * speed * np.cos(order * theta + order)
            v += 0.2 * np.sin(2 * np.pi * 1234.0 * t) + 0.05 * rng.standard_normal(len(t))
            x[start:start + len(t)] = v
            a[start:start + len(t)] = np.degrees(theta)
    return n


def run(command, env=None):
    """(wall s, CPU s = user + system, peak RSS MiB, stdout) of a command, measured by GNU time (the child's own
    figures: getrusage from this Python process would count the pages it inherits at fork)."""
    with tempfile.NamedTemporaryFile("w+", suffix=".time") as stats:
        start = time.perf_counter()
        proc = subprocess.run(["/usr/bin/time", "-o", stats.name, "-f", "%U %S %M"] + command, capture_output=True,
                              text=True, env=env)
        seconds = time.perf_counter() - start
        if proc.returncode != 0:
            sys.exit(f"failed: {' '.join(command)}\n{proc.stdout}{proc.stderr}")
        user, system, kib = stats.read().split()[-3:]
    return seconds, float(user) + float(system), float(kib) / 1024.0, proc.stdout


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--build", default=os.path.join(HERE, "..", "build"))
    p.add_argument("--minutes", type=float, default=10.0)
    p.add_argument("--work", default=None)
    p.add_argument("--keep", action="store_true")
    args = p.parse_args()
    exe = os.path.join(args.build, "postproc", "postproc")
    if not os.path.exists(exe):
        sys.exit(f"{exe} not found; build it: cmake --build {args.build} --target postproc")
    work = args.work or tempfile.mkdtemp(prefix="nvh_postproc_bench_")
    os.makedirs(work, exist_ok=True)
    signal = os.path.join(work, "signal.h5")
    t0 = time.perf_counter()
    n = write_signal(signal, args.minutes)
    print(f"signal: {n / 1e6:.2f} M samples at {FS:g} Hz ({n / FS / 60:.1f} min), run-up 1000-6000 rpm, "
          f"{os.path.getsize(signal) / 2**20:.0f} MiB, written in {time.perf_counter() - t0:.1f} s")

    stages = {
        "spectrum": ["spectrum", "--segment", "65536", "--window", "hann", "--type", "rms"],
        "octave": ["octave", "--fmin", "20", "--fmax", "10000"],
        "orders": ["orders", "--angle", "/crank_angle_deg", "--samples-per-cycle", "1024", "--max-order", "20"],
    }
    # The input's SHA-256 for the provenance is remembered in the file's attribute user.nvh.sha256 (common/
    # sha256.cpp): the first postproc run on a file computes it, later ones read it. Each stage is run both
    # ways: NVH_HASH_CACHE=0 (the digest computed: a file's first analysis) and with the digest remembered
    # (every later analysis of the same results file, as in the workflows).
    uncached = dict(os.environ, NVH_HASH_CACHE="0")
    base_uncached = run([exe, "stats", f"x={signal}:/signal", "-o", os.path.join(work, "baseline.h5"), "-q"],
                        env=uncached)
    time.sleep(1.1)  # a digest is remembered only for a file last modified over a second ago
    run([exe, "stats", f"x={signal}:/signal", "-o", os.path.join(work, "baseline.h5"), "-q"])  # remembers it
    base = run([exe, "stats", f"x={signal}:/signal", "-o", os.path.join(work, "baseline.h5"), "-q"])
    rows, checks, first = [], [], []
    for stage, options in stages.items():
        ours_h5 = os.path.join(work, f"ours_{stage}.h5")
        first.append(run([exe] + options[:1] + [f"x={signal}:/signal", "-o", ours_h5, "-q"] + options[1:],
                         env=uncached))
        ours = run([exe] + options[:1] + [f"x={signal}:/signal", "-o", ours_h5, "-q"] + options[1:])
        peer_npz = os.path.join(work, f"peer_{stage}.npz")
        peer = run(["/usr/bin/python3", os.path.join(HERE, "postproc_peer_scipy.py"), signal, peer_npz, stage])
        rows.append((stage, ours, peer))
        ref = np.load(peer_npz)
        with h5py.File(ours_h5, "r") as f:
            if stage == "spectrum":
                ours_rms = f["spectrum/x/amplitude"][()]
                big = ref["rms"] > 1e-3 * ref["rms"].max()
                checks.append(f"spectrum: largest relative difference of the RMS spectrum (bins above -60 dB) "
                              f"{np.max(np.abs(ours_rms[big] / ref['rms'][big] - 1)):.1e}")
            elif stage == "octave":
                ours_db = f["octave/x/level_db"][()]
                ref_db = 20 * np.log10(np.sqrt(ref["mean_square"]) / 1e-6)
                checks.append(f"octave: largest band level difference {np.max(np.abs(ours_db - ref_db)):.1e} dB "
                              f"over {len(ref_db)} bands")
            else:
                amp = f["orders/x/amplitude"][()]
                c = min(len(amp), len(ref["amplitude"]))
                diff = np.abs(amp[:c] - ref["amplitude"][:c]).max() / ref["amplitude"].max()
                checks.append(f"orders: {c} cycles x {amp.shape[1]} orders, largest amplitude difference "
                              f"{diff:.1e} of the largest amplitude")

    print(f"\n{'':10s} {'postproc':>24s} {'SciPy':>24s} {'SciPy / postproc':>20s} {'first analysis of the file':>30s}")
    print(f"{'stage':10s} {'wall s':>8s} {'CPU s':>7s} {'MiB':>7s} {'wall s':>8s} {'CPU s':>7s} {'MiB':>7s} "
          f"{'wall':>9s} {'CPU':>9s} {'CPU s':>10s} {'SciPy/ours CPU':>16s}")
    total = np.zeros(5)
    for (stage, ours, peer), once in zip(rows, first):
        words = peer[3].split()
        peer_wall, peer_cpu = float(words[1]), float(words[3])  # the peer's own timing: reading + analysis
        total += (ours[0], ours[1], peer_wall, peer_cpu, once[1])
        print(f"{stage:10s} {ours[0]:8.2f} {ours[1]:7.2f} {ours[2]:7.0f} {peer_wall:8.2f} {peer_cpu:7.2f} "
              f"{peer[2]:7.0f} {peer_wall / ours[0]:8.1f}x {peer_cpu / ours[1]:8.1f}x {once[1]:10.2f} "
              f"{peer_cpu / once[1]:15.1f}x")
    print(f"{'total':10s} {total[0]:8.2f} {total[1]:7.2f} {'':7s} {total[2]:8.2f} {total[3]:7.2f} {'':7s} "
          f"{total[2] / total[0]:8.1f}x {total[3] / total[1]:8.1f}x {total[4]:10.2f} {total[3] / total[4]:15.1f}x")
    print(f"{'baseline':10s} {base[0]:8.2f} {base[1]:7.2f} {base[2]:7.0f}   (postproc stats: start, reading; "
          f"{base_uncached[1]:.2f} s CPU with the SHA-256 computed)")
    analysis = total[1] - len(rows) * base[1]
    print(f"analysis alone (postproc CPU minus the baseline per stage): {analysis:.2f} s, "
          f"SciPy / postproc {total[3] / analysis:.1f}x")
    print("postproc: the whole process (start, the input's SHA-256 for provenance - remembered, or computed in the\n"
          "last columns -, reading, analysis, writing);\n"
          "SciPy: reading and analysis (interpreter start and imports excluded). CPU time is the fairer figure\n"
          "on a loaded machine; MiB is the peak resident set size.")
    print("\nsame work:")
    for c in checks:
        print("  " + c)
    if not args.keep and not args.work:
        shutil.rmtree(work)


if __name__ == "__main__":
    main()
