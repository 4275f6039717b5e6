#!/usr/bin/python3
"""A measured stability map of solve's time integrators (issue 16, item 2).

    bench/stability_map.py [--build /work/wt-stab/build] [--out docs/img/stability_map.png] [--jobs 2]
                           [--keep DIR] [--quick]

Every number comes from runs of the `solve` executable on scenes written here (a temporary directory, or
--keep DIR), read back with h5py, against references computed here with numpy from the equations alone:

(a) Two point masses (1 kg each) on the x axis: body 1 tied to ground softly (k0 = 200 N/m, d0 = 0.4 N s/m),
    body 2 coupled to body 1 by a linear spring-damper (k = 1e4 .. 1e8 N/m, d = 10 N s/m: the coupling mode's
    damping ratio falls from 0.07 to 0.0007 as k rises) - and a variant where the coupling is a `contact`
    (linear law, exponent 1, restitution 1, preloaded closed by a spring-damper with k = 0, d = 10 and a
    preload, so the equations are the same linear ones). Swept: the step h (omega_high h = 0.01 .. 100, 13
    steps) x k x the method: IDA with max_order = 1 .. 5 and the step forced (max_step = initial_step = h,
    tolerances so loose that the error test never rejects: rtol 0.5, atol 1 against motions of 1e-5 m), and
    generalized-alpha at a fixed step (adaptive = false) with rho_inf = 0, 0.5, 0.8, 1.
    Measured per run: the growth per step of each mode's amplitude (the state projected on the modes of the
    exact system: a linear method keeps the modes apart, so each modal amplitude is a geometric sequence once
    the start-up has died away) - unstable if any mode grows (> 1 + 1e-9 per step) or the run fails - and the
    largest error of x1, x2 over 20 periods of the coupling mode (at least one step) against the closed form
    x(t) = Re(V exp(Lambda t) V^-1 x0) of the 2-DOF system, relative to the largest exact displacement.
    Theory: a mode with eigenvalue lambda is stable under BDF-k if every root xi of
        sum_{j=1..k} (1/j) (1 - 1/xi)^j = lambda h
    has |xi| <= 1; under generalized-alpha (Jansen-Whiting-Hulbert, the scheme solve implements) if every
    root of det(B - xi A) = 0 (below, jwh_roots) does.
(b) BDF-3, 4, 5 on an undamped oscillator (1 kg, 100 N/m): the amplitude ratio per period measured with IDA
    (max_order = k, the step forced as above) against |xi_max(i w h)|^(2 pi / (w h)) from the roots above.
    IDA chooses its order itself (up to max_order); the results' steps_at_order_k say which it used.
(c) Generalized-alpha's spectral radius per step measured on the same oscillator, against the closed form
    of the scheme solve implements (Jansen, Whiting & Hulbert 2000, first-order form) and, for comparison,
    Chung & Hulbert's (1993) second-order algorithm at the same rho_inf.

Each map run lasts 20 periods of the coupling mode or 300 steps, whichever is longer; an instability that
grows from round-off by less than about 1 % per step may not show within it (docs/verification.md).
Writes the figure (panels a, b, c) and prints the tables: 1073 runs, about 1 minute on 2 cores (--quick: 387).
"""
import argparse
import concurrent.futures as cf
import math
import subprocess
import sys
import tempfile
from pathlib import Path

import h5py
import numpy as np

ROOT = Path(__file__).resolve().parent.parent
TWO_PI = 2 * math.pi

# ------------------------------------------------------------------ theory


def bdf_roots(k, z):
    """Roots xi of sum_{j=1..k} (1/j) (1 - u)^j - z = 0, u = 1/xi (BDF-k on y' = lambda y, z = lambda h)."""
    p = np.zeros(k + 1, complex)  # coefficients in u, ascending
    for j in range(1, k + 1):
        p[: j + 1] += np.polynomial.polynomial.polypow([1.0, -1.0], j) / j
    p[0] -= z
    u = np.roots(p[::-1])
    return 1.0 / u


def bdf_radius(k, z):
    return float(np.max(np.abs(bdf_roots(k, z))))


def jwh_params(rho):
    am = (3 - rho) / (2 * (1 + rho))
    af = 1 / (1 + rho)
    return am, af, 0.5 + am - af


