#!/usr/bin/env bash
# Studies that can tell (tools/experiments/studies_that_tell.md):
#  1. the reference cache: a four-scene sweep (1/4 resolution, 16 spp, 4
#     repeats, 4096-spp references) run twice, the second with other
#     backends, into an empty reference cache and into the one the first
#     filled; the wall time of each study;
#  2. repeats until the verdict: the cup and the dragon under path, 1/4
#     resolution, 16 spp, sobol, sobol-tabulated and optimized, 4 repeats
#     first, --target-stderr 0.05, --max-repeats 64, seed 2027 (no test uses
#     it): the repeats each row took and why it stopped.
# Usage: tools/experiments/studies_that_tell.sh OUT
#   PARTS (default "1 2"), SCENES, INTEGRATOR (part 1, default direct),
#   REFERENCE_SPP (default 4096)
source "$(dirname "$0")/common.sh"
out=${1:?usage: studies_that_tell.sh OUT}
mkdir -p "$out"
out=$(cd "$out" && pwd)
cd "$root"
scenes=${SCENES:-"default scenes/lte-orb.json scenes/dragon.json scenes/cup.json"}
refspp=${REFERENCE_SPP:-4096}
export NULD_CACHE="$out/set-cache"

timed() { # timed LABEL COMMAND...: appends "LABEL,seconds" to OUT/times.csv
  local label=$1 start
  shift
  start=$(date +%s%N)
  "$@" >"$out/$label.log" 2>&1 || { echo "$label failed:"; tail -5 "$out/$label.log"; exit 1; }
  echo "$label,$(seconds_since "$start")" >>"$out/times.csv"
}

if [[ " ${PARTS:-1 2} " == *" 1 "* ]]; then
  echo "study,seconds" >"$out/times.csv"
  sweep() { # sweep LABEL REFERENCE_CACHE BACKENDS
    # shellcheck disable=SC2086  # scenes are words
    NULD_REFERENCE_CACHE="$2" timed "$1" "$nuld" study render $scenes \
      --integrator "${INTEGRATOR:-direct}" --res-scale 0.25 --spp 16 --repeats 4 --seed 2027 \
      --reference-spp "$refspp" --backends "$3" --no-report -q -o "$out/$1"
  }
  sweep first "$out/references" sobol,halton
  sweep second_warm "$out/references" independent,sobol-tabulated,zsobol
  sweep second_cold "$out/references-cold" independent,sobol-tabulated,zsobol
  cat "$out/times.csv"
  for study in first second_warm second_cold; do
    echo "$study: $(awk -F, 'NR > 1 {printf "%s %s s (%s); ", $1, $8, $11}' "$out/$study/references.csv")"
  done
fi

if [[ " ${PARTS:-1 2} " == *" 2 "* ]]; then
  for scene in cup dragon; do
    NULD_REFERENCE_CACHE="$out/references" timed "adaptive_$scene" "$nuld" study render \
      "scenes/$scene.json" --integrator path --res-scale 0.25 --spp 16 --repeats 4 --seed 2027 \
      --reference-spp "$refspp" --backends sobol,sobol-tabulated,optimized --target-stderr 0.05 \
      --max-repeats 64 --no-report -o "$out/adaptive_$scene"
    "$python" - "$out/adaptive_$scene/render.csv" "$scene" <<'PY'
import csv, sys
for r in csv.DictReader(open(sys.argv[1])):
    print(f"{sys.argv[2]:7s} {r['backend']:16s} repeats {r['repeats']:>3s} stopped on {r['stopped_on']:9s}"
          f" worst relative stderr {float(r['worst_relative_stderr']):.3f}"
          f" mse/classic {r['mse_ratio_best_classic']} +- {r['mse_ratio_best_classic_stderr']}"
          f" winsorized/classic {r['winsorized_ratio_best_classic']} outliers {r['ruled_by_outliers'] or '-'}"
          f" top_share {float(r['top_share']):.3f}")
PY
  done
fi
