#!/usr/bin/env python3
"""Peer check of bench_condense_beam's eigen-solve with SciPy.

Reads DIR/K.mtx, DIR/M.mtx (free-DOF stiffness and mass, Matrix Market) and DIR/bench.json (written by
`bench_condense_beam --export DIR`), solves the same problem K x = lambda M x for the same number of
lowest modes with the same shift, scipy.sparse.linalg.eigsh(K, k, M=M, sigma, which='LM') (ARPACK
shift-invert mode 3 on a SuperLU factorization of K - sigma M), and prints both times, their ratio and the
largest relative difference of the elastic frequencies.

usage: peer_scipy_eigsh.py DIR [--repeat N]
"""
import argparse
import json
import os
import sys
import time

import numpy as np
import scipy
import scipy.io
import scipy.sparse.linalg as sla


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("dir", help="directory written by bench_condense_beam --export")
    parser.add_argument("--repeat", type=int, default=1, help="run eigsh N times, report the fastest")
    args = parser.parse_args()

    with open(os.path.join(args.dir, "bench.json")) as f:
        meta = json.load(f)
    t0 = time.perf_counter()
    K = scipy.io.mmread(os.path.join(args.dir, "K.mtx")).tocsc()
    M = scipy.io.mmread(os.path.join(args.dir, "M.mtx")).tocsc()
    read_seconds = time.perf_counter() - t0
    k = int(meta["k"])
    rigid = int(meta["rigid_body_modes"])
    shift = float(meta["shift"])  # our sigma = -shift (< 0)
    ours = np.asarray(meta["frequencies_hz"], dtype=float)

    best = None
    for _ in range(max(1, args.repeat)):
        t0 = time.perf_counter()
        lam = sla.eigsh(K, k=k, M=M, sigma=-shift, which="LM", return_eigenvectors=False)
        seconds = time.perf_counter() - t0
        best = seconds if best is None else min(best, seconds)
    lam = np.sort(lam)
    theirs = np.sqrt(np.clip(lam, 0.0, None)) / (2.0 * np.pi)

    elastic = slice(rigid, k)
    rel = np.abs(theirs[elastic] - ours[elastic]) / ours[elastic]
    worst = int(np.argmax(rel)) + rigid
    ratio = best / meta["seconds"]

    print(f"peer: scipy {scipy.__version__}, numpy {np.__version__}; {K.shape[0]} DOF, k = {k} modes, "
          f"sigma = {-shift:.6g} rad^2/s^2 (matrices read in {read_seconds:.2f} s)")
    print()
    print(f"  {'':34s} {'ours (' + meta['backend'] + ')':>16s} {'SciPy eigsh':>14s}")
    print(f"  {'eigen-solve wall [s]':34s} {meta['seconds']:16.3f} {best:14.3f}")
    print(f"  {'ratio SciPy / ours':34s} {'':16s} {ratio:14.2f}")
    print(f"  {'first elastic mode [Hz]':34s} {ours[rigid]:16.6f} {theirs[rigid]:14.6f}")
    print(f"  {'last mode [Hz]':34s} {ours[-1]:16.6f} {theirs[-1]:14.6f}")
    print(f"  {'largest rigid-body mode [Hz]':34s} {ours[rigid - 1]:16.3g} {theirs[rigid - 1]:14.3g}")
    print(f"  {'max relative difference (elastic)':34s} {rel.max():16.2e}   (mode {worst + 1}, "
          f"{ours[worst]:.6g} Hz)")
    return 0 if rel.max() < 1e-6 else 1


if __name__ == "__main__":
    sys.exit(main())