def jwh_roots(z, rho):
    """Generalized-alpha of Jansen, Whiting & Hulbert (2000) on y' = lambda y, z = lambda h:
        y1 = y0 + h v0 + h gamma (v1 - v0),   v0 + am (v1 - v0) = lambda (y0 + af (y1 - y0)),
    a 2 x 2 map [y0, h v0] -> [y1, h v1] whose roots xi solve det(B - xi A) = 0,
        A = [[1, -gamma], [-af z, am]],  B = [[1, 1 - gamma], [(1 - af) z, -(1 - am)]]:
        (am - gamma af z) xi^2 + (1 - 2 am - z ((1 - gamma) af + gamma (1 - af))) xi
          - (1 - am) - z (1 - gamma)(1 - af) = 0
    (the eigenvalues of A^-1 B, computed here with numpy)."""
    am, af, g = jwh_params(rho)
    a = np.array([[1, -g], [-z * af, am]], complex)
    b = np.array([[1, 1 - g], [z * (1 - af), -(1 - am)]], complex)
    return np.linalg.eigvals(np.linalg.solve(a, b))


def jwh_radius(z, rho):
    return float(np.max(np.abs(jwh_roots(z, rho))))


def chung_hulbert_radius(wh, rho):
    """Chung & Hulbert (J. Appl. Mech. 60, 1993) second-order generalized-alpha on x'' + w^2 x = 0:
    alpha_m = (2 rho - 1)/(rho + 1), alpha_f = rho/(rho + 1), gamma = 1/2 - alpha_m + alpha_f,
    beta = (1 - alpha_m + alpha_f)^2 / 4; the spectral radius of its 3 x 3 amplification matrix."""
    am, af = (2 * rho - 1) / (rho + 1), rho / (rho + 1)
    g, b = 0.5 - am + af, 0.25 * (1 - am + af) ** 2
    w2 = wh * wh
    lhs = np.array([[w2 * (1 - af), 0, 1 - am], [1, 0, -b], [0, 1, -g]])
    rhs = np.array([[-w2 * af, 0, -am], [1, 1, 0.5 - b], [0, 1, 1 - g]])
    return float(np.max(np.abs(np.linalg.eigvals(np.linalg.solve(lhs, rhs)))))


def method_radius(method, z):
    kind, par = method
    return bdf_radius(par, z) if kind == "ida" else jwh_radius(z, par)


# ------------------------------------------------------------------ the 2-DOF system

M1, M2 = 1.0, 1.0
K0, D0 = 200.0, 0.4        # soft tie of body 1 to ground
D = 10.0                   # coupling damper
L = 1e-2                   # m: free lengths. A length L + x rounds x to eps L (2e-13 of U0); shorter springs
                           # flip direction when a large step's predictor overshoots by L (seen at L = 1e-4)
U0 = 1e-5                  # m: initial displacement of body 2 from equilibrium
DELTA0 = 1e-3              # m: the contact's static penetration (variant "contact"): 100 U0, so that no
                           # predictor or Newton iterate opens it
STIFFNESSES = [1e4, 1e5, 1e6, 1e7, 1e8]
WH = np.logspace(-2, 2, 13)
METHODS = [("ida", 1), ("ida", 2), ("ida", 3), ("ida", 4), ("ida", 5),
           ("ga", 0.0), ("ga", 0.5), ("ga", 0.8), ("ga", 1.0)]
GROWTH_LIMIT = 1e-9        # per step: above it a mode grows


def label(method):
    kind, par = method
    return f"IDA max_order {par}" if kind == "ida" else f"g-alpha rho_inf {par:g}"


def state_matrix(k):
    mass = np.diag([M1, M2])
    stiff = np.array([[K0 + k, -k], [-k, k]])
    damp = np.array([[D0 + D, -D], [-D, D]])
    minv = np.linalg.inv(mass)
    return np.block([[np.zeros((2, 2)), np.eye(2)], [-minv @ stiff, -minv @ damp]])


class Modes:
    """Eigen-decomposition of the 2-DOF state matrix: s(t) = V exp(Lambda t) V^-1 s0 (modal superposition)."""

    def __init__(self, k):
        self.a = state_matrix(k)
        lam, vec = np.linalg.eig(self.a)
        self.lam, self.vec, self.inv = lam, vec, np.linalg.inv(vec)
        up = [i for i in range(4) if lam[i].imag > 0]
        up.sort(key=lambda i: abs(lam[i]))
        self.low, self.high = up  # the indices of the soft mode and the coupling mode (Im > 0 of each pair)
        self.w_high = abs(lam[self.high])
        self.zeta = [-lam[i].real / abs(lam[i]) for i in (self.low, self.high)]

    def exact(self, s0, t):
        c = self.inv @ s0
        return np.real(self.vec @ (c[:, None] * np.exp(np.outer(self.lam, t))))

    def amplitudes(self, s):
        q = self.inv @ s
        return np.abs(q[self.low]), np.abs(q[self.high])


def initial_state():
    # x1, x2 (from equilibrium), v1, v2: both modes excited
    return np.array([0.0, U0, math.sqrt(K0 / (M1 + M2)) * U0, 0.0])


