#!/usr/bin/env python3
"""Mutation fuzzer of the toolchain's input readers, run as a hostile user would (docs/reliability.md).

Each target takes seed inputs (the testdata files, shortened so one run takes well under a second, and the
small extras in tests/fuzz/corpus/), mutates one of them per trial, runs the real tool on it and judges
what the tool did:

  ok          exit 0, every float in the output finite (solve: status "complete"), no temporary left
  error       exit 1 with a message naming the input file (or, for a failure during a run, the time)
  usage       exit 2 (postproc's mutated command lines only)
  slow        still running at the time limit, stopped by SIGTERM within 5 s (not a defect: the mutant
              asked for a long run)
  -- defects --
  crash       killed by a signal (SIGSEGV, SIGABRT, ...)
  hang        ignores SIGTERM for 5 s at the time limit
  nonfinite   exit 0 with NaN or inf in the output
  unnamed     exit 1 with a message naming neither the file nor the time
  unexpected  "unexpected failure" (an exception that is not the project's Error leaked to main)
  leftover    a temporary (*.tmp-PID) or, after an error, a half-written output left behind
  odd         any other exit code, or exit 0 without the output

Targets (one per input reader, through the tool that reads it):
  component     condense COMPONENT.toml (beam and volume components)
  scene         solve SCENE.toml (scene reader, CSV tables, and the run itself)
  bearing       solve bearing-map BEARING.toml
  signal        postproc {spectrum,octave,orders,stats} on a mutated CSV signal and mutated options
  superelement  solve on a scene whose superelement file is corrupted (bytes flipped, zeroed, truncated)
  results       postproc on a corrupted results file

  fuzz.py BUILD_DIR WORK_DIR [--targets t1,t2] [--mutants N] [--seed S] [--jobs J] [--timeout T]
Exit code 0 when no trial found a defect, 1 otherwise; the defective mutants are kept in WORK_DIR/defects.
"""
import argparse
import concurrent.futures
import os
import random
import re
import shutil
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path

SOURCE = Path(__file__).resolve().parents[2]
CORPUS = Path(__file__).resolve().parent / "corpus"
DEFECTS = ("crash", "hang", "nonfinite", "unnamed", "unexpected", "leftover", "odd")

# ----------------------------------------------------------------------------------------------- mutations

SPECIAL_NUMBERS = ["inf", "-inf", "nan", "+inf", "1e308", "-1e308", "1.7976931348623157e308", "1e-320", "-1e-320",
                   "0", "-0.0", "-1", "1", "2147483647", "-2147483648", "9223372036854775807", "1e12", "1e-12",
                   "3.0e9", "65536", "0.5", "1e6", "123456789012345678901234567890"]
NUMBER = re.compile(rb"(?<![A-Za-z_\"])[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?")
STRING = re.compile(rb'"[^"\n]*"')


def mutate_number(text, rng):
    spots = list(NUMBER.finditer(text))
    if not spots:
        return text
    m = rng.choice(spots)
    old = m.group(0)
    roll = rng.random()
    if roll < 0.6:
        new = rng.choice(SPECIAL_NUMBERS).encode()
    elif roll < 0.8:  # scale by a power of ten
        try:
            new = repr(float(old) * 10.0 ** rng.randint(-12, 12)).encode()
        except ValueError:
            new = b"1e9"
    else:
        new = b"-" + old.lstrip(b"-+")
    return text[:m.start()] + new + text[m.end():]


def mutate_string(text, rng):
    spots = list(STRING.finditer(text))
    if not spots:
        return text
    m = rng.choice(spots)
    others = [s.group(0) for s in spots]
    choices = [b'""', b'"x"', b'"../../../../etc/passwd"', b'"/dev/zero"', b'"\\u0000"', rng.choice(others),
               b'"' + b"a" * 5000 + b'"', b'"' + rng.choice(others)[1:-1][::-1] + b'"']
    return text[:m.start()] + rng.choice(choices) + text[m.end():]


