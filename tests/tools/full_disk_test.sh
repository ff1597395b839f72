#!/usr/bin/env bash
# Writes onto a full disk (docs/architecture.md, "Writes"): a render, a study,
# a bank of sets and a reference each exit nonzero naming the file they could
# not write, leave nothing half-written under a final name and no cache entry
# that a later run would trust; the same command after space is freed
# succeeds. The disk is a 1 MiB tmpfs filled to 32 KiB where this machine
# lets the test mount one (root), else every file is limited to 4 KiB
# (ulimit -f, SIGXFSZ ignored): the same failing writes either way.
# Conventions of cli_test.sh.
set -uo pipefail
nuld=$1
dir=$(mktemp -d)
full="$dir/full"
mkdir "$full"
mounted=0
if [[ $(id -u) -eq 0 ]] && mount -t tmpfs -o size=1m tmpfs "$full" 2>/dev/null; then mounted=1; fi
cleanup() {
  [[ $mounted -eq 1 ]] && umount "$full"
  rm -rf "$dir"
}
trap cleanup EXIT
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }

fill() { # fill [KIB]: leaves KIB (default 32) free on the tmpfs
  local leave=${1:-32}
  limit_kib=$((leave > 0 ? 4 : 0))
  [[ $mounted -eq 1 ]] || return 0
  rm -f "$full/filler"
  local free_kib
  free_kib=$(df -k --output=avail "$full" | tail -1)
  head -c $(((free_kib - leave) * 1024)) /dev/zero >"$full/filler" 2>/dev/null
  [[ $leave -gt 0 ]] || cat /dev/zero >>"$full/filler" 2>/dev/null
}
free_space() { rm -f "$full/filler"; }
on_full() { # on_full COMMAND...: the command with the disk full (or files limited)
  if [[ $mounted -eq 1 ]]; then "$@"; return; fi
  # Its stdout and stderr through pipes, which the limit does not cover,
  # to writers outside the limited subshell.
  (trap '' XFSZ; ulimit -f "$limit_kib"; exec "$@") 2> >(cat >&2) | cat
  return "${PIPESTATUS[0]}"
}
# Every image under DIR decodes (oiiotool reads it whole), and no temporary
# file of a writer is left.
whole_images() { # whole_images WHAT DIR
  local what=$1 d=$2 f
  while IFS= read -r -d '' f; do
    oiiotool -q "$f" -o "$dir/check.exr" >/dev/null 2>&1 || fail "$what: $f stands truncated"
  done < <(find "$d" \( -name '*.exr' -o -name '*.png' \) -size +0 -print0)
  [[ -z $(find "$d" -name '*.png' -size 0) ]] || fail "$what: a 0-byte PNG stands: $(find "$d" -name '*.png' -size 0)"
  [[ -z $(find "$d" -name '.*.tmp*') ]] || fail "$what: temporaries left: $(find "$d" -name '.*.tmp*')"
}
refused_full() { # refused_full WHAT PATTERN COMMAND...: exit 1 naming PATTERN
  local what=$1 pattern=$2; shift 2
  on_full "$@" >"$dir/out" 2>"$dir/err"
  local rc=$?
  if [[ $rc -ne 1 ]] || ! grep -qF -- "$pattern" "$dir/err"; then
    fail "$what on a full disk: exit $rc, expected 1 and a message naming '$pattern':"
    cat "$dir/err"
  fi
}

# A render: neither the EXR nor the PNG stands.
fill
refused_full "a render" "$full/t." "$nuld" render default --res 64x48 --spp 4 -q -o "$full/t.exr"
[[ ! -e "$full/t.exr" && ! -e "$full/t.png" ]] || fail "a failed render left $(ls "$full")"
whole_images "a render" "$full"
free_space
"$nuld" render default --res 64x48 --spp 4 -q -o "$full/t.exr" >/dev/null 2>"$dir/err" ||
  { fail "the render after space is freed"; cat "$dir/err"; }
rm -f "$full/t.exr" "$full/t.png"

