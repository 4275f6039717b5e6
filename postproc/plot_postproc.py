#!/usr/bin/python3
"""Plots of a postproc output file (docs/postproc.md section 6), drawn with Debian's python3-matplotlib.

    /usr/bin/python3 postproc/plot_postproc.py POST.h5 OUTDIR

Writes PNGs into OUTDIR, one per figure, every axis labelled with its unit and every level with its dB
reference (read from the file's attributes):
  spectrum_<signal>.png      level spectrum on a dB axis
  spectrum_overlay.png       all signals of the file on one axis (e.g. measured UFF58 against simulated)
  octave_<signal>.png        fractional-octave bar chart with the overall level
  octave_leq_<signal>.png    band levels over time (Leq per interval), when present
  order_cuts_<signal>.png    the strongest orders against rpm
  campbell_<signal>.png      rpm x frequency colour map with order lines, when present
  order_cut_files.png        mean order amplitudes of several files against their rpm (orders --cut)
  erp_<body>.png             ERP per band (bars) with each region's contribution, and the area-mean
                             surface velocity level (postproc erp)
  history_<signal>.png       the windowed samples against the shaft angle in the cycle (or the crank angle,
                             or time) (postproc history)
  history_all.png            every signal of the file in a column of axes sharing that abscissa
"""
import os
import sys

import matplotlib

matplotlib.use("Agg")
import h5py  # noqa: E402
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def text(value):
    return value.decode() if isinstance(value, bytes) else str(value)


def save(fig, outdir, name):
    path = os.path.join(outdir, name)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    print(f"[plot] wrote {path}")


def plot_spectra(group, outdir):
    overlay, ax_all = plt.subplots(figsize=(9, 5))
    ylabel = None
    for name, g in group.items():
        f = g["frequency_hz"][()]
        level = g["level_db"][()]
        units = text(g["level_db"].attrs["units"])
        ylabel = f"level [{units}]"
        fig, ax = plt.subplots(figsize=(9, 5))
        ax.plot(f[1:], level[1:], lw=0.8)
        ax.set_xscale("log")
        ax.set_xlabel("frequency [Hz]")
        ax.set_ylabel(ylabel)
        ax.set_title(f"{name}: {text(g['amplitude'].attrs['spectrum_type'])} spectrum, "
                     f"{text(g.attrs['window'])}, df = {g.attrs['resolution_hz']:.3g} Hz")
        ax.grid(True, which="both", alpha=0.3)
        save(fig, outdir, f"spectrum_{name}.png")
        ax_all.plot(f[1:], level[1:], lw=0.8, label=name)
    ax_all.set_xscale("log")
    ax_all.set_xlabel("frequency [Hz]")
    ax_all.set_ylabel(ylabel or "level [dB]")
    ax_all.set_title("spectra")
    ax_all.grid(True, which="both", alpha=0.3)
    ax_all.legend()
    save(overlay, outdir, "spectrum_overlay.png")


def plot_octaves(group, outdir):
    for name, g in group.items():
        nominal = g["nominal_hz"][()]
        level = g["level_db"][()]
        units = text(g["level_db"].attrs["units"])
        weighting = text(g.attrs["weighting"])
        fig, ax = plt.subplots(figsize=(10, 5))
        labels = [f"{v:g}" for v in nominal]
        ax.bar(range(len(level)), level - level.min() + 10, bottom=level.min() - 10, color="tab:blue")
        ax.set_xticks(range(len(level)))
        ax.set_xticklabels(labels, rotation=90)
        ax.set_xlabel("band, nominal mid-band frequency [Hz]")
        ax.set_ylabel(f"level [{units}], weighting {weighting}")
        overall = float(g["overall_level_db"][()])
        ax.set_title(f"{name}: 1/{g.attrs['fraction']}-octave levels, overall {overall:.1f} dB")
        ax.grid(True, axis="y", alpha=0.3)
        save(fig, outdir, f"octave_{name}.png")
        if "leq_db" in g:
            leq = g["leq_db"][()]
            t = g["interval_start_s"][()]
            fig, ax = plt.subplots(figsize=(10, 5))
            mesh = ax.pcolormesh(np.arange(len(nominal) + 1), np.append(t, t[-1] + g.attrs["interval_s"]), leq,
                                 shading="flat", cmap="viridis")
            ax.set_xticks(np.arange(len(nominal)) + 0.5)
            ax.set_xticklabels(labels, rotation=90)
            ax.set_xlabel("band [Hz]")
            ax.set_ylabel("time [s]")
            fig.colorbar(mesh, label=f"Leq [{units}]")
            ax.set_title(f"{name}: band levels over time ({g.attrs['interval_s']:g} s intervals)")
            save(fig, outdir, f"octave_leq_{name}.png")


