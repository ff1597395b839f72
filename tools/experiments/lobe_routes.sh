#!/usr/bin/env bash
# BSDF sampling routes against the material's own sampler (tools/experiments/
# routes_against_baseline.md, "Lobe routes"): render studies of the four shipped
# scenes under both MIS integrators, 16 and 64 spp, 8 repeats, seed 9173 (no
# test uses it), 1/4 resolution, REFERENCE_SPP-spp references (default 1024),
# once per variant of the lobe options. Every variant of a (scene, integrator)
# scores against the same reference (made once, copied). Writes
# OUT/VARIANT/INTEGRATOR/render.csv and OUT/summary.csv (the rows with each
# backend's MSE ratio to sobol, its standard error, the seconds ratio and the
# brightest pixel of the first repeat relative to sobol's).
#
# Usage: tools/experiments/lobe_routes.sh OUT [VARIANT=FLAGS ...]
#   BACKENDS (default sobol,sobol-tabulated) are the backends compared;
#   SCENES (default "default scenes/lte-orb.json scenes/dragon.json
#   scenes/cup.json"), INTEGRATORS (default "direct path"), SPP (16,64).
# Default variants: before (every bin tabulated, no defensive split, tables
# at every bounce: the routes as they were) and after (the defaults).
source "$(dirname "$0")/common.sh"
out=${1:?usage: lobe_routes.sh OUT [VARIANT=FLAGS ...]}
shift
variants=("$@")
[[ ${#variants[@]} -gt 0 ]] ||
  variants=("before=--lobe-routes table --lobe-defensive 0 --lobe-bounces 0" "after=")
backends=${BACKENDS:-sobol,sobol-tabulated}
scenes=${SCENES:-"default scenes/lte-orb.json scenes/dragon.json scenes/cup.json"}
integrators=${INTEGRATORS:-"direct path"}
spp=${SPP:-16,64}
mkdir -p "$out"
cd "$root"

for integrator in $integrators; do
  for v in "${variants[@]}"; do
    name=${v%%=*} flags=${v#*=}
    dir="$out/$name/$integrator"
    mkdir -p "$dir"
    # The sets depend on the tables, not on the integrator (both weigh BSDF
    # samples by MIS): one set cache per variant, empty at its start, so
    # each variant's setup_seconds is what it costs from nothing.
    export NULD_CACHE="$out/$name/set-cache"
    for scene in $scenes; do
      # shellcheck disable=SC2086  # flags are words
      "$nuld" study render "$scene" --integrator "$integrator" --res-scale 0.25 --spp "$spp" \
        --repeats 8 --reference-spp "${REFERENCE_SPP:-1024}" --seed 9173 --backends "$backends" $flags \
        --no-report -q -o "$dir" >/dev/null
    done
  done
done

"$python" - "$out" <<'EOF'
import csv, glob, os, subprocess, sys
out = sys.argv[1]

def brightest(path):
    # oiiotool --stats prints "Stats Max: R G B (float)"
    text = subprocess.run(["oiiotool", "--stats", path], capture_output=True, text=True).stdout
    for line in text.splitlines():
        if "Stats Max" in line:
            return max(float(v) for v in line.split(":")[1].split("(")[0].split())
    return float("nan")

rows = []
for csv_path in sorted(glob.glob(os.path.join(out, "*", "*", "render.csv"))):
    variant, integrator = csv_path.split(os.sep)[-3:-1]
    table = list(csv.DictReader(open(csv_path)))
    sobol = {(r["scene"], r["spp"]): r for r in table if r["backend"] == "sobol"}
    for r in table:
        s = sobol.get((r["scene"], r["spp"]))
        if not s:
            continue
        ratio = float(r["mse"]) / float(s["mse"])
        # standard error of the ratio, from the two relative standard errors
        se = ratio * ((float(r["mse_stderr"]) / float(r["mse"])) ** 2 +
                      (float(s["mse_stderr"]) / float(s["mse"])) ** 2) ** 0.5
        base = os.path.dirname(csv_path)
        peak = brightest(os.path.join(base, r["image"])) / brightest(os.path.join(base, s["image"]))
        rows.append([r["scene"], integrator, variant, r["backend"], r["spp"], f"{ratio:.3f}",
                     f"{se:.3f}", f"{float(r['seconds']) / float(s['seconds']):.2f}",
                     f"{peak:.2f}", r["setup_seconds"], r.get("equal_time_ratio", "")])
with open(os.path.join(out, "summary.csv"), "w", newline="") as f:
    w = csv.writer(f)
    w.writerow(["scene", "integrator", "variant", "backend", "spp", "mse_ratio",
                "mse_ratio_stderr", "seconds_ratio", "brightest_ratio", "setup_seconds",
                "equal_time_ratio"])
    w.writerows(rows)
for r in rows:
    print(" ".join(f"{c:>14}" for c in r))
EOF
