#!/usr/bin/env bash
# Your own sampler as a row (tools/experiments/own_sampler.md): the example
# plugin (plugins/v1/example_independent.c, `independent` with another hash)
# against `independent` on the default scene under direct and path; then,
# from Python, scipy.stats.qmc engines dealt as one stream against
# per-pixel `sobol` on the dragon at 1/4 resolution (nuld.study), and the
# engines' render time against sobol's.
#
# Usage: tools/experiments/own_sampler.sh OUT
#   REPEATS (48 for the plugin, 8 for the engines), SEED (2027: no test uses it).
source "$(dirname "$0")/common.sh"
out=${1:?usage: own_sampler.sh OUT}
mkdir -p "$out"
cd "$root"
build=$(dirname "$nuld")
plugin=$build/libnuld_example_sampler.so
for integrator in direct path; do
  "$nuld" study render default --backends "independent,plugin:$plugin" --spp 4 \
    --repeats "${REPEATS:-48}" --integrator "$integrator" --seed "${SEED:-2027}" \
    --reference-spp 1024 --no-report -q -o "$out/plugin-$integrator"
done
PYTHONPATH=$build/python /usr/bin/python3 - "$out" "${SEED:-2027}" <<'PY'
import sys, time
from scipy.stats import qmc
import nuld
out, seed = sys.argv[1], int(sys.argv[2])
table = nuld.study("scenes/dragon.json", resolution_scale=0.25, spp=(16, 64), repeats=8, seed=seed,
                   rows={"sobol": "sobol",
                         "scipy-sobol": lambda s: qmc.Sobol(d=2, scramble=True, seed=s),
                         "scipy-halton": lambda s: qmc.Halton(d=2, scramble=True, seed=s)})
print(table)
table.to_csv(f"{out}/engines-dragon.csv")
PY