def integrator_text(method, h):
    kind, par = method
    if kind == "ida":
        return (f"[integrator]\nmethod = \"ida\"\nmax_order = {par}\nmax_step = {h!r}\ninitial_step = {h!r}\n"
                "rtol = 0.5\natol = 1.0\njacobian_cj_change = 1e-6\n")
    # generalized-alpha's tolerances only end Newton: tight, so that every step is solved to round-off
    return (f"[integrator]\nmethod = \"generalized-alpha\"\nstep = {h!r}\nadaptive = false\nrho_inf = {par!r}\n"
            "rtol = 1e-9\natol = 1e-10\n")


def two_body_scene(variant, k, method, h, end_time):
    s0 = initial_state()
    head = f"""[scene]
name = "stability-{variant}"
[[body]]
name = "ground"
type = "ground"
  [[body.marker]]
  name = "anchor"
  at = [{-L!r}, 0, 0]
[[body]]
name = "b1"
type = "point-mass"
mass = {M1!r}
position = [{s0[0]!r}, 0, 0]
velocity = [{s0[2]!r}, 0, 0]
  [[body.marker]]
  name = "c"
  z = [1, 0, 0]
[[body]]
name = "b2"
type = "point-mass"
mass = {M2!r}
position = [{L + s0[1]!r}, 0, 0]
velocity = [{s0[3]!r}, 0, 0]
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
"""
    if variant == "spring":
        coupling = f"""[[force]]
name = "coupling"
type = "spring-damper"
i = "b2.c"
j = "b1.c"
k = {k!r}
d = {D!r}
free_length = {L!r}
"""
    else:  # a linear contact, closed by a preload: gap = x2 - x1 - L - DELTA0 = -DELTA0 at equilibrium
        coupling = f"""[[force]]
name = "coupling"
type = "contact"
i = "b2.c"
j = "b1.c"
stiffness = {k!r}
exponent = 1.0
restitution = 1.0
clearance = {-(L + DELTA0)!r}
[[force]]
name = "damper"
type = "spring-damper"
i = "b2.c"
j = "b1.c"
d = {D!r}
free_length = {L!r}
preload = {k * DELTA0!r}
"""
    tail = f"""[clock]
end_time = {end_time!r}
{integrator_text(method, h)}[output]
sample_rate_hz = {1 / h!r}
markers = ["b1.c", "b2.c"]
bodies = false
forces = false
joints = false
"""
    return head + coupling + tail


def oscillator_scene(method, h, end_time, w):
    """1 kg on a bushing to ground (k = w^2 along x, nothing else), started 1e-5 m out: an undamped
    oscillator. A bushing, not a spring: its force is -k x from the displacement itself, so the motion keeps
    its relative precision however small it gets (a spring's length L + x rounds x to eps L)."""
    return f"""[scene]
name = "oscillator"
[[body]]
name = "ground"
type = "ground"
  [[body.marker]]
  name = "anchor"
[[body]]
name = "m"
type = "point-mass"
mass = 1.0
position = [{U0!r}, 0, 0]
  [[body.marker]]
  name = "c"
[[force]]
name = "k"
type = "bushing"
i = "m.c"
j = "ground.anchor"
stiffness = [{w * w!r}, 0, 0, 0, 0, 0]
damping = [0, 0, 0, 0, 0, 0]
[clock]
end_time = {end_time!r}
{integrator_text(method, h)}[output]
sample_rate_hz = {1 / h!r}
markers = ["m.c"]
bodies = false
forces = false
joints = false
"""


# ------------------------------------------------------------------ running


def run_solve(solve, workdir, name, text):
    toml = workdir / f"{name}.toml"
    out = workdir / f"{name}.h5"
    toml.write_text(text)
    p = subprocess.run([str(solve), str(toml), "-o", str(out), "-q"], capture_output=True, text=True)
    result = {"ok": p.returncode == 0, "message": (p.stderr or p.stdout).strip().splitlines()[-1:] or [""]}
    if not out.exists():
        return result
    with h5py.File(out, "r") as f:
        result["status"] = str(f.attrs.get("status", b""), "utf-8") if isinstance(f.attrs.get("status"), bytes) \
            else str(f.attrs.get("status"))
        result["t"] = f["time"][:]
        result["markers"] = {m: (f[f"markers/{m}/position"][:, 0], f[f"markers/{m}/velocity"][:, 0])
                             for m in f["markers"]}
        result["stats"] = {k: v.item() if hasattr(v, "item") else v for k, v in f["solver/statistics"].attrs.items()}
    if result["ok"]:
        out.unlink()  # keep the scene, drop the results (they can be remade)
    return result


