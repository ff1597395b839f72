#!/usr/bin/env bash
# Environment-map sampling, the classic question (tools/experiments/
# env_compensation.md): every scene with its map
# sampled by plain luminance (--env-importance luminance) and by luminance
# less its mean (luminance-compensated, the default: BSDF samples cover the
# dim texels under MIS), under both MIS integrators, 16 and 64 spp, 8
# repeats, seed 9173, 1/4 resolution, each study against its own
# REFERENCE_SPP-spp reference (default 4096) whose variance it reports.
# Writes OUT/IMPORTANCE/INTEGRATOR/render.csv and OUT/summary.csv
# (compensated MSE over plain MSE per scene, integrator, spp and backend).
#
# Usage: tools/experiments/env_compensation.sh OUT
#   BACKENDS (default sobol), SCENES (the four shipped scenes), INTEGRATORS, SPP, REFERENCE_SPP.
source "$(dirname "$0")/common.sh"
out=${1:?usage: env_compensation.sh OUT}
backends=${BACKENDS:-sobol}
scenes=${SCENES:-"scenes/lte-orb.json scenes/dragon.json scenes/cup.json default"}
integrators=${INTEGRATORS:-"direct path"}
spp=${SPP:-16,64}
reference_spp=${REFERENCE_SPP:-4096}
mkdir -p "$out"
out=$(cd "$out" && pwd)
cd "$root"

for importance in luminance luminance-compensated; do
  for integrator in $integrators; do
    # shellcheck disable=SC2086 # SCENES is a list
    "$nuld" study render $scenes --integrator "$integrator" --res-scale 0.25 \
      --env-importance "$importance" --spp "$spp" --repeats 8 \
      --reference-spp "$reference_spp" --seed 9173 --backends "$backends" --no-report -q \
      -o "$out/$importance/$integrator" >/dev/null
  done
done

"$python" - "$out" <<'PY'
import csv, os, sys
out = sys.argv[1]
def table(importance, integrator, name):
    path = os.path.join(out, importance, integrator, name)
    return list(csv.DictReader(open(path))) if os.path.isfile(path) else []
rows = []
for integrator in sorted(os.listdir(os.path.join(out, "luminance"))):
    plain = {(r["scene"], r["backend"], r["spp"]): r
             for r in table("luminance", integrator, "render.csv")}
    comp = {(r["scene"], r["backend"], r["spp"]): r
            for r in table("luminance-compensated", integrator, "render.csv")}
    refs = {imp: {r["scene"]: r["variance"] for r in table(imp, integrator, "references.csv")}
            for imp in ("luminance", "luminance-compensated")}
    for key, r in sorted(plain.items()):
        c = comp.get(key)
        if not c:
            continue
        scene, backend, spp = key
        m, n = float(r["mse"]), float(c["mse"])
        se = n / m * ((float(r["mse_stderr"]) / m) ** 2 + (float(c["mse_stderr"]) / n) ** 2) ** 0.5
        rows.append([scene, integrator, backend, spp, f"{m:.4g}", f"{n:.4g}", f"{n / m:.3f}",
                     f"{se:.3f}", refs["luminance"].get(scene, ""),
                     refs["luminance-compensated"].get(scene, "")])
with open(os.path.join(out, "summary.csv"), "w", newline="") as f:
    w = csv.writer(f)
    w.writerow(["scene", "integrator", "backend", "spp", "mse_luminance", "mse_compensated",
                "ratio", "stderr", "reference_variance_luminance",
                "reference_variance_compensated"])
    w.writerows(rows)
for r in rows:
    print(" ".join(f"{c:>10}" for c in r))
PY
