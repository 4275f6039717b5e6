#!/usr/bin/python3
"""Tests of pipelines/sweep (ctest: pipelines.sweep_local, pipelines.sweep_slurm).

    test_sweep.py local BUILD_DIR WORK_DIR   # make -j run, gather, failure report, staleness
    test_sweep.py slurm BUILD_DIR WORK_DIR   # a real single-node Slurm on localhost: sbatch --array, gather,
                                             # equal to the local run; exit 77 (ctest: skipped) only where
                                             # Slurm cannot start

The swept scene (oscillator.toml) is a mass on a spring-damper under a harmonic force, started on its
steady-state orbit: the gathered first-order amplitude of every point is checked against the closed form
X = F / sqrt((k - m w^2)^2 + (c w)^2) (effective value X / sqrt 2), tolerance 1e-4 relative (postproc's
order tracking reproduces a pure sine to 2e-5; solve runs at rtol 1e-9). The point with k = -1 must fail,
be reported by gather with its parameters and log, and leave the others gathered.
"""
import math
import os
import shutil
import signal
import socket
import subprocess
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent.parent
SWEEP = ROOT / "pipelines" / "sweep"
SWEEP_FILE = HERE / "oscillator.sweep.toml"
SKIP = 77

M, C, F, W = 1.0, 20.0, 100.0, 2 * math.pi * 10.0
K_VALUES = [2000.0, 3947.8417604357433, 8000.0]  # the good points of oscillator.sweep.toml, in order
TOL = 1e-4


def fail(msg: str):
    print(f"FAIL: {msg}", flush=True)
    sys.exit(1)


def run(cmd, env=None, expect=0, timeout=300) -> subprocess.CompletedProcess:
    print("$ " + " ".join(str(c) for c in cmd), flush=True)
    p = subprocess.run([str(c) for c in cmd], env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                       timeout=timeout)
    print(p.stdout, end="", flush=True)
    if expect is not None and p.returncode != expect:
        fail(f"{cmd[0]} {cmd[1] if len(cmd) > 1 else ''} exited with {p.returncode}, expected {expect}")
    return p


def closed_form_amplitude(k: float) -> float:
    return F / math.sqrt((k - M * W * W) ** 2 + (C * W) ** 2)


def check_gathered(d: Path, output: str):
    """Numbers of gather.h5 against the closed form; the failed point reported and the others kept."""
    import h5py
    import numpy as np

    with h5py.File(d / "gather.h5", "r") as g:
        if g.attrs["format"] != "nvh-sweep-gather":
            fail(f"{d}/gather.h5: format {g.attrs['format']}")
        status = [s.decode() if isinstance(s, bytes) else s for s in g["status"][:]]
        k = g["parameters/k"][:]
        amp = g["amplitude"][:]  # point, signal, order (peak)
        goal = g["goal"][:]
    if status[:3] != ["ok"] * 3 or not status[3].startswith("failed solve"):
        fail(f"statuses {status}; expected three ok and 'failed solve' for k = -1")
    for i, kv in enumerate(K_VALUES):
        if k[i] != kv:
            fail(f"point {i}: k = {k[i]}, expected {kv}")
        x_ref = closed_form_amplitude(kv)
        for name, j, ref in (("x", 0, x_ref), ("a", 1, x_ref * W * W)):
            err = abs(amp[i, j, 0] - ref) / ref
            print(f"point {i} (k = {kv:.1f} N/m): {name} order 1 = {amp[i, j, 0]:.7g}, closed form {ref:.7g}, "
                  f"relative error {err:.2e} (tolerance {TOL:.0e})")
            if err > TOL:
                fail(f"point {i}: order-1 amplitude of {name} off by {err:.2e}")
        goal_ref = math.sqrt((x_ref ** 2 + (x_ref * W * W) ** 2) / 2) / math.sqrt(2)
        if abs(goal[i] - goal_ref) / goal_ref > TOL:
            fail(f"point {i}: goal {goal[i]} against {goal_ref}")
    if not math.isnan(goal[3]):
        fail("the failed point has a goal value")
    if "point 3 (k = -1.0" not in output or "'force[1].k': expected a number in [0, 1e+20], got -1.0" not in output:
        fail("gather did not report the failed point with its parameters and the log's error line")
    best = int(np.nanargmin(goal))
    if best != 2:
        fail(f"lowest goal at point {best}, expected 2 (the stiffest spring)")
    print("gathered numbers match the closed form; the failed point is reported with its parameters and log")


