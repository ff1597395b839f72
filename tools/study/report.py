#!/usr/bin/python3
"""Plots and a static HTML report for a study directory (nuld study render / integrate).

Usage: /usr/bin/python3 tools/study/report.py STUDY_DIR

Reads STUDY_DIR/render.csv and references.csv (nuld study render) and
STUDY_DIR/integrate.csv (nuld study integrate) when present, writes
STUDY_DIR/plots/*.png and STUDY_DIR/index.html. The page uses relative links
only, so the directory can be copied and opened in a browser without a server.
"""

import datetime
import html
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.image as mpimg  # noqa: E402
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import plot_integrate  # noqa: E402  (the integrate study's plots, drawn once)
from atomic_output import save_figure, write_text  # noqa: E402
from render_plots import backend_label, by, num, read_csv, render_plots  # noqa: E402,F401

CROP_SCALE_PX = 192  # a zoomed crop is drawn this wide
TOO_NOISY_FACTOR = 10  # baselines.h, kTooNoisyFactor: render.csv's reference_too_noisy


def ratio_to_sobol(row, sobol_row):
    """MSE over sobol's with its standard error from the two relative ones
    (as ratioOfMeans in statistics.h, which fills render.csv's other ratios)."""
    if not sobol_row or not num(sobol_row["mse"]) > 0:
        return math.nan, math.nan
    q = num(row["mse"]) / num(sobol_row["mse"])
    if row is sobol_row:
        return 1.0, 0.0
    a = num(row["mse_stderr"]) / num(row["mse"]) if num(row["mse"]) > 0 else 0
    b = num(sobol_row["mse_stderr"]) / num(sobol_row["mse"])
    a = a if math.isfinite(a) else 0
    return q, q * math.sqrt(a * a + b * b)


