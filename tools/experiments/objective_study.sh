#!/usr/bin/env bash
# Algorithm 1 (soft boxes, sampled every epoch) against the exact L2asd
# objective (closed form, O(N^2) per step) on the uniform target and a grid
# (image) target: final L2asd, D* and wall time, same epochs and schedules.
# Writes OUT/objective.csv. Usage: objective_study.sh OUT [N ...]
source "$(dirname "$0")/common.sh"
out=${1:?output directory}; shift
ns=("$@"); ((${#ns[@]})) || ns=(64 256 1024)
prepare_output "$out"
csv="$out/objective.csv"
echo "target,n,objective,seconds,l2asd,dstar" >"$csv"
for spec in uniform "image:$out/test_image.pfm"; do
  name=${spec%%:*}
  for n in "${ns[@]}"; do
    for objective in soft l2asd; do
      f="$out/${name}_${n}_$objective.ptsb"
      start=$(date +%s%N)
      "$nuld" optimize --target "$spec" --n "$n" --instances 4 --seed 1 --objective "$objective" -q -o "$f" >/dev/null
      secs=$(seconds_since "$start")
      echo "$name,$n,$objective,$secs,$(l2_dstar "$f" "$spec")" >>"$csv"
    done
  done
done
column -s, -t "$csv"
