#!/usr/bin/env bash
# The main job: build, then compare the sampler backends on the built-in
# default scene (no files needed) and print an error table.
#
# Direct lighting isolates the first-bounce estimator the backends differ in.
# The reference is a 4096-spp Sobol render; each backend renders at 4, 16 and
# 64 spp and is compared with `nuld compare` (MSE and relMSE over pixels and
# RGB channels). `optimized-uniform` serves sets optimized by Algorithm 1 for
# the uniform target as the first bounce's primary samples (one set per pixel
# and pair under a random toroidal shift); its optimization time is printed
# separately, because it is paid once and reused by every render.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-"$root/build"}
"$root/tools/build.sh" "$build"
nuld="$build/nuld"
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT

res=96x64
common=(default --integrator direct --res $res -q)
now() { date +%s%N; }
seconds() { awk -v ns=$(($(now) - $1)) 'BEGIN {printf "%.2f", ns / 1e9}'; }

echo "reference: default scene, $res, direct lighting, 4096 spp (Sobol, seed 1000) ..."
"$nuld" render "${common[@]}" --spp 4096 --backend sobol --seed 1000 -o "$out/ref.exr" >/dev/null

opt_time=()
for spp in 16 64; do
  t=$(now)
  "$nuld" optimize --target uniform --n $spp --instances 8 --epochs 1000 --seed 1 -q \
    -o "$out/uniform_$spp.ptsb" >/dev/null
  opt_time+=("N=$spp: $(seconds "$t") s")
done

printf '\n%-18s %5s %12s %12s %9s\n' backend spp mse relmse seconds
for backend in independent sobol halton optimized-uniform; do
  for spp in 4 16 64; do
    name=$backend
    if [[ $backend == optimized-uniform ]]; then
      [[ $spp == 4 ]] && continue
      name="optimized:$out/uniform_$spp.ptsb"
    fi
    t=$(now)
    "$nuld" render "${common[@]}" --spp $spp --backend "$name" --seed 1 -o "$out/img.exr" >/dev/null
    secs=$(seconds "$t")
    read -r mse relmse < <("$nuld" compare "$out/img.exr" "$out/ref.exr" \
      --error-map "$out/err.png" | awk '{v[$1]=$2} END {print v["mse"], v["relmse"]}')
    printf '%-18s %5s %12.4e %12.4e %9s\n' "$backend" $spp "$mse" "$relmse" "$secs"
  done
done
echo "(one render per row against the reference; lower is better. Optimization of the"
echo " uniform sets, paid once: ${opt_time[*]}.)"