def mutate_lines(text, rng):
    lines = text.split(b"\n")
    if len(lines) < 2:
        return text
    i, j = rng.randrange(len(lines)), rng.randrange(len(lines))
    op = rng.randrange(4)
    if op == 0:
        del lines[i]
    elif op == 1:
        lines.insert(j, lines[i])
    elif op == 2:
        lines[i], lines[j] = lines[j], lines[i]
    else:  # change the type of a value: number <-> string <-> array <-> table <-> bool
        if b"=" in lines[i]:
            key = lines[i].split(b"=", 1)[0]
            lines[i] = key + b"= " + rng.choice([b'"text"', b"[1, 2, 3]", b"{ a = 1 }", b"true", b"[]", b"[[1], [2]]",
                                                 b"1979-05-27T07:32:00Z", b"[[]]", b'["a", 1]'])
    return b"\n".join(lines)


def mutate_bytes(text, rng):
    data = bytearray(text)
    if not data:
        return bytes(data)
    for _ in range(rng.randint(1, 4)):
        k = rng.randrange(len(data))
        op = rng.randrange(3)
        if op == 0:
            data[k] = rng.randrange(256)
        elif op == 1:
            data.insert(k, rng.choice(b"[]{}=\"'.,#\n\\0123456789e-+ \t\x00\xff"))
        else:
            del data[k]
    return bytes(data)


def mutate_extreme(text, rng):
    """Rare structural attacks: deep nesting, an endless line, a truncated file."""
    op = rng.randrange(4)
    if op == 0:
        depth = rng.choice([100, 1000, 6000, 50000])
        return text + b"\nzz = " + b"[" * depth + b"]" * depth + b"\n"
    if op == 1:
        depth = rng.choice([100, 6000])
        return text + b"\nzz = " + b"{a=" * depth + b"1" + b"}" * depth + b"\n"
    if op == 2:
        return text + b"\nzz = [" + b", ".join(b"%d.5" % i for i in range(rng.choice([1000, 100000]))) + b"]\n"
    return text[:rng.randrange(len(text) + 1)]


def mutate_text(text, rng):
    for _ in range(rng.choice([1, 1, 1, 2, 3])):
        roll = rng.random()
        if roll < 0.45:
            text = mutate_number(text, rng)
        elif roll < 0.6:
            text = mutate_string(text, rng)
        elif roll < 0.8:
            text = mutate_lines(text, rng)
        elif roll < 0.97:
            text = mutate_bytes(text, rng)
        else:
            text = mutate_extreme(text, rng)
    return text


def mutate_binary(data, rng):
    """Corrupt an HDF5 file: flip bytes, zero or randomise a block, truncate."""
    data = bytearray(data)
    op = rng.randrange(5)
    if op <= 1:
        for _ in range(rng.choice([1, 1, 2, 8, 32])):
            k = rng.randrange(len(data))
            data[k] ^= 1 << rng.randrange(8) if op == 0 else rng.randrange(1, 256)
    elif op == 2:
        k = rng.randrange(len(data))
        n = rng.choice([8, 64, 512, 4096])
        data[k:k + n] = bytes(min(n, len(data) - k))
    elif op == 3:
        k = rng.randrange(len(data))
        n = rng.choice([8, 64, 512])
        data[k:k + n] = bytes(rng.randrange(256) for _ in range(min(n, len(data) - k)))
    else:
        data = data[:rng.randrange(len(data))]
    return bytes(data)


# ------------------------------------------------------------------------------------------ seed corpus

def shorten_scene(text):
    """A testdata scene cut to a few crank degrees (or milliseconds), so a mutant runs in a fraction of a second."""
    text = re.sub(rb"(?m)^end_cycles\s*=.*$", b"end_angle_deg = 8", text)
    text = re.sub(rb"(?m)^end_time\s*=.*$", b"end_time = 0.004", text)
    return text


def run_checked(command, cwd=None):
    done = subprocess.run(command, cwd=cwd, capture_output=True, text=True)
    if done.returncode != 0:
        raise SystemExit("fuzz: preparing the corpus failed: " + " ".join(map(str, command)) + "\n" + done.stderr)