def plot_orders(group, outdir):
    for name, g in group.items():
        if name == "cut":
            order = g["order"][()]
            amp = g["amplitude"][()]
            rpm = g["rpm"][()]
            fig, ax = plt.subplots(figsize=(9, 5))
            strongest = np.argsort(amp.max(axis=0))[::-1][:6]
            for k in sorted(strongest):
                ax.plot(rpm, amp[:, k], "o-", label=f"order {order[k]:g}")
            ax.set_xlabel("shaft speed [rpm]")
            ax.set_ylabel("mean peak amplitude [signal unit]")
            ax.set_title("order cuts over the result files")
            ax.grid(True, alpha=0.3)
            ax.legend()
            save(fig, outdir, "order_cut_files.png")
            continue
        order = g["order"][()]
        level = g["level_db"][()]
        rpm = g["rpm"][()]
        units = text(g["level_db"].attrs["units"])
        strongest = np.argsort(level[:, 1:].max(axis=0))[::-1][:6] + 1
        fig, ax = plt.subplots(figsize=(9, 5))
        for k in sorted(strongest):
            ax.plot(rpm, level[:, k], lw=1.0, label=f"order {order[k]:g}")
        ax.set_xlabel("shaft speed [rpm]")
        ax.set_ylabel(f"level [{units}]")
        ax.set_title(f"{name}: order cuts ({g.attrs['cycle_deg']:g} deg cycles)")
        ax.grid(True, alpha=0.3)
        ax.legend()
        save(fig, outdir, f"order_cuts_{name}.png")
        if "campbell" in g:
            c = g["campbell"]
            f = c["frequency_hz"][()]
            r = c["rpm"][()]
            lv = c["level_db"][()]
            fig, ax = plt.subplots(figsize=(9, 6))
            if len(r) > 1:
                mesh = ax.pcolormesh(f, r, lv, shading="nearest", cmap="magma",
                                     vmin=np.percentile(lv, 5), vmax=lv.max())
                fig.colorbar(mesh, label=f"level [{text(c['level_db'].attrs['units'])}]")
            for k in (0.5, 1, 2, 3, 4, 6, 8):
                ax.plot(k * r / 60.0, r, "w--", lw=0.6)
                if k * r[-1] / 60.0 < f[-1]:
                    ax.text(k * r[-1] / 60.0, r[-1], f"{k:g}", color="w", fontsize=8)
            ax.set_xlim(f[0], f[-1])
            ax.set_xlabel("frequency [Hz]")
            ax.set_ylabel("shaft speed [rpm]")
            ax.set_title(f"{name}: Campbell diagram with order lines")
            save(fig, outdir, f"campbell_{name}.png")


def plot_erp(group, outdir):
    for name, g in group.items():
        nominal = g["nominal_hz"][()]
        erp = g["erp_level_db"][()]
        velocity = g["velocity_level_db"][()]
        x = np.arange(len(nominal))
        labels = [f"{v:g}" for v in nominal]
        fig, (ax, bx) = plt.subplots(2, 1, figsize=(10, 8), sharex=True)
        bottom = min(erp.min(), min((r["erp_level_db"][()].min() for r in g.get("regions", {}).values()),
                                    default=erp.min())) - 10
        bottom = max(bottom, erp.max() - 100)  # 100 dB of range: round-off floors stay off the chart
        ax.bar(x, erp - bottom, bottom=bottom, color="lightgray", label="whole surface")
        for region, r in g.get("regions", {}).items():
            ax.plot(x, r["erp_level_db"][()], "o-", label=region)
        ax.set_ylim(bottom, erp.max() + 5)
        ax.set_ylabel(f"ERP [{text(g['erp_level_db'].attrs['units'])}]")
        overall = float(g["overall_erp_level_db"][()])
        ax.set_title(f"{name}: equivalent radiated power, 1/{g.attrs['fraction']} octaves, overall "
                     f"{overall:.1f} dB (rho c = {g.attrs['rho_c_kg_m2_s']:.1f} kg/(m^2 s))")
        ax.grid(True, axis="y", alpha=0.3)
        ax.legend(fontsize=8)
        bx.plot(x, velocity, "k.-", label="whole surface (area mean)")
        for region, r in g.get("regions", {}).items():
            bx.plot(x, r["velocity_level_db"][()], ".-", label=region)
        bx.set_ylim(max(velocity.min(), velocity.max() - 100) - 5, velocity.max() + 5)
        bx.set_ylabel(f"normal velocity [{text(g['velocity_level_db'].attrs['units'])}]")
        bx.set_xticks(x)
        bx.set_xticklabels(labels, rotation=90)
        bx.set_xlabel("band, nominal mid-band frequency [Hz]")
        bx.grid(True, axis="y", alpha=0.3)
        bx.legend(fontsize=8)
        save(fig, outdir, f"erp_{name}.png")


