#!/usr/bin/env python3
"""README tables and figures of the intruder pull-out convergence study (issue 27), from its
result files.

usage: report.py [--check] [--figures DIR] [--results DIR] [--readme FILE]

Reads examples/intruder_pull_out_2d/results/<tag>/ (written by `intruder_pull_out_2d --study
<tag>`, see run_study.sh): plan.csv (the cases in run order, with kappa, I and the estimated
steps) and one directory per case done, <case>/summary.csv (every statistic, the parameters, the
cost, commit, date and machine), profile.csv (the pull per mm of travel), bands.csv (third-octave
spectrum) and velocity_map_h*.csv (two maps at loading peaks). A planned case without a
summary.csv is shown as "not run yet".

Rewrites the blocks of README.md between "<!-- BEGIN GENERATED: name -->" and
"<!-- END GENERATED: name -->" and draws the figures into --figures (default
out/intruder_pull_out_2d_study/figures; figures are not committed). With --check nothing is
written: the exit code is 1 if README.md differs from what the results give (the ctest
intruder_pull_out_2d_readme_matches_results).

002's values are those its text states (sections 2.4, 3.1, 3.2, 4); the tolerance used to call
one of ours "within 002's spread" is given with each in PAPER.
"""
import csv
import math
import os
import sys


HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "common"))
from readme_blocks import render  # noqa: E402  (examples/common/readme_blocks.py)
from result_csv import read_table  # noqa: E402  (examples/common/result_csv.py)
ROOT = os.path.normpath(os.path.join(HERE, "..", ".."))
RESULTS = os.path.join(HERE, "results")
README = os.path.join(HERE, "README.md")
TAGS = ("convergence", "dtcheck")
D = 3e-3  # mean diameter [m]

# Paper 002 as stated in its text, with the spread we allow (our choice where 002 gives none).
PAPER = {
    "spacing": 0.5 * D,    # 3.1: peaks spaced about d/2 (1 Hz at ~1 mm/s); test: the d/2 band stands out
    "quiet": 0.045,        # 3.1: fluctuations vanish in the top 45 mm ("nearly"): +- d
    "quiet_tol": D,
    "mu_above_h1": 0.24,   # 4, fig. 13: above H1 bulk and wall mu* decrease toward 0.24: +- 0.05
    "mu_tol": 0.05,
    "cone": 60.0,          # 3.2 c: opening angle of the cone 60 deg, "almost constant": +- 5 deg
    "cone_tol": 5.0,
    "phi": 0.82,           # 2.4: 0.82 +- 0.02
    "phi_tol": 0.02,
    "sliding": 0.20,       # 4, fig. 12c: slip threshold reached for less than 20 % of the contacts
    "h1": 0.078,           # 3.2 c: H1 = (L_c - L)/2 tan(beta) = 0.078 m
}


def read_csv(path):
    with open(path, newline="", encoding="utf-8") as f:
        return [r for r in csv.reader(f) if r and not r[0].startswith("#")]


def read_summary(path):
    s = {}
    for r in read_csv(path)[1:]:
        try:
            s[r[0]] = float(r[1])
        except ValueError:
            s[r[0]] = r[1]
    return s if "machine" in s else None


def load(tag):
    """The plan of a tag and the summaries of its cases done (None when there is no plan)."""
    base = os.path.join(RESULTS, tag)
    plan_file = os.path.join(base, "plan.csv")
    if not os.path.exists(plan_file):
        return None
    plan = read_table(plan_file)
    for c in plan:
        f = os.path.join(base, c["case"], "summary.csv")
        c["summary"] = read_summary(f) if os.path.exists(f) else None
        c["dir"] = os.path.join(base, c["case"])
    return {"tag": tag, "plan": plan}


def fmt(v, digits=3):
    if v is None or (isinstance(v, float) and not math.isfinite(v)):
        return "–"
    if isinstance(v, str):
        return v
    return f"{v:.{digits}g}"


def mm(v, digits=3):
    return "–" if v is None or not math.isfinite(v) else f"{1e3 * v:.{digits}g} mm"


