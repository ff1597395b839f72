"""Prints, per N and metric, the ratio of one sampler's value to another's."""
import csv
import sys
from collections import defaultdict

path, num, den = sys.argv[1], sys.argv[2], sys.argv[3]
rows = list(csv.DictReader(open(path)))
metrics = [m for m in ("l2star", "l2asd", "dstar") if m in rows[0]]
vals = defaultdict(dict)
for r in rows:
    vals[(int(r["n"]), r.get("target", ""))][r["sampler"]] = r
print(f"{'N':>6} {'target':<12}" + "".join(f"{m + ' ' + num + '/' + den:>26}" for m in metrics))
for key in sorted(vals):
    v = vals[key]
    if num in v and den in v:
        ratios = [float(v[num][m]) / float(v[den][m]) for m in metrics]
        print(f"{key[0]:>6} {key[1]:<12}" + "".join(f"{x:>26.3f}" for x in ratios))