def history_abscissa(g):
    for key, label in (("cycle_angle_deg", "crank angle in the cycle [deg]"), ("crank_angle_deg", "crank angle [deg]")):
        if key in g:
            return g[key][()], label
    return g["time_s"][()], "time [s]"


def plot_history(group, outdir):
    names = list(group.keys())
    fig_all, axes = plt.subplots(len(names), 1, figsize=(9, 2.2 * len(names) + 1), sharex=True, squeeze=False)
    for ax_all, name in zip(axes[:, 0], names):
        g = group[name]
        x, xlabel = history_abscissa(g)
        y = g["value"][()]
        units = text(g["value"].attrs["units"])
        fig, ax = plt.subplots(figsize=(9, 4.5))
        ax.plot(x, y, lw=0.8)
        ax.set_xlabel(xlabel)
        ax.set_ylabel(f"{name} [{units}]")
        ax.set_title(f"{name}: {len(y)} samples, {g.attrs['window_start_s']:.6g} to {g.attrs['window_end_s']:.6g} s")
        ax.grid(True, alpha=0.3)
        save(fig, outdir, f"history_{name}.png")
        ax_all.plot(x, y, lw=0.8)
        ax_all.set_ylabel(f"{name}\n[{units}]", fontsize=8)
        ax_all.grid(True, alpha=0.3)
    axes[-1, 0].set_xlabel(xlabel)
    save(fig_all, outdir, "history_all.png")


def plot_impacts(group, outdir):
    for name in group:
        g = group[name]
        angle = "force_crank_angle_deg" in g
        x = g["force_crank_angle_deg"][()] if angle else g["force_time_s"][()]
        xi = g["crank_angle_deg"][()] if angle else g["time_s"][()]
        force = g["force"][()]
        v = g["velocity"][()]
        energy = g["energy_j"][()] if "energy_j" in g else None
        fig, ax = plt.subplots(figsize=(9, 4.5))
        ax.plot(x, force, lw=0.8)
        ax.axhline(g.attrs["direction"] * g.attrs["threshold"], color="0.6", lw=0.6, ls="--", label="threshold")
        for k, at in enumerate(xi):
            ax.axvline(at, color="C3", lw=0.7)
            label = f"{v[k]:.3g} {text(g['velocity'].attrs['units'])}"
            if energy is not None:
                label += f", {energy[k] * 1e3:.3g} mJ"
            ax.annotate(label, (at, 0), xytext=(3, 8 + 12 * (k % 3)), textcoords="offset points", fontsize=7,
                        color="C3")
        ax.set_xlabel("crank angle [deg]" if angle else "time [s]")
        ax.set_ylabel(f"{name} [{text(g['force'].attrs['units'])}]")
        ax.set_title(f"{name}: {len(xi)} impact(s); velocity at impact" + (" and energy" if energy is not None else ""))
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=8)
        save(fig, outdir, f"impacts_{name}.png")


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    path, outdir = sys.argv[1], sys.argv[2]
    os.makedirs(outdir, exist_ok=True)
    with h5py.File(path, "r") as f:
        if "spectrum" in f:
            plot_spectra(f["spectrum"], outdir)
        if "octave" in f:
            plot_octaves(f["octave"], outdir)
        if "orders" in f:
            plot_orders(f["orders"], outdir)
        if "erp" in f:
            plot_erp(f["erp"], outdir)
        if "history" in f:
            plot_history(f["history"], outdir)
        if "impacts" in f:
            plot_impacts(f["impacts"], outdir)


if __name__ == "__main__":
    main()
