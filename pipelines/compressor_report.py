#!/usr/bin/python3
"""The hermetic compressor demo's report: the table of effective accelerations at the tops of the four
springs at the running frequency (amplitude and phase in x, y, z, as in Tables 1-2 of the paper
../shared/papers/002), the force into the shell, plots, and SUMMARY.txt saying what was computed and
where each file is.

    compressor_report.py DIR     # DIR holds compressor.results.h5 and the postproc files of Makefile.workflow

Reads only files written by solve and postproc (no analysis of its own beyond unit conversion):
  compressor.harmonics.h5  postproc stats --harmonics 1,2,3: per-cycle order amplitude (peak) and phase
  compressor.results.h5    solve's results: speed, time histories for the plots, provenance
Writes DIR/table.txt, DIR/table.csv, DIR/plots/{accelerations,table,shell_force}.png, DIR/SUMMARY.txt.

"Effective" is the RMS value of the harmonic, peak / sqrt(2) (the paper: "the effective value of the FFT
magnitude diagram at the current frequency"). Phases are given against spring 1's x (the paper's
reference, which shows 0 there) and against the crank angle (cosine phase, 0 deg = top dead centre).
"""
import math
import sys
from pathlib import Path

import h5py
import numpy as np

# The paper's Table 2 (computed, Adams) and Table 1 (measured): amplitude m/s^2, phase deg, for x, y, z.
PAPER_COMPUTED = {1: [(0.4, 0), (0.6, -130), (1.2, -120)], 2: [(0.4, 0), (0.5, 110), (1.2, -60)],
                  3: [(0.6, -70), (0.5, 125), (1.2, 55)], 4: [(0.6, -70), (0.6, -120), (1.1, 110)]}
PAPER_MEASURED = {1: [(0.5, 0), (0.6, -140), (1.3, -130)], 2: [(0.5, 0), (0.6, 106), (1.1, -50)],
                  3: [(0.7, -80), (0.5, 130), (1.3, 50)], 4: [(0.7, -80), (0.7, -130), (1.1, 130)]}
AXES = ("x", "y", "z")


def wrap(deg: float) -> float:
    """An angle in [-180, 180) deg (rounding noise below 1e-9 deg counts as 0)."""
    w = (deg + 180.0) % 360.0 - 180.0
    return 0.0 if abs(w) < 1e-9 else w


def harmonic(stats: h5py.File, name: str, order: int = 1) -> tuple[float, float]:
    """(peak amplitude, phase in deg) of one order of a signal in a postproc stats file."""
    g = stats["stats"][name]
    orders = list(g["harmonic_order"][:])
    k = orders.index(order)
    return float(g["harmonic_amplitude"][k]), float(g["harmonic_phase_deg"][k])


