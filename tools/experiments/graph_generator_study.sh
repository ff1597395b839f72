#!/usr/bin/env bash
# The graph generator against the baselines at unseen offsets (README.md in
# this folder, "The graph generator"): Owen-Sobol + inverse CDF, the direct optimizer, sets
# optimized for the periodic L2 discrepancy then Cranley-Patterson shifted
# and mapped (`optimize --objective l2per`, `map --shifts`), and one trained
# graph network per variant. Every row scores 16 sets (seed 7, never a
# training offset) against the target: grid L2, D* and the mean set
# distance (distinct sets score near Owen-Sobol's). Writes OUT/graph.csv.
# Usage: graph_generator_study.sh OUT [TARGET [N [STEPS]]]
# Defaults: quarterdisc, N 64, 1500 steps (about 3 minutes per variant on
# 2 cores at N 64).
source "$(dirname "$0")/common.sh"
out=${1:?output directory}
target=${2:-quarterdisc}
n=${3:-64}
steps=${4:-1500}
# name|train flags
variants=(
  "graph|--arch graph"
  "graph+gradient,2 stages|--arch graph --discrepancy-gradient --stages 2"
  "graph+gradient,4 stages,lr 1e-3|--arch graph --discrepancy-gradient --stages 4 --lr 1e-3 --lr-end 1e-5"
)
mkdir -p "$out"
csv="$out/graph.csv"
echo "sampler,n,train_seconds,l2asd,dstar,set_distance" >"$csv"
distance() { "$nuld" eval "$1" --target "$target" --metric l2 --set-distance | awk '$1 == "set_distance" {print $2}'; }
row() { echo "\"$1\",$n,$2,$(l2_dstar "$3" "$target"),$(distance "$3")" >>"$csv"; }

f="$out/owen_sobol_$n.txt"
"$nuld" generate --sequence sobol --scramble owen --target "$target" --n "$n" --instances 16 \
  --seed 7 -o "$f" 2>/dev/null
row owen-sobol "" "$f"
f="$out/direct_$n.txt"
start=$(date +%s%N)
"$nuld" optimize --target "$target" --n "$n" --instances 16 --seed 7 -q -o "$f" >/dev/null
row direct "$(seconds_since "$start")" "$f"
f="$out/periodic_$n.txt"
start=$(date +%s%N)
"$nuld" optimize --target uniform --n "$n" --objective l2per --epochs 2000 --lr 1e-2 --lr-end 1e-6 \
  --instances 4 --seed 3 -q -o "$out/periodic_uniform_$n.txt" >/dev/null
"$nuld" map "$out/periodic_uniform_$n.txt" --target "$target" --shifts 4 --seed 7 -o "$f" 2>/dev/null
row "periodic (l2per + shifts)" "$(seconds_since "$start")" "$f"

i=0
for v in "${variants[@]}"; do
  name=${v%%|*}
  read -r -a flags <<<"${v#*|}"
  model="$out/graph_${n}_$i.nuldnet"
  start=$(date +%s%N)
  "$nuld" train --target "$target" --n "$n" --steps "$steps" --seed 1 "${flags[@]}" -q \
    -o "$model" >/dev/null
  secs=$(seconds_since "$start")
  f="${model%.nuldnet}_16.txt"
  "$nuld" generate --model "$model" --instances 16 --seed 7 -o "$f" 2>/dev/null
  row "$name" "$secs" "$f"
  i=$((i + 1))
done
column -s, -t "$csv"
