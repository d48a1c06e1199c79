#!/usr/bin/env python3
"""README tables and figures of the paper-scale two-rod study, from its result files.

usage: report.py [--check] [--figures DIR]

Reads examples/two_rod_intrusion/results/<tag>/ (written by `two_rod_intrusion --study <tag>`,
see run_study.sh): runs/<case>.csv (one intrusion each, with commit, date and machine),
work_vs_gap_<shape>.csv and peak_<shape>.csv (the program's summary over the beds).

Rewrites the blocks of README.md between "<!-- BEGIN GENERATED: name -->" and
"<!-- END GENERATED: name -->", and draws the figures into --figures (default
out/two_rod_study/figures; figures are not committed). With --check nothing is written: the
exit code is 1 if README.md differs from what the results give (the test of tests/CMakeLists.txt).

The paper's values are those its text states (abstract, section II, figure captions); our copy
of the paper has no figures to digitise, so the plots mark the stated values and ranges.
"""
import glob
import math
import os
import re
import sys


HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "common"))
from readme_blocks import render  # noqa: E402  (examples/common/readme_blocks.py)
from result_csv import read_table as read_rows  # noqa: E402  (examples/common/result_csv.py)
RESULTS = os.path.join(HERE, "results")
README = os.path.join(HERE, "README.md")

# Paper 000 (Pravin et al. 2020), as stated in its text.
PAPER = {
    "peak_gap": 3.0,            # abstract, sections II-VI: peak of W at s/d ~ 3
    "peak_gap_range": (2.0, 4.0),  # fig. 2 caption: peak between 2 and 4 particle diameters
    "peak_over_plateau": 1.25,  # abstract: up to 25 % greater than W at large separation (> 11 d)
    "w_star_cylinder": 0.55,    # fig. 2 caption: W* = 0.55 J for the simulations (cylinders)
    "square_over_cylinder": 4.0 / 3.141592653589793,  # fig. 3: surface-area ratio 4/pi at large gaps
    "packing": 0.62,            # table I
}


def load(tag):
    """Everything of one study tag: cases, per-gap summary, peak summary (or None)."""
    base = os.path.join(RESULTS, tag)
    if not os.path.isdir(base):
        return None
    cases = []
    for f in sorted(glob.glob(os.path.join(base, "runs", "*.csv"))):
        name = os.path.basename(f)
        if name.startswith(("force_", "velocity_")):
            continue
        cases += read_rows(f)
    s = {"tag": tag, "cases": cases, "gaps": {}, "peak": {}}
    for f in glob.glob(os.path.join(base, "work_vs_gap_*.csv")):
        shape = os.path.basename(f)[len("work_vs_gap_"):-4]
        s["gaps"][shape] = read_rows(f)
    for f in glob.glob(os.path.join(base, "peak_*.csv")):
        shape = os.path.basename(f)[len("peak_"):-4]
        s["peak"][shape] = read_rows(f)[0]
    # A part stopped before its end has cases but no per-gap summary (the program writes it when
    # the part is complete): summarise the cases here, in the summary's columns.
    # A summary that a partial run wrote (a --gap-list or --seeds subset) covers fewer cases than
    # the directory holds: summarise the cases then, too.
    for shape in sorted({c["shape"] for c in cases}):
        of_shape = [c for c in cases if c["shape"] == shape and c["gap_over_d"] >= 0]
        covered = sum(int(r["beds"]) for r in s["gaps"].get(shape, []))
        if shape not in s["gaps"] or covered != len(of_shape):
            s["gaps"][shape] = summarise_cases([c for c in cases if c["shape"] == shape])
            s["peak"].pop(shape, None)
    return s


def summarise_cases(cases):
    """Per-gap mean and standard error over beds of W, the very strong forces and dF/dz (the
    columns of work_vs_gap_*.csv); the standard error is NaN for one bed."""
    def mean_se(xs):
        m = sum(xs) / len(xs)
        if len(xs) < 2:
            return m, float("nan")
        return m, math.sqrt(sum((x - m) ** 2 for x in xs) / (len(xs) - 1) / len(xs))
    rows = []
    for gap in sorted({c["gap_over_d"] for c in cases if c["gap_over_d"] >= 0}):
        at = [c for c in cases if c["gap_over_d"] == gap]
        w, w_se = mean_se([c["work"] for c in at])
        vs, vs_se = mean_se([c["very_strong"] for c in at])
        rows.append({"gap_over_d": gap, "beds": float(len(at)), "work_mean": w, "work_se": w_se,
                     "work_over_two_single": float("nan"), "very_strong_mean": vs, "very_strong_se": vs_se,
                     "slope_mean": mean_se([c["slope"] for c in at])[0]})
    return rows


