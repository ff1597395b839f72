#!/usr/bin/env bash
# Cross-checks nuld against Blender's Cycles on the scenes in scenes/ (README.md
# here): renders each with both renderers at SPP samples and SEEDS seeds
# (default 2), and prints per-channel mean ratios (nuld / Cycles), the pixel
# RMS of their difference against what the seed-to-seed noise alone gives,
# and nuld's noise over Cycles' (overall, per channel, and its bootstrap 5-95 %
# range over the seeds). Blender is an optional dependency: --install
# installs Debian's package; nothing else in the project installs it.
# A SCENE is a scene file or nuld's built-in `cornell` or `veach-mis`, which
# cycles_render.py rebuilds from the same numbers, or `gltf`: a scene made
# in Blender (gltf_blender.py), rendered by Cycles and exported by Blender's
# glTF exporter, which nuld renders as a glTF scene.
# Usage: [SEEDS=K] tools/crosscheck/crosscheck.sh [--install] OUT [SPP] [SCENE.json|cornell|veach-mis|gltf...]
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
if [[ "${1:-}" == "--install" ]]; then
  shift
  command -v blender >/dev/null || { apt-get update -q && apt-get install -y --no-install-recommends blender; }
fi
out=${1:?usage: crosscheck.sh [--install] OUT [SPP] [SCENE.json...]}
spp=${2:-1024}
shift $(( $# >= 2 ? 2 : 1 ))
scenes=("$@")
[[ ${#scenes[@]} -gt 0 ]] || scenes=("$here"/scenes/*.json)
command -v blender >/dev/null || { echo "crosscheck: blender not found; run with --install (Debian's blender package)" >&2; exit 1; }
nuld=${NULD:-"$root/build/nuld"}
[[ -x "$nuld" ]] || { echo "crosscheck: build nuld first (tools/build.sh) or set NULD" >&2; exit 1; }
assets=${NULD_ASSETS:-"$root/../shared/assets"}
seeds=${SEEDS:-2}  # renders per renderer and scene; more pin the noise ratio down
[[ $seeds =~ ^[0-9]+$ && $seeds -ge 2 ]] || { echo "crosscheck: SEEDS must be an integer >= 2" >&2; exit 1; }
mkdir -p "$out"
echo "scene,nuld_r,nuld_g,nuld_b,cycles_r,cycles_g,cycles_b,ratio_r,ratio_g,ratio_b,rms_difference,rms_noise,noise_ratio,noise_ratio_r,noise_ratio_g,noise_ratio_b,noise_ratio_5pct,noise_ratio_95pct,nuld_seconds,cycles_seconds"
for scene in "${scenes[@]}"; do
  name=$(basename "$scene" .json)
  asset_flag=(--assets "$assets")  # the built-in scenes need none
  case $scene in cornell | veach-mis | gltf) asset_flag=() ;; *.json) ;; *) echo "crosscheck: $scene: expected a .json scene file, cornell, veach-mis or gltf" >&2; exit 1 ;; esac
  nsec=0 csec=0
  for seed in $(seq 1 "$seeds"); do
    # Cycles first: for `gltf` it writes the file nuld renders.
    t0=$(date +%s.%N)
    if [[ $scene == gltf ]]; then
      blender -b --factory-startup -P "$here/gltf_blender.py" -- "$out/gltf_scene.glb" \
        "$out/${name}_cycles_$seed.exr" "$spp" "$seed" >"$out/${name}_cycles_$seed.log" 2>&1
    else
      blender -b --factory-startup -P "$here/cycles_render.py" -- "$scene" "$assets" \
        "$out/${name}_cycles_$seed.exr" "$spp" "$seed" >"$out/${name}_cycles_$seed.log" 2>&1
    fi || { echo "crosscheck: Cycles failed on $scene; see $out/${name}_cycles_$seed.log" >&2; exit 1; }
    t1=$(date +%s.%N)
    input=$scene
    [[ $scene == gltf ]] && input="$out/gltf_scene.glb"
    "$nuld" render "$input" "${asset_flag[@]}" --spp "$spp" --seed "$seed" --backend sobol -q \
      -o "$out/${name}_nuld_$seed.exr" >/dev/null
    t2=$(date +%s.%N)
    csec=$(python3 -c "print($csec + $t1 - $t0)") nsec=$(python3 -c "print($nsec + $t2 - $t1)")
  done
  files=()
  for r in nuld cycles; do
    for seed in $(seq 1 "$seeds"); do files+=("$out/${name}_${r}_$seed.exr"); done
  done
  row=$(blender -b --factory-startup -P "$here/compare.py" -- "$name" "$seeds" "${files[@]}" 2>&1 |
    sed -n 's/^ROW,//p')
  [[ -n "$row" ]] || { echo "crosscheck: comparing $name failed" >&2; exit 1; }
  echo "$row,$(python3 -c "print('%.2f,%.2f' % ($nsec / $seeds, $csec / $seeds))")"
done
