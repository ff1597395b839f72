#!/usr/bin/env bash
# The classic baseline and what survives it (tools/experiments/lobe_choice.md
# and tools/experiments/routes_against_baseline.md): render studies of the four
# shipped scenes under both MIS integrators, once per configuration, 16 and 64
# spp, 8 repeats, seed 9173 (no test uses it), 1/4 resolution. Each choice of a
# (scene, integrator) scores against a reference rendered with that choice
# (REFERENCE_SPP, default 4096 spp, in two halves that measure its own
# variance), which the reference cache keeps for every later run. Each choice
# has its own set cache, empty at its start, so setup seconds are what the
# sets cost from nothing.
#
# Writes OUT/CHOICE/INTEGRATOR/render.csv (with references.csv and
# verdicts.csv) and OUT/summary.csv: each row's MSE relative to sobol under
# BASELINE_CHOICE (default albedo, the default choice) and to the best
# classic row of its own study, with standard errors, the reference's
# variance and whether the reference is too noisy for the row.
#
# A configuration is a lobe choice (uniform, weight, albedo: --lobe-choice,
# with the scenes' own map importance, compensated by default) or `paper`
# (--lobe-choice uniform --env-importance luminance, the paper's).
#
# Usage: tools/experiments/lobe_choice.sh OUT
#   CHOICES (default "uniform weight albedo"), BACKENDS (default sobol,halton),
#   SCENES, INTEGRATORS (default "direct path"), SPP (16,64), REFERENCE_SPP,
#   BASELINE_CHOICE, REPEATS (default 8), RES_SCALE (default 0.25), SEED (of the studies, default 9173; the
#   references keep 9173), FLAGS (more options for every study, e.g. --lobe-routes table).
source "$(dirname "$0")/common.sh"
out=${1:?usage: lobe_choice.sh OUT}
choices=${CHOICES:-"uniform weight albedo"}
backends=${BACKENDS:-sobol,halton}
scenes=${SCENES:-"default scenes/lte-orb.json scenes/dragon.json scenes/cup.json"}
integrators=${INTEGRATORS:-"direct path"}
spp=${SPP:-16,64}
reference_spp=${REFERENCE_SPP:-4096}
baseline=${BASELINE_CHOICE:-albedo}
mkdir -p "$out"
out=$(cd "$out" && pwd)
cd "$root"
flags_of() {
  case $1 in
    paper) echo "--lobe-choice uniform --env-importance luminance" ;;
    *) echo "--lobe-choice $1" ;;
  esac
}

for integrator in $integrators; do
  for scene in $scenes; do
    for choice in $choices; do
      dir="$out/$choice/$integrator"
      NULD_CACHE="$out/$choice/set-cache" "$nuld" study render "$scene" \
        --integrator "$integrator" --res-scale "${RES_SCALE:-0.25}" --spp "$spp" --repeats "${REPEATS:-8}" \
        --reference-spp "$reference_spp" --seed "${SEED:-9173}" --backends "$backends" \
        $(flags_of "$choice") ${FLAGS:-} --no-report -q -o "$dir" >/dev/null
    done
  done
done

"$python" - "$out" "$baseline" <<'PY'
import csv, glob, os, sys
out, baseline = sys.argv[1], sys.argv[2]
rows, tables, refs = [], {}, {}
for path in sorted(glob.glob(os.path.join(out, "*", "*", "render.csv"))):
    choice, integrator = path.split(os.sep)[-3:-1]
    if choice == "references":
        continue
    for r in csv.DictReader(open(path)):
        tables[(integrator, r["scene"], r["spp"], choice, r["backend"])] = r
    for r in csv.DictReader(open(os.path.join(os.path.dirname(path), "references.csv"))):
        refs[(integrator, r["scene"])] = r["variance"]

def ratio(r, base):
    m, b = float(r["mse"]), float(base["mse"])
    return m / b, m / b * ((float(r["mse_stderr"]) / m) ** 2 + (float(base["mse_stderr"]) / b) ** 2) ** 0.5

for key, r in sorted(tables.items()):
    integrator, scene, spp, choice, backend = key
    base = tables.get((integrator, scene, spp, baseline, "sobol"))
    if not base:
        continue
    q, se = ratio(r, base)
    rows.append([scene, integrator, spp, choice, backend, f"{float(r['mse']):.4g}", f"{q:.3f}",
                 f"{se:.3f}", r.get("best_classic", ""), r.get("mse_ratio_best_classic", ""),
                 r.get("mse_ratio_best_classic_stderr", ""), refs.get((integrator, scene), ""),
                 r.get("reference_too_noisy", ""), r["setup_seconds"],
                 f"{float(r['seconds']) / float(base['seconds']):.2f}"])
with open(os.path.join(out, "summary.csv"), "w", newline="") as f:
    w = csv.writer(f)
    w.writerow(["scene", "integrator", "spp", "lobe_choice", "backend", "mse",
                f"mse_ratio_{baseline}_sobol", "stderr", "best_classic", "mse_ratio_best_classic",
                "mse_ratio_best_classic_stderr", "reference_variance", "reference_too_noisy",
                "setup_seconds", "seconds_ratio"])
    w.writerows(rows)
for r in rows:
    print(" ".join(f"{c:>10}" for c in r))
PY