def fmt(v, digits=4):
    if isinstance(v, str):
        return v
    if v != v:  # NaN
        return "–"
    return f"{v:.{digits}g}"


def table_work(s, shape):
    rows = s["gaps"].get(shape, [])
    peak = s["peak"].get(shape, {})
    if not rows:
        return "_No results yet: run `examples/two_rod_intrusion/run_study.sh`._\n"
    out = ["| s/d | beds | W [J] (mean ± s.e.) | W / 2 W_single | very strong forces (f_n > 6⟨f_n⟩) | dF/dz [N/m] |",
           "|---|---|---|---|---|---|"]
    for r in rows:
        out.append(f"| {fmt(r['gap_over_d'])} | {int(r['beds'])} | {fmt(r['work_mean'])} ± {fmt(r['work_se'], 2)} | "
                   f"{fmt(r['work_over_two_single'], 3)} | {fmt(r['very_strong_mean'])} ± {fmt(r['very_strong_se'], 2)} | "
                   f"{fmt(r['slope_mean'], 3)} |")
    if peak and len(rows) < 6:  # a peak and a plateau need the sweep, not the two gaps of a check
        out.append("")
        out.append(f"Peak: not computed from {len(rows)} gaps; it needs the sweep.")
    elif peak:
        out.append("")
        out.append(f"Peak over {int(peak['beds'])} complete bed(s): s/d = {fmt(peak['peak_gap_over_d'])} "
                   f"(parabola through the peak and its neighbours: {fmt(peak['peak_gap_parabola'], 3)}; "
                   f"bootstrap over beds, 16–84 %: {fmt(peak['peak_gap_p16'])}–{fmt(peak['peak_gap_p84'])}; "
                   f"per bed: {peak['peak_gap_per_bed']}), W* = {fmt(peak['work_peak'])} J, "
                   f"peak / plateau (mean W at s/d ≥ 11) = {fmt(peak['peak_over_plateau'], 3)} "
                   f"({fmt(peak['peak_over_plateau_p16'], 3)}–{fmt(peak['peak_over_plateau_p84'], 3)}), "
                   f"2 W_single = {fmt(peak['two_single_work'])} J.")
    return "\n".join(out) + "\n"


def threads_of(case):
    """OpenMP threads of a case, from its machine field ("..., 1 thread"); the first cases,
    written before the field said it, ran with 2."""
    m = re.search(r", (\d+) threads?$", case["machine"])
    return int(m.group(1)) if m else 2


