#!/usr/bin/env python3
"""Turn the taylorode app's CSV files into the README's figures (needs matplotlib).

usage: python3 tools/plot.py [--errors LOW:HIGH] CSV_DIR PNG_DIR

CSV_DIR holds what tools/figures.sh writes: the step histories vdp_<scheme>.csv of
`taylorode vdp --history` (columns step,t,h,err,outcome,newton_iterations,u1,u2; t is
where the attempt started), their summaries vdp_<scheme>.txt, sweep.csv of `taylorode
sweep` and s1_regions.csv of `taylorode stability`. Each figure answers one question:

  vdp_solution.png    where does each scheme put the fast jump of Van der Pol?
  vdp_step_size.png   which step sizes does each scheme take, and where does it reject?
  work_precision.png  which scheme reaches a given error in the least CPU time?
  s1_regions.png      for which z = h lambda is every scheme stable whatever the stiff part?
  peers_work_precision_vdp.png, peers_work_precision_all.png
                      CPU time against error beside CVODE and ARKODE on the peer harness's
                      problems, from the CSV files of `taylorode bench --csv` and the
                      harness (peers_*.csv, bench_*.csv): the peers in grey, each scheme in
                      its colour, its other error estimates dotted with open markers; when
                      the files give cpu_s_min and cpu_s_max (tools/ratios.py --median-csv:
                      cpu_s the median over the rounds) a bar spans each run's range over
                      the rounds; --errors shades the errors the CPU ratios compare
"""
import csv
import math
import os
import re
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib import ticker  # noqa: E402

DPI = 150
# one look per scheme, the same in every figure: colour, line style, marker
STYLES = {
    "ex-t-1": ("#7f7f7f", (0, (1, 1)), "v"),
    "ex-t-2": ("#bcbd22", (0, (3, 1, 1, 1)), "^"),
    "si-t-1": ("#1f77b4", "-", "o"),
    "si-t-2": ("#ff7f0e", "--", "s"),
    "si-t-2-paper": ("#8c564b", (0, (5, 2, 1, 2)), "P"),
    "i-t-1": ("#2ca02c", "-.", "D"),
    "i-t-2": ("#d62728", (0, (1, 1.5)), "X"),
    "imex-rk21": ("#9467bd", (0, (6, 2)), "*"),
    "radau5": ("#000000", "-", "h"),
}
ORDER = list(STYLES)


def style(name):
    return STYLES.get(name, ("#17becf", "-", "o"))


def read_rows(path):
    with open(path, newline="") as handle:
        return list(csv.DictReader(handle))


def by_registry_order(names):
    return sorted(names, key=lambda n: (ORDER.index(n) if n in ORDER else len(ORDER), n))


def histories(csv_dir):
    """Accepted steps (t_end, h, y) and rejected attempts (t, h) of each vdp_<scheme>.csv."""
    data = {}
    for file in os.listdir(csv_dir):
        match = re.fullmatch(r"vdp_(.+)\.csv", file)
        if not match:
            continue
        rows = read_rows(os.path.join(csv_dir, file))
        accepted = [r for r in rows if r["outcome"] == "accepted"]
        rejected = [r for r in rows if r["outcome"] != "accepted"]
        data[match.group(1)] = {
            "t": [float(r["t"]) + float(r["h"]) for r in accepted],
            "h": [float(r["h"]) for r in accepted],
            "y": [float(r["u1"]) for r in accepted],
            "t_rejected": [float(r["t"]) for r in rejected],
            "h_rejected": [float(r["h"]) for r in rejected],
        }
    return {name: data[name] for name in by_registry_order(data)}


def summary_error(csv_dir, scheme):
    """The error of y at t = 3000 that `taylorode vdp` printed, as text ('' if none)."""
    path = os.path.join(csv_dir, f"vdp_{scheme}.txt")
    if not os.path.exists(path):
        return ""
    match = re.search(r"error at t = \S+: y (\S+),", open(path).read())
    return match.group(1).rstrip(",") if match else ""


