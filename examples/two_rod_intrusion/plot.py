#!/usr/bin/env python3
"""Figures of the two-rod intrusion scene from its CSV files (matplotlib, Agg backend).

usage: plot.py [DIR]   (DIR: the scene's output directory, default out/two_rod_intrusion,
                        or . when run inside it)

Writes into DIR whatever the data allow:
  work_vs_gap.png        W(s/d) per rod shape (+ body work, 2 W_single, very strong forces)
  force_vs_depth.png     F(z) for every run (running mean over d/2 of depth)
  force_pdf.png          PDF of f_n/<f_n> at half depth
  velocity_profiles.png  V_y/U0 and V_z/U0 along y, 5 d below the rods, at half depth
  strain_rate.png        |strain rate| in the y-z plane at half depth, one panel per run
"""
import csv
import glob
import os
import re
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def read_csv(path):
    """Columns of a granule CSV as numpy arrays keyed by the name without its unit."""
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    names = [re.sub(r"\s*\[.*\]$", "", h) for h in rows[0]]
    data = np.array([[float(v) for v in r] for r in rows[1:]], dtype=float).reshape(-1, len(names))
    return {n: data[:, k] for k, n in enumerate(names)}


def gap_of(path):
    m = re.search(r"_s([0-9.eE+-]+)\.csv$", path)
    return float(m.group(1)) if m else None


def runs(directory, prefix, shape):
    """(label, gap or None, path) of every run file prefix_<shape>_s<g>.csv / _single.csv."""
    out = []
    for p in glob.glob(os.path.join(directory, f"{prefix}_{shape}_s*.csv")):
        if gap_of(p) is not None:
            out.append((f"s/d = {gap_of(p):g}", gap_of(p), p))
    out.sort(key=lambda t: t[1])
    single = os.path.join(directory, f"{prefix}_{shape}_single.csv")
    if os.path.exists(single):
        out.append(("single rod", None, single))
    return out


def shapes(directory):
    return [s for s in ("square", "cylinder") if os.path.exists(os.path.join(directory, f"work_vs_gap_{s}.csv"))]


def plot_work(directory, bed):
    fig, ax = plt.subplots(figsize=(6, 4.2))
    ax2 = None
    for shape in shapes(directory):
        t = read_csv(os.path.join(directory, f"work_vs_gap_{shape}.csv"))
        line, = ax.plot(t["gap_over_d"], t["work"], "o-", label=f"W, {shape}")
        ax.plot(t["gap_over_d"], t["body_work"], "x", color=line.get_color(), label=f"body work, {shape}")
        single = os.path.join(directory, f"single_rod_{shape}.csv")
        if os.path.exists(single):
            w1 = read_csv(single)["work"][0]
            ax.axhline(2 * w1, ls="--", color=line.get_color(), lw=1, label=f"2 W(single rod), {shape}")
        if np.any(t["very_strong"] > 0):
            ax2 = ax2 or ax.twinx()
            ax2.plot(t["gap_over_d"], t["very_strong"], "s:", color=line.get_color(), alpha=0.6,
                     label=f"very strong forces, {shape}")
    ax.set_xlabel("gap s/d")
    ax.set_ylabel("net work W [J]")
    title = "Two rods: net work vs gap"
    if bed is not None:
        title += f" (d = {1e3 * bed['diameter'][0]:g} mm)"
    ax.set_title(title)
    h, lab = ax.get_legend_handles_labels()
    if ax2 is not None:
        ax2.set_ylabel("contacts with f_n > 6<f_n> at half depth")
        h2, l2 = ax2.get_legend_handles_labels()
        h, lab = h + h2, lab + l2
    ax.legend(h, lab, fontsize=7, loc="lower right")
    fig.tight_layout()
    fig.savefig(os.path.join(directory, "work_vs_gap.png"), dpi=150)
    plt.close(fig)


def running_mean(x, n):
    if n <= 1 or len(x) < n:
        return x
    k = np.ones(n)
    return np.convolve(x, k, mode="same") / np.convolve(np.ones_like(x), k, mode="same")


def plot_force(directory, bed):
    fig, axes = plt.subplots(1, len(shapes(directory)), figsize=(6 * len(shapes(directory)), 4.2), squeeze=False)
    d = bed["diameter"][0] if bed is not None else 0.0
    for ax, shape in zip(axes[0], shapes(directory)):
        cmap = plt.get_cmap("viridis")
        rs = runs(directory, "force", shape)
        for k, (label, gap, path) in enumerate(rs):
            f = read_csv(path)
            dz = np.median(np.diff(f["depth"])) if len(f["depth"]) > 1 else 1.0
            n = max(1, int(round(0.5 * d / dz))) if d > 0 else 1
            color = "k" if gap is None else cmap(k / max(1, len(rs) - 1))
            ax.plot(100 * f["depth"], running_mean(f["force_z"], n), color=color, lw=1, label=label)
        ax.set_xlabel("depth z [cm]")
        ax.set_ylabel("vertical force on the rods F [N]")
        ax.set_title(f"F(z), {shape} rods (running mean over d/2)")
        ax.set_xlim(left=0)
        ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(os.path.join(directory, "force_vs_depth.png"), dpi=150)
    plt.close(fig)


