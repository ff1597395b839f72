#!/usr/bin/env bash
# A render study's CSV is the same between two builds (a refactor's before
# and after) row for row, but for the columns that measure time: a tiny
# study of the default scene with classic, learned and neural rows, run by
# each build into its own folder with one shared set cache (the image paths
# differ by that folder and are left out too).
#
# Usage: tools/experiments/identical_studies.sh BEFORE_NULD AFTER_NULD OUT
set -uo pipefail
before=${1:?usage: identical_studies.sh BEFORE_NULD AFTER_NULD OUT} after=${2:?} out=${3:?}
mkdir -p "$out"
export NULD_CACHE="$out/cache"
args=(study render default --backends sobol,pmj02,zsobol,optimized,optimized-bsdf,neural
  --spp 4,16 --repeats 3 --res 32 --reference-spp 64 --opt-instances 2 --opt-epochs 5
  --opt-lobe-epochs 5 --no-report -q)
"$before" "${args[@]}" -o "$out/before" >"$out/before.log" 2>&1 || { echo "before failed"; exit 1; }
"$after" "${args[@]}" -o "$out/after" >"$out/after.log" 2>&1 || { echo "after failed"; exit 1; }
/usr/bin/python3 - "$out/before/render.csv" "$out/after/render.csv" <<'PY'
import csv, sys
timed = ("seconds", "rays_per_second", "equal_time", "break_even", "total_seconds", "setup")
def rows(path):
    table = list(csv.DictReader(open(path)))
    # The time columns, and the files' paths (each build writes its own folder).
    return [{k: v for k, v in r.items() if not any(t in k for t in timed)
             and k not in ("image", "error_map")} for r in table]
a, b = rows(sys.argv[1]), rows(sys.argv[2])
differ = [(x, y) for x, y in zip(a, b) if x != y]
print(f"{len(a)} rows before, {len(b)} after, {len(differ)} differ outside the time columns")
for x, y in differ[:5]:
    print({k: (x[k], y.get(k)) for k in x if x[k] != y.get(k)})
sys.exit(1 if differ or len(a) != len(b) else 0)
PY
