#!/usr/bin/python3
"""solve against Simbody: reads the runs of bench/run_simbody_bench.sh (runs.csv: tool, method, parameter,
process CPU s, result file), takes the error of the crank angle at the end time against the reference
(Simbody Runge-Kutta-Merson at accuracy 1e-13, cross-checked against solve's IDA at rtol 1e-12), prints
the table, the cross-check and the ratios of CPU time at equal error, writes a CSV and the chart."""
import argparse, csv, math
import h5py
import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt

REFERENCE = ("simbody", "rkm", "1e-13")    # the reference run
SOLVE_TIGHT = ("solve", "ida", "1e-12")    # solve's tightest run: the cross-check
END_TIME = 1.0

ap = argparse.ArgumentParser()
ap.add_argument("runs")
ap.add_argument("-o", "--output", required=True)
ap.add_argument("--csv")
a = ap.parse_args()


def read_result(tool, path):
    """Final crank angle [rad], crank speed [rad/s], piston height [m], steps, integration time [s] measured
    inside the process (Simbody: std::clock CPU; solve: the sum of /solver/statistics wall_*_s, which solve
    measures with steady_clock, i.e. wall time), solve's share of it in the Jacobian."""
    if tool == "solve":
        with h5py.File(path, "r") as f:
            st = f["solver/statistics"].attrs
            return dict(t=float(f["time"][-1]), angle=math.radians(float(f["crank_angle_deg"][-1])),
                        speed=float(f["bodies/crank/angular_velocity"][-1, 2]),
                        piston=float(f["bodies/piston/position"][-1, 1]), steps=int(st["steps"]),
                        cpu_in=float(st["wall_residual_s"] + st["wall_jacobian_s"]
                                     + st["wall_linear_algebra_and_other_s"]),
                        jac=float(st["wall_jacobian_s"]) / max(float(st["wall_residual_s"] + st["wall_jacobian_s"]
                                     + st["wall_linear_algebra_and_other_s"]), 1e-12),
                        status=f.attrs["status"])
    kv = dict(w.split("=", 1) for w in open(path).read().split()[1:])
    return dict(t=float(kv["t"]), angle=float(kv["crank_angle_rad"]), speed=float(kv["crank_speed"]),
                piston=float(kv["piston_y"]), steps=int(kv["steps"]), cpu_in=float(kv["cpu_s"]), jac=None,
                status="complete")


runs = {}
for r in csv.DictReader(open(a.runs)):
    key = (r["tool"], r["method"], r["parameter"])
    runs[key] = dict(read_result(r["tool"], r["result"]), cpu=float(r["cpu_s"]))
startup = {tool: runs.pop((tool, "startup", "0"))["cpu"] for tool in ("solve", "simbody")}
for key, r in runs.items():
    if r["status"] != "complete" or abs(r["t"] - END_TIME) > 1e-12:
        raise SystemExit(f"{key}: run did not reach t = {END_TIME} (status {r['status']}, t = {r['t']})")
    r["net"] = max(r["cpu"] - startup[key[0]], 1e-3)

ref = runs[REFERENCE]
tight = runs[SOLVE_TIGHT]
print(f"\nreference: Simbody {REFERENCE[1].upper()} accuracy {REFERENCE[2]}: crank angle {ref['angle']:.12f} rad, "
      f"crank speed {ref['speed']:.10f} rad/s, piston height {ref['piston']:.12f} m at t = {END_TIME} s")
print("cross-check of the two tight runs (solve IDA rtol 1e-12 - Simbody RKM 1e-13): crank angle "
      f"{tight['angle'] - ref['angle']:.2e} rad, crank speed {tight['speed'] - ref['speed']:.2e} rad/s, "
      f"piston height {tight['piston'] - ref['piston']:.2e} m")
for key in (("simbody", "rkm", "1e-12"), ("simbody", "cpodes", "1e-12"), ("simbody", "rkf", "1e-12"),
            ("solve", "ida", "1e-10")):
    if key in runs:
        print(f"  {key[0]} {key[1]} {key[2]} - reference: crank angle {runs[key]['angle'] - ref['angle']:.2e} rad")
print(f"process start-up (zero-length run, subtracted below): solve {startup['solve']:.3f} s, "
      f"Simbody {startup['simbody']:.3f} s")

LABEL = {("solve", "ida"): "solve IDA (BDF), rtol", ("solve", "generalized-alpha"): "solve generalized-alpha, step",
         ("simbody", "rkm"): "Simbody Runge-Kutta-Merson, accuracy", ("simbody", "rkf"): "Simbody Runge-Kutta-Feldberg, accuracy",
         ("simbody", "cpodes"): "Simbody CPodes (BDF), accuracy"}
