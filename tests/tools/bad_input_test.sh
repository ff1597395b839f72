#!/usr/bin/env bash
# The bad-input corpus (tests/data/bad_inputs/cases.txt): every case must be
# refused with its expected message, never accepted, never a crash, and must
# write no output.
set -uo pipefail
nuld=$1
data=$(cd "$(dirname "$0")/../data/bad_inputs" && pwd)
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
mkfifo "$out/pipe"
failures=0 cases=0
while IFS= read -r line; do
  [[ -z "$line" || "$line" == \#* ]] && continue
  expected=${line%% | *}
  args=${line#* | }
  args=${args//DATA/$data}
  args=${args//OUT/$out}
  args=${args//FIFO/$out/pipe}
  cases=$((cases + 1))
  # shellcheck disable=SC2086  # the arguments are words by design
  timeout 120 "$nuld" $args >"$out/stdout" 2>"$out/stderr"
  rc=$?
  if [[ $rc -eq 0 || $rc -ge 124 ]]; then
    echo "FAIL ($rc): nuld $args"; cat "$out/stderr"; failures=$((failures + 1))
  elif ! grep -qF -- "$expected" "$out/stderr"; then
    echo "FAIL: nuld $args: expected a message containing '$expected', got:"
    cat "$out/stderr"; failures=$((failures + 1))
  elif compgen -G "$out/x.*" >/dev/null; then
    echo "FAIL: nuld $args: wrote $(ls "$out"/x.*) although it failed"; failures=$((failures + 1))
    rm -f "$out"/x.*
  fi
  [[ -p "$out/pipe" ]] || { echo "FAIL: nuld $args replaced the pipe"; failures=$((failures + 1)); rm -f "$out/pipe"; mkfifo "$out/pipe"; }
done <"$data/cases.txt"
echo "bad inputs: $cases cases, $failures failed"
((failures == 0))
