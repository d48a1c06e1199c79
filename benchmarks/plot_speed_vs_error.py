#!/usr/bin/env python3
"""Plots of bench_speed_vs_error's CSV files (matplotlib, Agg backend).

    python3 benchmarks/plot_speed_vs_error.py [CSV_DIR] [--out PNG_DIR]

CSV_DIR (default: the current directory) holds the speed_vs_error_*.csv files; the PNGs go to
PNG_DIR (default: CSV_DIR):
  speed_vs_error_dt.png      error against dt/t_c: restitution, contact duration (head-on
                             collision), gas energy, grid front speed
  speed_vs_error_cost.png    the same errors against the CPU time per particle and per
                             simulated contact time t_c
  speed_vs_error_scheme.png  why the errors scale as they do: the engine's step re-done on the
                             one-contact ODE, with and without a velocity predictor for the
                             damping force; and the gas energy against time
The vertical grey line marks the engine's default step (time_step_safety x Rayleigh time) of
each measurement; dotted grey lines are slopes dt^1 and dt^2.
"""
import argparse
import csv
import math
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

VV, SE, PD = 2.0, 1.0, 3.0  # the CSV's `integrator` column
# Symplectic Euler is drawn second, with large crosses, so that it stays visible where it lies
# exactly on velocity Verlet (which it does for everything but the gas energy; see the doc).
STYLE = {VV: dict(marker="o", ls="-", ms=4, label="velocity Verlet"),
         SE: dict(marker="x", ls="--", ms=8, label="symplectic Euler"),
         PD: dict(marker="s", ls="-.", ms=4, label="Verlet, predicted damping")}


def read(path):
    """CSV -> list of dicts keyed by the column name without its unit."""
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    keys = [h.split(" [")[0] for h in rows[0]]
    return [{k: float(v) for k, v in zip(keys, r)} for r in rows[1:]]


def finite(x):
    return x is not None and math.isfinite(x)


def select(rows, **kw):
    out = [r for r in rows if all(r[k] == v for k, v in kw.items())]
    return sorted(out, key=lambda r: r["dt_over_tc"])


def line(ax, rows, xkey, ykey, absval=True, **style):
    pts = [(r[xkey], abs(r[ykey]) if absval else r[ykey]) for r in rows
           if finite(r[xkey]) and finite(r[ykey]) and (not absval or r[ykey] != 0.0)]
    if pts:
        ax.plot([p[0] for p in pts], [p[1] for p in pts], **style)


def slopes(ax, rows, xkey, ykey, below=3.0):
    """Dotted guide lines ~dt and ~dt^2 starting a factor `below` under the first point of rows."""
    pts = [(r[xkey], abs(r[ykey])) for r in rows if finite(r[xkey]) and finite(r[ykey]) and r[ykey] != 0.0]
    if not pts:
        return
    x0, y0 = pts[0][0], pts[0][1] / below
    xs = [x0, x0 * 30.0]
    for p, lab in ((1, "dt"), (2, "dt$^2$")):
        ax.plot(xs, [y0 * (x / x0) ** p for x in xs], ls=":", color="0.45", lw=1)
        ax.annotate(lab, (xs[-1], y0 * (xs[-1] / x0) ** p), fontsize=8, color="0.3")


def default_line(ax, value):
    if finite(value):
        ax.axvline(value, color="0.7", lw=2, zorder=0)


def panels(fig_title, xkey, xlabel, d, path, by_cost):
    fig, axes = plt.subplots(2, 2, figsize=(12, 9.5))
    col, gas, grid, default = d["collision"], d["gas"], d["grid"], d["default"]
    dflt = {int(r["scene"]): r["dt_default_over_tc"] for r in default if r["scene"] >= 0}
    colours = {0.5: "C0", 0.9: "C1", 1.0: "C2"}

    # (a) restitution, (b) contact duration
    for ax, key, title in ((axes[0, 0], "e_error", "head-on collision: restitution |e - e_requested|"),
                           (axes[0, 1], "duration_rel_error",
                            "head-on collision: contact duration |t - t_ref| / t_ref")):
        for e, c in colours.items():
            for order in (VV, SE, PD):
                rows = select(col, restitution=e, integrator=order)
                st = dict(STYLE[order])
                st["label"] = f"e = {e:g}, {st['label']}, mean over phases"
                line(ax, rows, xkey, key + "_mean", color=c, **st)
                if order == VV:
                    line(ax, rows, xkey, key + "_max", color=c, ls=":", lw=1,
                         label=f"e = {e:g}, max over 32 phases")
        ax.set_title(title, fontsize=10)
        if not by_cost:
            default_line(ax, dflt.get(0))
            slopes(ax, select(col, restitution=0.5, integrator=VV), xkey, key + "_mean")

    # (c) gas energy
    ax = axes[1, 0]
    for order in (VV, SE):
        rows = [r for r in select(gas, integrator=order) if r["stable"] == 1.0]
        st = dict(STYLE[order])
        lab = st.pop("label")
        line(ax, rows, xkey, "max_rel_energy_error", color="C3", label=f"max |E - E0|/E0, {lab}", **st)
        line(ax, rows, xkey, "fluctuation", color="C4", label=f"rms fluctuation, {lab}", **st)
        line(ax, rows, xkey, "drift_per_tc", color="C5", label=f"|drift| per t_c, {lab}", **st)
    unstable = [r for r in gas if r["stable"] == 0.0]
    if unstable:
        n = int(gas[0]["particles"])
        ax.set_title(f"elastic gas ({n} spheres): energy; unstable at dt/t_c = "
                     + ", ".join(sorted({f'{r["dt_over_tc"]:.2f}' for r in unstable})), fontsize=10)
    else:
        ax.set_title("elastic gas: energy", fontsize=10)
    if not by_cost:
        default_line(ax, dflt.get(1))
        slopes(ax, select(gas, integrator=SE), xkey, "fluctuation")

    # (d) grid front speed
    ax = axes[1, 1]
    for case, c, name in ((0.0, "C0", "shock, v_im = 1 m/s"), (1.0, "C1", "acoustic, v_im = 1e-4 m/s")):
        for order in (VV, SE):
            # the reference run itself (smallest dt) is left out
            rows = select(grid, case=case, integrator=order)[1:]
            st = dict(STYLE[order])
            st["label"] = f"{name}, {st['label']}"
            line(ax, rows, xkey, "c_w_rel_error", color=c, **st)
        if not by_cost:
            default_line(ax, dflt.get(2 + int(case)))
    ax.set_title("struck 5x5 grid (001): |c_w - c_w(dt_min)| / c_w(dt_min)\n"
                 "(x axis: dt over the impact t_c, shock; over pi sqrt(m*/k_lin), acoustic)", fontsize=10)
    if not by_cost:
        slopes(ax, [r for r in select(grid, case=1.0, integrator=VV) if r["dt_over_tc"] > 0.004], xkey,
                "c_w_rel_error")

    for ax in axes.flat:
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel(xlabel)
        ax.grid(True, which="both", alpha=0.25)
        ax.legend(fontsize=6.5, loc="best")
    fig.suptitle(fig_title, fontsize=11)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
    print("wrote", path)


