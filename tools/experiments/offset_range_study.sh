#!/usr/bin/env bash
# Neural sets against the range of offsets one network must cover (README.md
# in this folder, "Torus harmonics and offset ranges"): trains the supplement's network on the
# quarter-disc with offsets restricted to [0, R)^2 (`nuld train
# --offset-range R`) for each R, and scores 16 sets at unseen z against the
# direct optimizer and Owen-Sobol + inverse CDF at the same N. The set
# distance column shows when the network collapses to one set. Writes
# OUT/offset_range.csv (one row per sampler; training seconds for the nets).
# Usage: offset_range_study.sh OUT [N [HIDDEN [STEPS [R ...]]]]
# Defaults: N 256, hidden 1024, 3000 steps, R = 1/256 1/64 1/16 1/8 1/4 1
# (about 2.5 minutes per R on 2 cores at these defaults).
source "$(dirname "$0")/common.sh"
out=${1:?output directory}
n=${2:-256}
hidden=${3:-1024}
steps=${4:-3000}
shift $(($# < 4 ? $# : 4))
ranges=("$@"); ((${#ranges[@]})) || ranges=(0.00390625 0.015625 0.0625 0.125 0.25 1)
target=quarterdisc
mkdir -p "$out"
csv="$out/offset_range.csv"
echo "sampler,n,hidden,offset_range,train_seconds,l2asd,dstar,set_distance" >"$csv"
distance() { "$nuld" eval "$1" --target "$target" --metric l2 --set-distance | awk '$1 == "set_distance" {print $2}'; }

f="$out/direct_$n.txt"
"$nuld" optimize --target "$target" --n "$n" --instances 16 --seed 7 -q -o "$f" >/dev/null
echo "direct,$n,,,,$(l2_dstar "$f" "$target"),$(distance "$f")" >>"$csv"
f="$out/owen_sobol_$n.txt"
"$nuld" generate --sequence sobol --scramble owen --target "$target" --n "$n" --instances 16 \
  --seed 7 -o "$f" 2>/dev/null
echo "owen-sobol,$n,,,,$(l2_dstar "$f" "$target"),$(distance "$f")" >>"$csv"

for r in "${ranges[@]}"; do
  model="$out/neural_${n}_h${hidden}_r$r.nuldnet"
  start=$(date +%s%N)
  "$nuld" train --target "$target" --n "$n" --hidden "$hidden" --steps "$steps" --seed 1 \
    --offset-range "$r" -q -o "$model" >/dev/null
  secs=$(seconds_since "$start")
  f="${model%.nuldnet}_16.txt"
  "$nuld" generate --model "$model" --instances 16 --seed 7 -o "$f" 2>/dev/null
  echo "neural,$n,$hidden,$r,$secs,$(l2_dstar "$f" "$target"),$(distance "$f")" >>"$csv"
done
column -s, -t "$csv"