def plot_pdf(directory):
    files = [(shape, r) for shape in shapes(directory) for r in runs(directory, "force_pdf", shape)]
    if not files:
        return
    fig, ax = plt.subplots(figsize=(6, 4.2))
    for shape, (label, _, path) in files:
        t = read_csv(path)
        c = 0.5 * (t["fn_over_mean_lo"] + t["fn_over_mean_hi"])
        ok = t["pdf"] > 0
        ax.semilogy(c[ok], t["pdf"][ok], ".-", lw=0.8, label=f"{shape}, {label}")
    ax.axvline(6, color="grey", ls="--", lw=1)
    ax.set_xlabel("f_n / <f_n>")
    ax.set_ylabel("PDF")
    ax.set_title("Normal forces between grains at half depth")
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(os.path.join(directory, "force_pdf.png"), dpi=150)
    plt.close(fig)


def plot_profiles(directory, u0):
    files = [(shape, r) for shape in shapes(directory) for r in runs(directory, "velocity_profile", shape)]
    if not files:
        return
    fig, (a1, a2) = plt.subplots(2, 1, figsize=(6.5, 6.5), sharex=True)
    for shape, (label, _, path) in files:
        t = read_csv(path)
        a1.plot(t["y_minus_centre_over_d"], t["v_y"] / u0, lw=1, label=f"{shape}, {label}")
        a2.plot(t["y_minus_centre_over_d"], t["v_z"] / u0, lw=1, label=f"{shape}, {label}")
    a1.set_ylabel("V_y / U0")
    a2.set_ylabel("V_z / U0")
    a2.set_xlabel("(y - y_centre) / d")
    a1.set_title("Grain velocity within 5 d below the rods, half depth")
    a1.legend(fontsize=6, ncol=2)
    for a in (a1, a2):
        a.axhline(0, color="grey", lw=0.5)
    fig.tight_layout()
    fig.savefig(os.path.join(directory, "velocity_profiles.png"), dpi=150)
    plt.close(fig)


def plot_strain(directory, bed):
    files = [(shape, r) for shape in shapes(directory) for r in runs(directory, "strain_rate", shape)]
    if not files:
        return
    d = bed["diameter"][0] if bed is not None else 1.0
    n = len(files)
    cols = min(4, n)
    rows = (n + cols - 1) // cols
    fig, axes = plt.subplots(rows, cols, figsize=(3.2 * cols, 2.8 * rows), squeeze=False)
    vmax = 0.0
    grids = []
    for shape, (label, _, path) in files:
        t = read_csv(path)
        ys = np.unique(t["y"])
        zs = np.unique(t["z"])
        e = np.full((len(zs), len(ys)), np.nan)
        iy = np.searchsorted(ys, t["y"])
        iz = np.searchsorted(zs, t["z"])
        e[iz, iy] = t["strain_rate"]
        grids.append((shape, label, ys, zs, e))
        if np.any(np.isfinite(e)):
            vmax = max(vmax, np.nanpercentile(e, 99))
    for ax, (shape, label, ys, zs, e) in zip(axes.flat, grids):
        yc = 0.5 * (ys[0] + ys[-1])
        im = ax.pcolormesh((ys - yc) / d, zs / d, e, shading="nearest", vmin=0, vmax=vmax or None, cmap="magma")
        ax.set_title(f"{shape}, {label}", fontsize=8)
        ax.set_aspect("equal")
        ax.set_xlabel("y/d")
        ax.set_ylabel("z/d")
    for ax in list(axes.flat)[len(grids):]:
        ax.axis("off")
    fig.colorbar(im, ax=axes.ravel().tolist(), label="|strain rate| [1/s]")
    fig.savefig(os.path.join(directory, "strain_rate.png"), dpi=150)
    plt.close(fig)


def main():
    if len(sys.argv) > 1:
        directory = sys.argv[1]
    else:
        cwd = os.path.abspath(".")
        inside = os.path.basename(cwd) == "two_rod_intrusion" and os.path.basename(os.path.dirname(cwd)) == "out"
        directory = "." if inside else os.path.join("out", "two_rod_intrusion")
    if not shapes(directory):
        sys.exit(f"plot.py: no work_vs_gap_<shape>.csv in {directory}; run the scene first")
    scene_csv = os.path.join(directory, "scene.csv")
    bed = read_csv(scene_csv) if os.path.exists(scene_csv) else None
    u0 = bed["speed"][0] if bed is not None else 1.0
    plot_work(directory, bed)
    plot_force(directory, bed)
    plot_pdf(directory)
    plot_profiles(directory, u0)
    plot_strain(directory, bed)
    print(f"plot.py: figures written to {directory}")


if __name__ == "__main__":
    main()
