#!/usr/bin/env bash
# The optimizer's performance benchmark: one 2048-point instance for
# envmap:grace_latlong.exr on the sphere, 16384 boxes, 5000 epochs, with exact
# mass (our default) and with the paper's Monte Carlo mass (65536 space
# samples), side by side in one run: wall time, peak memory, final L2asd and D*.
# Final discrepancies vary a lot from seed to seed, so the quality comparison
# repeats every variant for each seed and reports means and ranges.
# Usage: envmap_benchmark.sh OUT [ASSET_ROOT] [SEEDS (default "1 2 3 4")]
source "$(dirname "$0")/common.sh"
out=${1:?output directory}
assets=${2:-${NULD_ASSETS:-"$root/../shared/assets"}}
seeds=${3:-"1 2 3 4"}
map="$assets/envmaps/grace_latlong.exr"
[[ -f "$map" ]] || { echo "missing $map (pass the asset root)" >&2; exit 1; }
mkdir -p "$out"
csv="$out/envmap_benchmark.csv"
echo "mass,seed,seconds,peak_mb,l2asd,dstar" >"$csv"
# Algorithm 1 with exact and with MC mass, then (not the benchmark's
# setting, for comparison) the exact L2asd objective with the same schedule.
# Seeds are the outer loop so that each seed's variants run side by side.
for seed in $seeds; do
  for variant in sphere sphere-mc exact-objective; do
    f="$out/grace_${variant}_$seed.ptsb"
    args=(--preset sphere)
    [[ $variant == sphere-mc ]] && args=(--preset sphere-mc)
    [[ $variant == exact-objective ]] && args=(--preset sphere --objective l2asd)
    /usr/bin/time -f "%e %M" -o "$out/time_$variant.txt" \
      "$nuld" optimize --target "envmap:$map" --n 2048 "${args[@]}" --seed "$seed" -q -o "$f" >/dev/null
    read -r secs kb <"$out/time_$variant.txt"
    mass=exact; [[ $variant == sphere-mc ]] && mass=mc:65536
    [[ $variant == exact-objective ]] && mass="exact L2asd objective"
    echo "$mass,$seed,$secs,$((kb / 1024)),$(l2_dstar "$f" "envmap:$map")" >>"$csv"
  done
done
"$nuld" generate --sequence sobol --n 2048 --instances 16 --seed 1 --target "envmap:$map" -o "$out/grace_sobol.ptsb" 2>/dev/null
echo "sobol+icdf (16 instances),-,0,0,$(l2_dstar "$out/grace_sobol.ptsb" "envmap:$map")" >>"$csv"
column -s, -t "$csv"
# Per variant: mean and range over the seeds.
summary="$out/envmap_benchmark_summary.csv"
summarize_runs "$csv" mass >"$summary"
echo
column -s, -t "$summary"
