#!/usr/bin/env bash
# Result 1 of the optimizer issue: uniform 2D discrepancy against N of
#   sobol      Owen-scrambled Sobol          halton  randomized (Owen) Halton
#   optimized  Algorithm 1 (soft boxes)      exact   the exact L2asd objective
# Writes OUT/uniform.csv and OUT/uniform.png; point sets already in OUT are
# reused, so an interrupted run continues. Usage: uniform_discrepancy.sh OUT [N ...]
source "$(dirname "$0")/common.sh"
out=${1:?output directory}; shift
ns=("$@"); ((${#ns[@]})) || ns=(16 32 64 128 256 512 1024 2048 4096)
mkdir -p "$out"
csv="$out/uniform.csv"
echo "n,sampler,l2star,l2asd,dstar" >"$csv"
for n in "${ns[@]}"; do
  # 16 instances of the baselines; fewer optimized ones where they cost minutes.
  k=16; ((n >= 1024)) && k=8; ((n >= 2048)) && k=4
  [[ -f "$out/sobol_$n.ptsb" ]] ||
    "$nuld" generate --sequence sobol --scramble owen --n "$n" --instances 16 --seed 1 -o "$out/sobol_$n.ptsb" 2>/dev/null
  [[ -f "$out/halton_$n.ptsb" ]] ||
    "$nuld" generate --sequence halton --scramble owen --n "$n" --instances 16 --seed 1 -o "$out/halton_$n.ptsb" 2>/dev/null
  [[ -f "$out/optimized_$n.ptsb" ]] ||
    "$nuld" optimize --target uniform --n "$n" --instances "$k" --seed 1 -o "$out/optimized_$n.ptsb" >/dev/null
  [[ -f "$out/exact_$n.ptsb" ]] ||
    "$nuld" optimize --target uniform --n "$n" --instances "$k" --seed 1 --objective l2asd -q -o "$out/exact_$n.ptsb" >/dev/null
  for s in sobol halton optimized exact; do
    echo "$n,$s,$(metrics "$out/${s}_$n.ptsb" uniform l2star l2asd dstar)" >>"$csv"
  done
  echo "N = $n done" >&2
done
"$python" "$root/tools/experiments/plot_discrepancy.py" "$csv" "$out/uniform.png" --title "uniform target"
"$python" "$root/tools/experiments/ratio_table.py" "$csv" optimized sobol
"$python" "$root/tools/experiments/ratio_table.py" "$csv" exact sobol
