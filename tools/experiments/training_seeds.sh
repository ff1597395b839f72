#!/usr/bin/env bash
# How much a trained graph generator's quality hangs on its training seed:
# the documented command (tools/experiments/neural_generator.md, "The graph
# generator": discrepancy gradient, 4 stages, Owen base, lr 1e-3 -> 1e-5,
# 1500 steps) on grace_latlong.exr at N = 64 with seeds 0..K-1, each model
# scored as issue 19 scored it: envmap*cos integration MSE at offsets no
# training saw (the study's own seed), relative to Owen-Sobol + inverse
# CDF. Writes OUT/seed_S.nuldnet, OUT/train_seconds.csv and OUT/study/.
# Usage: training_seeds.sh OUT [SEEDS [STEPS [ASSETS]]]   (defaults 5, 1500)
# About 5 minutes per model on 2 cores.
source "$(dirname "$0")/common.sh"
out=${1:?output directory}
seeds=${2:-5}
steps=${3:-1500}
assets=${4:-${NULD_ASSETS:-$root/../shared/assets}}
grace="$assets/envmaps/grace_latlong.exr"
mkdir -p "$out"
times="$out/train_seconds.csv"
[[ -f "$times" ]] || echo "seed,train_seconds" >"$times"
samplers=sobol
for ((s = 0; s < seeds; ++s)); do
  model="$out/seed_$s.nuldnet"
  if [[ ! -f "$model" ]]; then
    start=$(date +%s%N)
    "$nuld" train --arch graph --base owen --discrepancy-gradient --stages 4 --lr 1e-3 --lr-end 1e-5 \
      --target "envmap:$grace" --n 64 --steps "$steps" --seed "$s" -q -o "$model" >/dev/null
    echo "$s,$(seconds_since "$start")" >>"$times"
  fi
  samplers+=",neural:$model"
done
"$nuld" study integrate -o "$out/study" --integrands 'envmap*cos' --n 64 --samplers "$samplers" \
  --envmaps "$grace" --assets "$assets" --no-plots -q
