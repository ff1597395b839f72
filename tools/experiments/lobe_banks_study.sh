#!/usr/bin/env bash
# Learned sets for BSDF sampling (README.md in this folder,
# "BSDF sampling"):
#  1. integration: the supplement's Disney lobe at theta_o = 20, 45, 70
#     degrees against a smooth light (disney*cosines) and against HDR maps
#     (disney*envmap at 45, disney-views*envmap at 20 and 70 degrees), N = 16
#     and 64: Owen-Sobol through the tabulated inverse CDF (sobol-tabulated;
#     `sobol` in the log, which predates the rename), through the
#     lobe-selection mapping (sobol, the paper's baseline; `sobol-lobes` in
#     the log) and
#     direct-optimized sets (exact L2asd objective with the bank term, weight
#     3: the studies' default), 128 instances each;
#  2. renders: dragon and cup at 1/4 resolution, 16 and 64 spp, 8 repeats,
#     with --integrator bsdf (sobol, sobol-tabulated, optimized-bsdf: lobe
#     tables of f cos) and --integrator direct (sobol, sobol-tabulated,
#     optimized, optimized-both: tables of the materials' sampling pdf).
# Banks without the bank term (the first measurements): add
# --opt-union-weight 0 to both studies; tables of f cos under MIS (section 7
# of the log): add --lobe-mix 0 to the direct renders.
# Usage: lobe_banks_study.sh OUT [REFERENCE_SPP [REPEATS]]
# Defaults: 2048-spp references, 8 repeats (about an hour on 2 cores).
source "$(dirname "$0")/common.sh"
out=${1:?output directory}
refspp=${2:-2048}
repeats=${3:-8}
mkdir -p "$out"
"$nuld" study integrate --integrands 'disney*cosines,disney*envmap,disney-views*envmap' --envmaps grace,beach \
  --samplers sobol,sobol-tabulated,optimized --n 16,64 --opt-objective l2asd \
  --optimized-instances 128 --no-plots -o "$out/integrate"
for scene in dragon cup; do
  "$nuld" study render "$root/scenes/$scene.json" --res-scale 0.25 --spp 16,64 --repeats "$repeats" \
    --reference-spp "$refspp" --integrator bsdf --backends sobol,sobol-tabulated,optimized-bsdf \
    --no-report -o "$out/${scene}_bsdf"
  "$nuld" study render "$root/scenes/$scene.json" --res-scale 0.25 --spp 16,64 --repeats "$repeats" \
    --reference-spp "$refspp" --integrator direct \
    --backends sobol,sobol-tabulated,optimized,optimized-both --no-report -o "$out/${scene}_direct"
done
