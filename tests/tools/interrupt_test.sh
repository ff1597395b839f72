#!/usr/bin/env bash
# Ctrl-C while a command makes sets: it says where their checkpoints are, and
# a rerun resumes them (render continues sets by itself). Split from
# cli_test.sh, whose conventions it keeps.
set -uo pipefail
nuld=$1
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
export NULD_CACHE="$dir/set-cache"
unset NULD_REFERENCE_CACHE  # references beside the sets of this cache
failures=0

# Ctrl-C while a render makes its sets says where their checkpoints are, and
# the rerun says it resumed them (render continues sets by itself).
interrupted=(render default --backend optimized --opt-objective soft --spp 4 --res 16 --opt-instances 2
  --opt-epochs 4000 -q -o "$dir/interrupted.exr")
# interrupted_while_making_sets WHAT CACHE COMMAND...: runs nuld with the set
# cache CACHE, presses Ctrl-C once a set's checkpoint exists, and expects exit
# 130 with the note naming where the checkpoints are.
interrupted_while_making_sets() {
  local what=$1 cache=$2; shift 2
  NULD_CACHE="$cache" "$nuld" "$@" >"$dir/out" 2>"$dir/err" &
  local pid=$!
  for _ in $(seq 1 300); do
    compgen -G "$cache/sets/*.ckpt" >/dev/null && break
    sleep 0.1
  done
  kill -INT "$pid"
  wait "$pid"
  local rc=$?
  if [[ $rc -ne 130 ]] || ! grep -q "nuld: interrupted; the sets being made keep their checkpoints in $cache/sets" "$dir/err"; then
    echo "FAIL: an interrupted $what notes where its sets' checkpoints are: exit $rc"; tail -c 300 "$dir/err"
    failures=$((failures + 1))
  fi
}
interrupted_while_making_sets render "$dir/interrupt-cache" "${interrupted[@]}"
NULD_CACHE="$dir/interrupt-cache" "$nuld" "${interrupted[@]}" >"$dir/out" 2>"$dir/err" ||
  { echo "FAIL: the interrupted render's rerun"; failures=$((failures + 1)); }
grep -q "nuld: note: sets resuming from $dir/interrupt-cache/sets/.*\.ckpt at epoch" "$dir/err" ||
  { echo "FAIL: a rerun says it resumed the interrupted sets"; tail -c 300 "$dir/err"; failures=$((failures + 1)); }

# Ctrl-C in nuld bank says where the checkpoints of its sets are.
interrupted_while_making_sets bank "$dir/bank-interrupt" bank default --backend optimized --opt-objective soft \
  --spp 4 --res 16 --opt-instances 2 --opt-epochs 4000 -q


echo "$((failures == 0 ? 1 : 0)) passed, $failures failed"
exit $((failures > 0))
