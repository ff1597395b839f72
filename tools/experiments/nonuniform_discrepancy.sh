#!/usr/bin/env bash
# Result 2 of the optimizer issue (the supplement's Fig. 4): non-uniform L2asd
# and D* against N for the bilinear, quarter-disc and image targets, of
#   sobol      Owen-Sobol mapped by the inverse CDF
#   halton     randomized Halton mapped by the inverse CDF
#   uniopt     uniformly optimized sets, then mapped (needs OUT_UNIFORM from
#              uniform_discrepancy.sh, else optimized here)
#   optimized  optimized directly for the target (density-mapped)
# Writes OUT/nonuniform.csv and OUT/nonuniform_<target>.png.
# Usage: nonuniform_discrepancy.sh OUT [UNIFORM_OUT] [N ...]
source "$(dirname "$0")/common.sh"
out=${1:?output directory}
uniform=${2:-}
shift $(($# >= 2 ? 2 : 1))
ns=("$@"); ((${#ns[@]})) || ns=(16 32 64 128 256 512 1024)
prepare_output "$out"
targets=("bilinear:0.2,1,1,3" quarterdisc "image:$out/test_image.pfm")
names=(bilinear quarterdisc image)
csv="$out/nonuniform.csv"
echo "n,target,sampler,l2asd,dstar" >"$csv"
for n in "${ns[@]}"; do
  k=16; ((n >= 1024)) && k=8
  uni="$uniform/optimized_$n.ptsb"
  if [[ -z "$uniform" || ! -f "$uni" ]]; then
    uni="$out/uniopt_$n.ptsb"
    [[ -f "$uni" ]] || "$nuld" optimize --target uniform --n "$n" --instances "$k" --seed 2 -q -o "$uni" >/dev/null
  fi
  for t in 0 1 2; do
    spec=${targets[$t]} name=${names[$t]}
    "$nuld" generate --sequence sobol --n "$n" --instances 16 --seed 1 --target "$spec" -o "$out/sobol_${name}_$n.ptsb" 2>/dev/null
    "$nuld" generate --sequence halton --n "$n" --instances 16 --seed 1 --target "$spec" -o "$out/halton_${name}_$n.ptsb" 2>/dev/null
    "$nuld" map "$uni" --target "$spec" -o "$out/uniopt_${name}_$n.ptsb" 2>/dev/null
    "$nuld" optimize --target "$spec" --n "$n" --instances "$k" --seed 1 -q -o "$out/optimized_${name}_$n.ptsb" >/dev/null
    for s in sobol halton uniopt optimized; do
      echo "$n,$name,$s,$(l2_dstar "$out/${s}_${name}_$n.ptsb" "$spec")" >>"$csv"
    done
  done
  echo "N = $n done" >&2
done
for name in "${names[@]}"; do
  "$python" - "$csv" "$name" "$out/nonuniform_$name.csv" <<'PY'
import csv, sys
rows = [r for r in csv.DictReader(open(sys.argv[1])) if r["target"] == sys.argv[2]]
with open(sys.argv[3], "w") as f:
    w = csv.DictWriter(f, fieldnames=["n", "sampler", "l2asd", "dstar"])
    w.writeheader()
    for r in rows:
        w.writerow({k: r[k] for k in w.fieldnames})
PY
  "$python" "$root/tools/experiments/plot_discrepancy.py" "$out/nonuniform_$name.csv" \
    "$out/nonuniform_$name.png" --title "$name target"
done
"$python" "$root/tools/experiments/ratio_table.py" "$csv" optimized sobol
