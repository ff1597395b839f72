#!/usr/bin/env bash
# The seed's blue-noise baselines next to Owen-Sobol and our optimized sets
# (the supplement's Fig. 2, issue 20): integration error against N for
# Gaussian x step and quarter-disc x bilinear in 2D and envmap x cos on the
# sphere, for sliced optimal transport and Gaussian blue noise optimized for
# the target (sot, gbn) and optimized uniformly then mapped (sot-mapped,
# gbn-mapped); bias and its standard error are columns of integrate.csv.
# Then discrepancy (grid L2, D*) and generation time per set of each
# generator at N = 256 and 1024 on the quarter-disc (OUT/discrepancy.csv).
# Usage: blue_noise_study.sh OUT [NS [INSTANCES [ASSETS]]]
# Defaults: N 16,64,256,1024, 16 sets per N. Minutes per N up to 256; N
# 1024 takes about an hour on 2 cores (the direct optimizer dominates).
source "$(dirname "$0")/common.sh"
out=${1:?output directory}
ns=${2:-16,64,256,1024}
instances=${3:-16}
assets=${4:-${NULD_ASSETS:-$root/../shared/assets}}
mkdir -p "$out"
"$nuld" study integrate -o "$out/integrate" --integrands 'gaussian*step,quarterdisc*bilinear,envmap*cos' \
  --envmaps grace --assets "$assets" --n "$ns" --instances 128 --optimized-instances "$instances" \
  --samplers sobol,optimized,sot,sot-mapped,gbn,gbn-mapped

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
