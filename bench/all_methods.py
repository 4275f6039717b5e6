#!/usr/bin/python3
"""Every testdata scene with each of solve's three integration methods (issue 16: "the three methods run every
testdata scene"), over a short interval from its start: whether the run completes, its CPU, steps and the first
line of its error.

For each scene under testdata/ (a TOML file with [[body]] tables; components and sweeps are skipped) the script
makes the scene's copy and its inputs in OUT (Makefile.workflow's rules: superelements by condense, tables
copied; a scene whose inputs no rule makes is reported as such), then runs three variants beside it:

  ida                the scene's own [integrator]
  generalized-alpha  the same keys with method = "generalized-alpha" and, if the scene has none, step =
                     its max_step or 20 us (adaptive, rho_inf 0.8)
  split              method = "split", exchange = "gauss-seidel" (Jacobi stalls on the valvetrain with a
                     bridge: docs/theory/split-integrator.md), macro_step = 10 x the scene's max_step or 200 us,
                     the groups of the joint graph (split_integrator.hpp); jacobian = "analytic"; with
                     --macro-tolerance T the macro step is chosen by the exchange's error estimate (S7), at most
                     that macro_step (a fixed 200 us crawls on the slap on the flexible block; 1e4 runs it)

each ending at start + SPAN (default 0.01 s; [steady_state] removed), with a wall-clock limit per run.

    /usr/bin/python3 bench/all_methods.py [--build build] [--out out] [--span 0.01] [--timeout 600]
                                          [--macro-tolerance T] [--only SUBSTRING ...]

Writes OUT/all_methods/all_methods.md (the table, as printed).
"""
import argparse
import re
import resource
import subprocess
import sys
import time
import tomllib
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "pipelines"))
from scene_inputs import scene_inputs  # noqa: E402


def scenes():
    for path in sorted((ROOT / "testdata").rglob("*.toml")):
        text = path.read_text()
        if re.search(r"^\[\[body\]\]", text, re.M) and "sweep" not in path.name:
            yield path


def section(text, name):
    """(start, end) of the [name] table's text, or None."""
    m = re.search(rf"^\[{re.escape(name)}\][^\n]*\n", text, re.M)
    if not m:
        return None
    nxt = re.search(r"^\[", text[m.end():], re.M)
    return m.start(), (m.end() + nxt.start()) if nxt else len(text)


def variant(text, doc, method, span, macro_tolerance=0.0):
    """The scene's text for `method`, ending at start + span."""
    for name in ("steady_state",):
        s = section(text, name)
        if s:
            text = text[:s[0]] + text[s[1]:]
    clock = doc.get("clock", {})
    start = clock.get("start_time", 0.0)
    s = section(text, "clock")
    if s:
        body = text[s[0]:s[1]]
        body = re.sub(r"^(end_time|end_angle_deg|end_cycles|end_time_limit|cycle_deg)\s*=.*\n", "", body, flags=re.M)
        body = body.rstrip("\n") + f"\nend_time = {start + span!r}\n\n"
        text = text[:s[0]] + body + text[s[1]:]
    else:
        text += f"\n[clock]\nend_time = {start + span!r}\n"
    integ = dict(doc.get("integrator", {}))
    max_step = integ.get("max_step", 0.0) or 0.0
    s = section(text, "integrator")
    body = text[s[0]:s[1]] if s else "[integrator]\n"
    body = re.sub(r"^method\s*=.*\n", "", body, flags=re.M)
    body = body.replace("[integrator]\n", f'[integrator]\nmethod = "{method}"\n', 1)
    if method == "generalized-alpha" and "step" not in integ:
        body = body.rstrip("\n") + f"\nstep = {max_step or 2e-5!r}\n\n"
    if method == "split":
        body = re.sub(r"^jacobian\s*=.*\n", "", body, flags=re.M)
        body = body.rstrip("\n") + f"\nmacro_step = {10 * max_step if max_step else 2e-4!r}\n"
        if macro_tolerance:
            body += f"macro_tolerance = {macro_tolerance!r}\n"
        body += 'exchange = "gauss-seidel"\n\n'
    text = (text[:s[0]] + body + text[s[1]:]) if s else text + "\n" + body
    return text


