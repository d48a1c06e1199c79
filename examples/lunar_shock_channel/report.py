#!/usr/bin/env python3
"""The generated tables of examples/lunar_shock_channel/README.md, from the committed results.

    python3 examples/lunar_shock_channel/report.py          # rewrite the README's blocks
    python3 examples/lunar_shock_channel/report.py --check  # exit 1 if the README differs

Reads results/validation/grid_summary.csv and grid_preload_at_paper_c0.csv, which
`lunar_shock_channel validation --results examples/lunar_shock_channel/results/validation`
writes (each with a first line naming commit, date and machine), and fills the README's
"<!-- BEGIN GENERATED: name -->" blocks, so that no number of the grid validation is copied by
hand. The figure (grid_preload.png) is drawn by plot.py.

The channel blocks come from the paper-scale study (`lunar_shock_channel --study TAG --results
examples/lunar_shock_channel/results`): one file per case in results/<tag>/, the cost files in
results/cost/. Rows of cases not run yet say so.
"""
import csv
import math
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "common"))
from readme_blocks import render  # noqa: E402
from result_csv import read_text_table  # noqa: E402

RESULTS = os.path.join(HERE, "results", "validation")
STUDY = os.path.join(HERE, "results")
README = os.path.join(HERE, "README.md")


def read(name):
    """(provenance line, rows as dicts keyed by the column name without its unit)."""
    return read_text_table(os.path.join(RESULTS, name))


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


# ---- the paper-scale channel ----------------------------------------------------------------

# 001 table 6 (phi_0 [%], c_0 [m/s]) and table 8 (v_p exponent n: c_w, sd, c_p, sd, delta_m [um], sd,
# dz [mm], sd); delta_0 of table 8's caption [um].
PAPER_T6 = {"loose": (54.72, 6.55), "medium": (58.65, 7.01), "compact": (61.96, 7.51)}
PAPER_DELTA0 = {"loose": 4.82, "medium": 4.81, "compact": 4.23}
PAPER_T8 = {
    "loose": [("-2", 6.17, 0.93, 7.10, 0.46, 4.49, 0.24, -0.07, 0.08), ("-1", 6.09, 0.97, 7.09, 0.42, 4.66, 0.26, -0.08, 0.08),
              ("-1/2", 6.26, 0.91, 7.09, 0.42, 4.83, 0.44, -0.07, 0.08),
              ("-1/4", 6.50, 0.90, 7.10, 0.44, 5.58, 1.06, 0.00, 0.12), ("0", 6.80, 0.95, 7.12, 0.51, 6.67, 0.48, 0.16, 0.11),
              ("1/4", 7.43, 0.97, 7.28, 0.48, 6.48, 0.49, 0.19, 0.10), ("1/2", 8.17, 0.91, 7.51, 0.56, 7.03, 0.55, -0.09, 0.12),
              ("3/4", 9.32, 0.85, 7.83, 0.65, 10.10, 0.77, -0.30, 0.18), ("1", 10.36, 0.54, 8.31, 0.77, 15.27, 0.56, 0.96, 0.43)],
    "medium": [("-2", 7.06, 0.57, 7.05, 0.15, 4.61, 0.19, 0.00, 0.02), ("-1", 6.99, 0.49, 6.97, 0.17, 4.90, 0.20, 0.00, 0.02),
               ("1", 12.71, 0.50, 9.12, 0.30, 15.75, 0.77, 3.07, 0.65)],
}


def exponent_value(n):
    a, _, b = n.partition("/")
    return 10 ** (float(a) / float(b) if b else float(a))


def study_rows(tag):
    """The case files of results/<tag>/ as dicts (no side files), with their provenance."""
    d = os.path.join(STUDY, tag)
    rows = []
    if not os.path.isdir(d):
        return rows
    for name in sorted(os.listdir(d)):
        if not name.endswith(".csv") or name.endswith("_depths.csv") or name.endswith("_columns.csv"):
            continue
        with open(os.path.join(d, name), newline="") as f:
            r = list(csv.reader(f))
        if len(r) < 2:
            continue
        rows.append(dict(zip([h.split(" [")[0] for h in r[0]], r[1])))
    return rows


def find(rows, packing, vp, eta=2.0, wave="P"):
    for r in rows:
        if (r["packing"] == packing and abs(float(r["v_p"]) - vp) < 1e-6 * vp and abs(float(r["rolling_damping"]) - eta) < 1e-9
                and r["wave"] == wave):
            return r
    return None


