#!/usr/bin/env bash
# How much a trained graph generator's quality hangs on its training seed:
# the documented command (tools/experiments/neural_generator.md, "The graph
# generator": discrepancy gradient, 4 stages, Owen base, lr 1e-3 -> 1e-5,
# 1500 steps) on grace_latlong.exr at N = 64 with seeds 0..K-1, each model
# scored as issue 19 scored it: envmap*cos integration MSE at offsets no
# training saw (the study's own seed), relative to Owen-Sobol + inverse
# CDF, over 512 sets of each model (1024 Owen-Sobol randomizations). Writes
# OUT/seed_S.nuldnet, OUT/train_seconds.csv and OUT/study/.
# Usage: [LR=1e-3] training_seeds.sh OUT [SEEDS [STEPS [ASSETS]]]
# (defaults 5 seeds, 1500 steps); about 5 minutes per model on 2 cores.
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
    "$nuld" train --arch graph --base owen --discrepancy-gradient --stages 4 --lr "${LR:-1e-3}" --lr-end 1e-5 \
      --target "envmap:$grace" --n 64 --steps "$steps" --seed "$s" -q -o "$model" >/dev/null
    echo "$s,$(seconds_since "$start")" >>"$times"
  fi
  samplers+=",neural:$model"
done
"$nuld" study integrate -o "$out/study" --integrands 'envmap*cos' --n 64 --samplers "$samplers" \
  --envmaps "$grace" --assets "$assets" --instances 1024 --optimized-instances 512 --no-plots -q
# Each model's MSE over Owen-Sobol's with its standard error, and the step
# whose weights --keep best kept (0: the untrained net).
"$python" - "$out" <<'PY'
import csv, sys
out = sys.argv[1]
rows = list(csv.DictReader(open(f"{out}/study/integrate.csv")))
base = next(r for r in rows if r["sampler"] == "sobol")
ms, se_s = float(base["rmse"]) ** 2, float(base["mse_stderr"])
for r in rows:
    if r["sampler"] == "sobol":
        continue
    m, se = float(r["rmse"]) ** 2, float(r["mse_stderr"])
    q = m / ms
    qse = q * ((se / m) ** 2 + (se_s / ms) ** 2) ** 0.5
    model = r["sampler"].split(":", 1)[1]  # the model file's stem
    v = [(float(x["validation_l2"]), int(x["step"]))
         for x in csv.DictReader(open(f"{out}/{model}.nuldnet.validation.csv"))]
    best = min(v)
    print(f"{model}: MSE/Owen-Sobol {q:.3f} +- {qse:.3f}; kept step {best[1]} "
          f"(held-out L2 {best[0]:.4f}, untrained {v[0][0]:.4f}, last {v[-1][0]:.4f})")
PY