def write_uff58(path, values, dt):
    """An ASCII Universal File dataset 58 (a time history in m/s^2), as postproc/uff58.cpp writes it."""
    none = "NONE".ljust(80)
    lines = ["    -1", "    58", "accel".ljust(80), none, none, none, none,
             "%5i%10i%5i%10i %-10s%10i%4i %-10s%10i%4i" % (1, 0, 0, 0, "NONE", 1, 3, "NONE", 0, 0),
             "%10i%10i%10i%13.6E%13.6E%13.5E" % (4, len(values), 1, 0.0, dt, 0.0),
             "%10i%5i%5i%5i %-20s %-20s" % (17, 0, 0, 0, "Time", "s"),
             "%10i%5i%5i%5i %-20s %-20s" % (12, 0, 0, 0, "accel", "m/s^2"),
             "%10i%5i%5i%5i %-20s %-20s" % (0, 0, 0, 0, "NONE", "NONE"),
             "%10i%5i%5i%5i %-20s %-20s" % (0, 0, 0, 0, "NONE", "NONE")]
    for i in range(0, len(values), 4):
        lines.append("".join("%20.12E" % v for v in values[i:i + 4]))
    lines.append("    -1")
    path.write_text("\n".join(lines) + "\n")


def prepare_corpus(build, root):
    """Seed folders: one per target, each holding the seeds and the files they read."""
    condense, solve = build / "condense/condense", build / "solve/solve"
    seeds = {}
    if root.exists():
        shutil.rmtree(root)
    # component: beam components as they are, and a coarse volume component (meshing stays fast)
    d = root / "component"
    d.mkdir(parents=True)
    for name in ["conrod.toml", "crankshaft.toml", "compressor/spring.toml", "compressor/pipe.toml"]:
        shutil.copy(SOURCE / "testdata" / name, d)
    for name in ["block.toml", "block.geo"]:
        shutil.copy(CORPUS / name, d)
    seeds["component"] = [(d, n) for n in ["conrod.toml", "crankshaft.toml", "spring.toml", "pipe.toml", "block.toml"]]
    # scene: the testdata scenes, shortened, next to the superelements and tables they read
    d = root / "scene"
    d.mkdir()
    for name in ["slider_crank", "piston_slap", "bearing_crankshaft", "slider_crank_flexible"]:
        (d / (name + ".toml")).write_bytes(shorten_scene((SOURCE / "testdata/scenes" / (name + ".toml")).read_bytes()))
    comp = (SOURCE / "testdata/compressor/compressor.toml").read_bytes()
    (d / "compressor.toml").write_bytes(shorten_scene(comp))
    for csv in (SOURCE / "testdata/compressor").glob("*.csv"):
        shutil.copy(csv, d)
    run_checked([condense, SOURCE / "testdata/conrod.toml", "-o", d / "conrod.h5", "-q"])
    for name in ["spring", "pipe", "shell"]:
        run_checked([condense, SOURCE / "testdata/compressor" / (name + ".toml"), "-o", d / (name + ".h5"), "-q"])
    seeds["scene"] = [(d, n) for n in ["slider_crank.toml", "piston_slap.toml", "bearing_crankshaft.toml",
                                       "slider_crank_flexible.toml", "compressor.toml"]]
    # superelement: the flexible slider-crank reading a corrupted conrod.h5
    seeds["superelement"] = [(d, "conrod.h5")]
    # bearing: the example of docs/bearing.md on a coarser grid
    d = root / "bearing"
    d.mkdir()
    shutil.copy(CORPUS / "bearing.toml", d)
    seeds["bearing"] = [(d, "bearing.toml")]
    # signal: a CSV signal with a time column; results: a short solve results file (with the crank angle)
    d = root / "signal"
    d.mkdir()
    with open(d / "signal.csv", "w") as f:
        f.write("time,accel,force\n")
        for i in range(4000):
            t = i / 4000.0
            f.write(f"{t:.6f},{(i * 7919 % 1000) / 500.0 - 1.0:.6f},{100.0 * ((i * 104729) % 997) / 997.0:.4f}\n")
    write_uff58(d / "signal.uff", [(i * 7919 % 1000) / 500.0 - 1.0 for i in range(2048)], 1.0 / 4096.0)
    run_checked([solve, seeds["scene"][0][0] / "slider_crank.toml", "-o", d / "results.h5", "-q"])
    seeds["signal"] = [(d, "signal.csv"), (d, "signal.uff")]
    seeds["results"] = [(d, "results.h5")]
    return seeds