def pm(mean, sd, digits=2):
    m, s = float(mean), float(sd)
    if math.isnan(m):
        return "no front"
    return f"{m:.{digits}f} ± {s:.{digits}f}"


def provenance_of(rows):
    if not rows:
        return ""
    dates = sorted(r["date"] for r in rows)
    commits = sorted({r["commit"] for r in rows})
    machines = sorted({r["machine"] for r in rows})
    return (f"\n_{len(rows)} case file(s); commit {', '.join(commits)}; dates {dates[0]} – {dates[-1]}; "
            f"machine {'; '.join(machines)}._\n")


def c0_of(rows, packing):
    cs = [float(r["c_w"]) for r in rows if r["packing"] == packing and float(r["v_p"]) <= 0.1 + 1e-12
          and r["wave"] == "P" and float(r["rolling_damping"]) == 2.0 and not math.isnan(float(r["c_w"]))]
    return sum(cs) / len(cs) if cs else None


def table6_block():
    rows = {p: study_rows(p) for p in ("loose", "medium")}
    out = ["| bed | 001 φ_0 | ours φ_0 (interior) | 001 c_0 [m/s] | ours c_0 [m/s] | ours / 001 |", "|---|---|---|---|---|---|"]
    for p in ("loose", "medium"):
        phi, c0p = PAPER_T6[p]
        c0 = c0_of(rows[p], p)
        if c0 is None:
            out.append(f"| {p} | {phi / 100:.4f} | not run yet | {c0p} | not run yet | |")
            continue
        ph = rows[p][0]["packing_interior"]
        out.append(f"| {p} | {phi / 100:.4f} | {float(ph):.4f} | {c0p} | {c0:.2f} | {c0 / c0p:.3f} |")
    out.append(provenance_of(rows["loose"] + rows["medium"]) or "\n_No case file yet._\n")
    return "\n".join(out) + "\n"


def table8_block():
    out = ["| bed | v_p [m/s] | 001 c_w [m/s] | ours c_w | 001 c_p [m/s] | ours c_p | 001 M | ours M "
           "| 001 δ_m/δ_0 | ours δ_m/δ_0 | 001 Δz [mm] | ours Δz [mm] |",
           "|---|---|---|---|---|---|---|---|---|---|---|---|"]
    every = []
    for p in ("loose", "medium"):
        rows = study_rows(p)
        every += rows
        c0 = c0_of(rows, p)
        for (n, cw, cws, cp, cps, dm, dms, dz, dzs) in PAPER_T8[p]:
            vp = exponent_value(n)
            m_paper = cp / PAPER_T6[p][1]
            paper = (f"{cw:.2f} ± {cws:.2f}", f"{cp:.2f} ± {cps:.2f}", f"{m_paper:.3f}",
                     f"{dm / PAPER_DELTA0[p]:.2f} ± {dms / PAPER_DELTA0[p]:.2f}", f"{dz:+.2f} ± {dzs:.2f}")
            r = find(rows, p, vp)
            if r is None:
                out.append(f"| {p} | 10^{n} | {paper[0]} | not run yet | {paper[1]} | not run yet | {paper[2]} | | "
                           f"{paper[3]} | not run yet | {paper[4]} | not run yet |")
                continue
            mach = f"{float(r['c_p']) / c0:.3f}" if c0 and not math.isnan(float(r["c_p"])) else "–"
            out.append(f"| {p} | 10^{n} | {paper[0]} | {pm(r['c_w'], r['c_w_sd'])} | {paper[1]} | {pm(r['c_p'], r['c_p_sd'])} "
                       f"| {paper[2]} | {mach} | {paper[3]} | {float(r['delta_m_over_delta_0']):.2f} | {paper[4]} "
                       f"| {float(r['dz']) * 1e3:+.2f} ± {float(r['dz_sd']) * 1e3:.2f} |")
    out.append(provenance_of(every) or "\n_No case file yet._\n")
    return "\n".join(out) + "\n"