# A reference into a cache on the full disk: never committed, the cache
# verifies, and the same command after space is freed makes it.
export NULD_CACHE="$full/cache"
unset NULD_REFERENCE_CACHE
reference=(render default --res 64x48 --reference --spp 256 --reference-pass-spp 64 -q)
fill
refused_full "a reference" "$full/cache/references/" "$nuld" "${reference[@]}" -o "$dir/r.exr"
[[ ! -e "$dir/r.exr" ]] || fail "a failed reference wrote its -o copy"
"$nuld" cache list >"$dir/list" 2>&1
grep -q complete "$dir/list" && fail "a failed reference is listed complete: $(cat "$dir/list")"
"$nuld" cache verify >"$dir/verify" 2>&1 || fail "the cache after a failed reference: $(cat "$dir/verify")"
whole_images "a reference" "$full"
free_space
"$nuld" "${reference[@]}" -o "$dir/r.exr" >"$dir/out" 2>"$dir/err" ||
  { fail "the reference after space is freed"; cat "$dir/err"; }
grep -q "^cache rendered" "$dir/out" || fail "the reference after space is freed: $(cat "$dir/out")"
"$nuld" cache verify >"$dir/verify" 2>&1 || fail "the cache after the reference: $(cat "$dir/verify")"
"$nuld" cache clear >/dev/null

# A bank of optimized sets (a few hundred bytes: the disk is full to the
# byte): no entry is committed half-written.
bank=(bank default --backend optimized --spp 4 --opt-instances 2 --opt-epochs 5 --integrator direct --res 16)
fill 0
refused_full "a bank" "$full/cache/sets/" "$nuld" "${bank[@]}"
"$nuld" cache verify >"$dir/verify" 2>&1 || fail "the cache after a failed bank: $(cat "$dir/verify")"
free_space
"$nuld" "${bank[@]}" >"$dir/out" 2>"$dir/err" || { fail "the bank after space is freed"; cat "$dir/err"; }
"$nuld" cache verify >"$dir/verify" 2>&1 || fail "the cache after the bank: $(cat "$dir/verify")"
unset NULD_CACHE

# A study onto the full disk (its cache elsewhere): exit 1 naming a file of
# the study's folder, no image truncated; after space is freed the same
# command finishes.
export NULD_CACHE="$dir/cache"
study=(study render default --backends sobol,independent --spp 4 --repeats 2 --res 32 --integrator direct
  --reference-spp 64 --no-report -q -o "$full/study")
"$nuld" render default --res 32 --reference --spp 64 --integrator direct -q -o "$dir/warm.exr" >/dev/null 2>&1
fill
refused_full "a study" "$full/study" "$nuld" "${study[@]}"
whole_images "a study" "$full"
free_space
"$nuld" "${study[@]}" >"$dir/out" 2>"$dir/err" || { fail "the study after space is freed"; cat "$dir/err"; }
[[ -s "$full/study/render.csv" ]] || fail "the study after space is freed wrote no render.csv"
whole_images "the study after space is freed" "$full"
# Its report onto the full disk: exit 1 naming the file it could not write
# (the comparison page's, written first, or a plot's).
fill
refused_full "a study's report" "$full/study/" "$nuld" study report "$full/study"
whole_images "a study's report" "$full"
[[ -z $(find "$full/study" -name '.*.tmp*') ]] || fail "the report left temporaries"
free_space

# A read-only cache: cache clear removes nothing and says so, exit 1.
export NULD_CACHE="$full/cache"
"$nuld" render default --res 12 --reference --spp 8 --reference-pass-spp 4 -q -o "$dir/ro.exr" >/dev/null 2>&1
if [[ $mounted -eq 1 ]]; then
  mount -o remount,ro "$full"
elif [[ $(id -u) -ne 0 ]]; then
  chmod -R a-w "$full/cache"
fi
if [[ $mounted -eq 1 || $(id -u) -ne 0 ]]; then
  "$nuld" cache clear >"$dir/out" 2>"$dir/err"
  rc=$?
  [[ $rc -eq 1 ]] && grep -q "cannot remove $full/cache/references/" "$dir/err" ||
    { fail "cache clear of a read-only cache: exit $rc"; cat "$dir/out" "$dir/err"; }
  [[ $mounted -eq 1 ]] && mount -o remount,rw "$full" || chmod -R u+w "$full/cache"
else
  echo "note: a read-only cache is not checked (root without mount)"
fi
unset NULD_CACHE

[[ $failures -eq 0 ]] && echo "full disk: all checks passed ($([[ $mounted -eq 1 ]] && echo tmpfs || echo 'ulimit -f'))"
exit $((failures > 0))