def growth_per_step(amp, floor=1e-10):
    """Geometric growth per sample of a modal amplitude: a least-squares line through log(amp) over the late
    half of the samples above floor * max(amp) (the start-up and the parasitic roots have died away there;
    below the floor round-off takes over). A mode that decays first (at the low orders of IDA's start, say)
    and grows again from its minimum is measured on the late half of that regrowth."""
    amp = np.asarray(amp, float)
    if amp.size < 3:
        return math.nan
    if not np.all(np.isfinite(amp)):
        return math.inf
    top = np.max(amp)
    if top == 0:
        return 0.0
    i_min = int(np.argmin(amp))
    if amp.size - i_min > 10 and amp[-1] > 100 * floor * top and amp[-1] > 10 * amp[i_min]:
        na, nb = i_min + (amp.size - i_min) // 2, amp.size - 1
    else:
        below = np.flatnonzero(amp <= floor * top)
        nb = (below[0] - 1) if below.size else amp.size - 1
        if nb < 2:
            return 0.0  # gone within two steps: strongly damped
        na = nb // 2
    n = np.arange(na, nb + 1)
    slope = np.polyfit(n, np.log(np.maximum(amp[na:nb + 1], 1e-300)), 1)[0]
    return float(math.exp(slope))


def order_fraction(stats, k):
    steps = [int(stats.get(f"steps_at_order_{j}", 0)) for j in range(1, 6)]
    total = sum(steps)
    return steps[k - 1] / total if total else math.nan, steps


# ------------------------------------------------------------------ (a) the map


def map_jobs(variant, stiffnesses, whs):
    jobs = []
    for k in stiffnesses:
        modes = Modes(k)
        t_err = 20 * TWO_PI / modes.w_high
        for wh in whs:
            h = wh / modes.w_high
            end = max(t_err, 300 * h)
            for method in METHODS:
                jobs.append(dict(variant=variant, k=k, wh=wh, h=h, end=end, t_err=t_err, method=method))
    return jobs


def evaluate_map_run(job, res):
    modes = Modes(job["k"])
    out = dict(job)
    out["failed"] = not res["ok"] or res.get("status") != "complete"
    out["message"] = res["message"][0] if res["message"] else ""
    out["stats"] = res.get("stats", {})
    # theory: the largest root over both modes
    z = [modes.lam[modes.low] * job["h"], modes.lam[modes.high] * job["h"]]
    out["theory"] = max(method_radius(job["method"], zz) for zz in z)
    if "t" not in res or len(res["t"]) < 2:
        out.update(growth=(math.inf, math.inf), error=math.inf, unstable=True)
        return out
    t = res["t"]
    x1, v1 = res["markers"]["b1.c"]
    x2, v2 = res["markers"]["b2.c"]
    s = np.vstack([x1, x2 - L, v1, v2])
    if not np.all(np.isfinite(s)):
        out.update(growth=(math.inf, math.inf), error=math.inf, unstable=True)
        return out
    lo, hi = modes.amplitudes(s)
    g = (growth_per_step(lo, floor=1e-10), growth_per_step(hi, floor=1e-10))
    out["growth"] = g
    exact = modes.exact(initial_state(), t)
    n = max(2, int(np.searchsorted(t, job["t_err"] * (1 + 1e-9), side="right")))
    err = np.max(np.abs(s[:2, :n] - exact[:2, :n]))
    out["error"] = float(err / np.max(np.abs(exact[:2, :n])))
    out["unstable"] = out["failed"] or any(gg > 1 + GROWTH_LIMIT for gg in g if not math.isnan(gg))
    return out


# ------------------------------------------------------------------ (b), (c) the oscillator

W_OSC = 10.0            # rad/s
OSC_STEPS = 400


def oscillator_jobs(methods, whs):
    return [dict(method=m, wh=wh, h=wh / W_OSC, end=OSC_STEPS * wh / W_OSC) for m in methods for wh in whs]


def evaluate_oscillator_run(job, res):
    out = dict(job)
    out["failed"] = not res["ok"] or res.get("status") != "complete"
    out["stats"] = res.get("stats", {})
    if "t" not in res:
        out["radius"] = math.nan
        return out
    x, v = res["markers"]["m.c"]
    amp = np.hypot(x, v / W_OSC)  # the modal amplitude of an undamped oscillator
    out["radius"] = growth_per_step(amp, floor=1e-250)
    return out


