#!/usr/bin/env python3
"""Figures of examples/lunar_shock_channel (paper 001 figs. 1, 6, 9, 15, 16).

usage: plot.py [OUT_DIR]   (default out/lunar_shock_channel)

Reads the CSV files written by `lunar_shock_channel validation` and `... channel` (whichever
exist) and writes PNG files next to them:
  validation.png        c_w / c_w(1 m/s) vs v_im, log-log, per material (001 fig. 1)
  channel_speeds_*.png  depth-averaged c_w and c_p vs v_p (001 fig. 9)
  channel_dz_*.png      bed-height change and delta_m/delta_0 vs y (001 figs. 15, 16)
  channel_arrivals_*.png  sensor position vs arrival time at mid depth (001 fig. 6)
"""
import csv
import math
import os
import sys

import matplotlib

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


def plot_validation(out):
    path = os.path.join(out, "validation.csv")
    if not os.path.exists(path):
        return
    d = read(path)
    names = {0: "first material", 1: "second material"}
    summ = os.path.join(out, "validation_summary.csv")
    labels = {}
    if os.path.exists(summ):
        s = read(summ)
        for m, c0p in zip(s["material"], s["c0_paper"]):
            labels[int(m)] = "steel" if c0p > 100 else "soft"
    fig, ax = plt.subplots(figsize=(5.5, 4))
    for m in sorted(set(int(x) for x in d["material"])):
        idx = [k for k, x in enumerate(d["material"]) if int(x) == m]
        v = [d["v_im"][k] for k in idx]
        c = [d["c_w_over_c_w_1"][k] for k in idx]
        v, c = finite(v, c)
        ax.loglog(v, c, "o-", label=labels.get(m, names.get(m, str(m))))
    vv = [1e-1, 10]
    ax.loglog(vv, [x ** 0.2 for x in vv], "k--", label=r"$v^{1/5}$")
    ax.set_xlabel(r"$v_{im}$ [m/s]")
    ax.set_ylabel(r"$c_w / c_w(1\,\mathrm{m/s})$")
    ax.legend()
    ax.set_title("5x5 grid: acoustic plateau and shock branch")
    fig.tight_layout()
    fig.savefig(os.path.join(out, "validation.png"), dpi=130)
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


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else "out/lunar_shock_channel"
    plot_validation(out)
    for tag in ("p", "s"):
        plot_channel(out, tag)
    print("figures written to", out)


if __name__ == "__main__":
    main()
