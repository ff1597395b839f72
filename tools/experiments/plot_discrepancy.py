"""Discrepancy against N, one panel per metric, one line per sampler (log-log)."""
import argparse
import csv
from collections import defaultdict

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

parser = argparse.ArgumentParser()
parser.add_argument("csv")
parser.add_argument("png")
parser.add_argument("--title", default="")
args = parser.parse_args()

rows = list(csv.DictReader(open(args.csv)))
metrics = [m for m in ("l2star", "l2asd", "dstar") if m in rows[0]]
series = defaultdict(lambda: defaultdict(list))
for r in rows:
    for m in metrics:
        series[m][r["sampler"]].append((int(r["n"]), float(r[m])))

fig, axes = plt.subplots(1, len(metrics), figsize=(4.2 * len(metrics), 3.6))
for ax, m in zip(axes, metrics):
    for sampler, pts in sorted(series[m].items()):
        pts.sort()
        ax.loglog([p[0] for p in pts], [p[1] for p in pts], "o-", label=sampler, ms=3)
    ax.set_xlabel("N")
    ax.set_title({"l2star": "L2*", "l2asd": "L2asd", "dstar": "D*"}[m])
    ax.grid(True, which="both", alpha=0.3)
axes[0].legend()
if args.title:
    fig.suptitle(args.title)
fig.tight_layout()
fig.savefig(args.png + ".tmp.png", dpi=120)
import os  # noqa: E402

os.replace(args.png + ".tmp.png", args.png)
