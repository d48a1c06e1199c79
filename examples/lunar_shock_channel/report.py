#!/usr/bin/env python3
"""The generated tables of examples/lunar_shock_channel/README.md, from the committed results.

    python3 examples/lunar_shock_channel/report.py          # rewrite the README's blocks
    python3 examples/lunar_shock_channel/report.py --check  # exit 1 if the README differs

Reads results/validation/grid_summary.csv and grid_preload_at_paper_c0.csv, which
`lunar_shock_channel validation --results examples/lunar_shock_channel/results/validation`
writes (each with a first line naming commit, date and machine), and fills the README's
"<!-- BEGIN GENERATED: name -->" blocks, so that no number of the grid validation is copied by
hand. The figure (grid_preload.png) is drawn by plot.py.
"""
import csv
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "common"))
from readme_blocks import render  # noqa: E402

RESULTS = os.path.join(HERE, "results", "validation")
README = os.path.join(HERE, "README.md")


def read(name):
    """(provenance line, rows as dicts keyed by the column name without its unit)."""
    with open(os.path.join(RESULTS, name), newline="") as f:
        lines = f.read().splitlines()
    prov = lines[0].lstrip("# ").strip() if lines and lines[0].startswith("#") else "provenance unknown"
    body = [l for l in lines if not l.startswith("#")]
    rows = list(csv.reader(body))
    names = [h.split(" [")[0] for h in rows[0]]
    return prov, [dict(zip(names, r)) for r in rows[1:]]


def g(x, digits=4):
    v = float(x)
    return f"{v:.{digits}g}"


def load_label(r):
    if r["load"] == "gravity":
        gv = float(r["gravity"])
        name = "Earth" if abs(gv - 9.81) < 1e-6 else "Moon" if abs(gv - 1.625) < 1e-6 else f"{gv:g} m/s²"
        return f"gravity, {name} ({gv:g} m/s²)"
    return f"uniform F0 = {g(r['preload'])} N"


def summary_block():
    prov, rows = read("grid_summary.csv")
    out = ["| material | load | static loads of the fitted contacts [N] | chain formula c_0 [m/s] "
           "| measured plateau [m/s] | table 1 c_0 [m/s] | measured / table 1 | c_w(1 m/s) [m/s] "
           "| shock exponent |", "|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        exp = (f"{float(r['shock_exponent']):.4f} ± {float(r['shock_exponent_uncertainty']):.4f}"
               if r["shock_exponent"] not in ("nan", "") and float(r["shock_points"]) >= 2 else "–")
        out.append(f"| {r['material']} | {load_label(r)} | {g(r['fitted_contact_load_min'], 3)}–"
                   f"{g(r['fitted_contact_load_max'], 3)} | {g(r['c0_chain'])} | {g(r['c0_measured'])} "
                   f"| {g(r['c0_paper'])} | {float(r['measured_over_paper']):.3f} | {g(r['c_w_1'])} | {exp} |")
    out.append("")
    out.append(f"_{prov}._")
    return "\n".join(out) + "\n", rows


def preload_block():
    prov, rows = read("grid_preload_at_paper_c0.csv")
    out = ["| material | table 1 c_0 [m/s] | F0 giving it by the chain formula [N] | F0 giving it, measured [N] "
           "| in weights m g (Earth) | in weights m g (Moon) | static overlap there [µm] |",
           "|---|---|---|---|---|---|---|"]
    for r in rows:
        out.append(f"| {r['material']} | {g(r['c0_paper'])} | {g(r['preload_chain'])} | {g(r['preload_measured'])} "
                   f"| {g(r['preload_measured_over_weight_earth'], 3)} | {g(r['preload_measured_over_weight_moon'], 3)} "
                   f"| {float(r['static_overlap_measured']) * 1e6:.3g} |")
    out.append("")
    out.append(f"_{prov}._")
    return "\n".join(out) + "\n", rows


def verdict_block(summary, preload):
    by = {r["material"]: r for r in preload}
    lines = []
    if "steel" in by and "soft" in by:
        ws = float(by["steel"]["preload_measured_over_weight_earth"])
        wf = float(by["soft"]["preload_measured_over_weight_earth"])
        lines.append(f"Table 1's plateaus need a static contact load of {ws:.3g} particle weights (steel) and "
                     f"{wf:.3g} (soft) under Earth gravity: a ratio of {ws / wf:.3g} between the two materials, "
                     "where one gravity acting on the same 5 × 5 grid loads both alike.")
    grav = [r for r in summary if r["load"] == "gravity"]
    for gv in sorted({r["gravity"] for r in grav}, key=float, reverse=True):
        rs = {r["material"]: r for r in grav if r["gravity"] == gv}
        if "steel" in rs and "soft" in rs:
            lines.append(f"Under g = {float(gv):g} m/s² the measured plateau is "
                         f"{float(rs['steel']['measured_over_paper']):.3f} of table 1 for steel and "
                         f"{float(rs['soft']['measured_over_paper']):.3f} for soft.")
    return " ".join(lines) + "\n"


def main():
    check = "--check" in sys.argv[1:]
    summary, srows = summary_block()
    preload, prows = preload_block()
    blocks = {"grid-summary": summary, "grid-preload": preload, "grid-verdict": verdict_block(srows, prows)}
    with open(README, encoding="utf-8") as f:
        text = f.read()
    new = render(text, blocks, "examples/lunar_shock_channel/README.md")
    if check:
        if new != text:
            print("report.py --check: README.md differs from the results; run examples/lunar_shock_channel/report.py")
            sys.exit(1)
        print("report.py --check: README.md matches the results")
        return
    with open(README, "w", encoding="utf-8") as f:
        f.write(new)
    print("README.md regenerated")


if __name__ == "__main__":
    main()
