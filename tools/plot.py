#!/usr/bin/env python3
"""Turn the taylorode app's CSV files into PNG figures (optional: needs matplotlib).

usage: python3 tools/plot.py CSV_DIR PNG_DIR

CSV_DIR holds what tools/figures.sh writes: vdp_<scheme>.csv step histories,
sweep.csv (work-precision) and s1_regions.csv (stability regions).
"""
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def read_rows(path):
    with open(path, newline="") as handle:
        return list(csv.DictReader(handle))


def accepted_history(path):
    rows = [r for r in read_rows(path) if r["outcome"] == "accepted"]
    t = [float(r["t"]) + float(r["h"]) for r in rows]
    h = [float(r["h"]) for r in rows]
    y = [float(r["u1"]) for r in rows]
    return t, h, y


def van_der_pol_figures(csv_dir, png_dir):
    histories = sorted(f for f in os.listdir(csv_dir) if f.startswith("vdp_") and f.endswith(".csv"))
    if not histories:
        return
    data = {f[4:-4]: accepted_history(os.path.join(csv_dir, f)) for f in histories}
    reference = data.get("radau5") or next(iter(data.values()))
    # the relaxation jump nearest t = 1.6 mu (mu = 1000): where y changes fastest
    t_ref, _, y_ref = reference
    candidates = [k for k in range(1, len(t_ref)) if 1500.0 < t_ref[k] < 1700.0]
    jump = max(candidates, key=lambda k: abs(y_ref[k] - y_ref[k - 1]) / max(t_ref[k] - t_ref[k - 1], 1e-300))
    t_jump = t_ref[jump]

    windows = [("whole run", None), ("before the jump near t = 1.6 mu", (t_jump - 4.0, t_jump + 0.2)),
               ("after the jump near t = 1.6 mu", (t_jump - 0.05, t_jump + 4.0))]
    fig, axes = plt.subplots(1, 3, figsize=(15, 4.2))
    for axis, (title, window) in zip(axes, windows):
        for name, (t, _, y) in data.items():
            if window:
                pairs = [(a, b) for a, b in zip(t, y) if window[0] <= a <= window[1]]
                if not pairs:
                    continue
                t_w, y_w = zip(*pairs)
                axis.plot(t_w, y_w, ".-", ms=3, lw=0.8, label=name)
            else:
                axis.plot(t, y, lw=0.8, label=name)
        axis.set_title(title)
        axis.set_xlabel("t")
        axis.set_ylabel("y")
    axes[0].legend(fontsize=8)
    fig.suptitle("Van der Pol, mu = 1000, IC1, paper settings (atol 1e-5)")
    fig.tight_layout()
    fig.savefig(os.path.join(png_dir, "vdp_solution.png"), dpi=90)
    plt.close(fig)

    fig, axis = plt.subplots(figsize=(8, 4.2))
    for name, (t, h, _) in data.items():
        axis.semilogy(t, h, lw=0.7, label=name)
    axis.set_xlabel("t")
    axis.set_ylabel("accepted step size h")
    axis.set_title("Step size along the Van der Pol run (mu = 1000, IC1)")
    axis.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(png_dir, "vdp_step_size.png"), dpi=90)
    plt.close(fig)


def work_precision_figure(csv_dir, png_dir):
    path = os.path.join(csv_dir, "sweep.csv")
    if not os.path.exists(path):
        return
    rows = [r for r in read_rows(path) if r["status"] == "ok"]
    fig, axis = plt.subplots(figsize=(7, 5))
    for scheme in dict.fromkeys(r["scheme"] for r in rows):
        points = [(float(r["cpu_seconds"]), float(r["error"])) for r in rows if r["scheme"] == scheme]
        points = [(c, e) for c, e in points if c > 0 and e > 0]
        if points:
            cpu, err = zip(*points)
            axis.loglog(cpu, err, "o-", label=scheme)
    axis.set_xlabel("CPU seconds (median of repeated runs)")
    axis.set_ylabel("relative error at t_end")
    problem = rows[0]["problem"] if rows else ""
    axis.set_title("Work-precision on " + problem + " (rtol = atol = tol, one point per decade)")
    axis.legend(fontsize=8)
    axis.grid(True, which="both", lw=0.3)
    fig.tight_layout()
    fig.savefig(os.path.join(png_dir, "work_precision.png"), dpi=90)
    plt.close(fig)


def stability_figure(csv_dir, png_dir):
    path = os.path.join(csv_dir, "s1_regions.csv")
    if not os.path.exists(path):
        return
    rows = read_rows(path)
    schemes = ["si-t-1", "si-t-2", "i-t-2", "imex-rk21"]
    fig, axes = plt.subplots(1, len(schemes), figsize=(15, 4))
    for axis, scheme in zip(axes, schemes):
        inside = [(float(r["re_z"]), float(r["im_z"])) for r in rows if r["scheme"] == scheme and r["inside"] == "1"]
        if inside:
            x, y = zip(*inside)
            axis.scatter(x, y, s=2, marker="s")
        axis.axhline(0, color="k", lw=0.5)
        axis.axvline(0, color="k", lw=0.5)
        axis.set_xlim(-3, 1)
        axis.set_ylim(-2, 2)
        axis.set_aspect("equal")
        axis.set_title("S1 of " + scheme)
        axis.set_xlabel("Re z")
    axes[0].set_ylabel("Im z")
    fig.suptitle("S1 = {z : |R(z, w)| <= 1 for every Re w <= 0}")
    fig.tight_layout()
    fig.savefig(os.path.join(png_dir, "s1_regions.png"), dpi=80)
    plt.close(fig)


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    csv_dir, png_dir = sys.argv[1], sys.argv[2]
    os.makedirs(png_dir, exist_ok=True)
    van_der_pol_figures(csv_dir, png_dir)
    work_precision_figure(csv_dir, png_dir)
    stability_figure(csv_dir, png_dir)


if __name__ == "__main__":
    main()