def scheme_figure(d, path):
    fig, axes = plt.subplots(1, 3, figsize=(17, 5.2))
    sch, col = d["scheme"], d["collision"]
    colours = {0.5: "C0", 0.9: "C1", 1.0: "C2"}
    for ax, key, title in ((axes[0], "e_error_mean", "restitution |e - e_requested|, mean over 32 phases"),
                           (axes[1], "duration_rel_error_mean", "contact duration |t - t_ref|/t_ref, mean over 32 phases")):
        for e, c in colours.items():
            line(ax, select(col, restitution=e, integrator=VV), "dt_over_tc", key, color=c, marker="o",
                 ls="none", ms=8, mfc="none", label=f"e = {e:g}: engine (velocity Verlet)")
            line(ax, select(col, restitution=e, integrator=PD), "dt_over_tc", key, color=c, marker="D",
                 ls="none", ms=6, mfc="none", label=f"e = {e:g}: engine (VelocityVerletPredictedDamping)")
            line(ax, select(sch, restitution=e, variant=0.0), "dt_over_tc", key, color=c, ls="-", lw=1,
                 label=f"e = {e:g}: engine's step re-done on the ODE")
            line(ax, select(sch, restitution=e, variant=1.0), "dt_over_tc", key, color=c, ls="--", marker="s", ms=3,
                 label=f"e = {e:g}: damping at a predicted v(t+dt)")
        slopes(ax, select(sch, restitution=0.9, variant=1.0), "dt_over_tc", key, below=10.0)
        ax.set_title(title, fontsize=10)
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("dt / t_c")
        ax.grid(True, which="both", alpha=0.25)
        ax.legend(fontsize=6.5)
    # Gas energy against time: smallest step, the engine's default step, largest stable sweep step.
    ax = axes[2]
    series, gas = d["gas_series"], d["gas"]
    stable = sorted({r["dt_over_tc"] for r in gas if r["stable"] == 1.0})
    default = [r["dt_over_tc"] for r in gas if r["safety"] == 0.2]
    sweep = [q for q in stable if not any(r["dt_over_tc"] == q and finite(r["safety"]) for r in gas)]
    show = list(dict.fromkeys([stable[0]] + default[:1] + sweep[-1:]))
    for k, q in enumerate(show):
        for order in (VV, SE):
            pts = [r for r in series if r["dt_over_tc"] == q and r["integrator"] == order and r["time_over_tc"] > 0]
            ax.plot([r["time_over_tc"] for r in pts], [max(abs(r["rel_energy_error"]), 1e-12) for r in pts],
                    color=f"C{k}", ls="-" if order == VV else "--", lw=1,
                    label=f"dt = t_c/{1 / q:.1f}{' (default)' if q in default else ''}, "
                          f"{'velocity Verlet' if order == VV else 'symplectic Euler'}")
    ax.set_yscale("log")
    ax.set_xlabel("t / t_c")
    ax.set_title("elastic gas: |E - E0| / E0 against time", fontsize=10)
    ax.grid(True, alpha=0.25)
    ax.legend(fontsize=6.5)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
    print("wrote", path)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("csv_dir", nargs="?", default=".")
    ap.add_argument("--out", default=None, help="directory of the PNG files (default: CSV_DIR)")
    a = ap.parse_args()
    out = a.out or a.csv_dir
    os.makedirs(out, exist_ok=True)
    d = {k: read(os.path.join(a.csv_dir, f"speed_vs_error_{k}.csv"))
         for k in ("collision", "gas", "gas_series", "grid", "default", "scheme")}
    panels("Error against time step (velocity Verlet, symplectic Euler; collisions also Verlet with predicted damping)",
           "dt_over_tc", "dt / t_c", d, os.path.join(out, "speed_vs_error_dt.png"), False)
    panels("Error against cost: CPU time (CLOCK_PROCESS_CPUTIME_ID, 1 thread) per particle per simulated t_c",
           "cpu_per_particle_per_tc", "CPU seconds per particle per simulated t_c", d,
           os.path.join(out, "speed_vs_error_cost.png"), True)
    scheme_figure(d, os.path.join(out, "speed_vs_error_scheme.png"))


if __name__ == "__main__":
    main()
