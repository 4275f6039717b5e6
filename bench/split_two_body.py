#!/usr/bin/python3
"""The split integrator ([integrator] method = "split") on bench/stability_map.py's two-body set-up.

    bench/split_two_body.py [--build build] [--end 0.1] [--macro-step 1e-3] [--keep DIR]

Two 1 kg point masses on the x axis: body 1 on a ground spring-damper (k0 = 200 N/m, d0 = 0.4 N s/m), body 2
coupled to body 1 by a spring-damper k = 1e4 .. 1e8 N/m, d = 10 N s/m (omega_c H = 0.14 .. 14 at H = 1 ms),
started at x1 = +1 mm, x2 = -1 mm. Each group (one body each) is its own IDA at rtol 1e-9, atol 1e-13.
Printed: the largest error of x1, x2 over the run against the closed form x(t) = Re(V exp(Lambda t) V^-1 x0)
(numpy, from the equations alone), relative to 1 mm, per exchange / extrapolation / correction and k; and
monolithic IDA at the same tolerances. A run that fails or takes longer than 60 s is "fail". About 1 minute.
Not part of stability_map.py's map: a diverging exchange makes each group's IDA take ever smaller steps, so
one unstable run can cost as much as the whole map.
"""
import argparse
import math
import pathlib
import subprocess
import tempfile

import h5py
import numpy as np

K0, D0, D, L = 200.0, 0.4, 10.0, 0.1
X0 = np.array([1e-3, -1e-3, 0.0, 0.0])
CASES = [
    ("Jacobi, p = 0", 'coupling_correction = false\nextrapolation = 0'),
    ("Jacobi, p = 1", 'coupling_correction = false'),
    ("Jacobi, p = 2", 'coupling_correction = false\nextrapolation = 2'),
    ("Gauss-Seidel, p = 0", 'coupling_correction = false\nextrapolation = 0\nexchange = "gauss-seidel"'),
    ("Gauss-Seidel, p = 1", 'coupling_correction = false\nexchange = "gauss-seidel"'),
    ("Jacobi, corrected", ''),
    ("Gauss-Seidel, corrected", 'exchange = "gauss-seidel"'),
]


def scene(k, integrator, end):
    return f"""[scene]
name = "split-two-body"
[[body]]
name = "ground"
type = "ground"
  [[body.marker]]
  name = "anchor"
  at = [{-L!r}, 0, 0]
[[body]]
name = "b1"
type = "point-mass"
mass = 1.0
position = [{X0[0]!r}, 0, 0]
  [[body.marker]]
  name = "c"
[[body]]
name = "b2"
type = "point-mass"
mass = 1.0
position = [{L + X0[1]!r}, 0, 0]
  [[body.marker]]
  name = "c"
[[force]]
name = "tie"
type = "spring-damper"
i = "b1.c"
j = "ground.anchor"
k = {K0!r}
d = {D0!r}
free_length = {L!r}
[[force]]
name = "coupling"
type = "spring-damper"
i = "b2.c"
j = "b1.c"
k = {k!r}
d = {D!r}
free_length = {L!r}
[clock]
end_time = {end!r}
[integrator]
rtol = 1e-9
atol = 1e-13
{integrator}
[output]
sample_rate_hz = 1000
markers = ["b1.c", "b2.c"]
bodies = false
forces = false
joints = false
"""


def exact(k, t):
    a = np.block([[np.zeros((2, 2)), np.eye(2)],
                  [-np.array([[K0 + k, -k], [-k, k]]), -np.array([[D0 + D, -D], [-D, D]])]])
    lam, v = np.linalg.eig(a)
    c = np.linalg.solve(v, X0.astype(complex))
    return np.real((v * c) @ np.exp(np.outer(lam, t))).T


def error(solve, work, k, integrator, end):
    toml, out = work / "run.toml", work / "run.h5"
    toml.write_text(scene(k, integrator, end))
    try:
        p = subprocess.run([str(solve), str(toml), "-o", str(out), "-q"], capture_output=True, timeout=60)
    except subprocess.TimeoutExpired:
        return math.inf
    if p.returncode != 0:
        return math.inf
    with h5py.File(out) as f:
        t = f["/time"][:]
        x1 = f["/markers/b1.c/position"][:, 0]
        x2 = f["/markers/b2.c/position"][:, 0] - L
    ex = exact(k, t)
    return max(np.abs(x1 - ex[:, 0]).max(), np.abs(x2 - ex[:, 1]).max()) / abs(X0[0])


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--build", default="build")
    ap.add_argument("--end", type=float, default=0.1)
    ap.add_argument("--macro-step", type=float, default=1e-3)
    ap.add_argument("--keep")
    a = ap.parse_args()
    solve = pathlib.Path(a.build) / "solve" / "solve"
    work = pathlib.Path(a.keep or tempfile.mkdtemp(prefix="split_two_body_"))
    work.mkdir(parents=True, exist_ok=True)
    ks = [1e4, 1e5, 1e6, 1e7, 1e8]
    h = a.macro_step
    print("| exchange | " + " | ".join(f"omega_c H = {math.sqrt(2 * k) * h:.2f}" for k in ks) + " |")
    print("|---" * (len(ks) + 1) + "|")
    fmt = lambda e: "fail" if not math.isfinite(e) else f"{e:.1e}"
    for name, keys in CASES:
        row = [error(solve, work, k, f'method = "split"\nmacro_step = {h!r}\n{keys}', a.end) for k in ks]
        print(f"| {name} | " + " | ".join(map(fmt, row)) + " |", flush=True)
    row = [error(solve, work, k, 'method = "ida"', a.end) for k in ks]
    print("| monolithic IDA | " + " | ".join(map(fmt, row)) + " |")


if __name__ == "__main__":
    main()
