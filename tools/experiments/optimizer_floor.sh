#!/usr/bin/env bash
# What the 2048-point sphere-preset instance on grace_latlong.exr (16384
# boxes, 5000 epochs, exact mass) costs at the least with today's
# arithmetic: its band pairs (band_pairs.cpp) at the loss kernel's rate when
# every pair is in the band (bench_sampler, alpha 20, where per-box work is
# negligible), plus the epochs' box sampling and exact masses
# (bench_sampler), against one full run timed alongside. Everything else a
# run does (the grid queries, interior counts and gradient scatter of 82
# million box visits, the inverse CDF, Adam) is what remains. Usage:
#   optimizer_floor.sh OUT [ASSET_ROOT] [SEED (default 1)]
source "$(dirname "$0")/common.sh"
out=${1:?output directory}
assets=${2:-${NULD_ASSETS:-"$root/../shared/assets"}}
seed=${3:-1}
map="$assets/envmaps/grace_latlong.exr"
bench="$root/build/tests/bench_sampler"
[[ -f "$map" ]] || { echo "missing $map (pass the asset root)" >&2; exit 1; }
[[ -x "$bench" ]] || { echo "build first: tools/build.sh (needs $bench)" >&2; exit 1; }
mkdir -p "$out"
c++ -O2 -std=c++20 -o "$out/band_pairs" "$root/tools/experiments/band_pairs.cpp"

# The points the loss sees: the mapped Owen-Sobol start and an optimized end.
"$nuld" generate --sequence sobol --n 2048 --seed "$seed" --target "envmap:$map" \
  -o "$out/sobol.txt" >/dev/null
start=$(date +%s%N)
"$nuld" optimize --target "envmap:$map" --n 2048 --preset sphere --seed "$seed" -q \
  -o "$out/optimized.txt" >/dev/null
run_s=$(seconds_since "$start")
for set in sobol optimized; do
  "$out/band_pairs" "$out/$set.txt" >"$out/band_pairs_$set.csv"
done
pairs() { awk -F, '$1 == "total_band_pairs" {print $2}' "$out/band_pairs_$1.csv"; }

# Medians of 3: milliseconds per epoch.
(cd "$root/build" && "$bench" \
  --benchmark_filter='BM_SoftBoxLossEnvmap/20|BM_BoxSamplingAndExactMassEnvmap' \
  --benchmark_repetitions=3 --benchmark_report_aggregates_only=true \
  --benchmark_format=csv 2>/dev/null) >"$out/bench.csv"
median_ms() { awk -F, -v n="\"$1/real_time_median\"" '$1 == n {print $3}' "$out/bench.csv"; }
epoch20_ms=$(median_ms BM_SoftBoxLossEnvmap/20)
mass_ms=$(median_ms BM_BoxSamplingAndExactMassEnvmap/16384)

awk -v run="$run_s" -v e20="$epoch20_ms" -v mass="$mass_ms" \
  -v ps="$(pairs sobol)" -v po="$(pairs optimized)" 'BEGIN {
  rate = 2048 * 16384 / ((e20 - mass) / 1000)  # band pairs per second, all in
  pairs = (ps > po ? ps : po)
  tp = pairs / rate; tm = mass / 1000 * 5000
  printf "quantity,value\n"
  printf "band pairs (mapped Owen-Sobol start),%.3g\n", ps
  printf "band pairs (optimized end),%.3g\n", po
  printf "loss kernel rate at alpha 20 (pairs/s),%.3g\n", rate
  printf "box sampling and exact mass per epoch (ms),%.3f\n", mass
  printf "floor: band pairs at that rate (s),%.1f\n", tp
  printf "floor: sampling and mass over 5000 epochs (s),%.1f\n", tm
  printf "floor: sum (s),%.1f\n", tp + tm
  printf "full run alongside (s),%.1f\n", run
  printf "left to everything else in a 10 s run (s),%.1f\n", 10 - tp - tm
  printf "everything else in the run alongside (s),%.1f\n", run - tp - tm
}' | tee "$out/optimizer_floor.csv" | column -s, -t
