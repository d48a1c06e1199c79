#!/usr/bin/env python3
"""Figures of examples/lunar_shock_channel (paper 001 figs. 1, 6, 9, 15, 16).

usage: plot.py [OUT_DIR]   (default out/lunar_shock_channel)

Reads the CSV files written by `lunar_shock_channel validation` and `... channel` (whichever
exist; the grid validation's from OUT_DIR, else the committed results/validation) and writes PNG
files to OUT_DIR:
  validation.png        c_w / c_w(1 m/s) vs v_im, log-log, per material and load (001 fig. 1)
  grid_preload.png      grid plateau / table 1's c_0 against the static contact load, with the
                        loads of the grid standing under Earth and lunar gravity
  channel_speeds_*.png  depth-averaged c_w and c_p vs v_p (001 fig. 9)
  channel_dz_*.png      bed-height change and delta_m/delta_0 vs y (001 figs. 15, 16)
  channel_arrivals_*.png  sensor position vs arrival time at mid depth (001 fig. 6)
  study_speeds.png      the paper-scale study (results/loose, results/medium): c_w, c_p,
                        delta_m/delta_0 and Delta z against v_p, with 001 table 8 beside them
                        (drawn when at least one case file exists)
"""
import csv
import math
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "common"))
from result_csv import read_table  # noqa: E402  (examples/common/result_csv.py)

import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def read(path):
    """Columns of a CSV file keyed by the name without its unit."""
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    names = [h.split(" [")[0] for h in rows[0]]
    cols = {n: [] for n in names}
    for r in rows[1:]:
        for n, v in zip(names, r):
            cols[n].append(float(v))
    return cols


def finite(*arrays):
    keep = [all(math.isfinite(a[k]) for a in arrays) for k in range(len(arrays[0]))]
    return [[a[k] for k in range(len(a)) if keep[k]] for a in arrays]


def load_name(r):
    if r["load"] == "gravity":
        return "g = %g m/s$^2$" % r["gravity"]
    return "F0 = %.3g N" % r["preload"]


def plot_validation(res, out):
    """c_w / c_w(1 m/s) against v_im for every material and load (001 fig. 1)."""
    path = os.path.join(res, "grid_speeds.csv")
    if not os.path.exists(path):
        return
    rows = read_table(path)
    fig, ax = plt.subplots(figsize=(6, 4.2))
    for key in dict.fromkeys((r["material"], load_name(r)) for r in rows):
        sel = [r for r in rows if (r["material"], load_name(r)) == key]
        v, c = finite([r["v_im"] for r in sel], [r["c_w_over_c_w_1"] for r in sel])
        ax.loglog(v, c, "o-" if key[0] == "steel" else "s--", ms=3, label="%s, %s" % key)
    vv = [1e-1, 10]
    ax.loglog(vv, [x ** 0.2 for x in vv], "k:", label=r"$v^{1/5}$")
    ax.set_xlabel(r"$v_{im}$ [m/s]")
    ax.set_ylabel(r"$c_w / c_w(1\,\mathrm{m/s})$")
    ax.legend(fontsize=7)
    ax.set_title("5 x 5 grid: acoustic plateau and shock branch")
    fig.tight_layout()
    fig.savefig(os.path.join(out, "validation.png"), dpi=130)
    plt.close(fig)


