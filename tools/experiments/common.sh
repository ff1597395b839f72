# Shared helpers for the experiment scripts (sourced, not run).
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
nuld=${NULD:-"$root/build/nuld"}
[[ -x "$nuld" ]] || { echo "build first: tools/build.sh (or set NULD=path/to/nuld)" >&2; exit 1; }
python=/usr/bin/python3  # Debian's, which has matplotlib
# The user's reference cache (backends/reference_cache.h), named before a
# script points NULD_CACHE at a fresh set cache per run: every study of the
# scripts then finds the references any earlier one rendered.
export NULD_REFERENCE_CACHE=${NULD_REFERENCE_CACHE:-${NULD_CACHE:-${XDG_CACHE_HOME:-$HOME/.cache}/nuld}/references}

# metrics FILE TARGET NAME... -> the named metrics of `nuld eval` (means over
# the file's instances), comma-separated
metrics() {
  local file=$1 target=$2
  shift 2
  "$nuld" eval "$file" --target "$target" --metric all |
    awk -v names="$*" '{v[$1] = $2} END {
      n = split(names, k, " ")
      for (i = 1; i <= n; i++) printf "%s%s", (i > 1 ? "," : ""), v[k[i]]
    }'
}

# l2_dstar FILE TARGET -> "l2asd,dstar"
l2_dstar() { metrics "$1" "$2" l2asd dstar; }

# prepare_output DIR: creates it and writes the experiments' image target
# DIR/test_image.pfm
prepare_output() {
  mkdir -p "$1"
  "$python" "$root/tools/experiments/make_test_image.py" "$1/test_image.pfm"
}

# seconds_since START_NS (from date +%s%N) -> elapsed seconds, one decimal
seconds_since() { awk -v ns=$(($(date +%s%N) - $1)) 'BEGIN {printf "%.1f", ns / 1e9}'; }

# summarize_runs CSV KEYS -> per group of runs (rows with equal values in the
# comma-separated columns KEYS, e.g. "run,binary"), in first-seen order: the
# seeds, mean / min / max of seconds, the peak of peak_mb, and mean / min /
# max of l2asd and dstar. CSV has a header naming those columns; rows whose
# seed is "-" (a reference row, not a run) are left out.
summarize_runs() {
  awk -F, -v keys="$2" '
    NR == 1 { for (i = 1; i <= NF; i++) col[$i] = i; nk = split(keys, kn, ","); next }
    $col["seed"] == "-" { next }
    {
      k = ""; for (i = 1; i <= nk; i++) k = k (i > 1 ? " " : "") $col[kn[i]]
      if (!(k in n)) order[++groups] = k
      n[k]++
      add(k, "s", $col["seconds"]); add(k, "l", $col["l2asd"]); add(k, "d", $col["dstar"])
      if ($col["peak_mb"] > mem[k]) mem[k] = $col["peak_mb"]
    }
    function add(k, m, v) {
      sum[k, m] += v
      if (!((k, m) in lo) || v < lo[k, m]) lo[k, m] = v
      if (!((k, m) in hi) || v > hi[k, m]) hi[k, m] = v
    }
    END {
      gsub(",", " ", keys)
      print keys ",seeds,mean_seconds,min_seconds,max_seconds,peak_mb,mean_l2asd,min_l2asd,max_l2asd,mean_dstar,min_dstar,max_dstar"
      for (g = 1; g <= groups; g++) { k = order[g]
        printf "%s,%d,%.1f,%.1f,%.1f,%d,%.3g,%.3g,%.3g,%.3g,%.3g,%.3g\n", k, n[k],
          sum[k, "s"] / n[k], lo[k, "s"], hi[k, "s"], mem[k], sum[k, "l"] / n[k], lo[k, "l"],
          hi[k, "l"], sum[k, "d"] / n[k], lo[k, "d"], hi[k, "d"] }
    }' "$1"
}
