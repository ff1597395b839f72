#!/usr/bin/env bash
# Result 4 of the optimizer issue: exact box mass against the supplement's
# Monte Carlo mass (K = 2^17 space samples, its 4K-box setting), final
# discrepancy and wall time, side by side. Writes OUT/mass.csv.
# Usage: mass_study.sh OUT [N ...]
source "$(dirname "$0")/common.sh"
out=${1:?output directory}; shift
ns=("$@"); ((${#ns[@]})) || ns=(256 1024)
prepare_output "$out"
csv="$out/mass.csv"
echo "target,n,mass,boxes,seconds,l2asd,dstar" >"$csv"
for spec in quarterdisc "image:$out/test_image.pfm"; do
  name=${spec%%:*}
  for n in "${ns[@]}"; do
    for preset in nonuniform nonuniform-mc; do
      f="$out/${name}_${n}_$preset.ptsb"
      start=$(date +%s%N)
      "$nuld" optimize --target "$spec" --n "$n" --instances 4 --seed 1 --preset "$preset" -q -o "$f" >/dev/null
      secs=$(seconds_since "$start")
      mass=exact; boxes=$( ((n >= 2048)) && echo 32768 || echo 8192)
      [[ $preset == nonuniform-mc ]] && { mass=mc:131072; ((n < 2048)) && boxes=4096; }
      echo "$name,$n,$mass,$boxes,$secs,$(l2_dstar "$f" "$spec")" >>"$csv"
    done
  done
done
column -s, -t "$csv"
