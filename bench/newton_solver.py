#!/usr/bin/python3
"""IDA's Newton matrix factorized by KLU against dense LU (solve/newton_matrix_solver.hpp), side by side.

Runs each scene three times - `[integrator] linear_solver` = "klu", "dense" and "auto" (the default, which
picks one from KLU's symbolic analysis of the pattern) - and prints the CPU time of each solve process (user +
system), its steps and Jacobians, the ratio KLU / dense, which solver "auto" chose, and the largest difference
of a few result channels between the two runs relative to their RMS (both solve the same equations: the
difference is the integration's own round-off sensitivity, not an error of either).

Scenes (made by Makefile.workflow's rules, which this script calls):
  engine_finite_mains  testdata/engine: the issue 15 benchmark configuration, one 720 deg cycle from the start
  engine_film4         the same with short main bearings, one cycle
  compressor           the demo (testdata/compressor/compressor.toml)
  valvetrain_flexible_rocker  testdata/valvetrain, the flexible rocker

    /usr/bin/python3 bench/newton_solver.py [--build build] [--out out] [--only NAME ...]

Writes OUT/bench_newton_solver/newton_solver.md (the table, as printed).
"""
import argparse
import re
import resource
import subprocess
import sys
from pathlib import Path

import h5py
import numpy as np

ROOT = Path(__file__).resolve().parent.parent


def one_cycle(text):
    """The scene without [steady_state], ending after one 720 deg cycle."""
    text = re.sub(r"^\[steady_state\].*?(?=^\[)", "", text, count=1, flags=re.M | re.S)
    return text.replace("cycle_deg = 720\n", "cycle_deg = 720\nend_cycles = 1\n", 1)


# name, directory under OUT, scene file there, edit of its text, channels compared
SCENES = [
    ("engine_finite_mains", "engine", "engine_finite_mains.toml", one_cycle,
     ["forces/mount1_z/force", "forces/main3/force", "markers/block.jacket4_thrust/acceleration"]),
    ("engine_film4", "engine", "engine_film4.toml", one_cycle,
     ["forces/mount1_z/force", "forces/main3/force", "markers/block.jacket4_thrust/acceleration"]),
    ("compressor", "compressor", "compressor.toml", lambda t: t, None),
    ("valvetrain_flexible_rocker", "valvetrain", "valvetrain_flexible_rocker.toml", lambda t: t, None),
]
PREREQUISITES = {
    "engine": ["engine/block.h5", "engine/crankshaft.h5", "engine/cylinder_pressure.csv",
               "engine/engine_finite_mains.toml", "engine/engine_film4.toml"],
    "compressor": ["compressor/compressor.toml", "compressor/shell.h5", "compressor/spring.h5", "compressor/pipe.h5",
                   "compressor/cylinder_force.csv", "compressor/motor_50hz.csv"],
    "valvetrain": ["valvetrain/rocker.h5", "valvetrain/valvetrain_flexible_rocker.toml"],
}


def with_solver(text, solver):
    return re.sub(r"^\[integrator\]\n", f'[integrator]\nlinear_solver = "{solver}"\n', text, count=1, flags=re.M)


def run(build, scene, output):
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    subprocess.run([str(build / "solve" / "solve"), str(scene), "-o", str(output), "-q", "--progress", "none"],
                   check=True)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = after.ru_utime - before.ru_utime + after.ru_stime - before.ru_stime
    with h5py.File(output, "r") as f:
        s = f["solver/statistics"].attrs
        return {"cpu": cpu, "steps": int(s["steps"]), "jacobians": int(s["jacobian_evaluations"]),
                "solver": s["linear_solver"].decode() if isinstance(s["linear_solver"], bytes)
                else str(s["linear_solver"])}


def difference(a, b, channels):
    """Largest RMS difference of the channels over their RMS (from the 100th sample: past the start)."""
    if not channels:
        with h5py.File(a, "r") as f:
            channels = [f"forces/{k}/force" for k in list(f["forces"].keys())[:3]]
    worst = 0.0
    with h5py.File(a, "r") as fa, h5py.File(b, "r") as fb:
        for c in channels:
            x, y = np.asarray(fa[c])[100:], np.asarray(fb[c])[100:]
            n = min(len(x), len(y))
            rms = np.sqrt(np.mean(y[:n] ** 2))
            if rms > 0:
                worst = max(worst, np.sqrt(np.mean((x[:n] - y[:n]) ** 2)) / rms)
    return worst


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--build", type=Path, default=ROOT / "build")
    ap.add_argument("--out", type=Path, default=ROOT / "out")
    ap.add_argument("--only", nargs="*")
    a = ap.parse_args()
    scenes = [s for s in SCENES if not a.only or s[0] in a.only]
    targets = sorted({str(a.out / p) for s in scenes for p in PREREQUISITES[s[1]]})
    subprocess.run(["make", "-f", str(ROOT / "Makefile.workflow"), f"OUT={a.out}", f"BUILD_DIR={a.build}", "-s",
                    *targets], check=True, cwd=ROOT)
    work = a.out / "bench_newton_solver"
    work.mkdir(parents=True, exist_ok=True)
    lines = ["| scene | KLU: CPU s (steps, Jacobians) | dense: CPU s (steps, Jacobians) | KLU / dense | auto chose |"
             " channels, KLU against dense |", "|---|---|---|---|---|---|"]
    print("\n".join(lines), flush=True)
    for name, sub, file, edit, channels in scenes:
        text = edit((a.out / sub / file).read_text())
        r = {}
        for solver in ("klu", "dense", "auto"):
            scene = a.out / sub / f"bench_newton_{name}_{solver}.toml"  # beside the scene's own inputs
            scene.write_text(with_solver(text, solver))
            r[solver] = run(a.build, scene, work / f"{name}_{solver}.h5")
            scene.unlink()
        k, d = r["klu"], r["dense"]
        diff = difference(work / f"{name}_klu.h5", work / f"{name}_dense.h5", channels)
        line = (f"| {name} | {k['cpu']:.2f} ({k['steps']}, {k['jacobians']}) | {d['cpu']:.2f} ({d['steps']}, "
                f"{d['jacobians']}) | {k['cpu'] / d['cpu']:.2f} | {r['auto']['solver']} | {diff:.1e} |")
        print(line, flush=True)
        lines.append(line)
    (work / "newton_solver.md").write_text("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
