#!/usr/bin/env bash
# Environment-map sampling, the classic question (tools/experiments/
# README.md, "MIS-compensated map sampling"): each asset scene as shipped
# (importance by luminance) and with "importance": "luminance-compensated"
# (the map's density less its mean, so that BSDF samples cover the dim
# texels under MIS), under both MIS integrators, 16 and 64 spp, 8 repeats,
# seed 9173, 1/4 resolution, each against its own REFERENCE_SPP-spp
# reference (default 4096) whose variance the study reports.
# Writes OUT/scenes/*.json, OUT/INTEGRATOR/render.csv and OUT/summary.csv
# (compensated MSE over plain MSE per scene, integrator, spp and backend).
#
# Usage: tools/experiments/env_compensation.sh OUT
#   BACKENDS (default sobol), SCENES (the three asset scenes), INTEGRATORS, SPP, REFERENCE_SPP.
source "$(dirname "$0")/common.sh"
out=${1:?usage: env_compensation.sh OUT}
backends=${BACKENDS:-sobol}
scenes=${SCENES:-"scenes/lte-orb.json scenes/dragon.json scenes/cup.json"}
integrators=${INTEGRATORS:-"direct path"}
spp=${SPP:-16,64}
reference_spp=${REFERENCE_SPP:-4096}
mkdir -p "$out/scenes"
out=$(cd "$out" && pwd)
cd "$root"

variants=()
for scene in $scenes; do
  slug=$(basename "$scene" .json)
  "$python" - "$scene" "$out/scenes/$slug-compensated.json" <<'PY'
import json, sys
scene = json.load(open(sys.argv[1]))
scene["environment"]["importance"] = "luminance-compensated"
json.dump(scene, open(sys.argv[2], "w"), indent=1)
PY
  variants+=("$scene" "$out/scenes/$slug-compensated.json")
done

for integrator in $integrators; do
  "$nuld" study render "${variants[@]}" --integrator "$integrator" --res-scale 0.25 \
    --spp "$spp" --repeats 8 --reference-spp "$reference_spp" --seed 9173 \
    --backends "$backends" --no-report -q -o "$out/$integrator" >/dev/null
done

"$python" - "$out" <<'PY'
import csv, os, sys
out = sys.argv[1]
rows = []
for integrator in sorted(os.listdir(out)):
    path = os.path.join(out, integrator, "render.csv")
    if not os.path.isfile(path):
        continue
    table = {(r["scene"], r["backend"], r["spp"]): r for r in csv.DictReader(open(path))}
    refs = {r["scene"]: r["variance"]
            for r in csv.DictReader(open(os.path.join(out, integrator, "references.csv")))}
    for (scene, backend, spp), r in sorted(table.items()):
        if scene.endswith("-compensated"):
            continue
        c = table.get((scene + "-compensated", backend, spp))
        if not c:
            continue
        m, n = float(r["mse"]), float(c["mse"])
        se = n / m * ((float(r["mse_stderr"]) / m) ** 2 + (float(c["mse_stderr"]) / n) ** 2) ** 0.5
        rows.append([scene, integrator, backend, spp, f"{m:.4g}", f"{n:.4g}", f"{n / m:.3f}",
                     f"{se:.3f}", refs.get(scene, ""), refs.get(scene + "-compensated", "")])
with open(os.path.join(out, "summary.csv"), "w", newline="") as f:
    w = csv.writer(f)
    w.writerow(["scene", "integrator", "backend", "spp", "mse_luminance", "mse_compensated",
                "ratio", "stderr", "reference_variance_luminance",
                "reference_variance_compensated"])
    w.writerows(rows)
for r in rows:
    print(" ".join(f"{c:>10}" for c in r))
PY
