#!/usr/bin/env bash
# Renders are bit-identical between two builds (a refactor's before and
# after): every shipped scene, every render word and both integrators, small
# and few-sample, compared pixel for pixel with oiiotool --diff --fail 0.
# The learned words' sets come from one set cache both builds share (made by
# the first, found by the second), so only the renderer and the backends are
# compared.
#
# Usage: tools/experiments/identical_renders.sh BEFORE_NULD AFTER_NULD OUT
#   SCENES (default "default dragon cup lte-orb"), ASSETS (../shared/assets),
#   WORDS (default every render word).
set -uo pipefail
before=${1:?usage: identical_renders.sh BEFORE_NULD AFTER_NULD OUT} after=${2:?} out=${3:?}
root=$(cd "$(dirname "$0")/../.." && pwd)
assets=${ASSETS:-$root/../shared/assets}
mkdir -p "$out/before" "$out/after"
export NULD_CACHE="$out/cache"
"$after" generate --sequence sobol --n 4 --instances 3 -o "$out/uniform4.txt" >/dev/null
words=${WORDS:-"independent independent-tabulated sobol sobol-tabulated halton halton-tabulated
  stratified pmj02 zsobol lattice lattice-baker optimized optimized-uniform optimized-bsdf optimized-both
  optimized+shift optimized:$out/uniform4.txt shifted:$out/uniform4.txt neural
  plugin:$(dirname "$after")/libnuld_example_sampler.so"}
sets=(--opt-instances 2 --opt-epochs 5 --opt-lobe-epochs 5)
compared=0 differ=0 refused=0
for scene in ${SCENES:-default dragon cup lte-orb}; do
  file=$scene
  [[ $scene == default ]] || file=$root/scenes/$scene.json
  for integrator in direct path; do
    for word in $words; do
      name=$(printf %s "$scene-$integrator-$word" | tr -c 'A-Za-z0-9_.+-' '_')
      args=(render "$file" --backend "$word" --integrator "$integrator" --res 48 --spp 4 --seed 3 -q)
      [[ $scene == default ]] || args+=(--assets "$assets")
      [[ $word == optimized* && $word != optimized:* ]] && args+=("${sets[@]}")
      if ! "$before" "${args[@]}" -o "$out/before/$name.exr" >"$out/before/$name.log" 2>&1; then
        # A word the scene cannot use (no map, no Disney material) is
        # refused by both builds alike.
        "$after" "${args[@]}" -o "$out/after/$name.exr" >"$out/after/$name.log" 2>&1 &&
          { echo "DIFFER $name: refused before, rendered after"; differ=$((differ + 1)); }
        refused=$((refused + 1))
        continue
      fi
      "$after" "${args[@]}" -o "$out/after/$name.exr" >"$out/after/$name.log" 2>&1 ||
        { echo "DIFFER $name: rendered before, refused after"; differ=$((differ + 1)); continue; }
      compared=$((compared + 1))
      if ! oiiotool --diff --fail 0 --warn 0 "$out/before/$name.exr" "$out/after/$name.exr" >/dev/null 2>&1; then
        echo "DIFFER $name"; differ=$((differ + 1))
      fi
    done
  done
done
echo "$compared renders compared, $differ differ, $refused refused by both"
exit $((differ > 0))
