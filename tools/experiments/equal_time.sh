#!/usr/bin/env bash
# Error against run time (tools/experiments/README.md, "Error against run
# time"): the learned backends against sobol at equal time, setup included.
#
#   1. The four shipped scenes at 1/4 resolution under both integrators, 16
#      and 64 spp, 8 repeats, seed 9173, from an empty set cache
#      (lobe_routes.sh with the defaults), rescored at K = 1 and K = 16.
#   2. Dragon and cup at full resolution, path, 64 spp, 8 repeats, 1024-spp
#      references, sobol and optimized-both, K = 16, from an empty cache.
#
# Prints the equal_time_ratio table (OUT/equal_time.csv). The sets are made
# once per scene (the direct pass); the path rows, which find them in the
# cache, are charged the same setup here so that both integrators count it.
# About 15 minutes on 2 cores; run it on an otherwise idle machine (the
# ratios are of measured times).
#
# Usage: tools/experiments/equal_time.sh OUT [REFERENCES]
#   REFERENCES: a lobe_routes.sh OUT/references directory to reuse.
source "$(dirname "$0")/common.sh"
out=${1:?usage: equal_time.sh OUT [REFERENCES]}
mkdir -p "$out"
[[ -n "${2:-}" && ! -e "$out/references" ]] && cp -r "$2" "$out/references"
backends=sobol,optimized,optimized-bsdf,optimized-both
BACKENDS=$backends "$root/tools/experiments/lobe_routes.sh" "$out" "defaults=" >/dev/null
cp "$out/summary.csv" "$out/summary_k1.csv"
BACKENDS=$backends "$root/tools/experiments/lobe_routes.sh" "$out" "defaults=--amortize 16" >/dev/null
cp "$out/summary.csv" "$out/summary_k16.csv"
export NULD_CACHE="$out/full-cache"
cd "$root"
for scene in dragon cup; do
  "$nuld" study render "scenes/$scene.json" --integrator path --spp 64 --repeats 8 --seed 9173 \
    --reference-spp 1024 --backends sobol,optimized-both --amortize 16 --no-report -q \
    -o "$out/full" >/dev/null
done

"$python" - "$out" <<'EOF'
import csv, os, sys
out = sys.argv[1]

def rows(path):
    return list(csv.DictReader(open(path)))

def ratio(row, sobol, setup, k):
    """MSE x (seconds + setup / K) over sobol's, with the MSE ratio's error."""
    q = float(row["mse"]) / float(sobol["mse"])
    t = (float(row["seconds"]) + setup / k) / float(sobol["seconds"])
    se = q * ((float(row["mse_stderr"]) / float(row["mse"])) ** 2 +
              (float(sobol["mse_stderr"]) / float(sobol["mse"])) ** 2) ** 0.5
    return q * t, se * t

table = []
direct = rows(os.path.join(out, "defaults", "direct", "render.csv"))
setup = {(r["scene"], r["backend"], r["spp"]): float(r["setup_seconds"]) for r in direct}
for integrator in ("direct", "path"):
    rs = rows(os.path.join(out, "defaults", integrator, "render.csv"))
    sobol = {(r["scene"], r["spp"]): r for r in rs if r["backend"] == "sobol"}
    for r in rs:
        if r["backend"] == "sobol":
            continue
        s = sobol[(r["scene"], r["spp"])]
        cost = setup[(r["scene"], r["backend"], r["spp"])]
        k1, e1 = ratio(r, s, cost, 1)
        k16, e16 = ratio(r, s, cost, 16)
        table.append([r["scene"], integrator, "1/4", r["backend"], r["spp"],
                      f"{float(r['mse']) / float(s['mse']):.3f}", f"{cost:.1f}",
                      f"{k1:.3g}", f"{e1:.2g}", f"{k16:.3g}", f"{e16:.2g}"])
full = rows(os.path.join(out, "full", "render.csv"))
sobol = {r["scene"]: r for r in full if r["backend"] == "sobol"}
for r in full:
    if r["backend"] == "sobol":
        continue
    s = sobol[r["scene"]]
    cost = float(r["setup_seconds"])
    k1, e1 = ratio(r, s, cost, 1)
    k16, e16 = ratio(r, s, cost, 16)
    table.append([r["scene"], "path", "full", r["backend"], r["spp"],
                  f"{float(r['mse']) / float(s['mse']):.3f}", f"{cost:.1f}",
                  f"{k1:.3g}", f"{e1:.2g}", f"{k16:.3g}", f"{e16:.2g}"])
header = ["scene", "integrator", "resolution", "backend", "spp", "mse_ratio", "setup_seconds",
          "equal_time_k1", "stderr_k1", "equal_time_k16", "stderr_k16"]
with open(os.path.join(out, "equal_time.csv"), "w", newline="") as f:
    csv.writer(f).writerows([header] + table)
for row in [header] + table:
    print(" ".join(f"{c:>14}" for c in row))
EOF
