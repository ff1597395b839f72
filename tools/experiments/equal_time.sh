#!/usr/bin/env bash
# Error against run time (tools/experiments/equal_time.md): the learned backends
# at equal time, setup included.
#
#   1. The four shipped scenes at 1/4 resolution under both integrators, 16
#      and 64 spp, 8 repeats, seed 9173, from an empty set cache
#      (lobe_routes.sh with the defaults), against sobol, rescored at K = 1
#      and K = 16 (OUT/equal_time.csv).
#   2. FULL_SCENES (default: dragon cup lte-orb) at full resolution under
#      both integrators, 64 spp, REPEATS (default 8) repeats, seed 9173,
#      1024-spp references: sobol, sobol-tabulated (the best classic row on
#      the dragon), optimized and optimized-both, each cell from an empty
#      set cache (cold) and again in a new process that finds the sets
#      there (warm; the reference copied). Prints per row its MSE and
#      render seconds over the best classic row's, its setup and
#      break_even_renders, the renders after which it reaches the best
#      classic row's error sooner (OUT/full_time.csv).
#
# PARTS (default "1 2") picks the parts. Part 1 takes about 15 minutes on
# 2 cores, part 2 about 8 minutes per scene and integrator at 8 repeats;
# run them on an otherwise idle machine (the ratios are of measured times).
#
# Usage: tools/experiments/equal_time.sh OUT [REFERENCES]
#   REFERENCES: a lobe_routes.sh OUT/references directory to reuse.
source "$(dirname "$0")/common.sh"
out=${1:?usage: equal_time.sh OUT [REFERENCES]}
mkdir -p "$out"
[[ -n "${2:-}" && ! -e "$out/references" ]] && cp -r "$2" "$out/references"
if [[ " ${PARTS:-1 2} " == *" 1 "* ]]; then
backends=sobol,optimized,optimized-bsdf,optimized-both
BACKENDS=$backends "$root/tools/experiments/lobe_routes.sh" "$out" "defaults=" >/dev/null
cp "$out/summary.csv" "$out/summary_k1.csv"
BACKENDS=$backends "$root/tools/experiments/lobe_routes.sh" "$out" "defaults=--amortize 16" >/dev/null
cp "$out/summary.csv" "$out/summary_k16.csv"
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
header = ["scene", "integrator", "resolution", "backend", "spp", "mse_ratio", "setup_seconds",
          "equal_time_k1", "stderr_k1", "equal_time_k16", "stderr_k16"]
with open(os.path.join(out, "equal_time.csv"), "w", newline="") as f:
    csv.writer(f).writerows([header] + table)
for row in [header] + table:
    print(" ".join(f"{c:>14}" for c in row))
EOF
fi

# Part 2: full resolution, cold and warm, against the best classic row.
if [[ " ${PARTS:-1 2} " == *" 2 "* ]]; then
  cd "$root"
  for scene in ${FULL_SCENES:-dragon cup lte-orb}; do
    for integrator in direct path; do
      cell="$out/full/$scene-$integrator"
      for run in cold warm; do
        NULD_CACHE="$cell/cache" "$nuld" study render "scenes/$scene.json" --integrator "$integrator" \
          --spp 64 --repeats "${REPEATS:-8}" --seed 9173 --reference-spp 1024 \
          --backends sobol,sobol-tabulated,optimized,optimized-both --no-report -q \
          -o "$cell/$run" >/dev/null
      done
    done
  done
  "$python" - "$out" <<'EOF'
import csv, glob, os, sys
out = sys.argv[1]
header = ["scene", "integrator", "cache", "backend", "best_classic", "mse_ratio", "stderr",
          "time_ratio", "setup_seconds", "break_even_renders", "stderr"]
table = []
for path in sorted(glob.glob(os.path.join(out, "full", "*", "*", "render.csv"))):
    run = os.path.basename(os.path.dirname(path))
    integrator = os.path.basename(os.path.dirname(os.path.dirname(path))).rsplit("-", 1)[1]
    rows = list(csv.DictReader(open(path)))
    seconds = {r["backend"]: float(r["seconds"]) for r in rows}
    for r in rows:
        best = r["best_classic"]
        if r["mse_ratio_best_classic"] in ("", "nan"):
            continue  # a classic row
        table.append([r["scene"], integrator, run, r["backend"], best,
                      f"{float(r['mse_ratio_best_classic']):.3f}",
                      f"{float(r['mse_ratio_best_classic_stderr']):.3f}",
                      f"{seconds[r['backend']] / seconds[best]:.3f}",
                      f"{float(r['setup_seconds']):.1f}", r["break_even_renders"],
                      r["break_even_renders_stderr"]])
with open(os.path.join(out, "full_time.csv"), "w", newline="") as f:
    csv.writer(f).writerows([header] + table)
for row in [header] + table:
    print(" ".join(f"{c:>13}" for c in row))
EOF
fi
