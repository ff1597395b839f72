#!/usr/bin/env bash
# The bad-input corpus (tests/data/bad_inputs/cases.txt): every case must be
# refused with its expected message, never accepted, never a crash, and must
# write no output.
set -uo pipefail
nuld=$1
data=$(cd "$(dirname "$0")/../data/bad_inputs" && pwd)
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
export NULD_CACHE="$out/set-cache"  # not the user's cache
unset NULD_REFERENCE_CACHE  # references beside the sets of this cache
# Cases marked "ASSETS " need the shipped maps; without them (no asset root,
# or $NULD_ASSETS naming a folder without envmaps/) they are skipped, as the
# other asset tests skip.
assets=${NULD_ASSETS:-"$(cd "$(dirname "$0")/../.." && pwd)/../shared/assets"}
have_assets=0
[[ -d "$assets/envmaps" ]] && have_assets=1
skipped=0
mkfifo "$out/pipe"
failures=0 cases=0
declare -A perCommand
while IFS= read -r line; do
  [[ -z "$line" || "$line" == \#* ]] && continue
  expected=${line%% | *}
  args=${line#* | }
  if [[ "$expected" == "ASSETS "* ]]; then
    expected=${expected#ASSETS }
    ((have_assets)) || { skipped=$((skipped + 1)); continue; }
  fi
  warn=0
  if [[ "$expected" == "WARN "* ]]; then warn=1 expected=${expected#WARN }; fi
  command=${args%% *}
  [[ "$command" == study ]] && command="study $(echo "$args" | cut -d' ' -f2)"
  perCommand[$command]=$((${perCommand[$command]:-0} + 1))
  args=${args//DATA/$data}
  args=${args//OUT/$out}
  args=${args//FIFO/$out/pipe}
  cases=$((cases + 1))
  # shellcheck disable=SC2086  # the arguments are words by design
  timeout 120 "$nuld" $args >"$out/stdout" 2>"$out/stderr"
  rc=$?
  if ((warn)); then
    if [[ $rc -ne 0 ]] || ! grep -qF -- "$expected" "$out/stderr"; then
      echo "FAIL ($rc): nuld $args: expected exit 0 and a warning containing '$expected', got:"
      cat "$out/stderr"; failures=$((failures + 1))
    fi
  elif [[ $rc -ne 1 && $rc -ne 2 ]]; then
    # Refused input exits 1, a usage error 2 (docs/usage.md); anything else
    # (0, a crash, a CLI11 code) is a failure.
    echo "FAIL ($rc): nuld $args: expected exit 1 or 2"; cat "$out/stderr"; failures=$((failures + 1))
  elif LC_ALL=C grep -q $'[\x01-\x08\x0b-\x1f\x7f]' "$out/stderr"; then
    # No reader echoes a file's raw bytes (sampler/io/input_file.h, quotedInput).
    echo "FAIL: nuld $args: the message echoes control bytes:"
    od -c "$out/stderr" | head -5; failures=$((failures + 1))
  elif ! grep -q "^nuld: error" "$out/stderr"; then
    echo "FAIL: nuld $args: the message lacks the 'nuld: error:' prefix:"
    cat "$out/stderr"; failures=$((failures + 1))
  elif ! grep -qF -- "$expected" "$out/stderr"; then
    echo "FAIL: nuld $args: expected a message containing '$expected', got:"
    cat "$out/stderr"; failures=$((failures + 1))
  elif compgen -G "$out/x.*" >/dev/null; then
    echo "FAIL: nuld $args: wrote $(ls "$out"/x.*) although it failed"; failures=$((failures + 1))
    rm -rf "$out"/x.*
  fi
  [[ -p "$out/pipe" ]] || { echo "FAIL: nuld $args replaced the pipe"; failures=$((failures + 1)); rm -f "$out/pipe"; mkfifo "$out/pipe"; }
done <"$data/cases.txt"
for c in "${!perCommand[@]}"; do echo "  $c: ${perCommand[$c]}"; done | sort
echo "bad inputs: $cases cases, $failures failed, $skipped skipped (no assets at $assets)"
((failures == 0))
