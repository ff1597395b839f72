"""The study page's error plots (report.py): error against spp and against
time, one line per backend, with reference slopes, and the CSV readers
both share."""

import csv
import math
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from atomic_output import save_figure  # noqa: E402


def read_csv(path):
    if not os.path.exists(path):
        return []
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def num(s):
    try:
        return float(s)
    except (TypeError, ValueError):
        return math.nan


def by(rows, key):
    out = {}
    for r in rows:
        out.setdefault(r[key], []).append(r)
    return out


def backend_label(name):
    # neural:/long/path/model.nuldnet -> neural:model
    if ":" in name:
        kind, rest = name.split(":", 1)
        return kind + ":" + os.path.splitext(os.path.basename(rest))[0]
    return name


def loglog_panel(ax, series, xlabel, ylabel, guide=None):
    for label, xs, ys, errs in series:
        pts = [(x, y, e) for x, y, e in zip(xs, ys, errs) if x > 0 and y > 0]
        if not pts:
            continue
        pts.sort()
        x, y, e = (np.array(v) for v in zip(*pts))
        ax.errorbar(x, y, yerr=np.where(np.isfinite(e), e, 0), marker="o", ms=3, capsize=2,
                    label=label)
    if guide and series:
        xs = [x for _, sx, _, _ in series for x in sx if x > 0]
        ys = [y for _, _, sy, _ in series for y in sy if y > 0]
        if xs and ys:
            x0, x1 = min(xs), max(xs)
            y0 = max(ys)
            for slope, style in guide:
                ax.plot([x0, x1], [y0, y0 * (x1 / x0) ** slope], style, color="grey", lw=0.8,
                        label=f"slope {slope:g}")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7)


def render_plots(scene, rows, plots_dir, slopes=None):
    """MSE and relMSE against spp, and MSE against seconds, one line per
    backend; on the spp panel each label carries the row's convergence
    rate (slopes.csv) where it has one."""
    groups = by(rows, "backend")
    slopes = slopes or {}

    def label(b, with_slope):
        s = slopes.get((scene, b))
        if with_slope and s and math.isfinite(num(s["mse_slope"])):
            return (f"{backend_label(b)} (slope {num(s['mse_slope']):.2f}"
                    f"±{num(s['mse_slope_stderr']):.2f})")
        return backend_label(b)

    def series(xkey, ykey, ekey):
        out = []
        for b, rs in groups.items():
            out.append((label(b, xkey == "spp" and ykey == "mse"), [num(r[xkey]) for r in rs],
                        [num(r[ykey]) for r in rs],
                        [num(r[ekey]) if ekey else math.nan for r in rs]))
        return out

    fig, axes = plt.subplots(1, 3, figsize=(15, 4.2))
    loglog_panel(axes[0], series("spp", "mse", "mse_stderr"), "samples per pixel", "MSE",
                 guide=[(-1, "--"), (-1.5, ":")])
    loglog_panel(axes[1], series("spp", "relmse", "relmse_stderr"), "samples per pixel",
                 "relMSE", guide=[(-1, "--"), (-1.5, ":")])
    # Error against time with setup on the axis: the line at the study's
    # --amortize K (total_seconds), hollow markers where every render pays
    # its whole setup (K = 1).
    amortize = num(rows[0].get("amortize")) if rows else math.nan
    has_total = all(math.isfinite(num(r.get("total_seconds"))) for r in rows)
    xkey = "total_seconds" if has_total else "seconds"
    loglog_panel(axes[2], series(xkey, "mse", "mse_stderr"),
                 (f"seconds per render + setup / {amortize:g}" if has_total else
                  "seconds per render (incl. sample generation)"), "MSE")
    if has_total and amortize != 1:
        for i, (b, rs) in enumerate(groups.items()):
            xs = [num(r["seconds"]) + num(r["setup_seconds"]) for r in rs]
            ys = [num(r["mse"]) for r in rs]
            axes[2].plot(xs, ys, "o", mfc="none", ms=5, color=f"C{i % 10}",
                         label="K = 1" if i == 0 else None)
        axes[2].legend(fontsize=7)
    # Each learned row's break-even renders against the best classic row.
    for r in rows:
        k = num(r.get("break_even_renders"))
        if not math.isnan(k):
            axes[2].annotate("never" if math.isinf(k) else f"pays@{k:.0f}",
                             (num(r[xkey]), num(r["mse"])), fontsize=6,
                             textcoords="offset points", xytext=(3, 3))
    fig.suptitle(f"{scene}: error against a reference")
    fig.tight_layout()
    name = f"render_{scene}.png"
    save_figure(fig, os.path.join(plots_dir, name), dpi=110)
    plt.close(fig)
    return "plots/" + name
