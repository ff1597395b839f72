#!/usr/bin/python3
"""Plots of `nuld study integrate` (the supplement's Fig. 2 style).

Usage: /usr/bin/python3 tools/study/plot_integrate.py STUDY_DIR

Reads STUDY_DIR/integrate.csv and writes, under STUDY_DIR/plots/:
  integrate_<integrand>.png  log-log RMSE against N (one line per sampler, with
                             N^-1/2 and N^-1 guides) and RMSE against the
                             seconds per set (generation + optimization setup)
  integrate_all.png          RMSE against N for every integrand side by side
Messages go to stderr (none when NULD_QUIET is set); stdout stays free for
the caller's table.
"""

import csv
import math
import os
import sys

try:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
except ImportError as e:  # the caller turns this into a warning
    sys.exit(f"plot_integrate.py: matplotlib is missing ({e}); "
             "install python3-matplotlib and run /usr/bin/python3")

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from atomic_output import save_figure  # noqa: E402

# A fixed colour and marker per sampler, so a sampler looks the same everywhere.
STYLES = {
    "independent": ("#7f7f7f", "o"), "sobol": ("#1f77b4", "s"), "halton": ("#2ca02c", "^"),
    "independent-tabulated": ("#bcbcbc", "o"), "sobol-tabulated": ("#9ecae1", "s"),
    "halton-tabulated": ("#a1d99b", "^"), "optimized": ("#d62728", "D"),
}
EXTRA = ["#9467bd", "#8c564b", "#e377c2", "#17becf", "#bcbd22", "#ff7f0e"]


def num(text):
    try:
        return float(text)
    except (TypeError, ValueError):
        return math.nan


def read_rows(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def grouped(rows, key):
    out = {}
    for r in rows:
        out.setdefault(r[key], []).append(r)
    return out


def style(sampler, extra_index):
    if sampler in STYLES:
        return STYLES[sampler]
    return EXTRA[extra_index % len(EXTRA)], "v"


def sampler_series(rows):
    """[(sampler, colour, marker, ns, rmses, seconds)] sorted by N."""
    series, extra = [], 0
    for sampler, rs in grouped(rows, "sampler").items():
        rs = sorted(rs, key=lambda r: num(r["n"]))
        colour, marker = style(sampler, extra)
        extra += sampler not in STYLES
        ns = [num(r["n"]) for r in rs]
        rmse = [num(r["rmse"]) for r in rs]
        secs = [num(r["gen_seconds_per_set"]) + num(r["setup_seconds_per_set"]) for r in rs]
        series.append((sampler, colour, marker, ns, rmse, secs))
    return series


def positive(xs, ys):
    pts = [(x, y) for x, y in zip(xs, ys) if x > 0 and y > 0 and math.isfinite(x * y)]
    return [p[0] for p in pts], [p[1] for p in pts]


def rmse_panel(ax, series, title):
    for sampler, colour, marker, ns, rmse, _ in series:
        x, y = positive(ns, rmse)
        if x:
            ax.loglog(x, y, marker=marker, color=colour, label=sampler, lw=1.4, ms=4)
    # Guides through the geometric mean of the first column's RMSEs.
    firsts = [(s[3][0], s[4][0]) for s in series if s[3] and s[4][0] > 0]
    all_n = sorted({n for s in series for n in s[3] if n > 0})
    if firsts and len(all_n) > 1:
        n0 = min(n for n, _ in firsts)
        r0 = math.exp(sum(math.log(r) for _, r in firsts) / len(firsts))
        for slope, ls, label in ((-0.5, "--", "N^-1/2"), (-1.0, ":", "N^-1")):
            ax.loglog(all_n, [r0 * (n / n0) ** slope for n in all_n], ls, color="black",
                      lw=0.9, alpha=0.6, label=label)
    ax.set_xlabel("N (points per set)")
    ax.set_ylabel("RMSE")
    ax.set_title(title, fontsize=10)
    ax.grid(True, which="both", alpha=0.25)


def time_panel(ax, series):
    for sampler, colour, marker, _, rmse, secs in series:
        x, y = positive(secs, rmse)
        if x:
            ax.loglog(x, y, marker=marker, color=colour, label=sampler, lw=1.4, ms=4)
    ax.set_xlabel("seconds per set (generation + optimization)")
    ax.set_ylabel("RMSE")
    ax.set_title("RMSE against cost", fontsize=10)
    ax.grid(True, which="both", alpha=0.25)


def safe_name(text):
    return "".join(c if c.isalnum() or c in "-_" else "_" for c in text)


def draw_plots(root, rows):
    """Writes the plots; returns {integrand: path relative to root} and the
    list of files written (the overview last)."""
    plots = os.path.join(root, "plots")
    os.makedirs(plots, exist_ok=True)
    by_integrand = grouped(rows, "integrand")
    written = []
    by_name = {}
    for integrand, rs in by_integrand.items():
        series = sampler_series(rs)
        fig, (a, b) = plt.subplots(1, 2, figsize=(11, 4.2))
        ref = rs[0]["reference"]
        rmse_panel(a, series, f"{integrand} (reference {ref})")
        time_panel(b, series)
        a.legend(fontsize=7, ncol=2)
        fig.tight_layout()
        name = os.path.join(plots, f"integrate_{safe_name(integrand)}.png")
        save_figure(fig, name, dpi=110)
        plt.close(fig)
        written.append(name)
        by_name[integrand] = os.path.relpath(name, root)

    cols = min(4, len(by_integrand))
    rows_n = math.ceil(len(by_integrand) / cols)
    fig, axes = plt.subplots(rows_n, cols, figsize=(4.2 * cols, 3.6 * rows_n), squeeze=False)
    for ax, (integrand, rs) in zip(axes.flat, by_integrand.items()):
        rmse_panel(ax, sampler_series(rs), integrand)
    for ax in list(axes.flat)[len(by_integrand):]:
        ax.axis("off")
    axes.flat[0].legend(fontsize=6, ncol=2)
    fig.tight_layout()
    name = os.path.join(plots, "integrate_all.png")
    save_figure(fig, name, dpi=100)
    plt.close(fig)
    written.append(name)
    return by_name, written


def main():
    if len(sys.argv) != 2:
        sys.exit("usage: plot_integrate.py STUDY_DIR")
    root = sys.argv[1]
    path = os.path.join(root, "integrate.csv")
    if not os.path.exists(path):
        sys.exit(f"plot_integrate.py: {path} does not exist")
    rows = read_rows(path)
    if not rows:
        print(f"plot_integrate.py: {path} has no rows; no plots", file=sys.stderr)
        return
    by_name, written = draw_plots(root, rows)
    if not os.environ.get("NULD_QUIET"):
        print(f"plot_integrate.py: wrote {len(written)} plots to {plots}", file=sys.stderr)


if __name__ == "__main__":
    main()
