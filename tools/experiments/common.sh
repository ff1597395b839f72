# Shared helpers for the experiment scripts (sourced, not run).
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
nuld=${NULD:-"$root/build/nuld"}
[[ -x "$nuld" ]] || { echo "build first: tools/build.sh (or set NULD=path/to/nuld)" >&2; exit 1; }
python=/usr/bin/python3  # Debian's, which has matplotlib

# metric FILE TARGET NAME -> the mean value of one metric
metric() { "$nuld" eval "$1" --target "$2" --metric "$3" | awk -v m="$3" '$1 == m {print $2}'; }

# row CSV N SAMPLER FILE TARGET: appends N,sampler,l2star,l2asd,dstar
row() {
  local csv=$1 n=$2 sampler=$3 file=$4 target=$5
  local vals
  vals=$("$nuld" eval "$file" --target "$target" --metric all |
    awk '{v[$1]=$2} END {printf "%s,%s,%s", v["l2star"], v["l2asd"], v["dstar"]}')
  echo "$n,$sampler,$vals" >>"$csv"
}

# l2_dstar FILE TARGET -> "l2asd,dstar" (means over the file's instances)
l2_dstar() {
  "$nuld" eval "$1" --target "$2" --metric all |
    awk '{v[$1]=$2} END {printf "%s,%s", v["l2asd"], v["dstar"]}'
}
