#!/usr/bin/env python3
"""Figures of one run of intruder_pull_out_2d (paper 002), with the paper's values beside ours.

    /usr/bin/python3 plot.py [OUT_DIR (out/intruder_pull_out_2d)]

Reads the files the program wrote into OUT_DIR (summary.csv, drag.csv, drag_spectrum.csv,
drag_bands.csv, velocity_map_h*.csv, centre_line.csv) and writes into the same directory:
  drag_mu_star.png    drag and mu* against the intruder height: peak, drop and reload, the quiet
                      top layer (ours at q = 2 %, 002's 45 mm = (W - L)/2), H1, 002's 0.24
  drag_spectrum.png   PSD of the drag's fluctuations against the wavelength, the d/2 band and its
                      neighbours, third-octave band means
  velocity_maps.png   v* = |V|/V in 002's three zones (blue < 0.25 < green < 0.75 < red) at the
                      loading peaks, with the cone's edges at 002's 60 deg and at ours
  centre_line.png     V_y/V along the cell's vertical mid-line against the intruder height (002 fig. 9)
"""
import csv
import glob
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.colors import BoundaryNorm, ListedColormap  # noqa: E402

PAPER = {"quiet_layer": 0.045, "cone_angle": 60.0, "mu_star_above_h1": 0.24, "phi": 0.82}


def read_table(path):
    """Columns of a CSV written by the program (comment lines skipped, units dropped)."""
    with open(path, newline="") as f:
        rows = [r for r in csv.reader(f) if r and not r[0].startswith("#")]
    names = [h.split(" [")[0] for h in rows[0]]
    cols = {n: [] for n in names}
    for r in rows[1:]:
        for n, v in zip(names, r):
            cols[n].append(float(v))
    return cols


def read_summary(path):
    out = {}
    with open(path, newline="") as f:
        rows = [r for r in csv.reader(f) if r and not r[0].startswith("#")]
    for r in rows[1:]:
        try:
            out[r[0]] = float(r[1])
        except ValueError:
            out[r[0]] = r[1]
    return out


def finite(x):
    return x is not None and isinstance(x, float) and math.isfinite(x)


def zone_cmap():
    return ListedColormap(["#3b6fd4", "#4caf50", "#e53935"]), BoundaryNorm([0.0, 0.25, 0.75, 1e9], 3)