# ------------------------------------------------------------------------------------------ the trials

def postproc_command(rng, signal_file, results):
    """A postproc command line with mutated option values on the signal or on the results file."""
    sub = rng.choice(["spectrum", "octave", "orders", "stats"])
    if sub == "orders" or (sub == "stats" and rng.random() < 0.5) or results:
        address = rng.choice(["results.h5:/markers/crank.pin/position[1]", "results.h5:/crank_angle_deg",
                              "results.h5:/markers/crank.pin/acceleration[x]"])
    else:
        address = rng.choice(["signal.uff", "signal.uff:1", "signal.uff:2"] if signal_file.endswith(".uff") else
                             ["signal.csv:accel", "signal.csv:force", "signal.csv:1", "signal.csv:9"])
    if sub == "orders" and not results and rng.random() < 0.5:
        address, extra = "signal.csv:accel", ["--angle", "signal.csv:force", "--angle-kind", "tacho"]
    else:
        extra = []
    values = SPECIAL_NUMBERS + ["2", "10", "720", "0.01", "1e-9", "3e3", "-5"]
    options = {
        "spectrum": ["--resolution", "--segment", "--overlap", "--fmax", "--start", "--end", "--integrate"],
        "octave": ["--fraction", "--fmin", "--fmax", "--interval", "--start", "--end"],
        "orders": ["--cycle", "--samples-per-cycle", "--max-order", "--skip-cycles", "--campbell-rpm-step",
                   "--campbell-fmax", "--campbell-resolution", "--pulses-per-rev", "--threshold"],
        "stats": ["--cycle", "--skip-cycles", "--start", "--end"],
    }[sub]
    args = [sub, address, "-o", "out.h5"] + extra
    for option in rng.sample(options, rng.randint(0, 2)):
        args += [option, rng.choice(values)]
    if sub == "orders" and rng.random() < 0.3:
        args += ["--campbell"]
    if sub == "stats" and rng.random() < 0.3:
        args += ["--band", rng.choice(values), rng.choice(values)]
    return args


def nonfinite_in(path):
    """The first dataset of an HDF5 file holding NaN or inf ("" if none)."""
    import h5py
    import numpy as np
    bad = []

    def visit(name, obj):
        if isinstance(obj, h5py.Dataset) and obj.dtype.kind == "f" and obj.size and not bad:
            if not np.all(np.isfinite(obj[()])):
                bad.append(name)

    with h5py.File(path, "r") as f:
        f.visititems(visit)
        status = f.attrs.get("status", b"complete")
    status = status.decode() if isinstance(status, bytes) else str(status)
    return (bad[0] if bad else ""), status


class Trial:
    def __init__(self, target, index, seed_dir, seed_name, command, mutated):
        self.target, self.index = target, index
        self.seed_dir, self.seed_name, self.command, self.mutated = seed_dir, seed_name, command, mutated


def names_of(trial):
    """What an error may name to be actionable: an input file of the command, or an option it was given."""
    names = {trial.seed_name}
    for a in trial.command[1:]:
        if a.startswith("--"):
            names.add(a[2:])
        elif "." in a and not a.startswith("out."):
            names.add(Path(a.split(":")[0]).name)
    return names


