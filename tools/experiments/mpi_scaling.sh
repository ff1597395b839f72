#!/usr/bin/env bash
# MPI scaling on this machine (backends/ranks.h): the wall time of a
# reference render (the lte-orb scene at 1/4 resolution, 16 passes) and of
# an optimization bank (16 sphere-preset sets of 64 points for grace, 1000
# epochs), run as one process (every core, TBB threads) and as 1, 2 and 4
# ranks (mpirun binds 1 and 2 ranks to a core each; 4 share the cores,
# oversubscribed, to show the overhead). Efficiency against one rank on one
# core: T(1 rank) / (cores used x T(K ranks)).
#
# Then, from one pass of each paper scene at full resolution, the cost of a
# sample (core-seconds per path sample) and the wall time the paper's
# references (2^17 spp lte-orb, 2^13 dragon, 2^16 cup) would take on 64 and
# 512 cores at the 2-rank efficiency measured here.
# Usage: mpi_scaling.sh OUT [ASSET_ROOT]
source "$(dirname "$0")/common.sh"
out=${1:?output directory}
assets=${2:-${NULD_ASSETS:-"$root/../shared/assets"}}
export NULD_ASSETS=$assets
mkdir -p "$out"
mpirun=(mpirun)
[[ $(id -u) -eq 0 ]] && mpirun+=(--allow-run-as-root)
cores=$(nproc)

# wall_time CSV_PREFIX COMMAND... : appends "PREFIX,seconds" to scaling.csv
wall_time() {
  local prefix=$1 start
  shift
  start=$(date +%s%N)
  "$@" >"$out/last.log" 2>&1 || { cat "$out/last.log" >&2; exit 1; }
  echo "$prefix,$(seconds_since "$start")" >>"$csv"
}

csv="$out/scaling.csv"
echo "job,layout,ranks,cores_used,seconds" >"$csv"
reference=(study render "$root/scenes/lte-orb.json" --res-scale 0.25 --backends sobol --spp 1
  --reference-spp 512 --reference-pass-spp 32 --no-report -q)
bank=(optimize --target "envmap:$assets/envmaps/grace_latlong.exr" --preset sphere --n 64
  --instances 16 --epochs 1000 -q)
for job in reference bank; do
  run() { # run DIR_OR_FILE LAUNCHER...
    local where=$1; shift
    rm -rf "$out/$where"
    if [[ $job == reference ]]; then "$@" "$nuld" "${reference[@]}" -o "$out/$where"
    else "$@" "$nuld" "${bank[@]}" -o "$out/$where.ptsb"; fi
  }
  wall_time "$job,one process,1,$cores" run "${job}_process"
  wall_time "$job,mpirun,1,1" run "${job}_1" "${mpirun[@]}" -np 1
  wall_time "$job,mpirun,2,$((cores < 2 ? cores : 2))" run "${job}_2" "${mpirun[@]}" -np 2
  wall_time "$job,mpirun oversubscribed,4,$cores" run "${job}_4" "${mpirun[@]}" --oversubscribe -np 4
done
echo "== wall time and efficiency (against 1 rank on 1 core)"
awk -F, 'NR > 1 { key = $1; if ($3 == 1 && $2 == "mpirun") one[key] = $5; row[NR] = $0 }
  END {
    printf "%-10s %-24s %5s %5s %9s %10s\n", "job", "layout", "ranks", "cores", "seconds", "efficiency"
    for (i = 2; i <= NR; ++i) {
      split(row[i], f, ",")
      printf "%-10s %-24s %5s %5s %9.1f %10.2f\n", f[1], f[2], f[3], f[4], f[5], one[f[1]] / (f[4] * f[5])
    }
  }' "$csv" | tee "$out/scaling.txt"

# The cost of a path sample in each paper scene at full resolution: one
# 16-spp render as one process on every core.
costs="$out/sample_costs.csv"
echo "scene,width,height,spp,seconds,core_ns_per_sample,paper_spp" >"$costs"
for entry in lte-orb:131072 dragon:8192 cup:65536; do
  scene=${entry%%:*} paper=${entry#*:}
  start=$(date +%s%N)
  "$nuld" render "$root/scenes/$scene.json" --spp 16 --backend halton -q -o "$out/$scene.exr" \
    >/dev/null 2>&1 || { echo "render of $scene failed" >&2; exit 1; }
  seconds=$(seconds_since "$start")
  read -r w h < <(/usr/bin/python3 -c "import json,sys; f=json.load(open(sys.argv[1]))['film']; print(f['width'], f['height'])" "$root/scenes/$scene.json")
  awk -v s="$scene" -v w="$w" -v h="$h" -v t="$seconds" -v c="$cores" -v p="$paper" \
    'BEGIN { printf "%s,%d,%d,16,%.2f,%.1f,%d\n", s, w, h, t, t * c / (w * h * 16) * 1e9, p }' >>"$costs"
done
one=$(awk -F, '$1 == "reference" && $2 == "mpirun" && $3 == 1 { print $5 }' "$csv")
two=$(awk -F, '$1 == "reference" && $2 == "mpirun" && $3 == 2 { print $5 }' "$csv")
echo
echo "== the paper's references at full resolution (startup time included in the efficiency)"
awk -F, -v one="$one" -v two="$two" -v c2="$((cores < 2 ? cores : 2))" 'NR > 1 {
    e = one / (c2 * two); if (e > 1) e = 1
    core_hours = $2 * $3 * $7 * $6 * 1e-9 / 3600
    if (!header++) printf "%-8s %9s %8s %11s %12s %14s %14s\n", "scene", "size", "spp", "ns/sample", "core-hours", "64 cores (h)", "512 cores (h)"
    printf "%-8s %4dx%-4d %8d %11.1f %12.1f %14.2f %14.3f\n", $1, $2, $3, $7, $6, core_hours, core_hours / (64 * e), core_hours / (512 * e)
  }' "$costs" | tee "$out/paper_estimates.txt"
echo "(efficiency of 2 ranks used: $(awk -v one="$one" -v two="$two" -v c="$((cores < 2 ? cores : 2))" 'BEGIN { e = one / (c * two); printf "%.2f", (e > 1 ? 1 : e) }'))"
