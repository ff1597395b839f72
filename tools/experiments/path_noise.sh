#!/usr/bin/env bash
# Path noise (README.md in this folder, "Path noise"): the seed-to-seed pixel variance of path
# traced renders at 64 spp (Owen-Sobol), with the time per render, for a
# Lambertian and a Disney sphere on a floor under beach and for the dragon
# and cup. The variance is half the mean squared difference of two renders,
# averaged over two pairs (four seeds). With REF_SPP set, each scene also
# gets a reference from this build at REF_SPP samples (seed 1000), and the
# mean squared error of the 64-spp renders against it (noise and any bias).
# Usage: [REF_SPP=S] path_noise.sh OUT [OTHER_NULD]   (OTHER_NULD: a second
# binary, e.g. an older build, measured the same way beside this one)
source "$(dirname "$0")/common.sh"
out=${1:?output directory}
mkdir -p "$out"
assets=${NULD_ASSETS:-"$root/../shared/assets"}
binaries=("$nuld")
[[ -n "${2:-}" ]] && binaries+=("$2")
scenes=("$root/tools/experiments/path_noise/lambertian_sphere.json:--res 256x192"
        "$root/tools/experiments/path_noise/disney_sphere.json:--res 256x192"
        "$root/scenes/dragon.json:" "$root/scenes/cup.json:")
echo "binary,scene,variance,mse_vs_reference,seconds_per_render"
if [[ -n "${REF_SPP:-}" ]]; then
  for entry in "${scenes[@]}"; do
    scene=${entry%%:*} res=${entry#*:} name=$(basename "$scene" .json)
    [[ -f "$out/reference_$name.exr" ]] && continue
    # shellcheck disable=SC2086
    "$nuld" render "$scene" --assets "$assets" --backend sobol --seed 1000 --spp "$REF_SPP" $res -q \
      -o "$out/reference_$name.exr" >/dev/null
  done
fi
for b in "${binaries[@]}"; do
  tag=$(echo "$b" | md5sum | cut -c1-8)
  for entry in "${scenes[@]}"; do
    scene=${entry%%:*} res=${entry#*:} name=$(basename "$scene" .json)
    total=0 mse=0
    for seed in 1 2 3 4; do
      # shellcheck disable=SC2086
      s=$("$b" render "$scene" --assets "$assets" --backend sobol --seed "$seed" --spp 64 $res -q \
            -o "$out/${tag}_${name}_$seed.exr" | awk '/^seconds/{print $2}')
      total=$($python -c "print($total + $s)")
      if [[ -n "${REF_SPP:-}" ]]; then
        m=$("$nuld" compare "$out/${tag}_${name}_$seed.exr" "$out/reference_$name.exr" \
          --error-map "$out/e.png" | awk '/^mse/{print $2}')
        mse=$($python -c "print($mse + $m / 4)")
      fi
    done
    a=$("$nuld" compare "$out/${tag}_${name}_1.exr" "$out/${tag}_${name}_2.exr" --error-map "$out/e.png" | awk '/^mse/{print $2}')
    c=$("$nuld" compare "$out/${tag}_${name}_3.exr" "$out/${tag}_${name}_4.exr" --error-map "$out/e.png" | awk '/^mse/{print $2}')
    $python -c "print('$b,$name,%.4g,%s,%.3f' % (($a + $c) / 4, ('%.4g' % $mse) if '${REF_SPP:-}' else '', $total / 4))"
  done
done