def duration(seconds):
    s = int(round(seconds))
    return f"{s // 3600}:{s // 60 % 60:02d}:{s % 60:02d}" if s >= 3600 else f"{s // 60}:{s % 60:02d}"


RATE_NS = 94.0  # ns per particle-step of the estimates: the median of the cases run (main), else issue 27's rate


def estimate_seconds(c):
    return RATE_NS * 1e-9 * c["disks"] * (c["fill_steps_estimate"] + c["pull_steps_estimate"])


def measured_rate(studies):
    rates = sorted(c["summary"]["ns_per_particle_step"] for st in studies.values() for c in st["plan"]
                   if c["summary"] and c["disks"] >= 1000)
    return rates[len(rates) // 2] if rates else 94.0


def reference_case(study):
    """The most converged case done: the smallest I, then the largest kappa."""
    done = [c for c in study["plan"] if c["summary"]] if study else []
    if not done:
        return None
    return min(done, key=lambda c: (round(c["inertial_number"], 12), -c["kappa"]))


def within(value, target, tol):
    if value is None or not math.isfinite(value):
        return "–"
    return "yes" if abs(value - target) <= tol else "no"


def table_paper(studies):
    conv = studies.get("convergence")
    ref = reference_case(conv)
    if not ref:
        return "_Not run yet: `examples/intruder_pull_out_2d/run_study.sh` (the convergence set)._\n"
    s = ref["summary"]
    verdict = "stands out" if s["half_d_stands_out"] == 1 else "does not stand out"
    rows = [
        f"Most converged case run: `{ref['case']}` (κ = {fmt(ref['kappa'])}, I = {fmt(ref['inertial_number'])}; "
        f"002: κ = {fmt(1.92e8 / (2500 * 0.82 * 9.81 * 0.15 * 0.009))} with t = 3 d, I = {fmt(1.2e-3 / math.sqrt(0.82 * 9.81 * 0.15))}).",
        "",
        "| quantity | 002 | ours | within 002's spread |",
        "|---|---|---|---|",
        f"| spacing of the drag peaks | ≈ d/2 = 1.5 mm (3.1) | d/2 band / neighbours R = {fmt(s['half_d_ratio'])} "
        f"(95 % point {fmt(s['half_d_critical'])}): {verdict}; maxima spaced {mm(s['event_spacing'])} "
        f"({fmt(s['event_spacing'] / D, 2)} d) | {'yes' if s['half_d_stands_out'] == 1 else 'no'} (a d/2 peak must stand out) |",
        f"| mean μ* above H1 (bulk / walls) | → 0.24 (4, fig. 13) | {fmt(s['mu_bulk_above_h1'])} / {fmt(s['mu_wall_above_h1'])}; "
        f"last 10 % of the pull {fmt(s['mu_bulk_end'])} / {fmt(s['mu_wall_end'])} | "
        f"{within(s['mu_bulk_end'], PAPER['mu_above_h1'], PAPER['mu_tol'])} (end value ± {PAPER['mu_tol']}) |",
        f"| quiet top layer | ≈ 45 mm (3.1) | {mm(s['quiet_thickness_q2'])} (drops > 2 % of the peak; 1 %: "
        f"{mm(s['quiet_thickness_q1'])}, 5 %: {mm(s['quiet_thickness_q5'])}) | "
        f"{within(s['quiet_thickness_q2'], PAPER['quiet'], PAPER['quiet_tol'])} (± d) |",
        f"| cone: edges' inclination | 60° (3.2 c) | {fmt(s['cone_angle'])}° (quartiles {fmt(s['cone_angle_p25'])}–"
        f"{fmt(s['cone_angle_p75'])}°, {int(s['cone_samples'])} drag maxima) | "
        f"{within(s['cone_angle'], PAPER['cone'], PAPER['cone_tol'])} (± 5°) |",
        f"| packing fraction | 0.82 ± 0.02 (2.4) | {fmt(s['phi_interior'])} interior, {fmt(s['phi_whole'])} whole bed | "
        f"{within(s['phi_interior'], PAPER['phi'], PAPER['phi_tol'])} |",
        f"| contacts at the Coulomb threshold | < 20 % (4, fig. 12c) | {fmt(100 * s['sliding_bulk'])} % of the bulk | "
        f"{'yes' if s['sliding_bulk'] < PAPER['sliding'] else 'no'} |",
        f"| wall bands mobile (v* ≥ 0.25), below / above H1 | mobility lost near the walls above H1 (4) | "
        f"{fmt(s['wall_mobility_below_h1'])} / {fmt(s['wall_mobility_above_h1'])} | – |",
        f"| drag peak, its height; drop, reload | high peak, disappears, new loading (3.1, fig. 6) | "
        f"{fmt(s['peak'])} N ({fmt(s['peak_over_column'])} M g L/W) at {mm(s['peak_height'])}; {fmt(s['drop'])} N at "
        f"{mm(s['drop_height'])}, {fmt(s['reload'])} N at {mm(s['reload_height'])} | – |",
    ]
    return "\n".join(rows) + "\n"


def table_convergence(study, tag):
    if not study:
        return f"_No plan yet: `intruder_pull_out_2d --study {tag} --list --results examples/intruder_pull_out_2d/results/{tag}`._\n"
    out = ["| case | κ | I | dt / dt_c | peak [N] (/ M g L/W) at h | drop → reload [N] | quiet layer (q = 2 %) | "
           "μ* above H1, bulk / walls | μ* end | d/2: R (95 % point) | maxima spacing / d | cone [°] (quartiles) | φ interior |",
           "|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for c in study["plan"]:
        s = c["summary"]
        head = f"| `{c['case']}` | {fmt(c['kappa'])} | {fmt(c['inertial_number'])} |"
        if not s:
            out.append(head + f" – | not run yet (about {duration(estimate_seconds(c))} at {RATE_NS:.0f} ns per particle-step) |"
                       " | | | | | | | |")
            continue
        out.append(
            head + f" {fmt(s['dt_pull_over_dt_c'])} | {fmt(s['peak'])} ({fmt(s['peak_over_column'])}) at {mm(s['peak_height'])} | "
            f"{fmt(s['drop'])} → {fmt(s['reload'])} | {mm(s['quiet_thickness_q2'])} | "
            f"{fmt(s['mu_bulk_above_h1'])} / {fmt(s['mu_wall_above_h1'])} | {fmt(s['mu_bulk_end'])} | "
            f"{fmt(s['half_d_ratio'])} ({fmt(s['half_d_critical'])}) | {fmt(s['event_spacing'] / D, 2)} | "
            f"{fmt(s['cone_angle'])} ({fmt(s['cone_angle_p25'])}–{fmt(s['cone_angle_p75'])}) | {fmt(s['phi_interior'])} |")
    return "\n".join(out) + "\n"

# The headlines whose convergence the study decides: summary key, scale, label.
HEADLINES = (
    ("peak_over_column", 1.0, "drag peak / (M g L/W)"),
    ("drop", 1.0, "drop [N]"),
    ("reload", 1.0, "reload [N]"),
    ("quiet_thickness_q2", 1e3, "quiet layer, q = 2 % [mm]"),
    ("mu_bulk_above_h1", 1.0, "μ* bulk above H1"),
    ("mu_bulk_end", 1.0, "μ* bulk, last 10 % of the pull"),
    ("half_d_ratio", 1.0, "d/2 band ratio R"),
    ("cone_angle", 1.0, "cone [°]"),
    ("phi_interior", 1.0, "φ interior"),
    ("sliding_bulk", 100.0, "bulk contacts at the threshold [%]"),
    ("wall_mobility_above_h1", 1.0, "wall bands mobile above H1"),
)


def arms(study):
    """The cross of the study: the kappa arm (V = 20 mm/s, seed 1), the I arm (E = 6e8 Pa, seed 1)
    and the beds at the cheapest point (E = 6e7 Pa, V = 20 mm/s), each sorted towards 002."""
    done = [c for c in study["plan"] if c["summary"]] if study else []
    e_arm = sorted([c for c in done if abs(c["pull_velocity"] - 0.02) < 1e-12 and int(c["seed"]) == 1],
                   key=lambda c: c["kappa"])
    v_arm = sorted([c for c in done if abs(c["youngs_modulus"] - 6e8) < 1.0 and int(c["seed"]) == 1],
                   key=lambda c: -c["inertial_number"])
    beds = [c for c in done if abs(c["youngs_modulus"] - 6e7) < 1.0 and abs(c["pull_velocity"] - 0.02) < 1e-12]
    return e_arm, v_arm, beds


def trend(arm, key, scale, sigma, xkey):
    """The values along an arm; the slope per decade of a straight line through its last three
    points against log10 of the arm's variable; z = that slope over its standard error for
    independent values of standard deviation sigma. |z| < 2 counts as converged: over the arm's
    last decade or so the headline moves no more than the beds scatter."""
    vals = [scale * c["summary"][key] for c in arm]
    if len(vals) < 2 or not sigma:
        return vals, None, None
    xs = [math.log10(c[xkey]) for c in arm[-3:]]
    ys = vals[-3:]
    xm, ym = sum(xs) / len(xs), sum(ys) / len(ys)
    sxx = sum((x - xm) ** 2 for x in xs)
    slope = sum((x - xm) * (y - ym) for x, y in zip(xs, ys)) / sxx
    return vals, slope, slope / (sigma / math.sqrt(sxx))


def table_converged(study):
    e_arm, v_arm, beds = arms(study)
    if len(beds) < 2 or len(e_arm) < 2:
        return "_Needs the beds at the cheapest point and two stiffnesses (`run_study.sh convergence`)._\n"
    ref = reference_case(study)
    out = [f"σ: standard deviation over the {len(beds)} beds at κ = {fmt(beds[0]['kappa'])}, I = "
           f"{fmt(beds[0]['inertial_number'])}. Slope: of a straight line through the arm's last three points "
           "against log10 κ or log10 I, per decade (towards 002: a rise of κ, a fall of I); z: the slope over its "
           "standard error for points that scatter by σ. |z| < 2 counts as converged. Value: the most converged "
           f"case run, `{ref['case']}`, ± σ.",
           "",
           "| quantity | σ | κ arm: " + " → ".join(fmt(c["kappa"], 2) for c in e_arm) + " | slope (z), κ | I arm: "
           + " → ".join(fmt(c["inertial_number"], 2) for c in v_arm) + " | slope (z), I | converged value |",
           "|---|---|---|---|---|---|---|"]
    for key, scale, label in HEADLINES:
        bed_vals = [scale * c["summary"][key] for c in beds]
        mean = sum(bed_vals) / len(bed_vals)
        sigma = math.sqrt(sum((v - mean) ** 2 for v in bed_vals) / (len(bed_vals) - 1))
        ev, es, ez = trend(e_arm, key, scale, sigma, "kappa")
        iv, is_, iz = trend(v_arm, key, scale, sigma, "inertial_number")
        if is_ is not None:
            is_ = -is_  # per decade of falling I
            iz = -iz

        def verdict(slope, z):
            return "–" if z is None else f"{fmt(slope, 2)} ({z:+.1f})" + ("" if abs(z) < 2 else " **not converged**")

        converged = (ez is not None and abs(ez) < 2) and (iz is None or abs(iz) < 2)
        value = f"{fmt(scale * ref['summary'][key])} ± {fmt(sigma, 2)}" + ("" if converged else " (not converged)")
        out.append(f"| {label} | {fmt(sigma, 2)} | " + ", ".join(fmt(v) for v in ev) + f" | {verdict(es, ez)} | "
                   + ", ".join(fmt(v) for v in iv) + f" | {verdict(is_, iz)} | {value} |")
    return "\n".join(out) + "\n"


def table_cost(studies):
    out = ["| case | disks | steps: fill + pull | wall time: fill + pull | ns per particle-step | commit | date (UTC) | machine |",
           "|---|---|---|---|---|---|---|---|"]
    total_est, total_run, n_run = 0.0, 0.0, 0
    for tag in TAGS:
        st = studies.get(tag)
        if not st:
            continue
        for c in st["plan"]:
            s = c["summary"]
            if not s:
                total_est += estimate_seconds(c)
                out.append(f"| `{c['case']}` | {int(c['disks'])} | estimated {fmt(c['fill_steps_estimate'])} + "
                           f"{fmt(c['pull_steps_estimate'])} | not run yet (about {duration(estimate_seconds(c))}) | | | | |")
                continue
            n_run += 1
            total_run += s["fill_wall_time"] + s["pull_wall_time"]
            out.append(f"| `{c['case']}` | {int(s['disks'])} | {fmt(s['fill_steps'])} + {fmt(s['pull_steps'])} | "
                       f"{s['fill_wall_time']:.0f} s + {s['pull_wall_time']:.0f} s | {s['ns_per_particle_step']:.0f} | "
                       f"{s['commit']} | {s['date'][:16]} | {s['machine']} |")
    if len(out) == 2:
        return "_No plan yet._\n"
    out.append("")
    out.append(f"{n_run} case(s) run in {duration(total_run)} of wall time; the cases not run yet need about "
               f"{duration(total_est)} at {RATE_NS:.0f} ns per particle-step (the median rate of the 1600-disk cases run, "
               "coarse-graining included; 94 ns was issue 27's rate before the 2D packed contacts). A bed shared by "
               "several cases is filled once (the first case pays it).")
    return "\n".join(out) + "\n"


def table_dtcheck(studies):
    st = studies.get("dtcheck")
    if not st:
        return "_No plan yet._\n"
    done = [c for c in st["plan"] if c["summary"]]
    if len(done) < 2:
        return ("_Not run yet (`run_study.sh dtcheck`): the quick cell at E = 6e8 Pa, V = 20 mm/s, pulled from one bed "
                "with the engine's step and with 002's dt_c / 60._\n")
    rows = ["| quantity | " + " | ".join(f"`{c['case']}` (dt = {fmt(c['summary']['dt_pull'])} s)" for c in done) + " |",
            "|---" * (len(done) + 1) + "|"]
    for key, label in (("peak", "peak [N]"), ("drag_mean", "mean drag [N]"), ("third1_drag_mean", "mean drag, first third [N]"),
                       ("third2_drag_mean", "mean drag, second third [N]"), ("mu_bulk_below_h1", "μ* bulk below H1"),
                       ("mu_bulk_above_h1", "μ* bulk above H1"), ("quiet_thickness_q5", "quiet layer, q = 5 % [m]"),
                       ("cone_angle", "cone [°]")):
        rows.append(f"| {label} | " + " | ".join(fmt(c["summary"][key]) for c in done) + " |")
    return "\n".join(rows) + "\n"


MODES = ("quick", "medium")
INTRUDER_LENGTH = 0.010  # L [m]


def load_modes():
    """The summaries of the quick and medium runs (run_study.sh modes), by mode; None if absent."""
    out = {}
    for m in MODES:
        f = os.path.join(RESULTS, "modes", m, "summary.csv")
        out[m] = read_summary(f) if os.path.exists(f) else None
    return out


def sci(v, digits=2):
    """2.0·10⁴ for 19890 (digits significant)."""
    if v == 0 or not math.isfinite(v):
        return fmt(v)
    e = math.floor(math.log10(abs(v)))
    if -2 <= e < digits:
        return fmt(v, digits)
    sup = str(e).translate(str.maketrans("-0123456789", "⁻⁰¹²³⁴⁵⁶⁷⁸⁹"))
    return f"{v / 10 ** e:.{digits - 1}f}·10{sup}"


def seconds(v):
    return f"{v:.1f} s" if v < 60 else duration(v)


def table_modes(modes):
    """The quick and medium modes beside 002: every figure from their summary.csv."""
    runs = [(m, modes.get(m)) for m in MODES]
    if not any(s for _, s in runs):
        return "_Not run yet (`run_study.sh modes`)._\n"
    lines = []
    for m, s in runs:
        if s is None:
            lines.append(f"{m}: not run yet (`run_study.sh modes`).")
            continue
        lines.append(f"{m}: commit {s['commit']}, {s['date']}, {s['machine']}; fill {seconds(s['fill_wall_time'])}, "
                     f"pull {seconds(s['pull_wall_time'])} of wall time (of which {seconds(s['analysis_wall_time'])} "
                     f"coarse-graining), {fmt(s['ns_per_particle_step'])} ns per particle-step.")
    head = "`OMP_NUM_THREADS=1 intruder_pull_out_2d [--medium]`, seed 1 (`run_study.sh modes`). " + " ".join(lines)

    def col(fn):
        return [fn(s) if s else "–" for _, s in runs]

    def hmm(v):
        return mm(v, 3)

    def quiet(s):
        half_gap = 0.5 * (s["cell_width"] - INTRUDER_LENGTH)
        return (f"{mm(s['quiet_thickness_q2'])} ({mm(s['quiet_thickness_q1'])}, {mm(s['quiet_thickness_q5'])}); "
                f"(W − L)/2 = {mm(half_gap)}")

    def maps(s):
        out = []
        for k in range(1, 10):
            if f"map{k}_height" not in s:
                break
            a = s[f"map{k}_cone_angle"]
            out.append(f"{f'{a:.0f}°' if isinstance(a, float) and math.isfinite(a) else '–'} at {hmm(s[f'map{k}_height'])}")
        return ", ".join(out) if out else "–"

    rows = [
        ("packing fraction (interior / whole bed)", "0.82 ± 0.02",
         col(lambda s: f"{s['phi_interior']:.3f} / {s['phi_whole']:.3f}")),
        ("mean surface", "150 mm", col(lambda s: hmm(s["mean_surface"]))),
        ("drag peak, height (÷ M g L/W)", "a high peak at the start",
         col(lambda s: f"{fmt(s['peak'])} N at {hmm(s['peak_height'])} ({fmt(s['peak_over_column'], 2)})")),
        ("drop → reload (d̄/2 running mean)", "the peak disappears, then a new loading",
         col(lambda s: f"{fmt(s['smoothed_peak'])} N at {hmm(s['smoothed_peak_height'])} → {fmt(s['drop'])} N at "
                       f"{hmm(s['drop_height'])} → {fmt(s['reload'])} N at {hmm(s['reload_height'])}")),
        ("drag by thirds: mean (std)", "relaxation, fluctuations shrinking upwards",
         col(lambda s: ", ".join(f"{fmt(s[f'third{k}_drag_mean'], 2)} ({fmt(s[f'third{k}_drag_std'], 2)})"
                                 for k in (1, 2, 3)) + " N")),
        ("quiet top layer, q = 2 % (1 %, 5 %)", "45 mm = (W − L)/2", col(quiet)),
        ("d̄/2 band: R (95 % point)", "peaks spaced ≈ d̄/2",
         col(lambda s: f"{fmt(s['half_d_ratio'])} ({fmt(s['half_d_critical'])}): "
                       + ("stands out" if s["half_d_stands_out"] else "does not stand out"))),
        ("spacing of the drag's maxima", "≈ d̄/2",
         col(lambda s: f"{hmm(s['event_spacing'])} ({fmt(s['event_spacing'] / D, 2)} d̄)")),
        ("largest power per octave", "—", col(lambda s: f"λ = {hmm(s['dominant_wavelength'])}")),
        ("μ* bulk / walls: below H1, above H1, end", "maximum low in the bed; → 0.24 above H1",
         col(lambda s: ", ".join(f"{s[f'mu_bulk_{w}']:.3f} / {s[f'mu_wall_{w}']:.3f}"
                                 for w in ("below_h1", "above_h1", "end")))),
        ("bulk contacts at the Coulomb threshold", "< 20 %", col(lambda s: f"{100 * s['sliding_bulk']:.1f} %")),
        ("cone's edges at the drag maxima: median (quartiles)", "60°",
         col(lambda s: f"{s['cone_angle']:.0f}° ({s['cone_angle_p25']:.0f}–{s['cone_angle_p75']:.0f}°)")),
        ("cone on the maps (loading peaks)", "60°", col(maps)),
        ("wall bands mobile, below / above H1", "mobility lost near the walls above H1",
         col(lambda s: f"{fmt(s['wall_mobility_below_h1'], 2)} / {fmt(s['wall_mobility_above_h1'], 2)}")),
    ]
    names = [f"{m} (κ = {sci(s['kappa'])}, I = {sci(s['inertial_number'])})" if s else m for m, s in runs]
    out = [head, "", "| quantity | 002 | " + " | ".join(names) + " |", "|---|---|" + "---|" * len(runs)]
    for name, paper, vals in rows:
        out.append(f"| {name} | {paper} | " + " | ".join(vals) + " |")
    return "\n".join(out) + "\n"


def blocks(studies, modes=None):
    return {
        "modes": table_modes(modes or {}),
        "paper-vs-ours": table_paper(studies),
        "convergence": table_convergence(studies.get("convergence"), "convergence"),
        "converged": table_converged(studies.get("convergence")),
        "dtcheck": table_dtcheck(studies),
        "cost": table_cost(studies),
    }


def figures(studies, outdir):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    os.makedirs(outdir, exist_ok=True)
    conv = studies.get("convergence")
    plan = conv["plan"] if conv else []
    done = [c for c in plan if c["summary"]]
    e_arm, v_arm, seeds = arms(conv)
    # Convergence figure: the headlines against kappa and against I, 002's values as lines.
    quantities = [
        ("quiet_thickness_q2", 1e3, "quiet layer [mm]", 1e3 * PAPER["quiet"]),
        ("mu_bulk_above_h1", 1.0, "μ* bulk above H1", PAPER["mu_above_h1"]),
        ("mu_bulk_end", 1.0, "μ* bulk, end of pull", PAPER["mu_above_h1"]),
        ("cone_angle", 1.0, "cone [°]", PAPER["cone"]),
        ("half_d_ratio", 1.0, "d/2 band ratio R", None),
        ("event_spacing", 1.0 / D, "maxima spacing / d", 0.5),
        ("peak_over_column", 1.0, "peak / (M g L/W)", None),
        ("phi_interior", 1.0, "φ interior", PAPER["phi"]),
    ]
    fig, axs = plt.subplots(2, len(quantities), figsize=(2.6 * len(quantities), 5.6), squeeze=False)
    for row, (arm, xkey, xlabel) in enumerate(((e_arm, "kappa", "κ (V = 20 mm/s)"), (v_arm, "inertial_number", "I (E = 6e8 Pa)"))):
        for col, (key, scale, label, paper) in enumerate(quantities):
            ax = axs[row][col]
            xs = [c[xkey] for c in arm]
            ys = [scale * c["summary"][key] for c in arm]
            ax.semilogx(xs, ys, "o-")
            if key == "half_d_ratio":
                ax.semilogx(xs, [c["summary"]["half_d_critical"] for c in arm], "k:", label="95 % point")
            if row == 0 and seeds:
                ax.semilogx([c["kappa"] for c in seeds], [scale * c["summary"][key] for c in seeds], "x", color="C1",
                            label="other beds")
            if paper is not None:
                ax.axhline(paper, color="r", ls="--", lw=1, label="002")
            if not arm:
                ax.text(0.5, 0.5, "not run yet", ha="center", transform=ax.transAxes)
            ax.set_xlabel(xlabel, fontsize=8)
            if row == 0:
                ax.set_title(label, fontsize=8)
            ax.tick_params(labelsize=7)
            if col == 0 and row == 0 and ax.get_legend_handles_labels()[0]:
                ax.legend(fontsize=6)
    fig.tight_layout()
    fig.savefig(os.path.join(outdir, "convergence.png"), dpi=120)
    plt.close(fig)
    # Drag and mu* against height for every case done.
    fig, (a1, a2) = plt.subplots(2, 1, figsize=(8, 7), sharex=True)
    for c in done:
        p = read_table(os.path.join(c["dir"], "profile.csv"))
        s = c["summary"]
        h = [1e3 * r["intruder_height"] for r in p]
        a1.plot(h, [r["drag"] / s["column_weight"] for r in p], lw=0.8, label=c["case"])
        a2.plot(h, [r["mu_star_bulk"] for r in p], lw=0.8)
    if done:
        h1 = done[0]["summary"]["h1"]
        a2.axvline(1e3 * h1, color="k", ls=":", label="H1")
        a2.axhline(PAPER["mu_above_h1"], color="r", ls="--", label="002: → 0.24 above H1")
        surf = done[0]["summary"]["mean_surface"]
        a1.axvline(1e3 * (surf - PAPER["quiet"]), color="C2", ls="--", label="002: top layer 45 mm")
    a1.set_ylabel("drag / (M g L/W), 1 mm bins")
    a2.set_ylabel("μ* bulk")
    a2.set_xlabel("intruder height [mm]")
    for a in (a1, a2):
        if a.get_legend_handles_labels()[0]:
            a.legend(fontsize=6)
    fig.tight_layout()
    fig.savefig(os.path.join(outdir, "drag_mu_star.png"), dpi=120)
    plt.close(fig)
    # Spectra.
    fig, ax = plt.subplots(figsize=(7, 4.5))
    for c in done:
        b = read_table(os.path.join(c["dir"], "bands.csv"))
        pk = c["summary"]["peak"]
        ax.loglog([1e3 * r["wavelength"] for r in b], [r["psd"] / pk ** 2 for r in b], "o-", ms=3, lw=0.8, label=c["case"])
    ax.axvline(1.5, color="r", ls="--", label="002: d/2")
    ax.invert_xaxis()
    ax.set_xlabel("wavelength [mm]")
    ax.set_ylabel("PSD / peak² [m]")
    if ax.get_legend_handles_labels()[0]:
        ax.legend(fontsize=6)
    fig.tight_layout()
    fig.savefig(os.path.join(outdir, "spectra.png"), dpi=120)
    plt.close(fig)
    # Maps of the reference case.
    ref = reference_case(conv)
    if ref:
        sys.path.insert(0, HERE)
        import plot  # noqa: E402  (the single-run figures' map drawing)

        s = ref["summary"]
        files = sorted(f for f in os.listdir(ref["dir"]) if f.startswith("velocity_map_h"))
        fig, axs = plt.subplots(1, max(1, len(files)), figsize=(3.5 * max(1, len(files)), 5), squeeze=False)
        for k, (ax, f) in enumerate(zip(axs[0], files)):
            m = plot.read_table(os.path.join(ref["dir"], f))
            height = s.get(f"map{k + 1}_height", float("nan"))
            cone = s.get(f"map{k + 1}_cone_angle", float("nan"))
            plot.draw_map(ax, m, s, height, cone, D, s["cell_width"], 0.010, 1e-3)
            ax.set_title(f"{ref['case']}\nh = {1e3 * height:.0f} mm, cone {cone:.0f}°", fontsize=8)
            if k == 0:
                ax.legend(fontsize=6, loc="upper left")
        fig.tight_layout()
        fig.savefig(os.path.join(outdir, "velocity_maps.png"), dpi=120)
        plt.close(fig)


def main(argv):
    global RESULTS, README, RATE_NS
    check = "--check" in argv
    outdir = os.path.join(ROOT, "out", "intruder_pull_out_2d_study", "figures")
    if "--figures" in argv:
        outdir = argv[argv.index("--figures") + 1]
    if "--results" in argv:  # another result tree (default: the committed one)
        RESULTS = argv[argv.index("--results") + 1]
    if "--readme" in argv:  # another README (default: the example's)
        README = argv[argv.index("--readme") + 1]
    studies = {t: s for t, s in ((t, load(t)) for t in TAGS) if s}
    RATE_NS = measured_rate(studies)
    with open(README, encoding="utf-8") as f:
        text = f.read()
    new = render(text, blocks(studies, load_modes()))
    if check:
        if new != text:
            print(f"report.py --check: {README} differs from the results in {RESULTS}; "
                  "run examples/intruder_pull_out_2d/report.py")
            return 1
        print("report.py --check: README.md matches the results")
        return 0
    with open(README, "w", encoding="utf-8") as f:
        f.write(new)
    figures(studies, outdir)
    print(f"{README} regenerated; figures in {os.path.normpath(outdir)}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
