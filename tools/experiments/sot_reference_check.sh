#!/usr/bin/env bash
# Our uniform sliced optimal transport sets next to the authors' public
# implementation (Paulin et al. 2020, github.com/loispaulin/
# Sliced-Optimal-Transport-Sampling, built separately: it needs GSL and
# OpenMP, which the project does not install). Theirs optimizes in the unit
# disc and maps it to the square area-preservingly (-c); ours optimizes in
# the square directly (closed-form slab means of its projections). Both at
# their defaults (theirs 4096 batches of 32 slices, ours 1024 of 64) and
# ours also at theirs. Prints L2* and D* (means over the sets), the
# spectrum's mean radial power at frequencies 1..sqrt(N)/2 (the blue-noise
# band) and seconds per set; writes OUT/sot_reference.csv.
# Usage: sot_reference_check.sh OUT PATH/TO/sot [SETS]
source "$(dirname "$0")/common.sh"
out=${1:?output directory}
theirs=${2:?path to the reference sot binary}
sets=${3:-8}
mkdir -p "$out"
csv="$out/sot_reference.csv"
echo "generator,n,l2star,dstar,low_band_power,seconds_per_set" >"$csv"

# low_band FILE N -> mean radial power at integer frequencies 1..sqrt(N)/2
low_band() {
  "$nuld" spectrum "$1" -o "$out/spectrum.png" --csv "$out/spectrum.csv" >/dev/null 2>&1
  awk -F, -v top="$(awk -v n="$2" 'BEGIN {print sqrt(n) / 2}')" \
    'NR > 1 && $1 >= 1 && $1 <= top {s += $2; c++} END {printf "%.4g", s / c}' "$out/spectrum.csv"
}

row() {  # NAME N FILE SECONDS
  local m
  m=$(metrics "$3" uniform l2star dstar)
  echo "$1,$2,$m,$(low_band "$3" "$2"),$4" >>"$csv"
}

for n in 256 1024; do
  # The reference: one run per set (its seed), converted to a nuld text file.
  f="$out/reference_$n.txt"
  printf '# nuld-pointset: 1\n# n: %d\n# instances: %d\n# generator: reference sot\n' "$n" "$sets" >"$f"
  start=$(date +%s%N)
  for s in $(seq 1 "$sets"); do
    "$theirs" -n "$n" -d 2 -c -s "$s" --silent -o "$out/ref.dat" >/dev/null
    echo "# set $((s - 1))" >>"$f"
    cat "$out/ref.dat" >>"$f"
  done
  row reference "$n" "$f" "$(awk -v t="$(seconds_since "$start")" -v k="$sets" 'BEGIN {printf "%.2f", t / k}')"
  for variant in "ours:" "ours_4096x32:--iterations 4096 --slices 32"; do
    name=${variant%%:*}
    f="$out/${name}_$n.txt"
    start=$(date +%s%N)
    # shellcheck disable=SC2086
    "$nuld" generate --sequence sot --target uniform --n "$n" --instances "$sets" --seed 7 \
      ${variant#*:} -q -o "$f" 2>/dev/null
    row "$name" "$n" "$f" "$(awk -v t="$(seconds_since "$start")" -v k="$sets" 'BEGIN {printf "%.2f", t / k}')"
  done
done
column -s, -t "$csv"
