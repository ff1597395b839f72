"""A render study from Python (tools/python/README.md, "Studies"): rows of
backend words, plugins and your own samplers, rendered with repeated seeds
against one reference and summarized with the statistics and verdicts of
`nuld study render` (nuld.mean_and_error, nuld.ratio_of_means)."""

import csv
import math

from . import _nuld


class StudyTable:
    """The rows of a study: one dict per (row, spp) with mse, its stderr,
    screen error, seconds and the ratios to the baseline row with their
    verdicts. str() gives the table; to_csv(path) writes it."""

    columns = ["row", "spp", "repeats", "mse", "mse_stderr", "screen", "screen_stderr", "seconds",
               "mse_ratio", "mse_ratio_stderr", "verdict", "screen_ratio", "screen_ratio_stderr",
               "screen_verdict", "time_ratio", "time_ratio_stderr", "time_verdict"]

    def __init__(self, rows, baseline, reference_variance):
        self.rows, self.baseline, self.reference_variance = rows, baseline, reference_variance

    def __iter__(self):
        return iter(self.rows)

    def __len__(self):
        return len(self.rows)

    def __str__(self):
        # The row column is as wide as the longest label: no label is cut.
        width = max([24] + [len(r["row"]) for r in self.rows])
        head = (f"{'row':<{width}} {'spp':>5} {'mse':>11} {'+-':>9} {'screen':>11} {'seconds':>8}"
                f"   {'mse/' + self.baseline[:10]:>16} {'vs':>6}   {'scr/base':>14} {'vs':>6}"
                f"   {'time/base':>14} {'vs':>6}")
        lines = [f"(reference's own variance {self.reference_variance:.4e}; a row below 10x it "
                 "is decided by the reference's noise)", head]

        def ratio(r, key):
            value, err = r[key], r[key + "_stderr"]
            return "-" if math.isnan(value) else f"{value:.3f}+-{err:.3f}"

        for r in self.rows:
            lines.append(
                f"{r['row']:<{width}} {r['spp']:>5} {r['mse']:>11.4e} {r['mse_stderr']:>9.2e}"
                f" {r['screen']:>11.4e} {r['seconds']:>8.3f}   {ratio(r, 'mse_ratio'):>16}"
                f" {r['verdict']:>6}   {ratio(r, 'screen_ratio'):>14} {r['screen_verdict']:>6}"
                f"   {ratio(r, 'time_ratio'):>14} {r['time_verdict']:>6}")
        return "\n".join(lines)

    def to_csv(self, path):
        """Writes the rows as CSV, the columns of StudyTable.columns."""
        with open(path, "w", newline="") as f:
            w = csv.DictWriter(f, fieldnames=self.columns)
            w.writeheader()
            for r in self.rows:
                w.writerow({k: r[k] for k in self.columns})


def _render_row(scene, label, row, spp, seed, render_args):
    """One render of a row: a backend word; a factory seed -> sampler (a
    scipy.stats.qmc engine or a callable n -> (n, 2)); or such a callable
    itself, which the repeat's seed, passed as n, answers with an array."""
    what = f"study: row {label!r}"
    if isinstance(row, str):
        sampler = None
    elif callable(row):
        made = row(seed)
        sampler = row if hasattr(made, "shape") and hasattr(made, "dtype") else made
    else:
        raise TypeError(f"{what}: expected a backend word or a callable seed -> sampler "
                        f"(a scipy.stats.qmc engine of d = 2 or a callable n -> (n, 2)), "
                        f"got {type(row).__name__}")
    try:
        if sampler is None:
            return _nuld.render(scene, backend=row, spp=spp, seed=seed, stats=True,
                                **render_args)
        return _nuld.render(scene, sampler=sampler, spp=spp, seed=seed, stats=True,
                            **render_args)
    except (TypeError, ValueError) as e:
        # The render's own words, under the study's and the row's names.
        message = str(e)
        if message.startswith("render: "):
            message = message[len("render: "):]
        raise type(e)(f"{what}: {message}") from None


