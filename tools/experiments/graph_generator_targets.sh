#!/usr/bin/env bash
# The graph generator with the Owen base on issue 19's three targets, as
# integration error against Owen-Sobol + inverse CDF and the direct
# optimizer (tools/experiments/graph_generator_log.md, session 2): the
# quarter-disc (quarterdisc*bilinear), grace_latlong.exr (envmap*cos,
# mapped and unmapped on the sphere) and the Disney lobe family
# (disney*cosines at 20, 45 and 70 degrees, gamma never a training one).
# The direct optimizer: its preset (soft boxes) on the quarter-disc, the
# exact L2asd objective with the bank term on the grid targets (map, lobe
# tables), as the studies build them. Each model: C's schedule (discrepancy gradient, 4 stages, lr 1e-3 ->
# 1e-5), STEPS steps. Writes OUT/<target>_<n>/integrate.csv per row and
# prints the tables; train times land in OUT/train_seconds.csv.
# Usage: graph_generator_targets.sh OUT [N [STEPS [ASSETS]]]
# Defaults: N 64, 1500 steps; about 5-8 minutes per model on 2 cores at N 64.
source "$(dirname "$0")/common.sh"
out=${1:?output directory}
n=${2:-64}
steps=${3:-1500}
assets=${4:-${NULD_ASSETS:-$root/../shared/assets}}
grace="$assets/envmaps/grace_latlong.exr"
mkdir -p "$out"
flags=(--arch graph --base owen --discrepancy-gradient --stages 4 --lr 1e-3 --lr-end 1e-5
  --seed 1 -q)
times="$out/train_seconds.csv"
[[ -f "$times" ]] || echo "model,n,train_seconds" >"$times"

train() {  # NAME TARGET STEPS [extra flags...]
  local name=$1 target=$2 count=$3
  shift 3
  local model="$out/${name}_$n.nuldnet"
  [[ -f "$model" ]] && return
  local start
  start=$(date +%s%N)
  "$nuld" train --target "$target" --n "$n" --steps "$count" "${flags[@]}" "$@" -o "$model" >/dev/null
  echo "$name,$n,$(seconds_since "$start")" >>"$times"
}

study() {  # DIR INTEGRANDS OBJECTIVE MODELS...
  local dir=$1 integrands=$2 objective=$3
  shift 3
  local samplers=sobol,optimized
  [[ $integrands == disney* ]] && samplers+=",sobol-tabulated"
  for m in "$@"; do samplers+=",neural:$m"; done
  "$nuld" study integrate -o "$dir" --integrands "$integrands" --n "$n" --samplers "$samplers" \
    --optimized-instances 64 --opt-objective "$objective" --envmaps "$grace" --assets "$assets" \
    --no-plots -q
}

train quarterdisc quarterdisc "$steps"
study "$out/quarterdisc_$n" 'quarterdisc*bilinear' soft "$out/quarterdisc_$n.nuldnet"
train grace "envmap:$grace" "$steps"
train grace_unmapped "envmap:$grace" "$steps" --mapping unmapped
study "$out/grace_$n" 'envmap*cos' l2asd "$out/grace_$n.nuldnet" "$out/grace_unmapped_$n.nuldnet"
# The lobe family tabulates a table per gamma: a third of the steps (each
# about 5x dearer).
train disney family:disney $((steps / 3))
study "$out/disney_$n" 'disney*cosines' l2asd "$out/disney_$n.nuldnet"
column -s, -t "$times"