def plot_grid_preload(res, out):
    """Measured plateau against the static contact load, in particle weights under Earth gravity,
    with table 1's c_0 and the loads of the grid standing under Earth and lunar gravity."""
    path = os.path.join(res, "grid_preload_sweep.csv")
    if not os.path.exists(path):
        return
    rows = read_table(path)
    summ = os.path.join(res, "grid_summary.csv")
    grav = [r for r in read_table(summ) if r["load"] == "gravity"] if os.path.exists(summ) else []
    fig, ax = plt.subplots(figsize=(6, 4.2))
    for k, mat in enumerate(dict.fromkeys(r["material"] for r in rows)):
        sel = [r for r in rows if r["material"] == mat]
        col = "C%d" % k
        w = [r["preload_over_weight_earth"] for r in sel]
        ax.loglog(w, [r["c0_measured"] / r["c0_paper"] for r in sel], "o-", color=col, ms=3,
                  label="%s: measured plateau" % mat)
        ax.loglog(w, [r["c0_chain"] / r["c0_paper"] for r in sel], ":", color=col, label="%s: chain formula" % mat)
        for r in grav:
            if r["material"] != mat:
                continue
            wt = sel[0]["preload"] / sel[0]["preload_over_weight_earth"]  # m g_Earth [N]
            lo, hi = r["fitted_contact_load_min"] / wt, r["fitted_contact_load_max"] / wt
            ax.axvspan(lo, hi, color=col, alpha=0.15)
            ax.plot([math.sqrt(lo * hi)], [r["measured_over_paper"]], "*", color=col, ms=10)
            ax.annotate("g = %g" % r["gravity"], (math.sqrt(lo * hi), r["measured_over_paper"]), fontsize=7,
                        xytext=(4, -10), textcoords="offset points", color=col)
    ax.axhline(1.0, color="k", lw=0.8)
    ax.set_xlabel(r"static contact load $F_0$ / particle weight $m g_\mathrm{Earth}$")
    ax.set_ylabel(r"plateau $c_0$ / table 1's $c_0$")
    ax.set_title("5 x 5 grid: plateau against the pre-load (stars: grid standing under g)", fontsize=9)
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "grid_preload.png"), dpi=130)
    plt.close(fig)


def plot_channel(out, tag):
    summ = os.path.join(out, "channel_summary_%s.csv" % tag)
    if not os.path.exists(summ):
        return
    s = read(summ)
    fig, ax = plt.subplots(figsize=(5.5, 4))
    ax.errorbar(s["v_p"], s["c_w"], yerr=s["c_w_sd"], fmt="o-", label="$c_w$ (initial)")
    ax.errorbar(s["v_p"], s["c_p"], yerr=s["c_p_sd"], fmt="s-", label="$c_p$ (propagating)")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("$v_p$ [m/s]")
    ax.set_ylabel("wave speed [m/s]")
    ax.legend()
    fig.tight_layout()
    fig.savefig(os.path.join(out, "channel_speeds_%s.png" % tag), dpi=130)
    plt.close(fig)

    cols = read(os.path.join(out, "channel_columns_%s.csv" % tag))
    fig, (a1, a2) = plt.subplots(2, 1, figsize=(6, 6), sharex=True)
    for vp in sorted(set(cols["v_p"])):
        idx = [k for k, x in enumerate(cols["v_p"]) if x == vp]
        y = [cols["y"][k] * 100 for k in idx]
        dz = [cols["dz"][k] * 1e3 for k in idx]
        dr = [cols["delta_m_over_delta_0"][k] for k in idx]
        a1.plot(*finite(y, dz), ".-", label="$v_p$ = %g m/s" % vp)
        a2.plot(*finite(y, dr), ".-")
    a1.axhline(0, color="k", lw=0.5)
    a1.set_ylabel(r"$\Delta z$ [mm]")
    a1.legend(fontsize=8)
    a2.set_ylabel(r"$\delta_m/\delta_0$")
    a2.set_xlabel("y [cm]")
    fig.tight_layout()
    fig.savefig(os.path.join(out, "channel_dz_%s.png" % tag), dpi=130)
    plt.close(fig)

    arr = read(os.path.join(out, "channel_arrivals_%s.csv" % tag))
    depths = sorted(set(arr["depth"]))
    mid = depths[len(depths) // 2]
    fig, ax = plt.subplots(figsize=(5.5, 4))
    for vp in sorted(set(arr["v_p"])):
        idx = [k for k, x in enumerate(arr["v_p"]) if x == vp and arr["depth"][k] == mid]
        t = [arr["arrival"][k] * 1e3 for k in idx]
        y = [arr["y"][k] * 100 for k in idx]
        ax.plot(*finite(t, y), "o", ms=3, label="$v_p$ = %g m/s" % vp)
    ax.set_xlabel("arrival time [ms]")
    ax.set_ylabel("sensor position y [cm]")
    ax.set_title("depth %.2f cm" % (mid * 100))
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "channel_arrivals_%s.png" % tag), dpi=130)
    plt.close(fig)