# Inputs that no Makefile.workflow rule makes (the tests and benches make them so): their commands.
SPECIAL = {
    "scenes/conrod.h5": lambda build, dst: [str(build / "condense" / "condense"), str(ROOT / "testdata" / "conrod.toml"),
                                            "-o", dst, "-q"],
    "scenes/simeon_rod.h5": lambda build, dst: ["/usr/bin/python3",
                                                str(ROOT / "testdata" / "scenes" / "make_simeon_rod.py"), "-o", dst],
    # the slap's flexible piston (testdata/slap/make_flexible_piston.py)
    "slap/piston_skirt.h5": lambda build, dst: [str(build / "condense" / "condense"),
                                                str(ROOT / "testdata" / "slap" / "piston_skirt.toml"), "-o", dst, "-q"],
    # the slap on the flexible block: the engine's block (testdata/engine/block.toml), condensed once for both
    "slap/block.h5": lambda build, dst: ["sh", "-c", f"make -s -f {ROOT}/Makefile.workflow OUT={Path(dst).parent.parent} "
                                                     f"BUILD_DIR={build} {Path(dst).parent.parent}/engine/block.h5 && "
                                                     f"ln -sf ../engine/block.h5 {dst}"],
}


def prepare(build, out, scene):
    """Make the scene's copy and its inputs in OUT; returns its copy's path, or an error string."""
    rel = scene.relative_to(ROOT / "testdata")
    copy = out / rel
    targets = [str(copy)]
    for p in scene_inputs(scene):
        dst = (copy.parent / p).resolve()
        key = str(dst.relative_to(out)) if dst.is_relative_to(out) else ""
        if key in SPECIAL:
            if not dst.exists():
                dst.parent.mkdir(parents=True, exist_ok=True)
                subprocess.run(SPECIAL[key](build, str(dst)), check=True, cwd=ROOT)
        else:
            targets.append(str(dst))
    r = subprocess.run(["make", "-f", str(ROOT / "Makefile.workflow"), f"OUT={out}", f"BUILD_DIR={build}", "-s",
                        *targets], cwd=ROOT, capture_output=True, text=True)
    if r.returncode != 0:
        last = (r.stderr.strip().splitlines() or ["?"])[-1]
        return f"inputs not made: {last[:120]}"
    return copy


def run(build, scene_copy, text, method, timeout):
    path = scene_copy.with_name(f"{scene_copy.stem}.methods_{method}.toml")
    result = path.with_suffix(".h5")
    path.write_text(text)
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.time()
    try:
        r = subprocess.run([str(build / "solve" / "solve"), str(path), "-o", str(result), "-q", "--progress",
                            "none"], capture_output=True, text=True, timeout=timeout)
        code, err = r.returncode, r.stderr.strip()
    except subprocess.TimeoutExpired:
        code, err = -1, f"not finished in {timeout} s wall"
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = after.ru_utime - before.ru_utime + after.ru_stime - before.ru_stime
    steps = ""
    if code == 0:
        import h5py
        with h5py.File(result, "r") as f:
            steps = int(f["solver/statistics"].attrs["steps"])
    path.unlink()
    result.unlink(missing_ok=True)
    if code == 0:
        return f"ok {cpu:.2f} s ({steps} steps)", True
    first = err.splitlines()[0] if err else f"exit {code}"
    first = re.sub(r"^\[solve\] error: ", "", first)
    return f"**failed** ({cpu:.1f} s): {first[:160]}", False


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--build", type=Path, default=ROOT / "build")
    ap.add_argument("--out", type=Path, default=ROOT / "out")
    ap.add_argument("--span", type=float, default=0.01, help="simulated seconds from the start (default 0.01)")
    ap.add_argument("--timeout", type=float, default=600, help="wall seconds per run (default 600)")
    ap.add_argument("--macro-tolerance", type=float, default=0.0,
                    help="the split's macro_tolerance (S7); 0 (default): the macro step fixed")
    ap.add_argument("--only", nargs="*", help="scenes whose path contains one of these")
    a = ap.parse_args()
    build, out = a.build.resolve(), a.out.resolve()
    lines = [f"| scene ({a.span} s) | ida | generalized-alpha | split |", "|---|---|---|---|"]
    print("\n".join(lines), flush=True)
    failures = 0
    for scene in scenes():
        rel = str(scene.relative_to(ROOT / "testdata"))
        if a.only and not any(s in rel for s in a.only):
            continue
        copy = prepare(build, out, scene)
        if isinstance(copy, str):
            line = f"| {rel} | {copy} | | |"
        else:
            text = copy.read_text()
            doc = tomllib.loads(text)
            cells = []
            for method in ("ida", "generalized-alpha", "split"):
                cell, ok = run(build, copy, variant(text, doc, method, a.span, a.macro_tolerance), method, a.timeout)
                failures += not ok
                cells.append(cell)
            line = f"| {rel} | " + " | ".join(cells) + " |"
        print(line, flush=True)
        lines.append(line)
    (out / "all_methods").mkdir(parents=True, exist_ok=True)
    (out / "all_methods" / "all_methods.md").write_text("\n".join(lines) + "\n")
    print(f"{failures} failed runs")


if __name__ == "__main__":
    main()