def judge(trial, cwd, timeout, outputs):
    """Run one mutant in `cwd` (its own copy of the seed folder) and classify the outcome."""
    for o in outputs:
        (cwd / o).unlink(missing_ok=True)
    start = time.monotonic()
    proc = subprocess.Popen(trial.command, cwd=cwd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                            start_new_session=True)
    verdict = None
    try:
        _, err = proc.communicate(timeout=timeout)
    except subprocess.TimeoutExpired:
        os.killpg(proc.pid, signal.SIGTERM)
        try:
            _, err = proc.communicate(timeout=5)
            verdict = "slow"
        except subprocess.TimeoutExpired:
            os.killpg(proc.pid, signal.SIGKILL)
            _, err = proc.communicate()
            verdict = "hang"
    seconds = time.monotonic() - start
    message = err.decode(errors="replace").strip()
    rc = proc.returncode
    leftovers = [p.name for p in cwd.iterdir() if ".tmp-" in p.name]
    for p in leftovers:
        (cwd / p).unlink(missing_ok=True)
    if verdict is None:
        if rc < 0:
            verdict = "crash"
            message = f"killed by signal {-rc} ({signal.Signals(-rc).name})\n" + message
        elif "unexpected failure" in message:
            verdict = "unexpected"
        elif rc == 0:
            verdict = "ok"
            for o in outputs:
                if o.endswith(".h5"):
                    if not (cwd / o).exists():
                        verdict, message = "odd", f"exit 0 without {o}"
                        break
                    try:
                        bad, status = nonfinite_in(cwd / o)
                    except Exception as e:  # noqa: BLE001 - an unreadable output is a defect too
                        verdict, message = "odd", f"exit 0 but {o} unreadable: {e}"
                        break
                    if bad:
                        verdict, message = "nonfinite", f"exit 0 with NaN/inf in {o}:/{bad} (status {status})"
                    elif status != "complete":
                        verdict, message = "odd", f"exit 0 with status {status}"
        elif rc == 1:
            named = any(n in message for n in names_of(trial)) or re.search(r"at t = |t = [-+0-9.e]+ s", message)
            verdict = "error" if named else "unnamed"
            results = cwd / "out.h5"
            if trial.target != "scene" and trial.target != "superelement" and results.exists():
                verdict, message = "leftover", "exit 1 but out.h5 was written\n" + message
            elif results.exists():  # solve keeps its samples; the status must say it failed
                try:
                    _, status = nonfinite_in(results)
                except Exception as e:  # noqa: BLE001
                    status = f"unreadable ({e})"
                if status != "failed":
                    verdict, message = "odd", f"exit 1 with status '{status}' in out.h5\n" + message
        elif rc == 2 and trial.target in ("signal", "results"):
            verdict = "usage"
        else:
            verdict = "odd"
            message = f"exit code {rc}\n" + message
    if leftovers and verdict not in ("hang",) and verdict not in DEFECTS:
        verdict, message = "leftover", "left " + ", ".join(leftovers) + "\n" + message
    return verdict, message, seconds


