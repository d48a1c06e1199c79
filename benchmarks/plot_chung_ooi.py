#!/usr/bin/env python3
"""Chung & Ooi (2011) Test 4 against granule's Hertz-Mindlin tangential histories (matplotlib, Agg).

    python3 benchmarks/plot_chung_ooi.py [CSV] [--out PNG]

CSV (default: build/tests/chung_ooi_test4.csv) is written by the test case "Chung & Ooi (2011)
Test 4: oblique impacts ..." of tests/contact/test_oblique_impact.cpp (run granule_tests once);
the PNG (default: chung_ooi_test4.png beside the CSV) shows the tangential restitution, the
rebound spin and the rebound angle of the contact patch against the incidence angle for the
default law (potential form), the force history with the unloading rescale (incremental) and the
LIGGGHTS 3.8 displacement form, with the published points (the same ones the test checks; see
the test for where they come from). Used by docs/physics.md, "Tangential laws".
"""
import argparse
import csv
import os
import re

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
TEST = os.path.join(HERE, "..", "tests", "contact", "test_oblique_impact.cpp")
LAWS = [("potential", "default (potential form)", "C0", "-"),
        ("incremental", "force history + unloading rescale", "C3", "--"),
        ("liggghts38", "LIGGGHTS 3.8 displacement form", "C2", ":")]


def published_points():
    """The points of kChungOoiTest4, read from the test so that the figure and the test agree."""
    text = open(TEST).read()
    block = text[text.index("kChungOoiTest4[] = {"):]
    block = block[:block.index("};")]
    return [tuple(float(x) for x in m.groups())
            for m in re.finditer(r"\{([-\d.]+), ([-\d.]+), ([-\d.]+), ([-\d.]+)\}", block)]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("csv", nargs="?", default=os.path.join("build", "tests", "chung_ooi_test4.csv"))
    ap.add_argument("--out", default=None)
    args = ap.parse_args()
    rows = list(csv.DictReader(open(args.csv)))
    ref = published_points()
    fig, axes = plt.subplots(1, 3, figsize=(13, 4))
    cols = [("e_t", "tangential restitution $v_t'/v_t$"), ("spin", "rebound spin [rad/s]"),
            ("rebound_deg", "rebound angle of the contact patch [deg]")]
    for k, (ax, (key, label)) in enumerate(zip(axes, cols)):
        for law, name, colour, style in LAWS:
            pts = [(float(r["angle_deg"]), float(r[key])) for r in rows if r["law"] == law]
            ax.plot([p[0] for p in pts], [p[1] for p in pts], style, color=colour, label=name)
        ax.plot([p[0] for p in ref], [p[k + 1] for p in ref], "ko", mfc="none", label="Chung & Ooi 2011")
        ax.set_xlabel("incidence angle [deg]")
        ax.set_ylabel(label)
        ax.grid(alpha=0.3)
    axes[0].legend(fontsize=8)
    fig.suptitle("Chung & Ooi (2011) Test 4: Al$_2$O$_3$ sphere on a rigid plane, 3.9 m/s, $\\mu$ = 0.092")
    fig.tight_layout()
    out = args.out or os.path.join(os.path.dirname(os.path.abspath(args.csv)), "chung_ooi_test4.png")
    fig.savefig(out, dpi=80)
    print(out)


if __name__ == "__main__":
    main()