def plot_study(out):
    """The paper-scale study's cases beside 001 table 8 (report.py holds the paper's values)."""
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    import report  # noqa: E402

    rows = {p: report.study_rows(p) for p in ("loose", "medium")}
    if not any(rows.values()):
        return
    fig, axes = plt.subplots(1, 3, figsize=(13, 4))
    colours = {"loose": "C0", "medium": "C1"}
    for p, rs in rows.items():
        paper = report.PAPER_T8[p]
        vp = [report.exponent_value(r[0]) for r in paper]
        d0 = report.PAPER_DELTA0[p]
        axes[0].errorbar(vp, [r[1] for r in paper], [r[2] for r in paper], fmt="s", mfc="none", color=colours[p],
                         label="001 %s c_w" % p)
        axes[0].errorbar(vp, [r[3] for r in paper], [r[4] for r in paper], fmt="^", mfc="none", color=colours[p],
                         label="001 %s c_p" % p)
        axes[1].plot(vp, [r[5] / d0 for r in paper], "s", mfc="none", color=colours[p], label="001 %s" % p)
        axes[2].errorbar(vp, [r[7] for r in paper], [r[8] for r in paper], fmt="s", mfc="none", color=colours[p],
                         label="001 %s" % p)
        mine = sorted((r for r in rs if r["wave"] == "P" and float(r["rolling_damping"]) == 2.0),
                      key=lambda r: float(r["v_p"]))
        if not mine:
            continue
        v = [float(r["v_p"]) for r in mine]
        axes[0].errorbar(v, [float(r["c_w"]) for r in mine], [float(r["c_w_sd"]) for r in mine], fmt="s-",
                         color=colours[p], label="ours %s c_w" % p)
        axes[0].errorbar(v, [float(r["c_p"]) for r in mine], [float(r["c_p_sd"]) for r in mine], fmt="^-",
                         color=colours[p], label="ours %s c_p" % p)
        axes[1].plot(v, [float(r["delta_m_over_delta_0"]) for r in mine], "s-", color=colours[p], label="ours %s" % p)
        axes[2].errorbar(v, [float(r["dz"]) * 1e3 for r in mine], [float(r["dz_sd"]) * 1e3 for r in mine], fmt="s-",
                         color=colours[p], label="ours %s" % p)
    for ax, lab in zip(axes, ("wave speed [m/s]", "δ_m / δ_0", "Δz [mm]")):
        ax.set_xscale("log")
        ax.set_xlabel("$v_p$ [m/s]")
        ax.set_ylabel(lab)
        ax.legend(fontsize=7)
    axes[0].set_yscale("log")
    fig.suptitle("paper-scale channel: open symbols 001 table 8, filled ours")
    fig.tight_layout()
    fig.savefig(os.path.join(out, "study_speeds.png"), dpi=130)
    plt.close(fig)


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else "out/lunar_shock_channel"
    # The grid validation's CSV files: in OUT_DIR when it was run without --results, else the
    # committed ones.
    res = out if os.path.exists(os.path.join(out, "grid_speeds.csv")) else os.path.join(
        os.path.dirname(os.path.abspath(__file__)), "results", "validation")
    os.makedirs(out, exist_ok=True)
    plot_validation(res, out)
    plot_grid_preload(res, out)
    for tag in ("p", "s"):
        plot_channel(out, tag)
    plot_study(out)
    print("figures written to", out)


if __name__ == "__main__":
    main()