# ------------------------------------------------------------------ main


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--build", default="/work/wt-stab/build", help="build directory with solve/solve")
    ap.add_argument("--out", default=str(ROOT / "docs/img/stability_map.png"))
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--keep", help="write the scenes here and keep them (default: a temporary directory)")
    ap.add_argument("--quick", action="store_true", help="fewer points (a check of the script)")
    args = ap.parse_args()
    solve = Path(args.build) / "solve" / "solve"
    if not solve.exists():
        sys.exit(f"no solve executable at {solve}")

    stiff = STIFFNESSES[::2] if args.quick else STIFFNESSES
    whs = WH[::2] if args.quick else WH
    contact_stiff = [1e5, 1e7] if args.quick else [1e4, 1e6, 1e8]
    osc_wh = np.logspace(math.log10(0.05), math.log10(20), 12 if args.quick else 23)
    ga_wh = np.logspace(-2, 2, 9 if args.quick else 17)

    tmp = None
    if args.keep:
        work = Path(args.keep)
        work.mkdir(parents=True, exist_ok=True)
    else:
        tmp = tempfile.TemporaryDirectory(prefix="stability_map_")
        work = Path(tmp.name)

    tasks = []  # (kind, job, name, text)
    for i, job in enumerate(map_jobs("spring", stiff, whs) + map_jobs("contact", contact_stiff, whs)):
        tasks.append(("map", job, f"map{i:04d}",
                      two_body_scene(job["variant"], job["k"], job["method"], job["h"], job["end"])))
    bdf = [("ida", 3), ("ida", 4), ("ida", 5)]
    ga = [("ga", r) for r in (0.0, 0.5, 0.8, 1.0)]
    for i, job in enumerate(oscillator_jobs(bdf, osc_wh) + oscillator_jobs(ga, ga_wh)):
        tasks.append(("osc", job, f"osc{i:04d}", oscillator_scene(job["method"], job["h"], job["end"], W_OSC)))

    print(f"{len(tasks)} runs of {solve} in {work} ({args.jobs} at a time)", flush=True)
    results = {"map": [], "osc": []}
    with cf.ThreadPoolExecutor(max_workers=args.jobs) as pool:
        futures = {pool.submit(run_solve, solve, work, name, text): (kind, job) for kind, job, name, text in tasks}
        for n, fut in enumerate(cf.as_completed(futures), 1):
            kind, job = futures[fut]
            res = fut.result()
            ev = evaluate_map_run(job, res) if kind == "map" else evaluate_oscillator_run(job, res)
            results[kind].append(ev)
            if n % 100 == 0:
                print(f"  {n}/{len(tasks)}", flush=True)

    report_map(results["map"], stiff, contact_stiff)
    bdf_rows = report_bdf([r for r in results["osc"] if r["method"][0] == "ida"])
    ga_rows = report_ga([r for r in results["osc"] if r["method"][0] == "ga"])
    plot(args.out, results["map"], stiff, whs, bdf_rows, ga_rows)
    print(f"wrote {args.out}")
    if tmp:
        tmp.cleanup()


# ------------------------------------------------------------------ tables


def theory_bands(method, k, lo=1e-3, hi=1e3, n=4001):
    """Theory: the omega_high h intervals (within [lo, hi]) where a mode of the 2-DOF system grows."""
    modes = Modes(k)
    grid = np.logspace(math.log10(lo), math.log10(hi), n)
    bad = np.array([max(method_radius(method, modes.lam[i] * wh / modes.w_high) for i in (modes.low, modes.high))
                    > 1 + 1e-12 for wh in grid])
    bands, i = [], 0
    while i < n:
        if bad[i]:
            j = i
            while j + 1 < n and bad[j + 1]:
                j += 1
            bands.append((grid[i], grid[j] if j + 1 < n else math.inf))
            i = j + 1
        else:
            i += 1
    return bands


def verdict_char(r):
    """. stable (theory too)  x unstable (theory too)  ! unstable, theory stable  o stable, theory unstable
    F the run failed"""
    if r["failed"]:
        return "F"
    theory_unstable = r["theory"] > 1 + 1e-12
    if r["unstable"]:
        return "x" if theory_unstable else "!"
    return "o" if theory_unstable else "."