def study(scene="default", rows=None, spp=(4, 16), repeats=8, seed=1, baseline=None,
          reference=None, reference_backend="halton", reference_spp=4096, **render_args):
    """Renders every row at every spp `repeats` times (seeds seed, seed + 1,
    ...) and compares each render with one reference.

    rows: a dict label -> row, or a list of backend words; a row is a
    backend word ('sobol', 'plugin:./libmine.so'), a callable taking the
    repeat's seed and returning a sampler for nuld.render(sampler=...), e.g.
    `lambda s: scipy.stats.qmc.Sobol(d=2, seed=s)` (a fresh engine a repeat),
    or a sampler callable n -> (n, 2) itself (told apart by what it returns
    for the seed: an array). A row's error names it: "study: row 'mine': ...".
    baseline: the label the ratios are against (default 'sobol' if a row,
    else the first). reference: an image, else the scene's reference of
    reference_spp (4096, the CLI's --reference-spp default) with
    reference_backend, as nuld.render(reference=True)
    and the CLI's studies make it (two independent halves, whose difference
    gives its own variance), found in the reference cache or rendered into
    it. Other keywords go to
    nuld.render (resolution_scale, integrator, max_depth, ...). Returns a
    StudyTable: the mean MSE and screen error with their standard errors,
    the mean render seconds, and the ratios to the baseline at equal spp
    (mse_ratio, screen_ratio) and at equal time (time_ratio: MSE x seconds),
    each with its standard error and verdict, as nuld study render's."""
    if rows is None:
        rows = ["sobol"]
    if not isinstance(rows, dict):
        rows = {str(r): r for r in rows}
    if not rows:
        raise ValueError("study: rows: expected at least one row")
    if baseline is None:
        baseline = "sobol" if "sobol" in rows else next(iter(rows))
    if baseline not in rows:
        raise ValueError(f"study: baseline: expected one of the rows' labels "
                         f"({', '.join(rows)}), got {baseline!r}")
    spps = [spp] if isinstance(spp, int) else list(spp)
    if isinstance(repeats, bool) or not isinstance(repeats, int) or repeats < 1:
        raise ValueError(f"study: repeats: expected a whole number >= 1, got {repeats!r}")
    reference_variance = float("nan")
    if reference is None:
        # The rows' lobe-table and set options do not apply to a classic
        # reference (its seed, the studies', is far from the rows').
        shared = {k: v for k, v in render_args.items()
                  if k not in ("lobe_mix", "lobe_routes", "lobe_defensive", "lobe_bounces",
                               "progress") and not k.startswith("opt_")}
        reference, made = _nuld.render(scene, reference=True, backend=reference_backend,
                                       spp=reference_spp, stats=True, **shared)
        reference_variance = made["variance"]
    cells = {}
    for label, row in rows.items():
        for n in spps:
            mse, screen, seconds = [], [], []
            for r in range(repeats):
                image, stats = _render_row(scene, label, row, n, seed + r, render_args)
                error = _nuld.compare(image, reference)
                mse.append(error["mse"])
                screen.append(error["screen"])
                seconds.append(stats["seconds"])
            cells[label, n] = {k: _nuld.mean_and_error(v)
                               for k, v in (("mse", mse), ("screen", screen), ("seconds", seconds))}
    out = []
    for label in rows:
        for n in spps:
            c, b = cells[label, n], cells[baseline, n]
            row = {"row": label, "spp": n, "repeats": repeats,
                   "mse": c["mse"]["mean"], "mse_stderr": c["mse"]["stderr"],
                   "screen": c["screen"]["mean"], "screen_stderr": c["screen"]["stderr"],
                   "seconds": c["seconds"]["mean"]}
            for key, name in (("mse", "mse_ratio"), ("screen", "screen_ratio")):
                q = _nuld.ratio_of_means(c[key]["mean"], c[key]["stderr"], b[key]["mean"],
                                         b[key]["stderr"])
                row[name], row[name + "_stderr"] = q["ratio"], q["stderr"]
                row["verdict" if key == "mse" else "screen_verdict"] = q["verdict"]
            # Equal time: MSE x seconds, the seconds' own noise left out as the CLI's.
            scale = c["seconds"]["mean"] / b["seconds"]["mean"]
            q = _nuld.ratio_of_means(c["mse"]["mean"] * scale, c["mse"]["stderr"] * scale,
                                     b["mse"]["mean"], b["mse"]["stderr"])
            row["time_ratio"], row["time_ratio_stderr"] = q["ratio"], q["stderr"]
            row["time_verdict"] = q["verdict"]
            if label == baseline:
                for name in ("mse_ratio", "screen_ratio", "time_ratio"):
                    row[name] = row[name + "_stderr"] = float("nan")
                row["verdict"] = row["screen_verdict"] = row["time_verdict"] = "-"
            out.append(row)
    return StudyTable(out, baseline, reference_variance)