def main(folder: Path) -> int:
    results = folder / "compressor.results.h5"
    harmonics = folder / "compressor.harmonics.h5"
    plots = folder / "plots"
    plots.mkdir(exist_ok=True)
    with h5py.File(results, "r") as r:
        t = r["time"][:]
        angle = r["crank_angle_deg"][:]
        cycles = (angle[-1] - angle[0]) / 360.0
        speed_rpm = (angle[-1] - angle[0]) / (t[-1] - t[0]) / 6.0
        status = r.attrs["status"]
        tops = {k: r[f"markers/unit.top{k}/acceleration"][:] for k in range(1, 5)}
        seats = {k: -r[f"joints/seat{k}/reaction_force"][:] for k in range(1, 5)}  # on the shell
        pipe = -r["joints/pipe_exit/reaction_force"][:]
    f_run = speed_rpm / 60.0

    with h5py.File(harmonics, "r") as s:
        acc = {(k, c): harmonic(s, f"top{k}_{c}") for k in range(1, 5) for c in AXES}
        acc2 = {(k, c): harmonic(s, f"top{k}_{c}", 2) for k in range(1, 5) for c in AXES}
        force = {(k, c): harmonic(s, f"seat{k}_{c}") for k in range(1, 5) for c in AXES}
        force.update({("pipe", c): harmonic(s, f"pipe_{c}") for c in AXES})
    ref_phase = acc[(1, "x")][1]

    # ---- the table (text and CSV)
    lines = [f"Effective acceleration at the tops of the four springs at the running frequency "
             f"({f_run:.2f} Hz, {speed_rpm:.0f} rpm): RMS m/s^2 and phase deg against spring 1 x",
             "(in brackets: the paper's Table 2, computed with Adams, and Table 1, measured)", "",
             f"{'':10}" + "".join(f"{c:^28}" for c in "XYZ"),
             f"{'':10}" + f"{'RMS':>7}{'phase':>7}  {'(T2/T1)':<12}" * 3]
    csv = ["spring,axis,rms_m_s2,phase_deg_vs_spring1_x,phase_deg_vs_crank,order2_rms_m_s2,"
           "paper_computed_rms,paper_computed_phase,paper_measured_rms,paper_measured_phase"]
    for k in range(1, 5):
        row = f"Spring {k}:"
        for i, c in enumerate(AXES):
            a, p = acc[(k, c)]
            pc, pm = PAPER_COMPUTED[k][i], PAPER_MEASURED[k][i]
            rel = wrap(p - ref_phase)
            row += f"{a / math.sqrt(2):7.2f}{int(round(rel)):7d}  ({pc[0]:.1f}/{pm[0]:.1f})".ljust(28)
            csv.append(f"{k},{c},{a / math.sqrt(2):.5g},{rel:.2f},{wrap(p):.2f},{acc2[(k, c)][0] / math.sqrt(2):.5g},"
                       f"{pc[0]},{pc[1]},{pm[0]},{pm[1]}")
        lines.append(row.rstrip())
    lines += ["", "Force into the shell at the running frequency (RMS N; on the shell, global axes):"]
    csv_force = ["point,axis,rms_n,phase_deg_vs_crank"]
    for key in [1, 2, 3, 4, "pipe"]:
        label = f"seat {key}" if key != "pipe" else "pipe exit"
        # the reaction is on the spring/pipe (body i); the shell gets its negative: phase + 180 deg
        vals = [(force[(key, c)][0] / math.sqrt(2), wrap(force[(key, c)][1] + 180.0)) for c in AXES]
        lines.append(f"  {label:10}" + "".join(f"  {c}: {v[0]:7.3f} N {v[1]:6.0f} deg" for c, v in zip(AXES, vals)))
        csv_force += [f"{key},{c},{v[0]:.5g},{v[1]:.2f}" for c, v in zip(AXES, vals)]
    table = "\n".join(lines) + "\n"
    (folder / "table.txt").write_text(table)
    (folder / "table.csv").write_text("\n".join(csv) + "\n")
    (folder / "shell_force.csv").write_text("\n".join(csv_force) + "\n")

    # ---- plots
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    last = t >= t[-1] - 3.0 / f_run  # the last three revolutions
    fig, axs = plt.subplots(3, 1, figsize=(9, 8), sharex=True)
    for i, c in enumerate(AXES):
        for k in range(1, 5):
            axs[i].plot(angle[last] - angle[last][0], tops[k][last, i], label=f"spring {k}")
        axs[i].set_ylabel(f"a_{c} [m/s^2]")
        axs[i].grid(alpha=0.3)
    axs[0].legend(ncol=4, fontsize=8)
    axs[-1].set_xlabel("crank angle over the last three revolutions [deg]")
    fig.suptitle(f"Acceleration at the tops of the springs ({speed_rpm:.0f} rpm)")
    fig.tight_layout()
    fig.savefig(plots / "accelerations.png", dpi=110)
    plt.close(fig)

    fig, axs = plt.subplots(1, 3, figsize=(11, 3.8), sharey=True)
    w = 0.27
    for i, c in enumerate(AXES):
        x = np.arange(1, 5)
        axs[i].bar(x - w, [acc[(k, c)][0] / math.sqrt(2) for k in x], w, label="this model")
        axs[i].bar(x, [PAPER_COMPUTED[k][i][0] for k in x], w, label="paper, Adams (Table 2)")
        axs[i].bar(x + w, [PAPER_MEASURED[k][i][0] for k in x], w, label="paper, measured (Table 1)")
        axs[i].set_title(c.upper())
        axs[i].set_xticks(x, [f"spring {k}" for k in x], fontsize=8)
        axs[i].grid(alpha=0.3, axis="y")
    axs[0].set_ylabel(f"effective acceleration at {f_run:.1f} Hz [m/s^2]")
    axs[0].legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(plots / "table.png", dpi=110)
    plt.close(fig)

    fig, axs = plt.subplots(3, 1, figsize=(9, 8), sharex=True)
    total = sum(seats.values()) + pipe
    for i, c in enumerate(AXES):
        for k in range(1, 5):
            axs[i].plot(angle[last] - angle[last][0], seats[k][last, i], lw=0.8, label=f"seat {k}")
        axs[i].plot(angle[last] - angle[last][0], pipe[last, i], lw=0.8, label="pipe exit")
        axs[i].plot(angle[last] - angle[last][0], total[last, i], "k", lw=1.2, label="sum")
        axs[i].set_ylabel(f"F_{c} [N]")
        axs[i].grid(alpha=0.3)
    axs[0].legend(ncol=6, fontsize=8)
    axs[-1].set_xlabel("crank angle over the last three revolutions [deg]")
    fig.suptitle("Force transmitted to the shell (springs and discharge pipe)")
    fig.tight_layout()
    fig.savefig(plots / "shell_force.png", dpi=110)
    plt.close(fig)

    # ---- summary
    d = folder
    summary = f"""Hermetic compressor study (the paper ../shared/papers/002, "Analysis of dynamic of a virtual compressor")
==========================================================================================================
Computed: the motor-compressor unit on four coil springs (flexible beams) and a discharge pipe (flexible
beam) inside a flexible shell on rubber grommets; crankshaft in two short journal bearings, driven by an
induction motor's torque-speed curve against the gas force of an R134a cycle. Run: {cycles:.0f} revolutions
({t[-1] - t[0]:.3f} s, status {status}), mean speed {speed_rpm:.0f} rpm = {f_run:.2f} Hz.

{table}
Files (all in {d}/):
  compressor.toml            the scene (from testdata/compressor/compressor.toml)
  spring.h5 pipe.h5 shell.h5 superelements from condense (testdata/compressor/*.toml)
  compressor.results.h5      solve's results: /markers/unit.top1..4/acceleration (spring tops), /joints/seat1..4
                             and /joints/pipe_exit/reaction_force (forces into the shell), bearings, motor
  compressor.harmonics.h5    postproc stats: orders 1-3, amplitude and phase of every channel
  compressor.spectra.h5      postproc spectrum: RMS spectra of the 12 spring-top accelerations (csv/, plots/)
  compressor.shellforce.h5   postproc spectrum: the forces into the shell (csv/, plots/shellforce/)
  table.txt table.csv        the table above; shell_force.csv: the first-order forces into the shell
  plots/table.png            this model against the paper's Tables 1-2
  plots/accelerations.png    spring-top accelerations over the last three revolutions
  plots/shell_force.png      forces into the shell over the last three revolutions
  plots/spectrum_*.png       spectra (postproc)
Next: make -f Makefile.workflow balancing (counterweight sweep), speed-sweep (order cuts); docs/pipelines.md.
"""
    (folder / "SUMMARY.txt").write_text(summary)
    return 0


if __name__ == "__main__":
    if len(sys.argv) != 2:
        print(__doc__, file=sys.stderr)
        sys.exit(2)
    sys.exit(main(Path(sys.argv[1])))
