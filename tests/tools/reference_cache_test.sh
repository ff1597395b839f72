#!/usr/bin/env bash
# The reference cache from the command line (backends/reference_cache.h):
# nuld render --reference renders a reference once and finds it after, a
# study finds it too and counts 0 s for it, an interrupted one resumes to
# the uninterrupted image, nuld cache lists and clears references (and
# nothing else), and bad input is refused; then a study's repeats until the
# target (docs/studies.md). Conventions of cli_test.sh.
set -uo pipefail
nuld=$1
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
export NULD_CACHE="$dir/cache"
unset NULD_REFERENCE_CACHE
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }
run() { # run LOG COMMAND...
  local log=$1; shift
  "$@" >"$dir/$log.out" 2>"$dir/$log.err" || { fail "$log: exit $?"; cat "$dir/$log.err"; }
}

reference=(render default --reference --spp 32 --res 24 --integrator direct -q)
run made "$nuld" "${reference[@]}" -o "$dir/ref.exr"
grep -q "^cache rendered" "$dir/made.out" || fail "the first reference was not rendered: $(cat "$dir/made.out")"
for f in ref.exr ref.half0.exr ref.half1.exr ref.png; do
  [[ -s "$dir/$f" ]] || fail "--reference did not write $f"
done
run found "$nuld" "${reference[@]}" -o "$dir/again.exr"
grep -q "^cache found" "$dir/found.out" || fail "the second reference was not found: $(cat "$dir/found.out")"
grep -q "^seconds 0.000" "$dir/found.out" || fail "a found reference counts 0 s"
cmp -s "$dir/ref.exr" "$dir/again.exr" || fail "the found reference differs from the one made"

# A study with the same scene and settings finds it.
run study "$nuld" study render default --res 24 --integrator direct --reference-spp 32 \
  --backends sobol --spp 4 --no-report -q -o "$dir/study"
grep -q "found in the reference cache" "$dir/study.err" || fail "the study did not find the reference"
awk -F, 'NR == 2 && $8 == "0" && $11 == "found" {ok = 1} END {exit !ok}' "$dir/study/references.csv" ||
  fail "references.csv: expected seconds 0 and cache found: $(cat "$dir/study/references.csv")"

# Interrupted by --reference-stop-after, listed in progress, then resumed to
# the image an uninterrupted run makes (in another cache).
partial=(render default --reference --spp 32 --res 20 --reference-pass-spp 8 --integrator direct -q)
run stopped "$nuld" "${partial[@]}" --reference-stop-after 1 -o "$dir/p.exr"
[[ -e "$dir/p.exr" ]] && fail "a stopped reference wrote its output"
run list "$nuld" cache list
grep -q "passes 1/4" "$dir/list.out" || fail "cache list shows the reference in progress: $(cat "$dir/list.out")"
grep -q "complete" "$dir/list.out" || fail "cache list shows the complete reference"
grep -q "2 references" "$dir/list.out" || fail "cache list counts the references"
run resumed "$nuld" "${partial[@]}" -o "$dir/p.exr"
NULD_CACHE="$dir/other" "$nuld" "${partial[@]}" -o "$dir/whole.exr" >/dev/null 2>&1
idiff -q -fail 0 -warn 0 "$dir/p.exr" "$dir/whole.exr" >/dev/null 2>&1 ||
  fail "the resumed reference differs from the uninterrupted one"

# Bad input: a learned backend, an unwritable cache, options without --reference.
"$nuld" render default --reference --backend optimized --res 8 -q -o "$dir/x.exr" 2>"$dir/err"
[[ $? -eq 2 ]] && grep -q "classic backend" "$dir/err" || fail "--reference with sets: $(cat "$dir/err")"
echo x >"$dir/file"
NULD_CACHE="$dir/file" "$nuld" render default --reference --res 8 --spp 4 -q -o "$dir/x.exr" 2>"$dir/err"
[[ $? -eq 1 ]] && grep -q "NULD_CACHE" "$dir/err" || fail "an unwritable cache: $(cat "$dir/err")"
"$nuld" render default --reference-stop-after 1 --res 8 -q -o "$dir/x.exr" 2>"$dir/err"
[[ $? -eq 2 ]] && grep -q -- "--reference" "$dir/err" || fail "--reference-stop-after alone: $(cat "$dir/err")"
"$nuld" study render default --max-repeats 8 --res 8 -q -o "$dir/x" 2>"$dir/err"
[[ $? -eq 2 ]] && grep -q -- "--target-stderr" "$dir/err" || fail "--max-repeats alone: $(cat "$dir/err")"