def make_trial(target, index, rng, seeds, build):
    solve, condense, postproc = str(build / "solve/solve"), str(build / "condense/condense"), str(
        build / "postproc/postproc")
    seed_dir, seed_name = rng.choice(seeds[target])
    original = (seed_dir / seed_name).read_bytes()
    if target == "component":
        command = [condense, seed_name, "-o", "out.h5", "-q"]
        mutated = mutate_text(original, rng)
    elif target == "scene":
        command = [solve, seed_name, "-o", "out.h5", "-q", "--progress", "none"]
        mutated = mutate_text(original, rng)
    elif target == "superelement":
        command = [solve, "slider_crank_flexible.toml", "-o", "out.h5", "-q", "--progress", "none"]
        mutated = mutate_binary(original, rng)
    elif target == "bearing":
        command = [solve, "bearing-map", seed_name, "-o", "out.h5", "--csv", "out.csv", "-q"]
        mutated = mutate_text(original, rng)
    elif target == "signal":
        command = [postproc] + postproc_command(rng, seed_name, False) + ["-q"]
        mutated = mutate_text(original, rng) if rng.random() < 0.7 else original
    else:  # results
        command = [postproc] + postproc_command(rng, seed_name, True) + ["-q"]
        mutated = mutate_binary(original, rng)
    return Trial(target, index, seed_dir, seed_name, command, mutated)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("build", type=Path)
    parser.add_argument("work", type=Path)
    parser.add_argument("--targets", default="component,scene,bearing,signal,superelement,results")
    parser.add_argument("--mutants", type=int, default=200, help="trials per target")
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--jobs", type=int, default=os.cpu_count() or 2)
    parser.add_argument("--timeout", type=float, default=20.0, help="seconds before SIGTERM")
    parser.add_argument("--verbose", action="store_true", help="print every trial")
    args = parser.parse_args()
    build, work = args.build.resolve(), args.work.resolve()
    targets = args.targets.split(",")
    seeds = prepare_corpus(build, work / "corpus")
    defects_dir = work / "defects"
    shutil.rmtree(defects_dir, ignore_errors=True)
    defects_dir.mkdir(parents=True)
    lock = threading.Lock()
    counts = {t: {} for t in targets}
    slowest = {t: 0.0 for t in targets}
    free_dirs = []  # per-worker copies of the corpus
    for w in range(args.jobs):
        copy = work / f"worker{w}"
        shutil.rmtree(copy, ignore_errors=True)
        shutil.copytree(work / "corpus", copy)
        free_dirs.append(copy)

    def run(trial):
        with lock:
            root = free_dirs.pop()
        cwd = root / trial.seed_dir.name
        path = cwd / trial.seed_name
        original = path.read_bytes()
        try:
            path.write_bytes(trial.mutated)
            outputs = ["out.h5", "out.csv"] if trial.target == "bearing" else ["out.h5"]
            verdict, message, seconds = judge(trial, cwd, args.timeout, outputs)
        finally:
            path.write_bytes(original)
            with lock:
                free_dirs.append(root)
        with lock:
            counts[trial.target][verdict] = counts[trial.target].get(verdict, 0) + 1
            slowest[trial.target] = max(slowest[trial.target], seconds)
            if verdict in DEFECTS:
                stem = f"{trial.target}-{trial.index:05d}-{verdict}"
                keep = defects_dir / stem
                keep.mkdir()
                (keep / trial.seed_name).write_bytes(trial.mutated)
                (keep / "README.txt").write_text(
                    f"seed folder: {trial.seed_dir}\ncommand (in a copy of that folder, with this file in it):\n  "
                    + " ".join(trial.command) + f"\n\n{verdict} after {seconds:.2f} s:\n{message}\n")
                print(f"fuzz: {stem}: {message.splitlines()[0] if message else ''}", flush=True)
            elif args.verbose:
                print(f"fuzz: {trial.target}-{trial.index:05d} {verdict} {seconds:.2f} s "
                      f"{message.splitlines()[0] if message else ''}", flush=True)

    rng = random.Random(args.seed)
    trials = [make_trial(t, i, rng, seeds, build) for t in targets for i in range(args.mutants)]
    start = time.monotonic()
    with concurrent.futures.ThreadPoolExecutor(max_workers=args.jobs) as pool:
        for f in [pool.submit(run, t) for t in trials]:
            f.result()
    total_defects = 0
    print(f"\nfuzz: {len(trials)} trials in {time.monotonic() - start:.0f} s (seed {args.seed}, "
          f"{args.jobs} jobs, time limit {args.timeout:g} s)")
    print(f"{'target':<14}" + "".join(f"{k:>11}" for k in ("ok", "error", "usage", "slow") + DEFECTS) + "  slowest")
    for t in targets:
        c = counts[t]
        total_defects += sum(c.get(k, 0) for k in DEFECTS)
        print(f"{t:<14}" + "".join(f"{c.get(k, 0):>11}" for k in ("ok", "error", "usage", "slow") + DEFECTS)
              + f"  {slowest[t]:.1f} s")
    if total_defects:
        print(f"fuzz: {total_defects} defects; the mutants are in {defects_dir}")
    return 1 if total_defects else 0


if __name__ == "__main__":
    sys.exit(main())
