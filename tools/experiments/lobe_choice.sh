#!/usr/bin/env bash
# The material's own lobe choice (materials/README.md, "Lobe choice"): render
# studies of the four shipped scenes under both MIS integrators with the
# classic backends, once per --lobe-choice, 16 and 64 spp, 8 repeats, seed
# 9173 (no test uses it), 1/4 resolution. Every choice of a (scene,
# integrator) scores against the same reference (REFERENCE_SPP, default
# 4096 spp, rendered once with the default choice and copied). Writes
# OUT/CHOICE/INTEGRATOR/render.csv and OUT/summary.csv: each row's MSE
# relative to the uniform choice's sobol, with its standard error.
#
# Usage: tools/experiments/lobe_choice.sh OUT
#   CHOICES (default "uniform weight albedo"), BACKENDS (default sobol,halton),
#   SCENES, INTEGRATORS (default "direct path"), SPP (16,64), REFERENCE_SPP.
source "$(dirname "$0")/common.sh"
out=${1:?usage: lobe_choice.sh OUT}
choices=${CHOICES:-"uniform weight albedo"}
backends=${BACKENDS:-sobol,halton}
scenes=${SCENES:-"default scenes/lte-orb.json scenes/dragon.json scenes/cup.json"}
integrators=${INTEGRATORS:-"direct path"}
spp=${SPP:-16,64}
reference_spp=${REFERENCE_SPP:-4096}
mkdir -p "$out"
cd "$root"

for integrator in $integrators; do
  refs="$out/references/$integrator"
  for scene in $scenes; do
    slug=$(basename "$scene" .json)
    if [[ ! -f "$refs/$slug/reference.exr" ]]; then
      # The reference alone: a study with no cell to render.
      "$nuld" study render "$scene" --integrator "$integrator" --res-scale 0.25 --spp 1 \
        --repeats 1 --reference-spp "$reference_spp" --seed 9173 --backends sobol \
        --no-report -q -o "$refs/study" >/dev/null
      mkdir -p "$refs/$slug"
      cp "$refs/study/$slug"/reference.{exr,state} "$refs/$slug/"
    fi
    for choice in $choices; do
      dir="$out/$choice/$integrator"
      mkdir -p "$dir/$slug"
      [[ -f "$dir/$slug/reference.exr" ]] || cp "$refs/$slug"/reference.{exr,state} "$dir/$slug/"
      "$nuld" study render "$scene" --integrator "$integrator" --res-scale 0.25 --spp "$spp" \
        --repeats 8 --reference-spp "$reference_spp" --seed 9173 --backends "$backends" \
        --lobe-choice "$choice" --no-report -q -o "$dir" >/dev/null
    done
  done
done

"$python" - "$out" <<'PY'
import csv, glob, os, sys
out = sys.argv[1]
rows, tables = [], {}
for path in sorted(glob.glob(os.path.join(out, "*", "*", "render.csv"))):
    choice, integrator = path.split(os.sep)[-3:-1]
    if choice == "references":
        continue
    for r in csv.DictReader(open(path)):
        tables[(choice, integrator, r["scene"], r["backend"], r["spp"])] = r
for (choice, integrator, scene, backend, spp), r in sorted(tables.items()):
    base = tables.get(("uniform", integrator, scene, "sobol", spp))
    if not base:
        continue
    m, b = float(r["mse"]), float(base["mse"])
    ratio = m / b
    se = ratio * ((float(r["mse_stderr"]) / m) ** 2 + (float(base["mse_stderr"]) / b) ** 2) ** 0.5
    rows.append([scene, integrator, spp, choice, backend, f"{m:.4g}", f"{ratio:.3f}", f"{se:.3f}",
                 f"{float(r['seconds']) / float(base['seconds']):.2f}"])
with open(os.path.join(out, "summary.csv"), "w", newline="") as f:
    w = csv.writer(f)
    w.writerow(["scene", "integrator", "spp", "lobe_choice", "backend", "mse",
                "mse_ratio_to_uniform_sobol", "stderr", "seconds_ratio"])
    w.writerows(rows)
for r in rows:
    print(" ".join(f"{c:>10}" for c in r))
PY