def draw_map(ax, m, s, height, cone, d, width, length, r_int):
    """One velocity map: zones, intruder, cone edges (002's 60 deg and ours) from its tips."""
    xs = sorted(set(m["x"]))
    ys = sorted(set(m["y"]))
    nx, ny = len(xs), len(ys)
    grid = [[float("nan")] * nx for _ in range(ny)]
    ix = {x: i for i, x in enumerate(xs)}
    iy = {y: j for j, y in enumerate(ys)}
    for x, y, v, phi in zip(m["x"], m["y"], m["speed_over_V"], m["packing_fraction"]):
        grid[iy[y]][ix[x]] = v if phi >= 0.3 else float("nan")
    cmap, norm = zone_cmap()
    ext = [1e3 * (xs[0] - 0.5 * (xs[1] - xs[0])), 1e3 * (xs[-1] + 0.5 * (xs[1] - xs[0])),
           1e3 * (ys[0] - 0.5 * (ys[1] - ys[0])), 1e3 * (ys[-1] + 0.5 * (ys[1] - ys[0]))]
    ax.imshow(grid, origin="lower", extent=ext, cmap=cmap, norm=norm, interpolation="nearest")
    ax.add_patch(plt.Rectangle((1e3 * (0.5 * width - 0.5 * length), 1e3 * (height - r_int)), 1e3 * length,
                               2e3 * r_int, color="k"))
    top = 1e3 * s["mean_surface"]
    for ang, style, label in ((PAPER["cone_angle"], "w--", "002: 60°"), (cone, "k-", "ours")):
        if not finite(ang):
            continue
        t = math.tan(math.radians(ang))
        for side in (-1, 1):
            x0 = 1e3 * (0.5 * width + side * 0.5 * length)
            # to the wall or the surface, whichever comes first
            run_x = 1e3 * (0.5 * width - 0.5 * length)
            rise = top - 1e3 * height
            dx = min(run_x, rise / t if t > 0 else run_x) if ang < 90 else rise / abs(t)
            sgn = side if ang < 90 else -side
            ax.plot([x0, x0 + sgn * dx], [1e3 * height, 1e3 * height + abs(t) * dx], style, lw=1.2,
                    label=label if side == 1 else None)
    ax.axhline(top, color="0.3", lw=0.6)
    ax.set_xlim(0, 1e3 * width)
    ax.set_ylim(0, top + 1e3 * d)
    ax.set_aspect("equal")


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else "out/intruder_pull_out_2d"
    s = read_summary(os.path.join(out, "summary.csv"))
    d = 3e-3
    width, length, r_int = s["cell_width"], 0.010, 1e-3
    surface = s["mean_surface"]
    h1 = s["h1"]
    dr = read_table(os.path.join(out, "drag.csv"))
    h = [1e3 * y for y in dr["intruder_height"]]

    # Drag and mu*.
    fig, (a1, a2) = plt.subplots(2, 1, sharex=True, figsize=(7, 7))
    a1.plot(h, dr["drag_force"], lw=0.7, color="C0", label="drag")
    travel = (h[-1] - h[0]) / max(1, len(h) - 1)  # [mm]
    half = max(1, int(round(1.5 / travel))) // 2  # running mean over d/2, as statistics.hpp
    f = dr["drag_force"]
    smooth = [sum(f[max(0, k - half):k + half + 1]) / len(f[max(0, k - half):k + half + 1]) for k in range(len(f))]
    a1.plot(h, smooth, lw=0.8, color="k", label="running mean over d/2 (drop, reload)")
    a1.plot(1e3 * s["peak_height"], s["peak"], "rv", label="peak")
    if finite(s["drop"]):
        a1.plot(1e3 * s["drop_height"], s["drop"], "k^", label="first drop")
    if finite(s["reload"]):
        a1.plot(1e3 * s["reload_height"], s["reload"], "kv", label="reload")
    a1.axvspan(1e3 * (surface - s["quiet_thickness_q2"]), 1e3 * surface, color="C2", alpha=0.15,
               label=f"quiet layer, ours (q = 2 %): {1e3 * s['quiet_thickness_q2']:.0f} mm")
    paper_quiet = 0.5 * (width - length)  # 002: the layer's thickness equals (W - L)/2 (45 mm)
    a1.axvline(1e3 * (surface - paper_quiet), color="C2", ls="--",
               label=f"002: quiet below {1e3 * paper_quiet:.0f} mm depth, = (W - L)/2")
    a1.axvline(1e3 * surface, color="0.4", lw=0.8)
    a1.set_ylabel("drag force [N]")
    a1.legend(fontsize=7)
    a2.plot(h, dr["mu_star_bulk"], lw=0.6, label="bulk")
    a2.plot(h, dr["mu_star_walls"], lw=0.6, label="walls")
    a2.axvline(1e3 * h1, color="k", ls=":", label=f"H1 = (W - L)/2 tan 60° = {1e3 * h1:.0f} mm")
    a2.hlines(PAPER["mu_star_above_h1"], 1e3 * h1, 1e3 * surface, colors="r", linestyles="--",
              label="002: above H1 both fall towards 0.24")
    a2.hlines(s["mu_bulk_above_h1"], 1e3 * h1, 1e3 * surface, colors="C0", linestyles="-", lw=2, alpha=0.5,
              label=f"ours, bulk mean above H1: {s['mu_bulk_above_h1']:.2f}")
    a2.set_ylim(0, 1)
    a2.set_ylabel("mean friction mobilisation μ*")
    a2.set_xlabel("intruder height [mm]")
    a2.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "drag_mu_star.png"), dpi=120)
    plt.close(fig)

    # Spectrum.
    sp = read_table(os.path.join(out, "drag_spectrum.csv"))
    bands = read_table(os.path.join(out, "drag_bands.csv"))
    fig, ax = plt.subplots(figsize=(7, 4.5))
    lam = [1e3 * x for x in sp["wavelength"]]
    ax.loglog(lam, sp["psd"], lw=0.5, color="0.6", label="periodogram (Hann)")
    ax.loglog([1e3 * x for x in bands["wavelength"]], bands["psd"], "o-", color="C0", label="third-octave means")
    q = 2 ** 0.25
    for lo, hi, c in ((1.5 / q, 1.5 * q, "C3"), (1.5 / q ** 3, 1.5 / q, "0.8"), (1.5 * q, 1.5 * q ** 3, "0.8")):
        ax.axvspan(lo, hi, color=c, alpha=0.25)
    ax.axvline(1.5, color="C3", ls="--", label="002: peaks spaced d/2 = 1.5 mm")
    verdict = "stands out" if s["half_d_stands_out"] == 1 else "does not stand out"
    ax.set_title(f"d/2 band / neighbours R = {s['half_d_ratio']:.2f} (95 % point {s['half_d_critical']:.2f}): {verdict}",
                 fontsize=9)
    ax.invert_xaxis()
    ax.set_xlabel("wavelength of the drag's fluctuation [mm]")
    ax.set_ylabel("PSD [N² m]")
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "drag_spectrum.png"), dpi=120)
    plt.close(fig)

    # Velocity maps.
    files = sorted(glob.glob(os.path.join(out, "velocity_map_h*.csv")))
    if files:
        fig, axs = plt.subplots(1, len(files), figsize=(2.6 * len(files), 5), squeeze=False)
        for k, (ax, f) in enumerate(zip(axs[0], files)):
            m = read_table(f)
            key = f"map{k + 1}_"
            height = s.get(key + "height", float("nan"))
            cone = s.get(key + "cone_angle", float("nan"))
            draw_map(ax, m, s, height, cone, d, width, length, r_int)
            ax.set_title(f"h = {1e3 * height:.0f} mm\ncone {cone:.0f}°" if finite(cone) else f"h = {1e3 * height:.0f} mm",
                         fontsize=8)
            ax.set_xlabel("x [mm]", fontsize=8)
            if k == 0:
                ax.set_ylabel("y [mm]")
                ax.legend(fontsize=6, loc="upper left")
        fig.suptitle("v* = |V|/V (w = %.1f d): blue < 0.25 < green < 0.75 < red" % (s["cg_width"] / d), fontsize=9)
        fig.tight_layout()
        fig.savefig(os.path.join(out, "velocity_maps.png"), dpi=120)
        plt.close(fig)

    # Centre line (002 fig. 9).
    path = os.path.join(out, "centre_line.csv")
    if os.path.exists(path):
        c = read_table(path)
        hs = sorted(set(c["intruder_height"]))
        ys = sorted(set(c["y"]))
        ih = {x: i for i, x in enumerate(hs)}
        iy = {y: j for j, y in enumerate(ys)}
        img = [[float("nan")] * len(hs) for _ in ys]
        for a, b, v in zip(c["intruder_height"], c["y"], c["vy_over_V"]):
            img[iy[b]][ih[a]] = v
        fig, ax = plt.subplots(figsize=(6, 4.5))
        im = ax.imshow(img, origin="lower", aspect="auto", cmap="RdBu_r", vmin=-1.5, vmax=1.5,
                       extent=[1e3 * hs[0], 1e3 * hs[-1], 1e3 * ys[0], 1e3 * ys[-1]])
        ax.plot([1e3 * hs[0], 1e3 * hs[-1]], [1e3 * hs[0], 1e3 * hs[-1]], "k-", lw=0.8, label="intruder")
        ax.axhline(1e3 * surface, color="0.3", lw=0.6)
        ax.set_xlabel("intruder height H [mm]")
        ax.set_ylabel("y on the mid-line [mm]")
        fig.colorbar(im, label="V_y / V")
        ax.legend(fontsize=7)
        fig.tight_layout()
        fig.savefig(os.path.join(out, "centre_line.png"), dpi=120)
        plt.close(fig)
    print("figures written to", out)


if __name__ == "__main__":
    main()
