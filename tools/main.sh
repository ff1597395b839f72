#!/usr/bin/env bash
# The main job: build, then run a small render study on the built-in default
# scene (no files needed) and print its error table.
#
# Direct lighting isolates the first-bounce estimator the backends differ in.
# The reference is a 4096-spp Halton render (the paper's reference sampler);
# every backend (the field's classic samplers, then two learned ones)
# renders at 4, 16 and 64 spp, four times with different seeds, and its MSE
# against the reference is the mean of the four. `optimized`
# serves sets optimized by Algorithm 1 for the sky's own map as distributed
# light samples, `optimized-uniform` sets optimized for the uniform target as
# primary samples; their optimization is paid once (setup_s) and reused by
# every render. The table ends with the equal-time verdict per spp: the
# backend with the lowest MSE x (render seconds + setup), ties within two
# standard errors named as ties. The study directory (CSV, images, plots, index.html, compare.html) is left
# in BUILD/study-default; `nuld study render --help` lists the knobs of the
# full studies (docs/studies.md).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-"$root/build"}
"$root/tools/build.sh" "$build"
out="$build/study-default"
rm -rf "$out"  # a fresh study: a rerun of the main job must not reuse old rows

"$build/nuld" study render default --integrator direct --res 96x64 --spp 4,16,64 \
  --repeats 4 --reference-spp 4096 \
  --backends independent,sobol,halton,sobol-tabulated,stratified,pmj02,zsobol,lattice,lattice-baker,optimized,optimized-uniform \
  --opt-instances 16 -q -o "$out"