def length_block():
    rows = study_rows("length")
    out = ["| v_p [m/s] | quantity | 0.5 m | 1 m | difference |", "|---|---|---|---|---|"]
    verdict = "not run yet"
    diffs = []
    for vp in (10.0, 0.1):
        for q, key in (("c_w [m/s]", "c_w"), ("c_p [m/s]", "c_p"), ("δ_m/δ_0", "delta_m_over_delta_0")):
            a = next((r for r in rows if abs(float(r["length"]) - 0.5) < 1e-9 and abs(float(r["v_p"]) - vp) < 1e-9), None)
            b = next((r for r in rows if abs(float(r["length"]) - 1.0) < 1e-9 and abs(float(r["v_p"]) - vp) < 1e-9), None)
            fa = f"{float(a[key]):.3f}" if a else "not run yet"
            fb = f"{float(b[key]):.3f}" if b else "not run yet"
            d = ""
            if a and b:
                x = abs(float(a[key]) - float(b[key])) / abs(float(b[key]))
                diffs.append(x)
                d = f"{100 * x:.1f} %" if not math.isnan(x) else "no value"
            out.append(f"| {vp:g} | {q} | {fa} | {fb} | {d} |")
    if len(diffs) == 6:
        ok = all(not math.isnan(x) and x <= 0.05 for x in diffs)
        verdict = ("passed: the studies use the 0.5 m channel" if ok
                   else "failed: the studies use the 1 m channel")
    out.append("")
    out.append(f"Verdict (tolerance 5 %): **{verdict}**.")
    out.append(provenance_of(rows))
    return "\n".join(out) + "\n"


def rolling_block():
    loose, roll = study_rows("loose") + study_rows("length"), study_rows("rolling")
    out = ["| v_p [m/s] | η_r | c_w [m/s] | c_p [m/s] | δ_m/δ_0 | Δz [mm] |", "|---|---|---|---|---|---|"]
    for vp in (0.1, 10.0):
        for eta, rows in ((2.0, loose), (0.0, roll)):
            r = find(rows, "loose", vp, eta)
            if r is None:
                out.append(f"| {vp:g} | {eta:g} | not run yet | | | |")
            else:
                out.append(f"| {vp:g} | {eta:g} | {pm(r['c_w'], r['c_w_sd'])} | {pm(r['c_p'], r['c_p_sd'])} "
                           f"| {float(r['delta_m_over_delta_0']):.2f} | {float(r['dz']) * 1e3:+.2f} |")
    out.append(provenance_of(roll))
    return "\n".join(out) + "\n"


def cost_file(name):
    path = os.path.join(STUDY, "cost", name)
    if not os.path.exists(path):
        return None, []
    return read_text_table(path)


def hms(s):
    s = float(s)
    if math.isnan(s):
        return "?"
    h = s / 3600
    return f"{h:.1f} h" if h >= 1 else f"{s / 60:.0f} min"