def report_map(rows, stiff, contact_stiff):
    print("\n(a) two bodies; per method and coupling stiffness k, one character per step of the grid")
    print("    (. stable, as theory; x unstable, as theory; ! unstable, theory stable; o stable, theory unstable;")
    print("     F failed). 'stable to': the largest step of the grid below which every step ran stable;")
    print("    theory: the w h bands where the fixed-order method's roots grow (BDF-k; JWH generalized-alpha);")
    print("    IDA < 90 %: the smallest w h where IDA took fewer than 90 % of its steps at max_order")
    for variant, ks in (("spring", stiff), ("contact", contact_stiff)):
        sel = [r for r in rows if r["variant"] == variant]
        if not sel:
            continue
        whs = sorted({r["wh"] for r in sel})
        print(f"\n  variant: {variant}; w h grid: " + " ".join(f"{w:.3g}" for w in whs))
        print(f"  {'method':22s} {'k N/m':>6s} {'zeta_c':>7s} {'verdicts':>{len(whs)}s} {'stable to w h':>13s}"
              f" {'= h s':>9s} {'theory unstable w h':>24s} {'err<1% to w h':>13s} {'IDA < 90 %':>10s}")
        for method in METHODS:
            for k in ks:
                rr = sorted([r for r in sel if r["method"] == method and r["k"] == k], key=lambda r: r["wh"])
                if not rr:
                    continue
                modes = Modes(k)
                stable_to = None
                for r in rr:
                    if r["unstable"]:
                        break
                    stable_to = r
                acc_to = None
                for r in rr:
                    if r["error"] >= 0.01 or r["unstable"]:
                        break
                    acc_to = r["wh"]
                bands = theory_bands(method, k)
                theory = ", ".join(f"{a:.3g}-{b:.3g}" for a, b in bands) or "none"
                low = "-"
                if method[0] == "ida":
                    lows = [r["wh"] for r in rr if r["stats"] and order_fraction(r["stats"], method[1])[0] < 0.9]
                    low = f"{lows[0]:.3g}" if lows else "never"
                st_wh = "all" if stable_to is rr[-1] else (f"{stable_to['wh']:.3g}" if stable_to else "none")
                st_h = f"{stable_to['h']:.3g}" if stable_to and stable_to is not rr[-1] else ("-" if not stable_to else
                                                                                           f">={rr[-1]['h']:.3g}")
                print(f"  {label(method):22s} {k:6.0e} {modes.zeta[1]:7.4f} {''.join(verdict_char(r) for r in rr)} "
                      f"{st_wh:>13s} {st_h:>9s} {theory:>24s} {(f'{acc_to:.3g}' if acc_to else 'none'):>13s} {low:>10s}")
        counts = {}
        for r in sel:
            c = verdict_char(r)
            fam = "IDA" if r["method"][0] == "ida" else "g-alpha"
            counts.setdefault(fam, {}).setdefault(c, 0)
            counts[fam][c] += 1
        for fam, c in counts.items():
            print(f"  {fam}: " + ", ".join(f"{n} '{ch}'" for ch, n in sorted(c.items())))
        ida = [r for r in sel if r["method"][0] == "ida" and r["method"][1] >= 3 and r["stats"]]
        for ch in ("o", "x"):
            pts = [r for r in ida if verdict_char(r) == ch]
            low = sum(order_fraction(r["stats"], r["method"][1])[0] < 0.9 for r in pts)
            print(f"  IDA max_order 3-5, '{ch}': {len(pts)} runs, {low} of them with < 90 % of the steps at max_order")
    # the contact variant against the spring variant, run by run
    pairs = {}
    for r in rows:
        pairs.setdefault((r["k"], r["wh"], r["method"]), {})[r["variant"]] = r
    both = [p for p in pairs.values() if len(p) == 2]
    if both:
        same = sum(p["spring"]["unstable"] == p["contact"]["unstable"] for p in both)
        ok = [p for p in both if not p["spring"]["unstable"] and not p["contact"]["unstable"]]
        derr = max((abs(p["spring"]["error"] - p["contact"]["error"]) / max(p["spring"]["error"], 1e-300)
                    for p in ok), default=math.nan)
        print(f"\n  contact against spring, same k, step and method: same verdict in {same} of {len(both)} runs; "
              f"largest relative difference of their errors where both are stable {derr:.2g}")
    fails = [r for r in rows if r["failed"]]
    print(f"\n  failed runs: {len(fails)}" + "".join(f"\n    {r['variant']} {label(r['method'])} k {r['k']:.0e} "
                                                    f"w h {r['wh']:.3g}: {r['message']}" for r in fails[:10]))
    rej = [r for r in rows if r["stats"] and int(r["stats"].get("rejected_steps", 0)) > 0]
    print(f"  runs with rejected steps (the forced step not held): {len(rej)}")


def report_bdf(rows):
    print("\n(b) BDF-k on an undamped oscillator (IDA, max_order = k, step forced): amplitude ratio per period")
    print(f"  {'k':>2s} {'w h':>7s} {'measured':>13s} {'theory BDF-k':>13s} {'rel. diff':>10s} {'steps at order 1..5':>24s}")
    out = []
    worst = {}
    for r in sorted(rows, key=lambda r: (r["method"][1], r["wh"])):
        k = r["method"][1]
        per_period = TWO_PI / r["wh"]
        theory = bdf_radius(k, 1j * r["wh"]) ** per_period
        meas = r["radius"] ** per_period if r["radius"] == r["radius"] else math.nan
        frac, steps = order_fraction(r["stats"], k) if r["stats"] else (math.nan, [])
        held = frac >= 0.95
        diff = (meas - theory) / theory
        if held:
            worst[k] = max(worst.get(k, 0.0), abs(diff))
        out.append(dict(k=k, wh=r["wh"], measured=meas, theory=theory, held=held, steps=steps))
        print(f"  {k:2d} {r['wh']:7.3g} {meas:13.8g} {theory:13.8g} {diff:10.2e} {str(steps):>24s}"
              + ("" if held else "  <- IDA left order k"))
    for k in sorted(worst):
        print(f"  BDF-{k}: largest relative difference where IDA held order {k} (>= 95 % of steps): {worst[k]:.2e}")
    return out


