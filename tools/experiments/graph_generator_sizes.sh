#!/usr/bin/env bash
# One graph model for several N (issue 19): the quarter-disc generator trained
# at N 64 alone and at N 32, 64 and 128 in turn (one size per step), each
# then asked for sets of N 16 ... 256, trained sizes and not. Reports the
# integration error on quarterdisc*bilinear against Owen-Sobol + inverse CDF
# (OUT/integrate/integrate.csv, 64 sets per N), grid L2 / D* of 16 sets per N
# at unseen offsets (OUT/discrepancy.csv), training seconds, and the
# inference time per set up to N 2048 (OUT/inference.csv).
# Usage: graph_generator_sizes.sh OUT [STEPS]
# Defaults: 1500 steps (C's schedule of the log); about 5 minutes per model
# on 2 cores.
source "$(dirname "$0")/common.sh"
out=${1:?output directory}
steps=${2:-1500}
mkdir -p "$out"
flags=(--arch graph --base owen --discrepancy-gradient --stages 4 --lr 1e-3 --lr-end 1e-5
  --seed 1 --target quarterdisc --steps "$steps" -q)
times="$out/train_seconds.csv"
echo "model,training_n,train_seconds" >"$times"
for spec in single:64 several:32,64,128; do
  name=${spec%%:*} sizes=${spec#*:}
  model="$out/$name.nuldnet"
  start=$(date +%s%N)
  [[ -f "$model" ]] || "$nuld" train --n "$sizes" "${flags[@]}" -o "$model" >/dev/null
  echo "$name,\"$sizes\",$(seconds_since "$start")" >>"$times"
done

"$nuld" study integrate -o "$out/integrate" --integrands 'quarterdisc*bilinear' \
  --n 16,32,64,128,256 --samplers sobol,neural:"$out/single.nuldnet",neural:"$out/several.nuldnet" \
  --optimized-instances 64 --no-plots -q

csv="$out/discrepancy.csv"
echo "sampler,n,l2asd,dstar" >"$csv"
for n in 16 32 64 128 256; do
  "$nuld" generate --sequence sobol --target quarterdisc --n "$n" --instances 16 --seed 7 \
    -o "$out/sobol_$n.txt" 2>/dev/null
  echo "sobol,$n,$(l2_dstar "$out/sobol_$n.txt" quarterdisc)" >>"$csv"
  for name in single several; do
    "$nuld" generate --model "$out/$name.nuldnet" --n "$n" --instances 16 --seed 7 \
      -o "$out/${name}_$n.txt" 2>/dev/null
    echo "$name,$n,$(l2_dstar "$out/${name}_$n.txt" quarterdisc)" >>"$csv"
  done
done

inference="$out/inference.csv"
echo "n,ms_per_set" >"$inference"
for n in 64 256 1024 2048; do
  start=$(date +%s%N)
  "$nuld" generate --model "$out/several.nuldnet" --n "$n" --instances 8 --seed 3 \
    -o "$out/timing.txt" 2>/dev/null
  awk -v t="$(seconds_since "$start")" -v n="$n" 'BEGIN {printf "%d,%.1f\n", n, t * 1000 / 8}' \
    >>"$inference"
done
column -s, -t "$times"
column -s, -t "$csv"
column -s, -t "$inference"
