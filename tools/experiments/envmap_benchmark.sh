#!/usr/bin/env bash
# The optimizer's performance benchmark: one 2048-point instance for
# envmap:grace_latlong.exr on the sphere, 16384 boxes, 5000 epochs, with exact
# mass (our default) and with the paper's Monte Carlo mass (65536 space
# samples), side by side in one run: wall time, peak memory, final L2asd and D*.
# Usage: envmap_benchmark.sh OUT [ASSET_ROOT]
source "$(dirname "$0")/common.sh"
out=${1:?output directory}
assets=${2:-${NULD_ASSETS:-"$root/../shared/assets"}}
map="$assets/envmaps/grace_latlong.exr"
[[ -f "$map" ]] || { echo "missing $map (pass the asset root)" >&2; exit 1; }
mkdir -p "$out"
csv="$out/envmap_benchmark.csv"
echo "mass,seconds,peak_mb,l2asd,dstar" >"$csv"
# Algorithm 1 with exact and with MC mass, then (not the benchmark's
# setting, for comparison) the exact L2asd objective with the same schedule.
for variant in sphere sphere-mc exact-objective; do
  f="$out/grace_$variant.ptsb"
  args=(--preset sphere)
  [[ $variant == sphere-mc ]] && args=(--preset sphere-mc)
  [[ $variant == exact-objective ]] && args=(--preset sphere --objective l2asd)
  /usr/bin/time -f "%e %M" -o "$out/time_$variant.txt" \
    "$nuld" optimize --target "envmap:$map" --n 2048 "${args[@]}" --seed 1 -q -o "$f" >/dev/null
  read -r secs kb <"$out/time_$variant.txt"
  mass=exact; [[ $variant == sphere-mc ]] && mass=mc:65536
  [[ $variant == exact-objective ]] && mass="exact L2asd objective"
  echo "$mass,$secs,$((kb / 1024)),$(l2_dstar "$f" "envmap:$map")" >>"$csv"
done
"$nuld" generate --sequence sobol --n 2048 --instances 16 --seed 1 --target "envmap:$map" -o "$out/grace_sobol.ptsb" 2>/dev/null
echo "sobol+icdf (16 instances),0,0,$(l2_dstar "$out/grace_sobol.ptsb" "envmap:$map")" >>"$csv"
column -s, -t "$csv"