def report_ga(rows):
    print("\n(c) generalized-alpha on an undamped oscillator: spectral radius per step")
    print(f"  {'rho_inf':>7s} {'w h':>8s} {'measured':>14s} {'JWH (solve)':>14s} {'Chung-Hulbert':>14s} {'meas-JWH':>10s}")
    out = []
    worst = {}
    for r in sorted(rows, key=lambda r: (r["method"][1], r["wh"])):
        rho = r["method"][1]
        jwh = jwh_radius(1j * r["wh"], rho)
        ch = chung_hulbert_radius(r["wh"], rho)
        d = r["radius"] - jwh
        worst[rho] = max(worst.get(rho, 0.0), abs(d))
        out.append(dict(rho=rho, wh=r["wh"], measured=r["radius"], jwh=jwh, ch=ch))
        print(f"  {rho:7.2g} {r['wh']:8.3g} {r['radius']:14.10f} {jwh:14.10f} {ch:14.10f} {d:10.1e}")
    for rho in sorted(worst):
        print(f"  rho_inf {rho:g}: largest |measured - JWH| {worst[rho]:.1e}")
    return out


# ------------------------------------------------------------------ figure


def plot(path, rows, stiff, whs, bdf_rows, ga_rows):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.colors import LogNorm

    fig = plt.figure(figsize=(17, 13.5))
    gs = fig.add_gridspec(3, 5, height_ratios=[1, 1, 1.25], hspace=0.42, wspace=0.28)
    sel = [r for r in rows if r["variant"] == "spring"]
    norm = LogNorm(1e-6, 1)
    kk = np.logspace(math.log10(min(stiff)) - 0.25, math.log10(max(stiff)) + 0.25, 41)
    wg = np.logspace(-2.2, 2.2, 177)
    sc = None
    for i, method in enumerate(METHODS):
        ax = fig.add_subplot(gs[i // 5, i % 5])
        # theory: where a mode grows (shaded, boundary solid) and where the coupling mode loses more than
        # 1 % of its amplitude per period to the method's damping (dashed)
        grow = np.zeros((kk.size, wg.size))
        loss = np.zeros_like(grow)
        for a, k in enumerate(kk):
            modes = Modes(k)
            for b, wh in enumerate(wg):
                h = wh / modes.w_high
                grow[a, b] = max(method_radius(method, modes.lam[j] * h) for j in (modes.low, modes.high))
                r = method_radius(method, 1j * wh)  # the coupling mode without its physical damping
                # per period: only where a period spans two steps or more (beyond, "per period" means nothing)
                loss[a, b] = r ** (TWO_PI / wh) if wh < math.pi else math.nan
        ax.contourf(wg, kk, grow, levels=[1 + 1e-12, 1e9], colors=["#f4c7c3"])
        if np.nanmin(loss) < 0.99 < np.nanmax(loss):  # not for BDF1 (> 1 % everywhere), rho_inf = 1 (nowhere)
            ax.contour(wg, kk, loss, levels=[0.99], colors=["0.35"], linestyles="--", linewidths=1.0)
        if grow.max() > 1 + 1e-12:
            ax.contour(wg, kk, grow, levels=[1 + 1e-12], colors=["#c0392b"], linewidths=1.2)
        for r in sel:
            if r["method"] != method:
                continue
            if r["unstable"]:
                ax.scatter(r["wh"], r["k"], marker="x", color="#c0392b", s=36, zorder=3)
            else:
                sc = ax.scatter(r["wh"], r["k"], c=[max(r["error"], 1e-6)], cmap="viridis", norm=norm, s=30,
                                edgecolors="k", linewidths=0.3, zorder=3)
            if method[0] == "ida" and r["stats"]:
                frac, _ = order_fraction(r["stats"], method[1])
                if frac < 0.9 and method[1] > 1:  # IDA used lower orders for most steps
                    ax.scatter(r["wh"], r["k"], marker="s", facecolors="none", edgecolors="#e67e22", s=70,
                               linewidths=0.8, zorder=2)
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlim(wg[0], wg[-1])
        ax.set_ylim(kk[0], kk[-1])
        ax.set_title(label(method), fontsize=10)
        if i % 5 == 0:
            ax.set_ylabel("coupling k [N/m]")
        ax.set_xlabel(r"$\omega_{high}\,h$", fontsize=9)
        ax.tick_params(labelsize=8)
    ax = fig.add_subplot(gs[1, 4])
    ax.axis("off")
    if sc is not None:
        cax = ax.inset_axes([0.0, 0.5, 0.07, 0.5])
        cb = fig.colorbar(sc, cax=cax)
        cb.set_label("relative error over 20 periods\nof the coupling mode", fontsize=8)
        cb.ax.tick_params(labelsize=7)
    ax.text(0.0, 0.36, "x  measured unstable (a mode grows / run fails)\n"
            "o  stable; colour: error against the closed form\n"
            "red area, line: theory (fixed order), a mode grows\n"
            "dashed: theory, coupling mode loses 1 %/period\n"
            "orange square: IDA took < 90 % of its steps\n    at max_order (it lowers the order itself)\n"
            r"$\zeta_{coupling}$ = 0.071 (1e4 N/m) .. 0.0007 (1e8 N/m)",
            transform=ax.transAxes, fontsize=8, va="top")
    fig.text(0.12, 0.905, "(a) two bodies, soft tie + spring-damper coupling: stability measured (markers) "
             "against theory (lines); IDA with the step forced, generalized-alpha at a fixed step", fontsize=11)

    # (b)
    ax = fig.add_subplot(gs[2, 0:2])
    wt = np.logspace(math.log10(0.03), math.log10(30), 400)
    colors = {3: "#1f77b4", 4: "#2ca02c", 5: "#d62728"}
    alpha_deg = {3: 86.03, 4: 73.35, 5: 51.84}
    for k in (3, 4, 5):
        th = np.array([bdf_radius(k, 1j * w) ** (TWO_PI / w) - 1 for w in wt])
        ax.plot(wt, th, color=colors[k], lw=1.4, label=f"BDF-{k} theory, A({alpha_deg[k]}°)")
        pts = [b for b in bdf_rows if b["k"] == k]
        ax.scatter([b["wh"] for b in pts if b["held"]], [b["measured"] - 1 for b in pts if b["held"]],
                   color=colors[k], s=28, zorder=3)
        ax.scatter([b["wh"] for b in pts if not b["held"]], [b["measured"] - 1 for b in pts if not b["held"]],
                   facecolors="none", edgecolors=colors[k], s=40, zorder=3)
    ax.scatter([], [], color="0.4", s=28, label="IDA, max_order k: order k held")
    ax.scatter([], [], facecolors="none", edgecolors="0.4", s=40, label="IDA lowered the order itself")
    ax.axhline(0, color="k", lw=0.6)
    ax.set_xscale("log")
    ax.set_yscale("symlog", linthresh=1e-6)
    ax.set_xlabel(r"$\omega h$")
    ax.set_ylabel("amplitude ratio per period - 1\n(> 0: grows, unstable)")
    ax.set_title("(b) BDF 3-5 on an undamped mode: growth per period", fontsize=11, loc="left")
    ax.legend(fontsize=7.5, loc="center right")
    ax.grid(alpha=0.3, which="both")

    # (c)
    ax = fig.add_subplot(gs[2, 2:5])
    wt = np.logspace(-2, 2, 300)
    colors = {0.0: "#1f77b4", 0.5: "#2ca02c", 0.8: "#d62728", 1.0: "#9467bd"}
    for rho in (0.0, 0.5, 0.8, 1.0):
        ax.plot(wt, [jwh_radius(1j * w, rho) for w in wt], color=colors[rho], lw=1.4,
                label=fr"$\rho_\infty$ = {rho:g}")
        ax.plot(wt, [chung_hulbert_radius(w, rho) for w in wt], color=colors[rho], lw=1.0, ls=":")
        pts = [g for g in ga_rows if g["rho"] == rho]
        ax.scatter([g["wh"] for g in pts], [g["measured"] for g in pts], color=colors[rho], s=28, zorder=3)
    ax.set_xscale("log")
    ax.set_xlabel(r"$\omega h$")
    ax.set_ylabel("spectral radius per step")
    ax.set_ylim(-0.02, 1.05)
    ax.set_title("(c) generalized-alpha: measured (dots) against the closed forms", fontsize=11, loc="left")
    ax.plot([], [], color="0.4", lw=1.4, label="Jansen-Whiting-Hulbert, first-order form (solve's scheme)")
    ax.plot([], [], color="0.4", lw=1.0, ls=":", label="Chung-Hulbert, second-order form")
    ax.scatter([], [], color="0.4", s=28, label="measured")
    ax.legend(fontsize=7.5, loc="lower left")
    ax.grid(alpha=0.3, which="both")
    Path(path).parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=110, bbox_inches="tight")


if __name__ == "__main__":
    main()
