#!/usr/bin/env bash
# The field's classic samplers as rows (tools/experiments/classic_samplers.md):
# render studies of the shipped scenes with every classic word, MSE and the
# screen-space error (the error image low-passed by a 1-pixel Gaussian), at
# 4 and 16 spp by default; then the integration study's 2D integrands with
# sobol, pmj02, stratified, lattice and lattice-baker at N = 16 to 1024.
#
# Writes OUT/SCENE-INTEGRATOR/render.csv (one study each) and
# OUT/integrate/integrate.csv.
#
# Usage: tools/experiments/classic_samplers.sh OUT
#   SCENES (default "default scenes/dragon.json scenes/cup.json scenes/lte-orb.json"),
#   INTEGRATORS (default "direct path"), SPP (4,16), REPEATS (8), SEED (7717: no test
#   uses it), REFERENCE_SPP (4096), RES_SCALE (0.25 for the asset scenes),
#   BACKENDS (default every classic word), PARTS ("render integrate").
source "$(dirname "$0")/common.sh"
out=${1:?usage: classic_samplers.sh OUT}
scenes=${SCENES:-"default scenes/dragon.json scenes/cup.json scenes/lte-orb.json"}
integrators=${INTEGRATORS:-"direct path"}
backends=${BACKENDS:-sobol,sobol-tabulated,halton,stratified,pmj02,zsobol,lattice,lattice-baker,independent}
parts=${PARTS:-"render integrate"}
mkdir -p "$out"
cd "$root"

if [[ " $parts " == *" render "* ]]; then
  for scene in $scenes; do
    name=$(basename "$scene" .json)
    # The built-in scene is small already; the asset scenes at RES_SCALE.
    scale=()
    [[ $scene == default ]] || scale=(--res-scale "${RES_SCALE:-0.25}")
    for integrator in $integrators; do
      "$nuld" study render "$scene" "${scale[@]}" --integrator "$integrator" \
        --spp "${SPP:-4,16}" --repeats "${REPEATS:-8}" --seed "${SEED:-7717}" \
        --reference-spp "${REFERENCE_SPP:-4096}" --backends "$backends" --no-report -q \
        -o "$out/$name-$integrator" >"$out/$name-$integrator.txt"
    done
  done
fi

if [[ " $parts " == *" integrate "* ]]; then
  "$nuld" study integrate --integrands 'gaussian*step,quarterdisc*bilinear' \
    --samplers sobol,pmj02,stratified,lattice,lattice-baker,halton,independent --n 16,64,256,1024 \
    --instances 64 --seed "${SEED:-7717}" --no-plots -q -o "$out/integrate" \
    >"$out/integrate.txt"
fi