# clear removes the references and keeps a file it did not write.
entry=$(awk -F, 'NR == 2 {print $NF}' "$dir/study/references.csv")
echo mine >"$entry/notes.txt"
run clear "$nuld" cache clear
[[ -e "$entry/notes.txt" && ! -e "$entry/reference.exr" ]] || fail "cache clear removed the wrong files"
[[ -s "$dir/study/default/reference.exr" ]] || fail "cache clear took the study's reference"

# A damaged reference is named by cache verify, never served, and rendered
# again to the clean image; cache remove takes one entry by key.
small=(render default --reference --spp 8 --res 12 --reference-pass-spp 4 --integrator direct -q)
run clean "$nuld" "${small[@]}" -o "$dir/clean.exr"
other=(render default --reference --spp 8 --res 12 --reference-pass-spp 4 --integrator direct --seed 9 -q)
run other "$nuld" "${other[@]}" -o "$dir/other.exr"
entry=$(sed -n 's/^nuld: the reference is now in the cache: //p' "$dir/clean.err")
cp "$dir/other.exr" "$entry/reference.exr"
"$nuld" cache verify >"$dir/verify.out" 2>&1 && fail "cache verify passed a swapped reference"
grep -q "damaged $entry/reference.exr" "$dir/verify.out" || fail "cache verify names the swapped image: $(cat "$dir/verify.out")"
run again "$nuld" "${small[@]}" -o "$dir/again.exr"
grep -q "is damaged" "$dir/again.err" || fail "the damaged reference is noted: $(cat "$dir/again.err")"
idiff -q -fail 0 -warn 0 "$dir/clean.exr" "$dir/again.exr" >/dev/null 2>&1 || fail "the reference made again differs from the clean one"
run verified "$nuld" cache verify
run remove "$nuld" cache remove "${entry##*_}"
[[ ! -e "$entry" ]] || fail "cache remove KEY left $entry"
"$nuld" cache remove 0123456789abcdef >/dev/null 2>"$dir/err"
[[ $? -eq 1 ]] && grep -q "no entry of key" "$dir/err" || fail "cache remove of no entry: $(cat "$dir/err")"
"$nuld" cache remove nothex >/dev/null 2>"$dir/err"
[[ $? -eq 2 ]] && grep -q "16 hex digits" "$dir/err" || fail "cache remove of a bad key: $(cat "$dir/err")"

# cache clear while another process makes a reference: the entry is
# skipped and named, and the other process finishes it.
long=(render default --reference --spp 64 --res 64 --reference-pass-spp 4 --integrator path -q)
"$nuld" "${long[@]}" -o "$dir/long.exr" >"$dir/long.out" 2>"$dir/long.err" &
maker=$!
for _ in $(seq 100); do
  "$nuld" cache list 2>/dev/null | grep -q "making it" && break
  sleep 0.1
done
run busy "$nuld" cache clear
grep -q "^skipped .*process $maker is making or reading it" "$dir/busy.out" ||
  fail "cache clear names the entry it skipped: $(cat "$dir/busy.out")"
wait $maker || { fail "the reference being made when the cache was cleared: exit $?"; cat "$dir/long.err"; }
[[ -s "$dir/long.exr" ]] || fail "the reference being made when the cache was cleared wrote nothing"

# A cache that is a regular file is an error, not an empty cache.
NULD_CACHE="$dir/file" "$nuld" cache clear >/dev/null 2>"$dir/err"
[[ $? -eq 1 ]] && grep -q "not a folder" "$dir/err" || fail "cache clear of a file: $(cat "$dir/err")"

# Repeats until the target: every row says how it stopped.
run adaptive "$nuld" study render default --res 24 --integrator direct --reference-spp 32 \
  --backends sobol,independent --spp 4 --repeats 2 --target-stderr 0.05 --max-repeats 8 --no-report -o "$dir/adaptive"
grep -Eq "^independent +4 +8 budget|^independent +4 +[0-9]+ precision" "$dir/adaptive.out" ||
  fail "the table says how the rows stopped: $(cat "$dir/adaptive.out")"
[[ $(($(wc -l <"$dir/adaptive/default/repeats.csv") - 1)) -eq $(awk -F, 'NR > 1 {n += $4} END {print n}' "$dir/adaptive/render.csv") ]] ||
  fail "repeats.csv holds every repeat of render.csv's rows"

[[ $failures -eq 0 ]] && echo "reference cache: all checks passed"
exit $((failures > 0))
