#!/usr/bin/env python3
"""Plots of the intruder pull-out example (paper 002): drag force and mean friction mobilisation
against the intruder height, and the drag's power spectrum.

    python3 plot.py [OUT_DIR (out/intruder_pull_out_2d)]

Writes drag_mu_star.png and drag_spectrum.png into OUT_DIR.
"""
import csv
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def read(path):
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    header = rows[0]
    cols = {h.split(" [")[0]: [] for h in header}
    for row in rows[1:]:
        for h, v in zip(header, row):
            cols[h.split(" [")[0]].append(float(v))
    return cols


def main():
    out = Path(sys.argv[1] if len(sys.argv) > 1 else "out/intruder_pull_out_2d")
    d = read(out / "drag.csv")
    h = [1e3 * y for y in d["intruder_height"]]
    fig, (a1, a2) = plt.subplots(2, 1, sharex=True, figsize=(6, 6))
    a1.plot(h, d["drag_force"], lw=0.8)
    a1.set_ylabel("drag force [N]")
    a1.axhline(0.0, color="k", lw=0.5)
    a2.plot(h, d["mu_star_bulk"], lw=0.8, label="bulk")
    a2.plot(h, d["mu_star_walls"], lw=0.8, label="walls")
    a2.set_ylabel("mean friction mobilisation μ* [-]")
    a2.set_xlabel("intruder height [mm]")
    a2.legend()
    fig.tight_layout()
    fig.savefig(out / "drag_mu_star.png", dpi=120)

    s = read(out / "drag_spectrum.csv")
    fig, ax = plt.subplots(figsize=(6, 4))
    ax.loglog(s["frequency"], s["psd"], lw=0.8)
    ax.set_xlabel("frequency [Hz]")
    ax.set_ylabel("PSD of detrended drag [N²/Hz]")
    fig.tight_layout()
    fig.savefig(out / "drag_spectrum.png", dpi=120)
    print("wrote", out / "drag_mu_star.png", "and", out / "drag_spectrum.png")


if __name__ == "__main__":
    main()
