# Shared helpers for the experiment scripts (sourced, not run).
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
nuld=${NULD:-"$root/build/nuld"}
[[ -x "$nuld" ]] || { echo "build first: tools/build.sh (or set NULD=path/to/nuld)" >&2; exit 1; }
python=/usr/bin/python3  # Debian's, which has matplotlib

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
