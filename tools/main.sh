#!/usr/bin/env bash
# The main job: build, then compare the sampler backends and print an error
# table. Until the renderer lands this compares point sets (discrepancy of
# inverse-CDF-mapped baselines and of directly optimized sets), not renders.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-"$root/build"}
"$root/tools/build.sh" "$build"
nuld="$build/nuld"
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
n=256
instances=16
printf '%-10s %-16s %12s %12s %12s\n' target backend l2star l2asd dstar
for target in uniform quarterdisc "bilinear:1,2,0.5,3"; do
  for backend in "random none" "sobol owen" "halton owen"; do
    set -- $backend
    "$nuld" generate --sequence "$1" --scramble "$2" --n $n --instances $instances --seed 1 \
      --target "$target" -o "$out/p.txt" 2>/dev/null
    vals=$("$nuld" eval "$out/p.txt" --metric all | awk '{v[$1]=$2} END {printf "%12.3e %12.3e %12.3e", v["l2star"], v["l2asd"], v["dstar"]}')
    printf '%-10s %-16s %s\n' "${target%%:*}" "$1+$2" "$vals"
  done
  # Algorithm 1 with the supplement's preset for the target (4 instances).
  "$nuld" optimize --target "$target" --n $n --instances 4 --seed 1 -q -o "$out/o.ptsb" >/dev/null
  vals=$("$nuld" eval "$out/o.ptsb" --metric all | awk '{v[$1]=$2} END {printf "%12.3e %12.3e %12.3e", v["l2star"], v["l2asd"], v["dstar"]}')
  printf '%-10s %-16s %s\n' "${target%%:*}" "optimized" "$vals"
done
echo "(N = $n, means over $instances instances, 4 for optimized; lower is better)"