# ---------------------------------------------------------------------------------------------- local
def test_local(build: Path, work: Path):
    d = work / "local"
    shutil.rmtree(d, ignore_errors=True)
    run([SWEEP, "run", SWEEP_FILE, "-d", d, "--build", build, "-j", "2"], expect=1)  # one point fails
    out = run([SWEEP, "gather", SWEEP_FILE, "-d", d], expect=1).stdout
    check_gathered(d, out)
    # A second run redoes nothing but the failed point (make: only what changed).
    stamp = (d / "points/000/results.h5").stat().st_mtime_ns
    run([SWEEP, "run", SWEEP_FILE, "-d", d, "--build", build, "-j", "2"], expect=1)
    if (d / "points/000/results.h5").stat().st_mtime_ns != stamp:
        fail("an unchanged point was run again")
    # Staleness: change a point's scene after the run; gather must call it stale from the provenance hashes.
    scene = d / "points/001/scene.toml"
    scene.write_text(scene.read_text() + "\n# edited after the run\n")
    out = run([SWEEP, "gather", SWEEP_FILE, "-d", d], expect=1).stdout
    if "point 1 is stale: input scene.toml changed since the run" not in out:
        fail("gather did not tell the edited point as stale")
    print("PASS: local sweep")


# ---------------------------------------------------------------------------------------------- slurm
def skip(msg: str):
    print(f"SKIPPED: {msg}", flush=True)
    sys.exit(SKIP)


def ensure_slurm():
    need = ["sbatch", "sinfo", "slurmctld", "slurmd", "munged"]
    missing = [t for t in need if not shutil.which(t, path=os.environ.get("PATH", "") + ":/usr/sbin:/sbin")]
    if missing and os.geteuid() == 0 and shutil.which("apt-get"):
        print(f"installing slurm-wlm and munge (missing: {', '.join(missing)})", flush=True)
        env = dict(os.environ, DEBIAN_FRONTEND="noninteractive")
        subprocess.run(["apt-get", "install", "-y", "-qq", "--no-install-recommends", "slurm-wlm", "munge"], env=env,
                       stdout=subprocess.DEVNULL, stderr=subprocess.STDOUT)
        missing = [t for t in need if not shutil.which(t, path=os.environ.get("PATH", "") + ":/usr/sbin:/sbin")]
    if missing:
        skip(f"Slurm cannot start: {', '.join(missing)} not installed "
             f"(make -f Makefile.workflow slurm-deps, as root)")
    if os.geteuid() != 0:
        skip("Slurm cannot start: slurmd must run as root to start jobs (run the test as root, as CI does)")


class SlurmCluster:
    """munged, slurmctld and slurmd on localhost in a temporary folder; stopped by their PIDs."""

    def __init__(self, root: Path):
        self.root = root
        self.procs: list[subprocess.Popen] = []
        self.env = dict(os.environ)

    def start(self):
        r = self.root
        shutil.rmtree(r, ignore_errors=True)
        for sub in ("munge", "state", "spool", "log"):
            (r / sub).mkdir(parents=True)
        os.chmod(r, 0o755)
        os.chmod(r / "munge", 0o755)  # 0700 fails: clients must reach the socket
        import pwd
        munge_uid = pwd.getpwnam("munge").pw_uid
        key = r / "munge" / "munge.key"
        key.write_bytes(os.urandom(1024))
        os.chmod(key, 0o400)
        os.chown(key, munge_uid, -1)
        os.chown(r / "munge", munge_uid, -1)
        socket_path = r / "munge" / "munge.socket"
        munged = shutil.which("munged", path="/usr/sbin:/sbin:" + os.environ.get("PATH", ""))
        self.spawn(["runuser", "-u", "munge", "--", munged, "--foreground", f"--socket={socket_path}",
                    f"--key-file={key}", f"--pid-file={r}/munge/munged.pid", f"--log-file={r}/log/munged.log",
                    f"--seed-file={r}/munge/seed", "--num-threads=2"], "munged")
        host = socket.gethostname().split(".")[0]
        base_port = 20000 + os.getpid() % 20000
        conf = r / "slurm.conf"
        conf.write_text(f"""# written by tests/pipelines/test_sweep.py: a single-node cluster on localhost
ClusterName=nvhtest
SlurmctldHost={host}(127.0.0.1)
SlurmctldPort={base_port}
SlurmdPort={base_port + 1}
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket={socket_path}
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
MailProg=/bin/true
ReturnToService=2
StateSaveLocation={r}/state
SlurmdSpoolDir={r}/spool
SlurmctldPidFile={r}/slurmctld.pid
SlurmdPidFile={r}/slurmd.pid
SlurmctldLogFile={r}/log/slurmctld.log
SlurmdLogFile={r}/log/slurmd.log
NodeName={host} NodeAddr=127.0.0.1 CPUs={os.cpu_count() or 2} State=UNKNOWN
PartitionName=test Nodes={host} Default=YES MaxTime=INFINITE State=UP
""")
        self.env["SLURM_CONF"] = str(conf)
        for _ in range(50):  # munged's socket
            if socket_path.exists():
                break
            time.sleep(0.1)
        sbin = "/usr/sbin:/sbin:" + os.environ.get("PATH", "")
        self.spawn([shutil.which("slurmctld", path=sbin), "-D", "-i", "-f", conf], "slurmctld")
        self.spawn([shutil.which("slurmd", path=sbin), "-D", "-f", conf], "slurmd")
        deadline = time.time() + 30
        state = ""
        while time.time() < deadline:
            p = subprocess.run(["sinfo", "-h", "-N", "-o", "%T"], env=self.env, stdout=subprocess.PIPE,
                               stderr=subprocess.STDOUT, text=True)
            state = p.stdout.strip()
            if p.returncode == 0 and state == "idle":
                print(f"slurm: node {host} idle (slurm.conf in {r})", flush=True)
                return True
            if any(proc.poll() is not None for proc in self.procs):
                break
            time.sleep(0.5)
        logs = "".join(f"\n--- {f.name}\n" + "\n".join(f.read_text(errors="replace").splitlines()[-8:])
                       for f in sorted((r / "log").glob("*.log")))
        dead = [f"{proc.args[0] if isinstance(proc.args, list) else proc.args} exited {proc.returncode}"
                for proc in self.procs if proc.poll() is not None]
        print(f"slurm did not come up: sinfo says '{state}'; {'; '.join(dead)}{logs}", flush=True)
        return False

    def spawn(self, cmd, name):
        log = open(self.root / "log" / f"{name}.stdout", "w")
        self.procs.append(subprocess.Popen([str(c) for c in cmd], env=self.env, stdout=log,
                                           stderr=subprocess.STDOUT, start_new_session=True))

    def stop(self):
        for proc in reversed(self.procs):  # slurmd, slurmctld, munged: each by its own PID
            if proc.poll() is None:
                proc.send_signal(signal.SIGTERM)
                try:
                    proc.wait(timeout=10)
                except subprocess.TimeoutExpired:
                    proc.kill()
                    proc.wait()
        print("slurm: daemons stopped (PIDs " + ", ".join(str(p.pid) for p in self.procs) + ")", flush=True)