curves = {}
for key, r in runs.items():
    if key == REFERENCE:
        continue
    r["err"] = abs(r["angle"] - ref["angle"])
    r["err_piston"] = abs(r["piston"] - ref["piston"])
    curves.setdefault(key[:2], []).append((key[2], r))
for pts in curves.values():
    pts.sort(key=lambda p: -float(p[0]))

print("\nerror = |crank angle - reference| at t = 1 s [rad]; CPU = process user+sys, least of the repeats, "
      "minus start-up;\nus/step = that CPU / steps; jac = solve's share of its integration time in the Jacobian (analytic; wall time)")
print(f"{'run':<40} {'param':>6} {'CPU s':>7} {'steps':>6} {'us/step':>7} {'jac':>4} {'angle err':>9} {'piston err':>10}")
rows = []
for (tool, method), pts in curves.items():
    for param, r in pts:
        jac = f"{100 * r['jac']:3.0f}%" if r["jac"] is not None else f"{'-':>4}"
        print(f"{LABEL[(tool, method)]:<40} {param:>6} {r['net']:7.3f} {r['steps']:6d} "
              f"{1e6 * r['net'] / r['steps']:7.1f} {jac} {r['err']:9.2e} {r['err_piston']:10.2e}")
        rows.append(dict(tool=tool, method=method, parameter=param, cpu_process_s=r["cpu"],
                         cpu_net_s=round(r["net"], 4), integration_s_in_process=r["cpu_in"], steps=r["steps"],
                         jacobian_share=r["jac"] if r["jac"] is not None else "",
                         crank_angle_rad=repr(r["angle"]), error_crank_angle_rad=r["err"],
                         error_piston_m=r["err_piston"]))
if a.csv:
    with open(a.csv, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)


def cheapest(pts, level):
    """Least net CPU of a run of this curve whose error is at most level (None if none reaches it)."""
    c = [r["net"] for _, r in pts if r["err"] <= level]
    return min(c) if c else None


print("\nCPU at equal error: the cheapest run of each curve reaching the error; ratio solve / Simbody")
levels = [1e-2, 1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9]
names = [("solve", "ida"), ("solve", "generalized-alpha"), ("simbody", "rkm"), ("simbody", "rkf"), ("simbody", "cpodes")]
short = {("solve", "ida"): "IDA", ("solve", "generalized-alpha"): "gen-alpha", ("simbody", "rkm"): "RKM",
         ("simbody", "rkf"): "RKF", ("simbody", "cpodes"): "CPodes"}
fmt = lambda x: f"{x:9.3f}" if x is not None else f"{'-':>9}"
print(f"{'error <=':>9} " + " ".join(f"{short[n]:>9}" for n in names) + f" {'IDA/RKM':>8} {'IDA/CPodes':>10} {'IDA/best':>8}")
for lv in levels:
    c = {n: cheapest(curves.get(n, []), lv) for n in names}
    best_simbody = min([c[n] for n in names[2:] if c[n] is not None], default=None)
    ratio = lambda x, y: f"{x / y:8.1f}" if x is not None and y is not None else f"{'-':>8}"
    print(f"{lv:9.0e} " + " ".join(fmt(c[n]) for n in names) + f" {ratio(c[names[0]], c[names[2]])} "
          f"{ratio(c[names[0]], c[names[4]]):>10} {ratio(c[names[0]], best_simbody)}")

fig, ax = plt.subplots(figsize=(8, 5.5))
style = {("solve", "ida"): ("o-", "C0"), ("solve", "generalized-alpha"): ("s-", "C9"),
         ("simbody", "rkm"): ("^-", "C3"), ("simbody", "rkf"): ("v--", "C1"), ("simbody", "cpodes"): ("D-.", "C2")}
for n in names:
    pts = curves.get(n)
    if not pts:
        continue
    ax.loglog([r["err"] for _, r in pts], [r["net"] for _, r in pts], style[n][0], color=style[n][1], label=LABEL[n].rsplit(",", 1)[0])
    for param, r in pts:
        ax.annotate(param, (r["err"], r["net"]), fontsize=6, color=style[n][1], xytext=(3, 2), textcoords="offset points")
ax.set_xlabel("error of the crank angle at t = 1 s [rad]  (reference: Simbody RKM at 1e-13)")
ax.set_ylabel("CPU time, user + sys, less process start-up [s]")
ax.set_title("Free rigid slider-crank under gravity, 1 s (about 5 revolutions): solve against Simbody")
ax.title.set_fontsize(10)
ax.grid(True, which="both", alpha=0.3)
ax.legend(fontsize=8)
fig.tight_layout()
fig.savefig(a.output, dpi=110)
