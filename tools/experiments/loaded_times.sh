#!/usr/bin/env bash
# Equal-time verdicts on a loaded machine (tools/experiments/equal_time.md,
# "Interleaved repeats on a loaded machine"): one study, same seed, run
# quiet and then twice beside a second process that spins and rests at
# random (0.3-3 s each: other work coming and going), and each row's median
# render time over sobol's, its equal-time ratio and verdict per run.
#
# Usage: tools/experiments/loaded_times.sh OUT
#   SCENE (default scenes/dragon.json), INTEGRATOR (direct), SPP (16,64),
#   BACKENDS (independent,sobol,halton,pmj02,zsobol,lattice), REPEATS (8),
#   RES_SCALE (0.25), SEED (9173).
source "$(dirname "$0")/common.sh"
out=${1:?usage: loaded_times.sh OUT}
mkdir -p "$out"
out=$(cd "$out" && pwd)
cd "$root"
study() {
  NULD_CACHE="$out/set-cache" "$nuld" study render "${SCENE:-scenes/dragon.json}" \
    --integrator "${INTEGRATOR:-direct}" --res-scale "${RES_SCALE:-0.25}" --spp "${SPP:-16,64}" \
    --repeats "${REPEATS:-8}" --seed "${SEED:-9173}" \
    --backends "${BACKENDS:-independent,sobol,halton,pmj02,zsobol,lattice}" \
    --no-report -q -o "$out/$1" >/dev/null
}
load() {
  "$python" -c '
import random, time
random.seed(11)
while True:
    end = time.time() + random.uniform(0.3, 3)
    while time.time() < end:
        pass
    time.sleep(random.uniform(0.3, 3))' >/dev/null 2>&1 &
  echo $!  # (its output elsewhere, or $(load) would wait for it)
}
study quiet
for run in loaded1 loaded2; do
  pid=$(load)
  study "$run"
  kill "$pid"
  wait "$pid" 2>/dev/null || true
done
"$python" - "$out" <<'PY'
import csv, os, sys
out = sys.argv[1]
def verdict(q, se):
    q, se = float(q), float(se)
    if not se > 0:
        return "n/a"
    return "better" if q + 2 * se < 1 else "worse" if q - 2 * se > 1 else "tie"
runs = ["quiet", "loaded1", "loaded2"]
tables = {r: list(csv.DictReader(open(os.path.join(out, r, "render.csv")))) for r in runs}
sobol = {(r, t["spp"]): float(t["seconds"]) for r in runs for t in tables[r] if t["backend"] == "sobol"}
print("| backend | spp | " + " | ".join(f"{r}: time / sobol, MSE x time / sobol" for r in runs) + " |")
print("|---|---|" + "---|" * len(runs))
for i, row in enumerate(tables["quiet"]):
    if row["backend"] == "sobol":
        continue
    cells = []
    for r in runs:
        t = tables[r][i]
        cells.append(f"{float(t['seconds']) / sobol[r, t['spp']]:.2f} (mad {float(t['seconds_mad']):.3f} s), "
                     f"{float(t['equal_time_ratio']):.3f}±{float(t['equal_time_ratio_stderr']):.3f} "
                     f"{verdict(t['equal_time_ratio'], t['equal_time_ratio_stderr'])}")
    print(f"| {row['backend']} | {row['spp']} | " + " | ".join(cells) + " |")
PY