def test_slurm(build: Path, work: Path):
    import h5py
    import numpy as np

    ensure_slurm()
    cluster = SlurmCluster(Path("/tmp") / f"nvh-slurm-{os.getpid()}")
    try:
        if not cluster.start():
            skip("Slurm cannot start on this machine (see the daemons' messages above)")
        d = work / "slurm"
        shutil.rmtree(d, ignore_errors=True)
        p = run([SWEEP, "submit", SWEEP_FILE, "-d", d, "--build", build, "--max-parallel", "2", "--wait"],
                env=cluster.env, expect=None, timeout=120)
        if "sbatch --array=0-3%2" not in p.stdout:
            fail("the sweep was not submitted as one job array --array=0-3%2")
        if not (d / "slurm" / "job_id").exists():
            fail("sbatch did not accept the job array")
        out = run([SWEEP, "gather", SWEEP_FILE, "-d", d], env=cluster.env, expect=1).stdout
        check_gathered(d, out)
        task_logs = sorted((d / "slurm").glob("*_*.out"))
        if len(task_logs) != 4:
            fail(f"expected 4 array task outputs in {d}/slurm, found {len(task_logs)}")
        jobs = {(d / f"points/{i:03d}/log.txt").read_text().splitlines()[1].split()[-1] for i in range(4)}
        print(f"array tasks: {sorted(jobs)}")
    finally:
        cluster.stop()
        shutil.rmtree(cluster.root, ignore_errors=True)
    # The same sweep run locally: the gathered numbers must be equal.
    local = work / "local_ref"
    shutil.rmtree(local, ignore_errors=True)
    run([SWEEP, "run", SWEEP_FILE, "-d", local, "--build", build, "-j", "2"], expect=1)
    run([SWEEP, "gather", SWEEP_FILE, "-d", local], expect=1)
    with h5py.File(d / "gather.h5", "r") as a, h5py.File(local / "gather.h5", "r") as b:
        for name in ("amplitude", "phase_deg", "goal", "speed_rpm"):
            x, y = a[name][:], b[name][:]
            same = np.array_equal(np.isnan(x), np.isnan(y)) and np.allclose(x[~np.isnan(x)], y[~np.isnan(y)],
                                                                            rtol=1e-12, atol=0)
            if not same:
                fail(f"gather.h5 /{name}: the Slurm run differs from the local run")
        print("the Slurm run's gathered amplitude, phase, goal and speed equal the local run's (rtol 1e-12)")
    print("PASS: Slurm sweep")


def main():
    if len(sys.argv) != 4 or sys.argv[1] not in ("local", "slurm"):
        print(__doc__)
        return 2
    build, work = Path(sys.argv[2]).resolve(), Path(sys.argv[3]).resolve()
    work.mkdir(parents=True, exist_ok=True)
    (test_local if sys.argv[1] == "local" else test_slurm)(build, work)
    return 0


if __name__ == "__main__":
    sys.exit(main())