def cost_block():
    out = []
    prov, seg = cost_file("cost_measured.csv")
    if seg:
        out += ["| phase | channel | particles | steps | dt [s] | wall [s] | ns per particle-step (wall) "
                "| ns per particle-step (CPU, both threads) | load average before / after |",
                "|---|---|---|---|---|---|---|---|---|"]
        for r in seg:
            out.append(f"| {r['phase']} | {float(r['length']):g} m | {float(r['particles']):.0f} | {float(r['steps']):.0f} "
                       f"| {float(r['dt']):g} | {float(r['wall']):.1f} | {float(r['ns_per_particle_step']):.0f} "
                       f"| {float(r['cpu_ns_per_particle_step']):.0f} | {float(r['load_before']):.1f} / {float(r['load_after']):.1f} |")
        out += ["", f"_{prov}._", ""]
    else:
        out += ["Cost not measured yet (`--measure-cost`).", ""]
    prov, pc = cost_file("pour_check.csv")
    if pc:
        out += ["| seed | pour step [s] | particles | packing fraction (interior) | coordination | δ_0 [µm] "
                "| pour simulated [s] | pour wall [s] | ns per particle-step |", "|---|---|---|---|---|---|---|---|---|"]
        for r in pc:
            out.append(f"| {r['seed']} | {float(r['dt_pour']):g} | {r['particles']} | {float(r['packing_interior']):.4f} "
                       f"| {float(r['coordination']):.3f} | {float(r['delta_0']) * 1e6:.3f} | {float(r['pour_time']):.3f} "
                       f"| {float(r['pour_wall']):.0f} | {float(r['pour_ns_per_particle_step']):.0f} |")
        out.append("")
        by = {}
        for r in pc:
            by.setdefault(float(r["dt_pour"]), []).append(r)
        means = {}
        for dt in sorted(by, reverse=True):
            rs = by[dt]
            stats = []
            for key in ("particles", "packing_interior", "coordination"):
                xs = [float(r[key]) for r in rs]
                m = sum(xs) / len(xs)
                sd = math.sqrt(sum((x - m) ** 2 for x in xs) / (len(xs) - 1)) if len(xs) > 1 else float("nan")
                stats.append((m, sd))
            means[dt] = stats
            out.append(f"Pour at {dt:g} s, {len(rs)} seeds: {stats[0][0]:.0f} ± {stats[0][1]:.0f} grains, interior packing "
                       f"{stats[1][0]:.4f} ± {stats[1][1]:.4f}, coordination {stats[2][0]:.3f} ± {stats[2][1]:.3f} "
                       "(mean ± sd).")
        if 1e-5 in means and 1e-6 in means:
            a, b = means[1e-5], means[1e-6]
            out.append(f"At 1e-6 s against 1e-5 s: grains {100 * (b[0][0] / a[0][0] - 1):+.1f} %, interior packing "
                       f"{100 * (b[1][0] / a[1][0] - 1):+.1f} %, coordination {100 * (b[2][0] / a[2][0] - 1):+.1f} %.")
        out += ["", f"_{prov}._", ""]
    prov, est = cost_file("cost_estimate.csv")
    if est:
        out += ["| estimate, 2 threads | grains (largest bed) | pour | settle | shock | wall, as measured | CPU-hours "
                "| wall, idle machine | CPU-hours, idle |", "|---|---|---|---|---|---|---|---|---|"]
        for r in est:
            if r["kind"] == "case":
                continue
            if r["kind"] == "study":
                what = f"study `{r['tag']}` ({'0.5 m and 1 m' if r['tag'] == 'length' else format(float(r['length']), 'g') + ' m'})"
            else:
                what = f"paper run: {r['tag']}"
            out.append(f"| {what} | {float(r['particles']):.0f} | {hms(r['pour'])} | {hms(r['settle'])} | {hms(r['shock'])} "
                       f"| {hms(r['total'])} | {float(r['cpu_hours']):.1f} | {hms(r['total_idle'])} "
                       f"| {float(r['cpu_hours_idle']):.1f} |")
        out += ["", f"_{prov}; settling assumed {est[0]['settle_time_assumed']} s simulated; \"as measured\": the wall time "
                "per particle-step of the segments above, under their load; \"idle\": their CPU time over the 2 threads._"]
    return "\n".join(out) + "\n"


def cost_verdict_block():
    """One generated sentence: the loose sweep's estimate against issue 26's target of ~3 h."""
    prov, est = cost_file("cost_estimate.csv")
    if not est:
        return "Cost not estimated yet (`--measure-cost`, then `--study TAG --list`).\n"
    st = {r["tag"]: r for r in est if r["kind"] == "study"}
    paper = [r for r in est if r["kind"] == "paper"]
    out = []
    if "loose" in st and "length" in st:
        lo, le = st["loose"], st["length"]
        both = float(lo["total"]) + float(le["total"])
        both_idle = float(lo["total_idle"]) + float(le["total_idle"])
        shock_share = (float(lo["shock"]) + float(le["shock"])) / both
        out.append(f"The loose sweep (the length check, which pours and settles the 0.5 m and 1 m beds and runs four "
                   f"of its cases, then the rest of table 8 on the 0.5 m bed) is estimated at {hms(both)} wall on 2 "
                   f"threads at the measured rate ({hms(both_idle)} on an idle machine), against issue 26's target of "
                   f"about 3 h; {100 * shock_share:.0f} % of it is shock steps at 1e-6 s.")
    if paper:
        r = paper[0]
        out.append(f"One full 2 m run of 001 ({r['tag']}) is estimated at {float(r['cpu_hours']):.0f} CPU-hours "
                   f"({float(r['cpu_hours_idle']):.0f} on an idle machine).")
    return " ".join(out) + "\n"


def main():
    check = "--check" in sys.argv[1:]
    summary, srows = summary_block()
    preload, prows = preload_block()
    blocks = {"grid-summary": summary, "grid-preload": preload, "grid-verdict": verdict_block(srows, prows),
              "channel-table6": table6_block(), "channel-table8": table8_block(), "channel-length": length_block(),
              "channel-rolling": rolling_block(), "channel-cost": cost_block(),
              "channel-cost-verdict": cost_verdict_block()}
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
