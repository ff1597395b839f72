#!/usr/bin/env bash
# The option sweep: every option that takes a value, of every command, given
# a value that names nothing (OUT/no/such/@@: no such name, number, file or
# directory) after a minimal valid command line. Each must be refused like
# any bad input: a message starting 'nuld: error' that names the option or
# the value, no control bytes, nothing written under OUT but what the
# command line already names; and exit 2 (a value outside the option's
# grammar, or an option that does not apply), except the options that name
# a file or directory (`paths` below), which exit 1: the command line is
# well formed, what it names cannot be used (docs/usage.md, "Conventions
# worth knowing"). Options read from `--help`, so a new option joins the
# sweep by itself (and must then take a side).
# Usage: option_sweep_test.sh NULD DATA_DIR
set -uo pipefail
set -f  # the base command lines hold words like gaussian*step
nuld=$1
data=$2
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
export NULD_CACHE="$out/set-cache"
unset NULD_REFERENCE_CACHE  # references beside the sets of this cache
bad="$out/no/such/@@"
failures=0 cases=0

# A minimal valid command line per command (DATA: the bad-input corpus's
# folder, OUT: scratch).
declare -A base=(
  [generate]="--n 4 -o OUT/g.txt"
  [map]="DATA/valid.txt --target uniform -o OUT/m.txt"
  [eval]="DATA/valid.txt"
  [export]="DATA/valid.txt -o OUT/e.csv"
  [optimize]="--target uniform --n 4 --epochs 2 -o OUT/o.txt"
  [plot]="DATA/valid.txt -o OUT/p.png"
  [spectrum]="DATA/valid.txt -o OUT/s.png"
  [render]="default --res 8 --spp 1 -o OUT/r.exr"
  [compare]="OUT/r.exr OUT/r.exr"
  [bank]="default --res 8 --spp 1 --opt-instances 2 --opt-epochs 2"
  [study render]="default --backends sobol --spp 1 --res 8 --reference-spp 4 -o OUT/sr"
  [study integrate]="--integrands gaussian*step --samplers sobol --n 4 --instances 2 -o OUT/si"
  [train]="--target uniform --n 4 --hidden 8 --steps 2 --batch 2 --boxes 16 -o OUT/t.nuldnet"
)
# Options whose value names a file or directory the command opens ("COMMAND
# OPTION"): a missing one exits 1.
declare -A paths=(
  ["generate --model"]=1 ["compare --error-map"]=1 ["compare --flip-map"]=1 ["spectrum --csv"]=1
  ["study integrate --neural"]=1
)
# Options that take any value by design ("COMMAND OPTION"), with the reason.
declare -A free=(
  ["bank --output"]="creates the bank directory, parents included, as study render -o does"
)

