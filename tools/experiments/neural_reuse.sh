#!/usr/bin/env bash
# Neural lobe banks from an empty and from a warm set cache
# (tools/experiments/neural_lobe_model.md, "Neural banks across processes"): per
# scene and integrator, two studies of sobol, sobol-tabulated and neural with
# one NULD_CACHE, the second in a new process; prints each row's render seconds
# over sobol's. 1/4 resolution, 16 and 64 spp, 8 repeats, seed 9173. The
# second study copies the first one's reference (its seconds do not depend
# on it).
#
# Usage: tools/experiments/neural_reuse.sh OUT
#   SCENES (default: the four shipped scenes), INTEGRATORS (default "direct path"),
#   REFERENCE_SPP (default 4096)
source "$(dirname "$0")/common.sh"
out=${1:?usage: neural_reuse.sh OUT}
scenes=${SCENES:-"scenes/dragon.json scenes/lte-orb.json scenes/cup.json default"}
integrators=${INTEGRATORS:-"direct path"}
mkdir -p "$out"
out=$(cd "$out" && pwd)
cd "$root"
for scene in $scenes; do
  slug=$(basename "$scene" .json)
  for integrator in $integrators; do
    cell="$out/$slug-$integrator"
    for run in cold warm; do
      NULD_CACHE="$cell/cache" "$nuld" study render "$scene" --integrator "$integrator" \
        --res-scale 0.25 --spp 16,64 --repeats 8 --reference-spp "${REFERENCE_SPP:-4096}" \
        --seed 9173 --backends sobol,sobol-tabulated,neural --no-report -q -o "$cell/$run" >/dev/null
      "$python" - "$cell/$run/render.csv" "$slug $integrator $run" <<'PY'
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
sobol = {r["spp"]: float(r["seconds"]) for r in rows if r["backend"] == "sobol"}
print(sys.argv[2], " ".join(f"{r['backend']}@{r['spp']} {float(r['seconds']) / sobol[r['spp']]:.2f}"
                            for r in rows if r["backend"] != "sobol"))
PY
    done
  done
done