def jump_time(t, y, low, high):
    """First time in (low, high) where y crosses zero upwards (the fast jump), or None."""
    for k in range(1, len(t)):
        if low < t[k] < high and y[k - 1] < 0.0 <= y[k]:
            return t[k]
    return None


def van_der_pol_solution(data, csv_dir, png_dir):
    mu = 1000.0
    jumps = {name: jump_time(d["t"], d["y"], 1.5 * mu, 1.7 * mu) for name, d in data.items()}
    known = [t for t in jumps.values() if t is not None]
    if not known:
        return
    window = (min(known) - 1.0, max(known) + 1.0)
    reference = data.get("radau5") or next(iter(data.values()))

    fig, (whole, zoom) = plt.subplots(1, 2, figsize=(12, 5.4), gridspec_kw={"width_ratios": [1, 1.6]})
    whole.plot(reference["t"], reference["y"], color="k", lw=1.0)
    whole.axvline(0.5 * (window[0] + window[1]), color="#e6a700", ls="--", lw=1.0)
    whole.annotate(f"right: t in [{window[0]:.0f}, {window[1]:.0f}]", xy=(window[1], 0.0),
                   xytext=(window[1] + 120, 0.3), fontsize=9, arrowprops={"arrowstyle": "->", "lw": 0.8})
    whole.set_title("y(t) over the whole run (radau5)")
    whole.set_xlabel("t")
    whole.set_ylabel("y")
    whole.grid(True, lw=0.3)

    for name, d in data.items():
        colour, line, marker = style(name)
        pairs = [(t, y) for t, y in zip(d["t"], d["y"]) if window[0] <= t <= window[1]]
        if not pairs:
            continue
        t_w, y_w = zip(*pairs)
        error = summary_error(csv_dir, name)
        label = name + (f"  (error of y at t = 3000: {error})" if error else "")
        zoom.plot(t_w, y_w, color=colour, ls=line, lw=1.4, marker=marker, ms=4, markevery=max(1, len(t_w) // 12),
                  label=label)
    zoom.set_xlim(*window)
    zoom.set_title("The jump near t = 1.6 mu: where each scheme puts it")
    zoom.set_xlabel("t")
    zoom.set_ylabel("y")
    zoom.grid(True, lw=0.3)
    zoom.legend(fontsize=8, loc="upper center", bbox_to_anchor=(0.5, -0.13), ncol=2, frameon=False)
    fig.suptitle("Van der Pol, mu = 1000, IC1, the paper's settings (atol 1e-5, I controller)")
    fig.tight_layout()
    fig.savefig(os.path.join(png_dir, "vdp_solution.png"), dpi=DPI)
    plt.close(fig)


def van_der_pol_step_sizes(data, png_dir):
    names = list(data)
    fig, axes = plt.subplots(len(names), 1, figsize=(10, 1.55 * len(names) + 0.8), sharex=True, sharey=True)
    if len(names) == 1:
        axes = [axes]
    for axis, name in zip(axes, names):
        d = data[name]
        colour, _, _ = style(name)
        axis.semilogy(d["t"], d["h"], color=colour, lw=0.9)
        if d["t_rejected"]:
            axis.semilogy(d["t_rejected"], d["h_rejected"], "x", color="#e41a1c", ms=4, mew=0.8)
        axis.text(0.005, 0.9, f"{name}: {len(d['h']):,} accepted, {len(d['h_rejected']):,} rejected (x)",
                  transform=axis.transAxes, va="top", fontsize=9,
                  bbox={"facecolor": "white", "edgecolor": "none", "alpha": 0.8})
        axis.set_ylabel("h")
        axis.grid(True, lw=0.3)
    axes[-1].set_xlabel("t")
    fig.suptitle("Step sizes along the Van der Pol run (mu = 1000, IC1, paper settings); x = rejected attempt")
    fig.tight_layout()
    fig.savefig(os.path.join(png_dir, "vdp_step_size.png"), dpi=DPI)
    plt.close(fig)


def work_precision_figure(csv_dir, png_dir):
    path = os.path.join(csv_dir, "sweep.csv")
    if not os.path.exists(path):
        return
    rows = read_rows(path)
    fig, axis = plt.subplots(figsize=(8, 5.5))
    failed = {}
    for scheme in by_registry_order(dict.fromkeys(r["scheme"] for r in rows)):
        points = [(float(r["cpu_seconds"]), float(r["error"]), r["tol"]) for r in rows
                  if r["scheme"] == scheme and r["status"] == "ok"]
        points = [p for p in points if p[0] > 0 and p[1] > 0]
        if not points:
            failed[scheme] = sorted({r["status"] for r in rows if r["scheme"] == scheme})
            continue
        colour, line, marker = style(scheme)
        cpu, err, _ = zip(*points)
        axis.loglog(cpu, err, color=colour, ls=line, marker=marker, ms=6, lw=1.4, label=scheme)
    axis.set_xlabel("CPU seconds (median of repeated runs)")
    axis.set_ylabel("relative error at t_end")
    problem = rows[0]["problem"] if rows else ""
    tols = sorted({float(r["tol"]) for r in rows})
    if tols:
        axis.set_title(f"Work-precision on {problem}: rtol = atol from {tols[-1]:.0e} to {tols[0]:.0e}, "
                       "one point per decade", fontsize=10)
    if failed:
        note = "; ".join(f"{scheme}: no point ({', '.join(status)})" for scheme, status in failed.items())
        axis.text(0.99, 0.01, note, transform=axis.transAxes, ha="right", va="bottom", fontsize=8)
    axis.legend(fontsize=9)
    axis.grid(True, which="both", lw=0.3)
    fig.tight_layout()
    fig.savefig(os.path.join(png_dir, "work_precision.png"), dpi=DPI)
    plt.close(fig)


# the peer solvers, in shades of grey and wide; the harness's error measure per problem
PEER_STYLES = {"cvode_bdf": ("#8c8c8c", "-", "o"), "ark_imex3": ("#c8c8c8", "-", "s")}
PEER_LABELS = {"cvode_bdf": "CVODE (BDF)", "ark_imex3": "ARKODE (IMEX, order 3)"}
PEER_ERROR = {"e5": "err_grid"}


def peer_rows(csv_dir):
    """Rows of every peers_*.csv and bench_*.csv in csv_dir that finished ("ok")."""
    rows = []
    for file in sorted(os.listdir(csv_dir)):
        if re.fullmatch(r"(peers|bench)_.+\.csv", file):
            rows += [r for r in read_rows(os.path.join(csv_dir, file)) if (r.get("status") or "ok") == "ok"]
    return rows


def solver_style(solver):
    """(colour, line, marker, filled, width) of a peer or of taylorode_<scheme>[_<estimate>]:
    a scheme's default solid with filled markers, its other error estimates dotted with
    open ones."""
    if solver in PEER_STYLES:
        return PEER_STYLES[solver] + (True, 3.0)
    colour, _, marker = style(solver_style_name(solver))
    if solver_style_name(solver) != solver.removeprefix("taylorode_"):
        return colour, ":", marker, False, 1.1
    return colour, "-", marker, True, 1.4


def sci(value):
    """1e-08 -> 1e-8"""
    return f"{value:.0e}".replace("e-0", "e-").replace("e+0", "e")


def draw_peer_series(axis, rows, problem, solvers, errors=None):
    key = PEER_ERROR.get(problem, "err_end")
    if errors:
        axis.axhspan(*errors, color="#fff3c4", zorder=0, lw=0)
    for solver in solvers:
        points = []
        for r in rows:
            if r["problem"] != problem or r["solver"] != solver:
                continue
            try:
                cpu, err = float(r["cpu_s"]), float(r[key])
            except (TypeError, ValueError):
                continue
            try:
                low, high = float(r.get("cpu_s_min")), float(r.get("cpu_s_max"))
            except (TypeError, ValueError):
                low = high = cpu
            if cpu > 0 and err > 0 and math.isfinite(cpu) and math.isfinite(err):
                points.append((cpu, err, cpu - low if low > 0 else 0.0, high - cpu if high > 0 else 0.0))
        if not points:
            continue
        points.sort()
        colour, line, marker, filled, width = solver_style(solver)
        cpu, err, below, above = zip(*points)
        axis.loglog(cpu, err, color=colour, ls=line, marker=marker, ms=4, lw=width,
                    mfc=colour if filled else "none",
                    label=PEER_LABELS.get(solver, solver.removeprefix("taylorode_")))
        if any(below) or any(above):
            axis.errorbar(cpu, err, xerr=[below, above], fmt="none", ecolor=colour, elinewidth=0.8, capsize=0)
    axis.grid(True, which="both", lw=0.3)
    axis.xaxis.set_minor_formatter(ticker.NullFormatter())


def peers_figures(csv_dir, png_dir, errors=None):
    rows = peer_rows(csv_dir)
    rounds = max((int(r["rounds"]) for r in rows if (r.get("rounds") or "").isdigit()), default=1)
    cpu_label = "CPU seconds per solve" + (f" (median over {rounds} rounds, bar: their range)" if rounds > 1 else "")
    shaded = f"; shaded: the errors the ratios compare, {sci(errors[0])} to {sci(errors[1])}" if errors else ""
    if not any(r["solver"] in PEER_STYLES for r in rows):
        return
    solvers = [s for s in PEER_STYLES if any(r["solver"] == s for r in rows)]
    ours = sorted({r["solver"] for r in rows if r["solver"] not in PEER_STYLES},
                  key=lambda s: (ORDER.index(solver_style_name(s)) if solver_style_name(s) in ORDER else len(ORDER), s))
    solvers += ours
    fig, axes = plt.subplots(1, 2, figsize=(12, 5.2))
    for axis, problem, start in zip(axes, ("vdp1e3_wp", "vdp1e3_up"), ("prepared", "unprepared")):
        draw_peer_series(axis, rows, problem, solvers, errors)
        axis.set_title(f"Van der Pol mu = 1e3, {start} start: error at t = 3000", fontsize=10)
        axis.set_xlabel(cpu_label)
    axes[0].set_ylabel("max-norm error")
    axes[0].legend(fontsize=8, ncol=2)
    tols = sorted({float(r["tol"]) for r in rows if r["problem"] == "vdp1e3_wp" and r["tol"] not in ("", "paper")})
    tol_text = f"from {sci(tols[-1])} to {sci(tols[0])}" if tols else ""
    fig.suptitle(f"Work-precision beside CVODE and ARKODE (wide grey lines), rtol = atol = tol {tol_text};\n"
                 f"each scheme with its default error estimate (solid) and others (dotted){shaded}", fontsize=9)
    fig.tight_layout()
    fig.savefig(os.path.join(png_dir, "peers_work_precision_vdp.png"), dpi=110)
    plt.close(fig)

    problems = list(dict.fromkeys(r["problem"] for r in rows if r["problem"] != "vdp-paper"))
    columns = 4
    lines = math.ceil(len(problems) / columns)
    fig, axes = plt.subplots(lines, columns, figsize=(4.3 * columns, 3.5 * lines + 0.8), squeeze=False)
    for k, axis in enumerate(axes.flat):
        if k >= len(problems):
            axis.set_visible(False)
            continue
        draw_peer_series(axis, rows, problems[k], solvers, errors)
        axis.set_title(f"{problems[k]} ({PEER_ERROR.get(problems[k], 'err_end')})", fontsize=9)
        axis.tick_params(labelsize=7)
    handles, labels = {}, {}
    for axis in axes.flat:
        for handle, label in zip(*axis.get_legend_handles_labels()):
            handles.setdefault(label, handle)
    fig.legend(list(handles.values()), list(handles), loc="lower center", ncol=min(len(handles), 6), fontsize=8)
    fig.supxlabel(cpu_label + shaded, y=0.06)
    fig.supylabel("error (the harness's measure)")
    fig.tight_layout(rect=(0, 0.08, 1, 1))
    fig.savefig(os.path.join(png_dir, "peers_work_precision_all.png"), dpi=90)
    plt.close(fig)


def solver_style_name(solver):
    """The scheme a taylorode_<scheme>[_<estimate>] solver runs."""
    name = solver.removeprefix("taylorode_")
    for estimate in ("_embedded", "_doubling", "_defect"):
        name = name.removesuffix(estimate)
    return name


def stability_figure(csv_dir, png_dir):
    path = os.path.join(csv_dir, "s1_regions.csv")
    if not os.path.exists(path):
        return
    rows = read_rows(path)
    schemes = list(dict.fromkeys(r["scheme"] for r in rows))  # the registry's order
    columns = 3
    lines = math.ceil(len(schemes) / columns)
    fig, axes = plt.subplots(lines, columns, figsize=(3.6 * columns, 3.5 * lines + 0.6), sharex=True, sharey=True,
                             squeeze=False)
    for k, axis in enumerate(axes.flat):
        if k >= len(schemes):
            axis.set_visible(False)
            continue
        scheme = schemes[k]
        cells = [r for r in rows if r["scheme"] == scheme]
        xs = sorted({float(r["re_z"]) for r in cells})
        ys = sorted({float(r["im_z"]) for r in cells})
        ix = {x: i for i, x in enumerate(xs)}
        iy = {y: j for j, y in enumerate(ys)}
        inside = [[0.0] * len(xs) for _ in ys]
        for r in cells:
            inside[iy[float(r["im_z"])]][ix[float(r["re_z"])]] = float(r["inside"])
        colour, _, _ = style(scheme)
        if any(v for row in inside for v in row):
            axis.contourf(xs, ys, inside, levels=[0.5, 1.5], colors=[colour], alpha=0.35)
            axis.contour(xs, ys, inside, levels=[0.5], colors=[colour], linewidths=1.5)
        else:
            axis.text(0.5, 0.5, "S1 is empty", transform=axis.transAxes, ha="center", va="center", fontsize=11)
        axis.axhline(0, color="k", lw=0.5)
        axis.axvline(0, color="k", lw=0.5)
        axis.set_xlim(xs[0], xs[-1])
        axis.set_ylim(ys[0], ys[-1])
        axis.set_aspect("equal")
        axis.set_title(scheme)
        axis.grid(True, lw=0.3)
    for axis in axes[-1]:
        axis.set_xlabel("Re z")
    for axis in axes[:, 0]:
        axis.set_ylabel("Im z")
    fig.suptitle("S1 = {z : |R(z, w)| <= 1 for every Re w <= 0}, z = h lambda of f, w = h nu of g "
                 "(shaded, on a grid over the frame)", fontsize=10)
    fig.tight_layout()
    fig.savefig(os.path.join(png_dir, "s1_regions.png"), dpi=DPI)
    plt.close(fig)


def main():
    arguments = sys.argv[1:]
    errors = None
    if arguments[:1] == ["--errors"] and len(arguments) > 1:
        try:
            errors = tuple(sorted(float(v) for v in arguments[1].split(":")))
        except ValueError:
            sys.exit(f"plot.py: --errors wants LOW:HIGH, not {arguments[1]}")
        if len(errors) != 2:
            sys.exit(f"plot.py: --errors wants LOW:HIGH, not {arguments[1]}")
        arguments = arguments[2:]
    if len(arguments) != 2:
        sys.exit(__doc__)
    csv_dir, png_dir = arguments
    os.makedirs(png_dir, exist_ok=True)
    data = histories(csv_dir)
    if data:
        van_der_pol_solution(data, csv_dir, png_dir)
        van_der_pol_step_sizes(data, png_dir)
    work_precision_figure(csv_dir, png_dir)
    stability_figure(csv_dir, png_dir)
    peers_figures(csv_dir, png_dir, errors)


if __name__ == "__main__":
    main()