"$nuld" render default --res 8 --spp 1 -q -o "$out/r.exr" >/dev/null 2>&1
for command in "${!base[@]}"; do
  # shellcheck disable=SC2086  # the command is words
  options=$("$nuld" $command --help 2>/dev/null |
    grep -oE '^\s+(-[a-zA-Z],)?--[a-z][a-z0-9-]* [A-Z:]+' | grep -oE -- '--[a-z][a-z0-9-]*' | sort -u)
  for option in $options; do
    [[ -n "${free["$command $option"]:-}" ]] && continue
    cases=$((cases + 1))
    args=${base[$command]//DATA/$data}
    args=${args//OUT/$out}
    # shellcheck disable=SC2086
    timeout 120 "$nuld" $command $args "$option" "$bad" >"$out/stdout" 2>"$out/stderr"
    rc=$?
    expected=2
    [[ -n "${paths["$command $option"]:-}" ]] && expected=1
    if [[ $rc -ne $expected ]]; then
      echo "FAIL ($rc, expected $expected): nuld $command $option '$bad':"; head -3 "$out/stderr"
      failures=$((failures + 1))
    elif ! grep -q '^nuld: error' "$out/stderr"; then
      echo "FAIL: nuld $command $option: no 'nuld: error' message:"; head -3 "$out/stderr"
      failures=$((failures + 1))
    elif ! grep -qF -e "$option" -e "@@" "$out/stderr"; then
      echo "FAIL: nuld $command $option: the message names neither the option nor the value:"
      head -3 "$out/stderr"; failures=$((failures + 1))
    elif LC_ALL=C grep -q $'[\x01-\x08\x0b-\x1f\x7f]' "$out/stderr"; then
      echo "FAIL: nuld $command $option: control bytes in the message"; failures=$((failures + 1))
    fi
  done
done

# Every word of the backend registry (nuld help backends, by section) is
# taken exactly where it serves: a word the command takes lets the command
# line reach the next bad option (the refusal names that option), one it
# does not is refused naming where it serves. PATHS and MODEL stand for a
# name the grammar accepts; the files are not opened at parse time.
"$nuld" help backends >"$out/backends.txt"
section() { # the words of the section from line $1 to line $2
  sed -n "/^$1/,/^$2/p" "$out/backends.txt" | sed -n '/^  [a-z]/p' | awk '{print $1}' |
    sed -e 's/\[:[A-Z]*\]//' -e 's/:PATHS/:f.txt/' -e 's/:MODEL/:m.nuldnet/'
}
everywhere=$(section "Sampler backends" "Renders only")
rendersOnly=$(section "Renders only" "study integrate only")
integrateOnly=$(section "study integrate only" "NO SUCH LINE")
words=0
takes() { # takes WHAT EXPECTED-OPTION COMMAND...: the refusal names EXPECTED-OPTION
  local what=$1 expected=$2; shift 2
  words=$((words + 1))
  "$@" >/dev/null 2>"$out/stderr"
  if ! grep -q -- "^nuld: error: $expected" "$out/stderr"; then
    echo "FAIL: $what: expected a refusal of $expected, got:"; head -2 "$out/stderr"
    failures=$((failures + 1))
  fi
}
for w in $everywhere $rendersOnly $integrateOnly; do
  rendersToo=1 integratesToo=1
  # shellcheck disable=SC2086  # the lists are words
  [[ " $(echo $integrateOnly) " == *" $w "* ]] && rendersToo=0
  # shellcheck disable=SC2086
  [[ " $(echo $rendersOnly) " == *" $w "* ]] && integratesToo=0
  ((rendersToo)) && expected=--spp || expected=--backend
  takes "render --backend $w" "$expected" "$nuld" render default --backend "$w" --spp 0 -o "$out/w.exr"
  ((integratesToo)) && expected=--n || expected=--samplers
  takes "study integrate --samplers $w" "$expected" "$nuld" study integrate --samplers "$w" --n 0 -o "$out/wi"
done
(($(echo $everywhere $rendersOnly $integrateOnly | wc -w) >= 16)) ||
  { echo "FAIL: help backends lists fewer words than the registry holds"; failures=$((failures + 1)); }

# A render the machine cannot hold is refused before anything is allocated
# (the renderer's check, renderMemoryBytes through requireMemory, which
# nuld.render makes too): a rejected value, exit 2, in under a second, with
# the memory it would need. The CLI's largest request (32768 x 32768 pixels,
# 2^24 spp, paths of 1000 bounces) exceeds any machine's memory; a 32000 x
# 32000 render at the scene's spp needs about 23 GiB (the image and its
# preview), which only a smaller machine refuses.
cases=$((cases + 1))
start=$(date +%s%N)
timeout 20 "$nuld" render default --res 32768x32768 --spp 16777216 --max-depth 1000 -q \
  -o "$out/huge.exr" >"$out/stdout" 2>"$out/stderr"
rc=$? ms=$((($(date +%s%N) - start) / 1000000))
if [[ $rc -ne 2 ]] || ! grep -q '^nuld: error: render: --res: a 32768 x 32768 render at 16777216 spp needs about .* of memory, more than this machine' "$out/stderr"; then
  echo "FAIL ($rc): render --res 32768x32768 --spp 16777216: expected exit 2 and the memory needed:"
  head -3 "$out/stderr"; failures=$((failures + 1))
elif ((ms >= 1000)); then
  echo "FAIL: render --res 32768x32768 --spp 16777216: refused after $ms ms, not under a second"
  failures=$((failures + 1))
elif compgen -G "$out/huge.*" >/dev/null; then
  echo "FAIL: render --res 32768x32768: wrote $(ls "$out"/huge.*) although it refused"
  failures=$((failures + 1))
fi

echo "option sweep: $cases options, $words backend-word checks, $failures failed"
((failures == 0))
