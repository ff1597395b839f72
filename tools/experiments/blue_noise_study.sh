#!/usr/bin/env bash
# The seed's blue-noise baselines next to Owen-Sobol and our optimized sets
# (the supplement's Fig. 2, issue 20): integration error against N for
# Gaussian x step and quarter-disc x bilinear in 2D and envmap x cos on the
# sphere, for sliced optimal transport and Gaussian blue noise optimized for
# the target (sot, gbn) and optimized uniformly then mapped (sot-mapped,
# gbn-mapped); bias and its standard error are columns of integrate.csv.
# The direct optimizer's row runs up to N 256 (OUT/integrate); the larger N
# (BIG, default 1024) compare the others only (OUT/integrate_big: 16 direct
# sets of 1024 points per target take about an hour on 2 cores).
# Then per generator at N = 256 and 1024 on the quarter-disc: grid L2, D*
# and generation time per set (OUT/discrepancy.csv), and on the uniform
# square the spectrum's mean radial power in the blue-noise band, integer
# frequencies 1 .. sqrt(N)/2 (OUT/spectra.csv; random points give 1).
# Usage: blue_noise_study.sh OUT [NS [INSTANCES [ASSETS [BIG]]]]
# Defaults: N 16,64,256, 16 sets per N, BIG 1024 (empty: skip). About
# half an hour on 2 cores.
source "$(dirname "$0")/common.sh"
out=${1:?output directory}
ns=${2:-16,64,256}
instances=${3:-16}
assets=${4:-${NULD_ASSETS:-$root/../shared/assets}}
big=${5-1024}
mkdir -p "$out"
study() {  # DIR NS SAMPLERS
  "$nuld" study integrate -o "$1" --integrands 'gaussian*step,quarterdisc*bilinear,envmap*cos' \
    --envmaps grace --assets "$assets" --n "$2" --instances 128 --optimized-instances "$instances" \
    --optimized-max-n 4096 --samplers "$3" -q
}
study "$out/integrate" "$ns" sobol,optimized,sot,sot-mapped,gbn,gbn-mapped
[[ -z $big ]] || study "$out/integrate_big" "$big" sobol,sot,sot-mapped,gbn,gbn-mapped

csv="$out/discrepancy.csv"
echo "generator,n,l2asd,dstar,seconds_per_set" >"$csv"
for n in 256 1024; do
  for g in sot sot-mapped gbn gbn-mapped sobol; do
    f="$out/qd_${g}_$n.ptsb"
    start=$(date +%s%N)
    "$nuld" generate --sequence "$g" --target quarterdisc --n "$n" --instances 4 --seed 7 -q \
      -o "$f" 2>/dev/null
    secs=$(awk -v t="$(seconds_since "$start")" 'BEGIN {printf "%.3f", t / 4}')
    echo "$g,$n,$(l2_dstar "$f" quarterdisc),$secs" >>"$csv"
  done
done
column -s, -t "$csv"

spectra="$out/spectra.csv"
echo "generator,n,low_band_power" >"$spectra"
for n in 256 1024; do
  for g in sobol sot gbn independent; do
    f="$out/uniform_${g}_$n.ptsb"
    if [[ $g == independent ]]; then
      "$nuld" generate --sequence random --n "$n" --instances 16 --seed 7 -o "$f" 2>/dev/null
    else
      "$nuld" generate --sequence "$g" --n "$n" --instances 16 --seed 7 -q -o "$f" 2>/dev/null
    fi
    "$nuld" spectrum "$f" -o "$out/spectrum_${g}_$n.png" --csv "$out/spectrum_${g}_$n.csv" >/dev/null 2>&1
    awk -F, -v g="$g" -v n="$n" 'NR > 1 && $1 >= 1 && $1 <= sqrt(n) / 2 {s += $2; c++}
      END {printf "%s,%d,%.4g\n", g, n, s / c}' "$out/spectrum_${g}_$n.csv" >>"$spectra"
  done
done
column -s, -t "$spectra"
