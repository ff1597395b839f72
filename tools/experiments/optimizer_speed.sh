#!/usr/bin/env bash
# The optimizer against another build of it, side by side: the 2048-point
# sphere-preset instance on grace_latlong.exr (2048 points, 16384 boxes,
# 5000 epochs, exact mass) and 16 instances at N = 64, each seed run by both
# binaries one after the other so that machine load affects both alike.
# Wall time, peak memory, and the final L2asd and D* of every run; then means
# and ranges per binary. Usage:
#   optimizer_speed.sh OUT OLD_NULD [ASSET_ROOT] [SEEDS (default "1 2 3 4")]
source "$(dirname "$0")/common.sh"
out=${1:?output directory}
old=${2:?the other nuld binary}
assets=${3:-${NULD_ASSETS:-"$root/../shared/assets"}}
seeds=${4:-"1 2 3 4"}
map="$assets/envmaps/grace_latlong.exr"
[[ -f "$map" ]] || { echo "missing $map (pass the asset root)" >&2; exit 1; }
[[ -x "$old" ]] || { echo "not an executable: $old" >&2; exit 1; }
mkdir -p "$out"
csv="$out/optimizer_speed.csv"
echo "run,binary,seed,seconds,peak_mb,l2asd,dstar" >"$csv"
for seed in $seeds; do
  for run in "n2048:--n 2048" "n64x16:--n 64 --instances 16"; do
    name=${run%%:*}
    read -r -a args <<<"${run#*:}"
    for which in old new; do
      bin=$nuld
      [[ $which == old ]] && bin=$old
      f="$out/${name}_${which}_$seed.ptsb"
      /usr/bin/time -f "%e %M" -o "$out/time.txt" \
        "$bin" optimize --target "envmap:$map" "${args[@]}" --preset sphere --seed "$seed" -q -o "$f" >/dev/null
      read -r secs kb <"$out/time.txt"
      echo "$name,$which,$seed,$secs,$((kb / 1024)),$(l2_dstar "$f" "envmap:$map")" >>"$csv"
    done
  done
done
column -s, -t "$csv"
echo
summarize_runs "$csv" run,binary | tee "$out/optimizer_speed_summary.csv" | column -s, -t