def table_cost(studies):
    out = ["| study | threads | cases | grains | packing φ (interior) | wall time per case [s] | ns per particle-step | CPU-hours | commits | dates (UTC) |",
           "|---|---|---|---|---|---|---|---|---|---|"]
    machines = set()
    for s in studies:
        for nt in sorted({threads_of(x) for x in s["cases"]}):
            c = [x for x in s["cases"] if threads_of(x) == nt]
            grains = sorted({int(x["particles"]) for x in c})
            phis = sorted({round(x["packing_fraction"], 4) for x in c})
            wall = [x["wall_time"] for x in c]
            ns = [x["ns_per_particle_step"] for x in c]
            commits = sorted({x["commit"] for x in c})
            dates = sorted(x["date"] for x in c)
            machines |= {re.sub(r", \d+ threads?$", "", x["machine"]) for x in c}
            out.append(f"| {s['tag']} | {nt} | {len(c)} | {', '.join(map(str, grains))} | {', '.join(map(str, phis))} | "
                       f"{min(wall):.0f}–{max(wall):.0f} | {min(ns):.0f}–{max(ns):.0f} | {nt * sum(wall) / 3600:.2f} | "
                       f"{', '.join(commits)} | {dates[0][:16]} – {dates[-1][:16]} |")
    if len(out) == 2:
        return "_No results yet: run `examples/two_rod_intrusion/run_study.sh`._\n"
    out.append("")
    out.append(f"Machine: {'; '.join(sorted(machines))}. Wall times include loading the bed and the "
               "half-depth analysis, not the pours. Cases run while the machine did other work are slower; "
               "the fastest 2-thread cases are the machine's rate.")
    sq = next((s for s in studies if s["tag"] == "square"), None)
    two = [x for x in sq["cases"] if threads_of(x) == 2] if sq else []
    if two:
        best = sorted(x["ns_per_particle_step"] for x in two)[: max(1, len(two) // 3)]
        ns = sum(best) / len(best)
        grains = sum(x["particles"] for x in two) / len(two)
        steps = sum(x["wall_time"] * 1e9 / (x["ns_per_particle_step"] * x["particles"]) for x in two) / len(two)
        scale = (0.25 * 0.25) / (0.09 * 0.09)  # the paper's 25 x 25 cm box over ours, same fill
        case_h = ns * 1e-9 * grains * scale * steps / 3600
        out.append("")
        out.append(f"At the fastest third of the 2-thread square cases ({ns:.0f} ns per particle-step, "
                   f"{grains / 1e3:.0f}k grains, {steps:.0f} steps per case), a case takes "
                   f"{ns * 1e-9 * grains * steps / 60:.1f} min; the 33 square cases "
                   f"{33 * ns * 1e-9 * grains * steps / 3600:.1f} h. "
                   f"In the paper's 25 × 25 × 10 cm box (≈ {grains * scale / 1e3:.0f}k grains) a case would take "
                   f"≈ {case_h:.1f} h with 2 threads and the 33 square cases ≈ {33 * case_h:.0f} h, pours not counted.")
    return "\n".join(out) + "\n"


# How the paper states peak over plateau: a bound over its simulations, not one value.
PAPER_RATIO = f"up to {PAPER['peak_over_plateau']} (abstract)"


def paper_box_peak(rows):
    """The peak of one bed's W(s/d) in the paper's box from the gaps run so far: the largest W,
    whether run gaps within 2 d on both sides bracket it, the parabola's vertex through it
    and its run neighbours, and the plateau (mean W at s/d >= 11). None without a plateau gap."""
    w = {r["gap_over_d"]: r["work_mean"] for r in rows}
    plateau = [w[g] for g in w if g >= 11]
    inner = {g: v for g, v in w.items() if g < 11}
    if not plateau or not inner:
        return None
    g0 = max(inner, key=inner.get)
    # neighbours close enough for a parabola: within 2 d (the sweep's spacing around the peak is 1 d)
    below = [g for g in w if g0 - 2 <= g < g0]
    above = [g for g in w if g0 < g <= g0 + 2]
    out = {"gap": g0, "work": w[g0], "plateau": sum(plateau) / len(plateau), "plateau_gaps": sorted(g for g in w if g >= 11),
           "gaps": sorted(w), "bracketed": bool(below) and bool(above), "vertex": float("nan")}
    out["ratio"] = out["work"] / out["plateau"]
    if below and above:
        a, b = max(below), min(above)
        (x0, y0), (x1, y1), (x2, y2) = (a, w[a]), (g0, w[g0]), (b, w[b])
        # vertex of the parabola through the three points (unequal spacing allowed)
        num = (x1 - x0) ** 2 * (y1 - y2) - (x1 - x2) ** 2 * (y1 - y0)
        den = (x1 - x0) * (y1 - y2) - (x1 - x2) * (y1 - y0)
        if den != 0:
            out["vertex"] = x1 - 0.5 * num / den
    return out


def rows_paper_box(s):
    """The paper-vs-ours rows of the 25 cm box (one bed, a subset of the gaps)."""
    if not s or not s["gaps"].get("square"):
        return []
    pk = paper_box_peak(s["gaps"]["square"])
    if not pk:
        return []
    gaps = ", ".join(fmt(g) for g in pk["gaps"])
    where = (f"{fmt(pk['gap'])} (parabola {fmt(pk['vertex'], 3)}; 1 bed, s/d = {gaps} run)" if pk["bracketed"]
             else f"largest W at {fmt(pk['gap'])} of s/d = {gaps}: not bracketed yet")
    plateau = " and ".join(fmt(g) for g in pk["plateau_gaps"])
    return [f"| (s/d) of the peak, square rods, 25 × 25 cm box (the paper's) | ≈ 3 (2–4) | {where} |",
            f"| peak / plateau, square rods, 25 × 25 cm box (plateau: s/d = {plateau}) | {PAPER_RATIO} | "
            f"{fmt(pk['ratio'], 3)} (1 bed{'' if pk['bracketed'] else '; the largest W run so far'}) |"]


def table_paper(studies):
    by = {s["tag"]: s for s in studies}
    sq = by.get("square", {"peak": {}, "gaps": {}})
    cy = by.get("cylinder", {"peak": {}, "gaps": {}})
    p = sq["peak"].get("square", {})
    pc = cy["peak"].get("cylinder", {})
    rows = ["| quantity | paper 000 | ours (paper scale) |", "|---|---|---|"]
    if p:
        rows.append(f"| (s/d) of the peak, square rods, 9 × 9 cm box | ≈ 3 (2–4) | {fmt(p['peak_gap_over_d'])} "
                    f"(bootstrap 16–84 %: {fmt(p['peak_gap_p16'])}–{fmt(p['peak_gap_p84'])}, {int(p['beds'])} beds) |")
        rows.append(f"| peak / plateau (s/d ≥ 11), square rods, 9 × 9 cm box | {PAPER_RATIO} | {fmt(p['peak_over_plateau'], 3)} "
                    f"({fmt(p['peak_over_plateau_p16'], 3)}–{fmt(p['peak_over_plateau_p84'], 3)}) |")
    p13 = by.get("box13", {"peak": {}})["peak"].get("square", {})
    if p13:
        rows.append(f"| (s/d) of the peak, square rods, 13 × 13 cm box | ≈ 3 (2–4) | {fmt(p13['peak_gap_over_d'])} "
                    f"(parabola {fmt(p13['peak_gap_parabola'], 3)}; bootstrap 16–84 %: {fmt(p13['peak_gap_p16'])}–"
                    f"{fmt(p13['peak_gap_p84'])}, {int(p13['beds'])} beds) |")
        rows.append(f"| peak / plateau (s/d ≥ 11), square rods, 13 × 13 cm box | {PAPER_RATIO} | "
                    f"{fmt(p13['peak_over_plateau'], 3)} ({fmt(p13['peak_over_plateau_p16'], 3)}–"
                    f"{fmt(p13['peak_over_plateau_p84'], 3)}) |")
    rows += rows_paper_box(by.get("box25"))
    ratios = []
    for tag, side in (("square", "9"), ("box13", "13"), ("box17", "17"), ("box25", "25")):
        w = {r["gap_over_d"]: r for r in by.get(tag, {"gaps": {}})["gaps"].get("square", [])}
        if 3 in w and 15 in w:
            ratios.append(f"{fmt(w[3]['work_mean'] / w[15]['work_mean'], 3)} ({side} cm, {int(w[3]['beds'])} "
                          f"bed{'s' if w[3]['beds'] > 1 else ''})")
    w3 = []
    for tag, side in (("square", "9"), ("box13", "13"), ("box17", "17"), ("box25", "25")):
        w = {r["gap_over_d"]: r for r in by.get(tag, {"gaps": {}})["gaps"].get("square", [])}
        if 3 in w:
            w3.append(f"{fmt(w[3]['work_mean'], 3)} J ({side} cm, {int(w[3]['beds'])} bed{'s' if w[3]['beds'] > 1 else ''})")
    if len(w3) > 1:
        rows.append("| W(s/d = 3), square rods, by box side | – | " + ", ".join(w3) + " |")
    if len(ratios) > 1:
        rows.append(f"| W(s/d = 3) / W(s/d = 15), square rods, by box side | up to {PAPER['peak_over_plateau']} (abstract; 25 cm box) | "
                    + ", ".join(ratios) + " |")
    if pc:
        rows.append(f"| (s/d) of the peak, cylinders | ≈ 2–3 (figs. 2C, 3) | {fmt(pc['peak_gap_over_d'])} ({int(pc['beds'])} bed) |")
        rows.append(f"| W*, cylinders | 0.55 J | {fmt(pc['work_peak'], 3)} J |")
    rho = by.get("rho1774")
    if rho and rho["gaps"].get("cylinder"):
        w = max(r["work_mean"] for r in rho["gaps"]["cylinder"])
        rows.append(f"| W* of cylinders with grains of 1774 kg/m³ (1100 read as bulk density) | 0.55 J | {fmt(w, 3)} J |")
    if sq["gaps"].get("square") and cy["gaps"].get("cylinder"):
        ws = {r["gap_over_d"]: r["work_mean"] for r in sq["gaps"]["square"]}
        wc = {r["gap_over_d"]: r["work_mean"] for r in cy["gaps"]["cylinder"]}
        common = [g for g in sorted(ws) if g in wc]
        if common:
            ratios = ", ".join(f"{fmt(ws[g] / wc[g], 3)} (s/d = {fmt(g)})" for g in common)
            rows.append(f"| W_square / W_cylinder | ≈ 4/π = 1.27 at s/d = 0 and s/d > 5 | {ratios} |")
    phis = [c["packing_fraction"] for s in studies for c in s["cases"] if s["tag"] in ("square", "cylinder")]
    if phis:
        rows.append(f"| packing fraction | 0.62 | {fmt(min(phis), 3)}–{fmt(max(phis), 3)} (interior, 2 d from walls and surface) |")
    if len(rows) == 2:
        return "_No results yet: run `examples/two_rod_intrusion/run_study.sh`._\n"
    return "\n".join(rows) + "\n"


# The box-size checks: each pair is (smaller box's tag, larger box's tag, their sides).
BOX_CHECKS = (("square", "box13", "9 × 9 cm", "13 × 13 cm"), ("box13", "box17", "13 × 13 cm", "17 × 17 cm"),
              ("box17", "box25", "17 × 17 cm", "25 × 25 cm (the paper's)"))


def standard_errors(a, b):
    """Standard errors of two boxes' mean W at one gap. A box with one bed has no spread of its
    own: it gets the one-bed spread of the other box, se * sqrt(beds) (the beds' scatter is
    assumed not to depend on the box)."""
    sa, sb = a["work_se"], b["work_se"]
    if not math.isfinite(sb) and math.isfinite(sa):
        sb = sa * math.sqrt(a["beds"])
    if not math.isfinite(sa) and math.isfinite(sb):
        sa = sb * math.sqrt(b["beds"])
    return sa, sb


def box_accepted(studies, small_tag, big_tag):
    """None when the check has not run; else whether W changes by less than the combined standard
    error at every gap both boxes ran."""
    by = {s["tag"]: s for s in studies}
    small, big = by.get(small_tag), by.get(big_tag)
    if not small or not big or not big["gaps"].get("square") or not small["gaps"].get("square"):
        return None
    ws = {r["gap_over_d"]: r for r in small["gaps"]["square"]}
    both = [(ws[r["gap_over_d"]], r) for r in big["gaps"]["square"] if r["gap_over_d"] in ws]
    if not both:
        return None
    return all(abs(b["work_mean"] - a["work_mean"]) < math.hypot(*standard_errors(a, b)) for a, b in both)


def beds(r):
    n = int(r["beds"])
    return f"{n} beds" if n > 1 else "1 bed; ± the other box's one-bed spread"


def table_box(studies):
    by = {s["tag"]: s for s in studies}
    rows = []
    for small_tag, big_tag, small_name, big_name in BOX_CHECKS:
        small, big = by.get(small_tag), by.get(big_tag)
        if rows:
            rows.append("")
        if not small or not big or not big["gaps"].get("square"):
            rows.append(f"{small_name} against {big_name}: _not run yet (`run_study.sh {big_tag}`)._")
            continue
        ws = {r["gap_over_d"]: r for r in small["gaps"].get("square", [])}
        both = [(ws[r["gap_over_d"]], r) for r in big["gaps"]["square"] if r["gap_over_d"] in ws]
        rows += [f"| s/d | W, {small_name} [J] | W, {big_name} [J] | difference | combined s.e. | dF/dz, {small_name} → "
                 f"{big_name} [N/m] |", "|---|---|---|---|---|---|"]
        for a, b in both:
            diff = b["work_mean"] - a["work_mean"]
            se = math.hypot(*standard_errors(a, b))
            sa, sb = standard_errors(a, b)
            rows.append(f"| {fmt(a['gap_over_d'])} | {fmt(a['work_mean'])} ± {fmt(sa, 2)} ({beds(a)}) | "
                        f"{fmt(b['work_mean'])} ± {fmt(sb, 2)} ({beds(b)}) | "
                        f"{100 * diff / a['work_mean']:+.1f} % | {100 * se / a['work_mean']:.1f} % | "
                        f"{fmt(a['slope_mean'], 3)} → {fmt(b['slope_mean'], 3)} |")
        ok = box_accepted(studies, small_tag, big_tag)
        if ok is None:
            continue
        rows.append("")
        rows.append(f"Verdict: the {small_name} box is " + ("accepted: W changes by less than the combined standard "
                    "error at every gap checked." if ok else "**not accepted**: W changes by more than the combined "
                    "standard error."))
        g = {a["gap_over_d"]: (a, b) for a, b in both}
        if len(g) >= 2:
            lo, hi = min(g), max(g)
            rows.append(f"W(s/d = {fmt(lo)}) / W(s/d = {fmt(hi)}): {fmt(g[lo][0]['work_mean'] / g[hi][0]['work_mean'], 3)} "
                        f"in the {small_name} box, {fmt(g[lo][1]['work_mean'] / g[hi][1]['work_mean'], 3)} in the "
                        f"{big_name} box.")
    return "\n".join(rows) + "\n"


def verdict(studies):
    """Issue 25's test, box by box: is the peak at s/d 2-4 and peak over plateau within the
    paper's bound ('up to 25 %' above W beyond 11 d)?"""
    by = {s["tag"]: s for s in studies}
    lo, hi = PAPER["peak_gap_range"]
    bound = PAPER["peak_over_plateau"]

    def judge(gap, ratio):
        where = "inside" if lo <= gap <= hi else "outside"
        within = "within" if 1.0 < ratio <= bound else "outside"
        return f"peak {where} the paper's {fmt(lo)}–{fmt(hi)}, peak / plateau {within} its bound"

    out = []
    for tag, side in (("square", "9 × 9 cm"), ("box13", "13 × 13 cm")):
        pk = by.get(tag, {"peak": {}})["peak"].get("square")
        if pk:
            out.append(f"* {side} box, {int(pk['beds'])} beds, every gap: peak at s/d = {fmt(pk['peak_gap_over_d'])} "
                       f"(parabola {fmt(pk['peak_gap_parabola'], 3)}), peak / plateau "
                       f"{pk['peak_over_plateau']:.3f}: {judge(pk['peak_gap_over_d'], pk['peak_over_plateau'])}.")
    b25 = by.get("box25")
    pk = paper_box_peak(b25["gaps"]["square"]) if b25 and b25["gaps"].get("square") else None
    if pk and pk["bracketed"]:
        w = {r["gap_over_d"]: r["work_mean"] for r in b25["gaps"]["square"]}
        second = max((g for g in w if g != pk["gap"] and g < 11), key=w.get)
        # One bed's scatter at the peak gap: the 13 cm box's bed-to-bed standard deviation.
        b13 = {r["gap_over_d"]: r for r in by.get("box13", {"gaps": {}})["gaps"].get("square", [])}
        scatter = ""
        if pk["gap"] in b13 and b13[pk["gap"]]["beds"] > 1:
            r13 = b13[pk["gap"]]
            sd = r13["work_se"] * math.sqrt(r13["beds"]) / r13["work_mean"]
            scatter = f", against one bed's scatter of {100 * sd:.1f} % (the 13 cm box's beds at s/d = {fmt(pk['gap'])})"
        out.append(f"* 25 × 25 cm box (the paper's), 1 bed, s/d = {', '.join(fmt(g) for g in pk['gaps'])}: peak at "
                   f"s/d = {fmt(pk['gap'])} (parabola {fmt(pk['vertex'], 3)}), peak / plateau {pk['ratio']:.3f}: "
                   f"{judge(pk['gap'], pk['ratio'])}. The next largest W, at s/d = {fmt(second)}, is "
                   f"{100 * (pk['work'] - w[second]) / pk['work']:.1f} % lower{scatter}.")
    elif pk:
        out.append(f"* 25 × 25 cm box (the paper's), 1 bed: the peak is not located yet (largest W at s/d = "
                   f"{fmt(pk['gap'])} of {', '.join(fmt(g) for g in pk['gaps'])}; it needs the gaps on both sides).")
    if not out:
        return "_No complete sweep yet._\n"
    return "\n".join(out) + "\n"


def table_law(studies):
    """The law check: W at the gaps of `legacy9` in the 9 cm box, LIGGGHTS 3.8's Hertz-Mindlin
    (the law paper 000 ran with) against the force history every other part uses."""
    by = {s["tag"]: s for s in studies}
    inc, leg = by.get("square"), by.get("legacy9")
    if not leg or not leg["gaps"].get("square") or not inc:
        return "_Not run yet (`run_study.sh legacy9`)._\n"
    wi = {r["gap_over_d"]: r for r in inc["gaps"].get("square", [])}
    both = sorted(((wi[r["gap_over_d"]], r) for r in leg["gaps"]["square"] if r["gap_over_d"] in wi),
                  key=lambda ab: ab[0]["gap_over_d"])
    out = ["| s/d | W, force history [J] | W, LIGGGHTS 3.8 law [J] | difference | combined s.e. |",
           "|---|---|---|---|---|"]
    for a, b in both:
        sa, sb = standard_errors(a, b)
        out.append(f"| {fmt(a['gap_over_d'])} | {fmt(a['work_mean'])} ± {fmt(sa, 2)} ({int(a['beds'])}) | "
                   f"{fmt(b['work_mean'])} ± {fmt(sb, 2)} ({int(b['beds'])}) | "
                   f"{100 * (b['work_mean'] - a['work_mean']) / a['work_mean']:+.1f} % | "
                   f"{100 * math.hypot(sa, sb) / a['work_mean']:.1f} % |")
    g = {a["gap_over_d"]: (a, b) for a, b in both}
    wide = max(g) if g else None
    if wide is not None and wide >= 11:
        out.append("")
        for gap in sorted(k for k in g if k < wide):
            (a, b), (aw, bw) = g[gap], g[wide]
            ra, rb = a["work_mean"] / aw["work_mean"], b["work_mean"] / bw["work_mean"]
            # Standard error of a ratio of two independent means, to first order.
            def se(x, y, sx, sy):
                return (x / y) * math.hypot(sx / x, sy / y)
            sa = se(a["work_mean"], aw["work_mean"], *[standard_errors(a, b)[0], standard_errors(aw, bw)[0]])
            sb = se(b["work_mean"], bw["work_mean"], *[standard_errors(a, b)[1], standard_errors(aw, bw)[1]])
            out.append(f"W(s/d = {fmt(gap)}) / W(s/d = {fmt(wide)}): {ra:.3f} ± {sa:.3f} with the force history, "
                       f"{rb:.3f} ± {sb:.3f} with the LIGGGHTS 3.8 law (paper 000: up to {PAPER['peak_over_plateau']}).")
    return "\n".join(out) + "\n"


def blocks(studies):
    by = {s["tag"]: s for s in studies}
    sq = by.get("square", {"gaps": {}, "peak": {}})
    cy = by.get("cylinder", {"gaps": {}, "peak": {}})
    return {
        "paper-vs-ours": table_paper(studies),
        "verdict": verdict(studies),
        "work-square": table_work(sq, "square"),
        "work-cylinder": table_work(cy, "cylinder"),
        "work-square-13": table_work(by.get("box13", {"gaps": {}, "peak": {}}), "square"),
        "work-square-25": table_work(by.get("box25", {"gaps": {}, "peak": {}}), "square"),
        "box-check": table_box(studies),
        "law-check": table_law(studies),
        "cost": table_cost(studies),
    }


def figures(studies, outdir):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np

    os.makedirs(outdir, exist_ok=True)
    by = {s["tag"]: s for s in studies}
    # W(s/d) with error bars, the paper's peak band and plateau ratio, very strong forces.
    fig, ax = plt.subplots(figsize=(7, 4.5))
    ax2 = ax.twinx()
    for tag, shape, col in (("square", "square", "C0"), ("cylinder", "cylinder", "C1")):
        rows = by.get(tag, {"gaps": {}})["gaps"].get(shape)
        if not rows:
            continue
        g = np.array([r["gap_over_d"] for r in rows])
        w = np.array([r["work_mean"] for r in rows])
        e = np.array([r["work_se"] for r in rows])
        e = np.where(np.isfinite(e), e, 0.0)
        ax.errorbar(g, w, yerr=e, fmt="o-", color=col, capsize=3, label=f"W, {shape} ({int(max(r['beds'] for r in rows))} beds)")
        vs = np.array([r["very_strong_mean"] for r in rows])
        ax2.plot(g, vs, "s--", color=col, alpha=0.5, label=f"very strong forces, {shape}")
        pk = by[tag]["peak"].get(shape)
        if pk and np.isfinite(pk["work_plateau"]):
            ax.axhline(PAPER["peak_over_plateau"] * pk["work_plateau"], color=col, ls=":", lw=1,
                       label=f"paper: peak up to 1.25 × our plateau ({shape})")
    ax.axvspan(*PAPER["peak_gap_range"], color="0.85", zorder=0, label="paper: peak at s/d 2–4")
    ax.set_xlabel("gap s/d")
    ax.set_ylabel("W [J]")
    ax2.set_ylabel("very strong forces at z = 4 cm")
    h1, l1 = ax.get_legend_handles_labels()
    h2, l2 = ax2.get_legend_handles_labels()
    ax.legend(h1 + h2, l1 + l2, fontsize=7, loc="lower right")
    fig.tight_layout()
    fig.savefig(os.path.join(outdir, "work_vs_gap.png"), dpi=130)
    plt.close(fig)
    # F(z), mean over beds, for a few gaps.
    fig, ax = plt.subplots(figsize=(6, 4))
    base = os.path.join(RESULTS, "square", "runs")
    for g in (0, 3, 6, 15, "single"):
        tag = f"s{g}" if g != "single" else "single"
        files = sorted(glob.glob(os.path.join(base, f"force_square_bed*_{tag}.csv")))
        if not files:
            continue
        data = [read_rows(f) for f in files]
        z = np.array([r["depth"] for r in data[0]])
        n = min(len(d) for d in data)
        f = np.mean([[r["force_z"] for r in d[:n]] for d in data], axis=0)
        ax.plot(100 * z[:n], f, label=f"{'single rod' if g == 'single' else f's/d = {g}'} ({len(files)} beds)")
    ax.set_xlabel("depth z [cm]")
    ax.set_ylabel("F [N]")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(outdir, "force_vs_depth.png"), dpi=130)
    plt.close(fig)
    # V_y, V_z below the rods (paper fig. 6), first bed.
    fig, axs = plt.subplots(1, 2, figsize=(10, 3.8), sharex=True)
    for g in (0, 2, 3, 4, 6):
        f = os.path.join(base, f"velocity_square_bed1_s{g}.csv")
        if not os.path.exists(f):
            continue
        r = read_rows(f)
        y = np.array([x["y_minus_centre_over_d"] for x in r])
        axs[0].plot(y, [x["v_y"] for x in r], label=f"s/d = {g}")
        axs[1].plot(y, [x["v_z"] for x in r], label=f"s/d = {g}")
    for a, t in zip(axs, ("V_y [m/s]", "V_z [m/s]")):
        a.set_xlabel("y/d from the pair's centre")
        a.set_ylabel(t)
        a.set_xlim(-15, 15)
        a.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(os.path.join(outdir, "velocity_profiles.png"), dpi=130)
    plt.close(fig)
    # Strain-rate maps (paper fig. 7), first bed.
    files = sorted(glob.glob(os.path.join(RESULTS, "square", "fields", "strain_rate_square_bed1_s*.csv")),
                   key=lambda p: float(re.search(r"_s([0-9.]+)\.csv$", p).group(1)))
    if files:
        fig, axs = plt.subplots(1, len(files), figsize=(3 * len(files), 3), squeeze=False)
        for a, f in zip(axs[0], files):
            r = read_rows(f)
            y = np.array([x["y_minus_centre_over_d"] for x in r])
            z = np.array([x["z_minus_rod_bottom_over_d"] for x in r])
            e = np.array([x["strain_rate"] for x in r])
            sc = a.scatter(y, z, c=e, s=4, cmap="viridis", vmin=0, vmax=np.nanpercentile(e, 98))
            a.set_title(os.path.basename(f)[len("strain_rate_square_bed1_"):-4].replace("s", "s/d = "), fontsize=9)
            a.set_xlabel("y/d")
            a.set_xlim(-15, 15)
        axs[0][0].set_ylabel("(z − rod bottom)/d")
        fig.colorbar(sc, ax=axs[0].tolist(), label="|ε̇| [1/s]")
        fig.savefig(os.path.join(outdir, "strain_rate.png"), dpi=130)
        plt.close(fig)


def main(argv):
    check = "--check" in argv
    outdir = os.path.join(HERE, "..", "..", "out", "two_rod_study", "figures")
    if "--figures" in argv:
        outdir = argv[argv.index("--figures") + 1]
    studies = [s for s in (load(t) for t in ("square", "cylinder", "rho1774", "box13", "box17", "box25", "legacy9")) if s]
    with open(README, encoding="utf-8") as f:
        text = f.read()
    new = render(text, blocks(studies))
    if check:
        if new != text:
            print("report.py --check: README.md differs from the results; run examples/two_rod_intrusion/report.py")
            return 1
        print("report.py --check: README.md matches the results")
        return 0
    with open(README, "w", encoding="utf-8") as f:
        f.write(new)
    figures(studies, outdir)
    print(f"README.md regenerated; figures in {os.path.normpath(outdir)}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
