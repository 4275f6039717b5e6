#!/usr/bin/python3
"""Test of pipelines/solve_to, the make rules' way of running solve (ctest: pipelines.solve_to).

    test_solve_to.py BUILD_DIR WORK_DIR

solve writes its results file as it goes (status "running"), so that a killed run can continue with --restart.
Under a make target's name such a file would pass for done; solve_to writes RESULTS.h5.part and renames it
when solve exits 0. Checked here, on the sweep tests' oscillator (oscillator.toml) run for 3,000 forcing
periods and started on its steady-state orbit:
  1. SIGTERM to solve_to mid-run: exit 3 (solve's "interrupted"), the part kept, no RESULTS.h5;
  2. the next solve_to continues the part (--restart) to exit 0: RESULTS.h5 with every sample from t = 0 to the
     end (count = duration x rate + 1), status "complete", no part left; the last displacement equals the
     closed form X sin(w t - phi) (Thomson & Dahleh eq. 3.1-3) to 1e-5 of X;
  3. a part older than the scene is not continued but removed (the scene changed: the run starts again);
  4. a failing run (a negative mass) exits 1 and leaves no RESULTS.h5.
"""
import math
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import h5py

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent.parent
SOLVE_TO = ROOT / "pipelines" / "solve_to"

M, C, K, F, W = 1.0, 20.0, 1000.0, 100.0, 2 * math.pi * 10.0
CYCLES = 3000  # of the 10 Hz forcing (the shaft turns at 600 rpm: one revolution per forcing period)
RATE = 200.0   # samples per second
TOL = 1e-5     # of the amplitude X


def fail(msg: str):
    print(f"FAIL: {msg}", flush=True)
    sys.exit(1)


def scene_text(mass: float = M) -> str:
    """oscillator.toml started on its steady orbit, CYCLES periods long, sampled at RATE."""
    x_amp = F / math.hypot(K - M * W * W, C * W)
    phi = math.atan2(C * W, K - M * W * W)
    x0, v0 = -x_amp * math.sin(phi), x_amp * W * math.cos(phi)
    text = (HERE / "oscillator.toml").read_text()
    text = text.replace("position = [0.0, 0, 0]       # sweep: x0", f"position = [{x0!r}, 0, 0]")
    text = text.replace("velocity = [0.0, 0, 0]       # sweep: v0", f"velocity = [{v0!r}, 0, 0]")
    text = text.replace("mass = 1.0\nposition", f"mass = {mass!r}\nposition")
    text = text.replace("end_cycles = 4", f"end_cycles = {CYCLES}")
    text = text.replace("sample_rate_hz = 2000", f"sample_rate_hz = {RATE:g}")
    for key in ("end_cycles", "sample_rate_hz", "position = [" + repr(x0)):
        if key not in text:
            fail(f"oscillator.toml changed: could not set {key}")
    return text


def solve_to(solve: Path, scene: Path, out: Path, term_after: float | None = None):
    cmd = [str(SOLVE_TO), str(solve), str(scene), str(out), "--progress", "none"]
    print("$ " + " ".join(cmd), flush=True)
    p = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    if term_after is not None:
        time.sleep(term_after)
        p.send_signal(signal.SIGTERM)
    text, _ = p.communicate(timeout=300)
    print(text, end="", flush=True)
    return p.returncode, text


def main():
    build, work = Path(sys.argv[1]), Path(sys.argv[2])
    solve = build / "solve" / "solve"
    work.mkdir(parents=True, exist_ok=True)
    scene, out = work / "oscillator.toml", work / "oscillator.results.h5"
    part = Path(str(out) + ".part")
    for f in (out, part):
        f.unlink(missing_ok=True)
    scene.write_text(scene_text())

    # 1. interrupted: the part stays, the target does not appear
    rc, _ = solve_to(solve, scene, out, term_after=2.0)
    if rc != 3:
        fail(f"solve_to under SIGTERM exited with {rc}, expected 3 (the run must last over 2 s: raise CYCLES)")
    if out.exists() or not part.exists():
        fail("after the interrupt: expected the part and no results file")
    with h5py.File(part, "r") as f:
        kept = len(f["time"])
        print(f"interrupted: status {f.attrs['status']}, {kept} samples kept", flush=True)

    # 2. continued to the end: the whole run under the target's name
    rc, text = solve_to(solve, scene, out)
    if rc != 0 or "continuing" not in text:
        fail(f"the second solve_to exited with {rc} (expected 0) or did not continue the part")
    if part.exists() or not out.exists():
        fail("after the finished run: expected the results file and no part")
    with h5py.File(out, "r") as f:
        t = f["time"][...]
        x = f["markers/mass.c/position"][...]
        status = f.attrs["status"]
    expected = round(CYCLES / 10.0 * RATE) + 1
    x_amp = F / math.hypot(K - M * W * W, C * W)
    phi = math.atan2(C * W, K - M * W * W)
    err = abs(x[-1, 0] - x_amp * math.sin(W * t[-1] - phi)) / x_amp
    print(f"continued: status {status}, {len(t)} samples (expected {expected}), t {t[0]} .. {t[-1]} s, "
          f"last displacement {err:.2e} of X from the closed form (tolerance {TOL:g})", flush=True)
    if status != "complete" or len(t) != expected or t[0] != 0.0 or kept >= expected:
        fail("the continued run is not the whole run")
    if not err < TOL:
        fail(f"last displacement {err:.3e} of X from the closed form, tolerance {TOL:g}")

    # 3. a part older than the scene is removed, not continued
    rc, _ = solve_to(solve, scene, out, term_after=2.0)
    if rc != 3 or not part.exists():
        fail("the third run was to be interrupted and leave a part")
    past = time.time() - 3600
    os.utime(part, (past, past))
    rc, text = solve_to(solve, scene, out, term_after=2.0)
    if "removing" not in text or "continuing" in text:
        fail("a part older than the scene was continued")
    part.unlink(missing_ok=True)
    out.unlink(missing_ok=True)

    # 4. a failing run leaves no target
    scene.write_text(scene_text(mass=-1.0))
    rc, _ = solve_to(solve, scene, out)
    if rc != 1 or out.exists():
        fail(f"a scene with a negative mass: exit {rc} (expected 1) and results file {out.exists()} (expected none)")
    part.unlink(missing_ok=True)
    print("PASS", flush=True)


if __name__ == "__main__":
    main()