def crop_window(reference_png, size):
    """The size x size window with the most reference detail (gradient energy)."""
    img = mpimg.imread(reference_png)[..., :3].astype(float)
    lum = img @ np.array([0.2126, 0.7152, 0.0722])
    h, w = lum.shape
    size = max(1, min(size, h, w))
    gy, gx = np.gradient(lum)
    energy = np.cumsum(np.cumsum(np.pad(gx * gx + gy * gy, ((1, 0), (1, 0))), 0), 1)
    best, where = -1.0, (0, 0)
    step = max(1, size // 4)
    for y in range(0, h - size + 1, step):
        for x in range(0, w - size + 1, step):
            e = (energy[y + size, x + size] - energy[y, x + size] - energy[y + size, x] +
                 energy[y, x])
            if e > best:
                best, where = e, (y, x)
    return where[0], where[1], size


def save_crop(src_png, window, dst_png):
    y, x, size = window
    img = mpimg.imread(src_png)[y:y + size, x:x + size, :3]
    factor = max(1, CROP_SCALE_PX // size)
    img = np.repeat(np.repeat(img, factor, 0), factor, 1)  # nearest neighbour: pixels stay visible
    plt.imsave(dst_png, np.clip(img, 0, 1))


# The false-colour error maps' ramp and scale (renderer/image_metrics.cpp,
# errorMap): the pixel's relative squared error, 1e-4 to 1 on a log axis,
# through these colours.
ERROR_RAMP = [(0.02, 0.02, 0.15), (0.1, 0.3, 0.9), (0.1, 0.8, 0.3), (1.0, 0.9, 0.1), (1, 1, 1)]


def error_scale(plots_dir):
    """A colour bar for the error maps; its path relative to the page."""
    from matplotlib.colors import LinearSegmentedColormap, LogNorm
    name = "error_scale.png"
    fig, ax = plt.subplots(figsize=(1.3, 3.2))
    cmap = LinearSegmentedColormap.from_list("nuld_error", ERROR_RAMP)
    bar = fig.colorbar(plt.cm.ScalarMappable(norm=LogNorm(1e-4, 1), cmap=cmap), cax=ax)
    bar.set_label("relative squared error")
    fig.subplots_adjust(left=0.05, right=0.35, top=0.95, bottom=0.05)
    save_figure(fig, os.path.join(plots_dir, name), dpi=110)
    plt.close(fig)
    return "plots/" + name


def pays_after(row):
    """break_even_renders in words: 'after K renders' or 'never'."""
    k = num(row.get("break_even_renders"))
    if math.isinf(k):
        return "never (not ahead per render)"
    se = num(row.get("break_even_renders_stderr"))
    spread = f" (±{se:.0f})" if math.isfinite(se) else " (±∞: a tie per render)"
    return f"after {k:.0f} render{'s' if k != 1 else ''}{spread}"


def fmt(v, digits=3):
    v = num(v)
    if not math.isfinite(v):
        return "–"
    return f"{v:.{digits}e}"


def spectrum_plots(root, scene, rows, plots_dir):
    """The radially averaged power spectrum of each backend's error (the
    study's BACKEND_sppN_spectrum.csv, the repeats' mean), one panel per spp:
    white-noise error is flat, blue-noise error rises with the frequency."""
    spps = sorted({int(r["spp"]) for r in rows})
    curves = {}
    for r in rows:
        path = os.path.join(root, os.path.splitext(r["image"])[0] + "_spectrum.csv")
        if os.path.exists(path):
            points = [(num(p["cycles_per_pixel"]), num(p["power"])) for p in read_csv(path)]
            curves[(r["backend"], int(r["spp"]))] = [(f, p) for f, p in points if f > 0]
    if not curves:
        return None
    fig, axes = plt.subplots(1, len(spps), figsize=(5 * len(spps), 4), squeeze=False)
    for ax, s in zip(axes[0], spps):
        for i, b in enumerate(dict.fromkeys(r["backend"] for r in rows)):
            c = curves.get((b, s))
            if c:
                ax.plot([f for f, _ in c], [p for _, p in c], label=backend_label(b),
                        color=f"C{i % 10}", lw=1)
        ax.set_yscale("log")
        ax.set_xlabel("frequency (cycles per pixel)")
        ax.set_ylabel("error power (luminance)")
        ax.set_title(f"{s} spp")
        ax.legend(fontsize=7)
    fig.suptitle(f"{scene}: radially averaged power spectrum of the error")
    fig.tight_layout()
    name = f"spectrum_{scene}.png"
    save_figure(fig, os.path.join(plots_dir, name), dpi=110)
    plt.close(fig)
    return "plots/" + name


def render_section(root, scene, rows, ref, plots_dir, scale):
    out = [f'<h2 id="{html.escape(scene)}">Scene: {html.escape(scene)}</h2>']
    if ref:
        out.append(f"<p>Reference: {html.escape(ref['backend'])}, {ref['spp']} spp, "
                   f"{ref['resolution']}, {ref['integrator']} integrator, "
                   f"{num(ref['seconds']):.1f} s of rendering; its own variance "
                   f"{fmt(ref.get('variance'))} (relMSE {fmt(ref.get('relvariance'))}), "
                   "estimated from its two independent halves, is part of every MSE below "
                   "(mse_less_reference in render.csv removes it).</p>")
        # A reference's own noise adds about max spp / reference spp to every
        # MSE ratio's denominator: below 16x it blurs the comparison.
        top = max(int(num(r["spp"])) for r in rows)
        if num(ref["spp"]) < 16 * top:
            out.append(f"<p class='bad'>Weak reference: {ref['spp']} spp is less than 16× the "
                       f"largest spp rendered ({top}); its own noise is a noticeable part of "
                       "every MSE at that spp.</p>")
    nonfinite = sum(int(num(r["nonfinite_pixels"])) for r in rows)
    rejected = sum(int(num(r.get("rejected_samples", 0))) for r in rows)
    out.append(f"<p class='{'bad' if nonfinite or rejected else 'note'}'>Stability: "
               f"{nonfinite} non-finite pixels and {rejected} non-finite samples (dropped by "
               f"the renderer) over all {len(rows)} renders.</p>")
    slopes = {(r["scene"], r["backend"]): r
              for r in labelled(read_csv(os.path.join(root, "slopes.csv")), "backend")}
    plot = render_plots(scene, rows, plots_dir, slopes)
    out.append(f'<p><img class="plot" src="{plot}" alt="error plots of {html.escape(scene)}"></p>')
    spectrum = spectrum_plots(root, scene, rows, plots_dir)
    if spectrum:
        out.append(f'<p><img class="plot" src="{spectrum}" alt="error spectra of '
                   f'{html.escape(scene)}"><br><small>How the error is spread over the '
                   "screen: flat is white noise, rising is blue noise (the screen_mse column "
                   "low-passes the error by a 1-pixel Gaussian, which keeps the low "
                   "frequencies).</small></p>")

    spps = sorted({int(r["spp"]) for r in rows})
    backends = list(dict.fromkeys(r["backend"] for r in rows))
    cell = {(r["backend"], int(r["spp"])): r for r in rows}
    sobol = {s: cell[("sobol", s)] for s in spps if ("sobol", s) in cell}
    out.append("<table><tr><th>backend</th>" +
               "".join(f"<th>spp {s}</th>" for s in spps) + "<th>setup s</th></tr>")
    for b in backends:
        tds = []
        for s in spps:
            r = cell.get((b, s))
            if not r:
                tds.append("<td>–</td>")
                continue
            ratio, se = ratio_to_sobol(r, sobol.get(s))
            # A win is a ratio two standard errors below 1, not one below 1
            # by noise; a loss, two above.
            # One repeat's error is 0, which decides nothing.
            cls = ("" if not se > 0 else
                   "win" if ratio + 2 * se < 1 else "loss" if ratio - 2 * se > 1 else "")
            tip = (f"relMSE {fmt(r['relmse'])}, {num(r['seconds']):.3f} s, "
                   f"{int(num(r['repeats']))} repeat(s)")
            eq = num(r.get("equal_time_ratio"))
            cq, cse = num(r.get("mse_ratio_best_classic")), num(r.get("mse_ratio_best_classic_stderr"))
            tds.append(f'<td class="{cls}" title="{html.escape(tip)}">{fmt(r["mse"])}'
                       + (f"<br><small>×{ratio:.2f}±{se:.2f} sobol</small>"
                          if math.isfinite(ratio) else "")
                       + (f"<br><small>×{cq:.2f}±{cse:.2f} best classic "
                          f"({html.escape(backend_label(r['best_classic']))})</small>"
                          if math.isfinite(cq) else "")
                       + (f"<br><small>×{eq:.2f} at equal time</small>"
                          if math.isfinite(eq) and b != "sobol" else "")
                       + (f"<br><small>pays for its setup {pays_after(r)}</small>"
                          if r.get("break_even_renders", "nan") != "nan" else "")
                       + ("<br><small class='bad'>reference too noisy for this row</small>"
                          if r.get("reference_too_noisy") == "1" else "")
                       + (f"<br><small>{int(num(r['repeats']))} repeats, stopped on "
                          f"{html.escape(r['stopped_on'])}</small>"
                          if r.get("stopped_on") in ("precision", "budget") else "")
                       + ("<br><small class='bad'>ruled by outliers: winsorized ×"
                          f"{num(r.get('winsorized_ratio_best_classic')):.2f}±"
                          f"{num(r.get('winsorized_ratio_best_classic_stderr')):.2f}</small>"
                          if r.get("ruled_by_outliers") == "1" else "")
                       + "</td>")
        setup = max(num(cell[(b, s)]["setup_seconds"]) for s in spps if (b, s) in cell)
        out.append(f"<tr><th>{html.escape(backend_label(b))}</th>{''.join(tds)}"
                   f"<td>{setup:.1f}</td></tr>")
    amortize = num(rows[0].get("amortize")) if rows else math.nan
    out.append("</table><p class='note'>MSE against the reference (hover for relMSE, seconds "
               "and repeats) and its ratio to Owen-Sobol's at the same spp with its standard "
               "error: green where it beats Owen-Sobol by two standard errors, red where it "
               "loses by two; a learned backend's ratio to the best classic one (the classic "
               "backend with the lowest MSE at that spp: independent, sobol, halton, "
               "sobol-tabulated, whichever ran); 'at equal time': MSE × (seconds + setup / "
               f"{amortize:g}) over Owen-Sobol's. 'Reference too noisy for this row': its "
               f"MSE is less than {TOO_NOISY_FACTOR}× the reference's own variance, which then decides the "
               "comparison. 'Stopped on precision' or 'on budget': with a target standard "
               "error, whether every MSE ratio of the row reached it or its repeats ran out. "
               "'Ruled by outliers': the ratio to the best classic row of the MSE with each "
               "image's largest 0.1 % of pixel errors winsorized reaches another verdict than "
               "the MSE's: a few pixels decide it. 'Pays for its setup after K renders': the fewest renders sharing "
               "its setup after which the learned row reaches the best classic row's error "
               "sooner (break_even_renders).</p>")
    verdicts = [v for v in labelled(read_csv(os.path.join(root, "verdicts.csv")),
                                    "best", "tied", "runner_up", "best_classic")
                if v["scene"] == scene]
    if verdicts:
        out.append("<p><b>Lowest error for the time</b> (MSE × total seconds, setup spread "
                   f"over {amortize:g} render(s)):</p><ul>")
        for v in verdicts:
            names = [v["best"]] + v["tied"].split()
            who = (html.escape(names[0]) if len(names) == 1 else
                   "a tie between " + ", ".join(html.escape(n) for n in names) +
                   " (within two standard errors)")
            line = f"<li>{v['spp']} spp: {who}"
            if math.isfinite(num(v["equal_time_ratio"])):
                line += (f", ×{num(v['equal_time_ratio']):.2f}±"
                         f"{num(v['equal_time_ratio_stderr']):.2f} of sobol's")
            if v["runner_up"]:
                line += (f"; ahead of {html.escape(v['runner_up'])} at ×"
                         f"{num(v['separation']):.2f}±{num(v['separation_stderr']):.2f}")
            if math.isfinite(num(v.get("mse_ratio_best_classic"))):
                line += (f"; MSE ×{num(v['mse_ratio_best_classic']):.2f}±"
                         f"{num(v['mse_ratio_best_classic_stderr']):.2f} of the best classic's "
                         f"({html.escape(backend_label(v['best_classic']))}), pays for its "
                         f"setup {pays_after(v)}")
            out.append(line + "</li>")
        out.append("</ul>")

    # Images at the smallest and largest spp: full frame, zoomed crop, error map.
    ref_png = os.path.join(root, scene, "reference.png")
    window = crop_window(ref_png, 32) if os.path.exists(ref_png) else None
    crops = os.path.join(plots_dir, "crops")
    os.makedirs(crops, exist_ok=True)

    def figure(png_rel, caption, tag, exr_rel=None):
        png = os.path.join(root, png_rel)
        if not os.path.exists(png):
            return ""
        crop_html = ""
        if window:
            crop_rel = f"plots/crops/{scene}_{tag}.png"
            save_crop(png, window, os.path.join(root, crop_rel))
            crop_html = f'<img class="crop" src="{crop_rel}" alt="crop">'
        link = ""
        if exr_rel and os.path.exists(os.path.join(root, exr_rel)):
            link = f' <a href="{html.escape(exr_rel)}">EXR</a>'
        return (f'<figure><img class="full" src="{png_rel}" alt="{html.escape(caption)}">'
                f"{crop_html}<figcaption>{html.escape(caption)}{link}</figcaption></figure>")

    out.append('<div class="row">' +
               figure(f"{scene}/reference.png", "reference", "reference",
                      f"{scene}/reference.exr") + "</div>")
    # Every spp rendered; the smallest and largest open, the others folded.
    for s in spps:
        figs = []
        for b in backends:
            r = cell.get((b, s))
            if not r:
                continue
            tag = f"{os.path.splitext(os.path.basename(r['image']))[0]}"
            figs.append(figure(os.path.splitext(r["image"])[0] + ".png",
                               f"{backend_label(b)}, {s} spp, MSE {fmt(r['mse'])}", tag,
                               r["image"]))
            err = r["error_map"]
            if os.path.exists(os.path.join(root, err)):
                figs.append(f'<figure><img class="full" src="{err}" alt="error map">'
                            f"<figcaption>relative error, {html.escape(backend_label(b))}"
                            "</figcaption></figure>")
            # Repeat 0's HDR-FLIP map (magma: black no difference, bright large).
            flip = err[:-len("_error.png")] + "_flip.png" if err.endswith("_error.png") else ""
            if flip and os.path.exists(os.path.join(root, flip)):
                figs.append(f'<figure><img class="full" src="{flip}" alt="FLIP map">'
                            f"<figcaption>ꟻLIP {fmt(r.get('flip'))}, "
                            f"{html.escape(backend_label(b))}</figcaption></figure>")
        figs.append(f'<figure class="scale"><img class="scale" src="{scale}" '
                    'alt="error colour scale"><figcaption>error maps: (image − reference)² / '
                    "(reference² + 0.01), mean of the channels (relMSE per pixel)"
                    "</figcaption></figure>")
        is_open = " open" if s in (spps[0], spps[-1]) else ""
        out.append(f"<details{is_open}><summary><h3>{s} spp</h3></summary>"
                   f"<div class='row'>{''.join(figs)}</div></details>")
    return "\n".join(out)


def integrate_section(root, rows):
    out = ["<h2 id='integrate'>Integration error</h2>",
           "<p>RMSE of the importance-sampling estimate against the reference integral, "
           "bias (mean − reference, ± its standard error) and generation time per set.</p>"]
    plots, _ = plot_integrate.draw_plots(root, rows)
    for integrand, plot in plots.items():
        out.append(f"<h3>{html.escape(integrand)}</h3>"
                   f'<p><img class="plot-small" src="{plot}" alt="{html.escape(integrand)}"></p>')
        rs = [r for r in rows if r["integrand"] == integrand]
        out.append("<table><tr><th>sampler</th><th>N</th><th>instances</th><th>RMSE</th>"
                   "<th>rel. RMSE</th><th>bias</th><th>± stderr</th><th>gen s/set</th></tr>")
        for r in rs:
            out.append(f"<tr><th>{html.escape(backend_label(r['sampler']))}</th><td>{r['n']}</td>"
                       f"<td>{r['instances']}</td><td>{fmt(r['rmse'])}</td>"
                       f"<td>{fmt(r['rel_rmse'])}</td><td>{fmt(r['bias'])}</td>"
                       f"<td>{fmt(r.get('bias_stderr'))}</td>"
                       f"<td>{fmt(r.get('gen_seconds_per_set'), 2)}</td></tr>")
        out.append("</table>")
    return "\n".join(out)


STYLE = """
body { font-family: sans-serif; margin: 1em 2em; max-width: 1400px; }
@media (max-width: 1400px) {
  img.full { width: 220px; }
  figcaption { max-width: 220px; }
}
table { border-collapse: collapse; margin: 0.5em 0; font-size: 0.9em; }
td, th { border: 1px solid #ccc; padding: 3px 8px; text-align: right; }
td.win { background: #dff5df; }
td.loss { background: #f8e0e0; }
.row { display: flex; flex-wrap: wrap; gap: 10px; }
figure { margin: 0; }
figcaption { font-size: 0.8em; max-width: 260px; }
img.full { width: 260px; image-rendering: pixelated; display: block; }
img.crop { width: 128px; image-rendering: pixelated; display: block; margin-top: 3px; }
img.scale { height: 190px; display: block; }
figure.scale figcaption { max-width: 140px; }
img.plot { max-width: 100%; }
summary h3 { display: inline; }
details { margin: 0.6em 0; }
img.plot-small { max-width: 900px; width: 100%; }
.note { color: #555; font-size: 0.85em; }
.bad { color: #b00; font-weight: bold; }
"""


# A row's backend word -> its label (render.csv's label column: LABEL of
# LABEL=WORD, else the word), which the page shows wherever it names a row.
LABELS = {}


def labelled(rows, *columns):
    for r in rows:
        for c in columns:
            if r.get(c):
                r[c] = " ".join(LABELS.get(w, w) for w in r[c].split(" "))
    return rows


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    root = sys.argv[1]
    render_rows = read_csv(os.path.join(root, "render.csv"))
    LABELS.update({r["backend"]: r.get("label") or r["backend"] for r in render_rows})
    labelled(render_rows, "backend", "best_classic", "best_classic_screen", "best_classic_flip")
    refs = {r["scene"]: r for r in read_csv(os.path.join(root, "references.csv"))}
    integrate_rows = read_csv(os.path.join(root, "integrate.csv"))
    if not render_rows and not integrate_rows:
        sys.exit(f"report.py: {root} has neither render.csv nor integrate.csv")
    plots_dir = os.path.join(root, "plots")
    os.makedirs(plots_dir, exist_ok=True)

    body = []
    scenes = by(render_rows, "scene")
    scale = error_scale(plots_dir) if scenes else None
    for scene, rows in scenes.items():
        body.append(render_section(root, scene, rows, refs.get(scene), plots_dir, scale))
    if integrate_rows:
        body.append(integrate_section(root, integrate_rows))
    toc = " · ".join([f'<a href="#{html.escape(s)}">{html.escape(s)}</a>' for s in scenes] +
                     (['<a href="#integrate">integration</a>'] if integrate_rows else []))
    data = " · ".join(f'<a href="{name}">{name}</a>'
                      for name in ("render.csv", "verdicts.csv", "references.csv",
                                   "slopes.csv", "integrate.csv")
                      if os.path.exists(os.path.join(root, name)))
    # The comparison page nuld writes beside it (tools/study/compare_page.h).
    compare = ('<br><a href="compare.html">Compare the renders at full size</a> '
               '(flip between rows, zoom, exposure, error and FLIP maps)'
               if os.path.exists(os.path.join(root, "compare.html")) else "")
    # No absolute path on the page: it is meant to be copied and shared.
    page = (f"<!DOCTYPE html><html><head><meta charset='utf-8'>"
            f"<meta name='viewport' content='width=device-width, initial-scale=1'>"
            f"<title>nuld study</title><style>{STYLE}</style></head><body><h1>nuld study</h1>"
            f"<p class='note'>Generated {datetime.datetime.now():%Y-%m-%d %H:%M}. {toc}"
            f"<br>Data: {data}{compare}</p>" + "\n".join(body) + "</body></html>\n")
    write_text(os.path.join(root, "index.html"), page)
    print(f"report: {os.path.join(root, 'index.html')}")


if __name__ == "__main__":
    main()
