#!/usr/bin/env bash
# A user's sampler plugin end to end (plugins/README.md): built outside the
# tree against plugins/nuld_sampler.h alone, it renders, joins a study as a
# row and ties nuld's own `independent`, which it re-implements; plugins that
# misbehave are refused in words.
# Usage: plugin_test.sh NULD SOURCE_DIR TEST_PLUGIN_DIR C_COMPILER
set -uo pipefail
nuld=$1 source=$2 plugins=$3 cc=$4
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
export NULD_CACHE="$dir/set-cache"
unset NULD_REFERENCE_CACHE  # references beside the sets of this cache
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }
ok() { # ok DESCRIPTION COMMAND...
  local what=$1; shift
  "$@" >"$dir/out" 2>"$dir/err" || { fail "$what: exited $?"; cat "$dir/err"; }
}
refused() { # refused DESCRIPTION PATTERN COMMAND...: exit 1 or 2 with PATTERN in the message
  local what=$1 pattern=$2; shift 2
  "$@" >"$dir/out" 2>"$dir/err"
  local rc=$?
  if [[ $rc -eq 0 || $rc -ge 128 ]] || ! grep -qF -- "$pattern" "$dir/err"; then
    fail "$what: exit $rc, expected a message with '$pattern', got:"; cat "$dir/err"
  fi
}

# Outside the tree, with the header alone, as plugins/README.md says: the
# version-1 example against the version-1 header it was written for (a
# plugin of then, loaded unchanged), and the version-2 one below.
mkdir "$dir/mine" "$dir/latin"
cp "$source/plugins/v1/nuld_sampler.h" "$source/plugins/v1/example_independent.c" "$dir/mine/"
cp "$source/plugins/nuld_sampler.h" "$source/plugins/example_latin.c" "$dir/latin/"
ok "the version-2 example builds against the header alone" \
  "$cc" -std=c99 -O2 -Wall -Werror -shared -fPIC -fvisibility=hidden \
  "$dir/latin/example_latin.c" -o "$dir/latin/liblatin.so"
ok "it renders the cornell box, serving the light and the camera" \
  "$nuld" render cornell --backend "plugin:$dir/latin/liblatin.so:camera,light" --res 32 -q -o "$dir/l.exr"
ok "the example builds against the header alone" \
  "$cc" -std=c99 -O2 -Wall -Werror -shared -fPIC -fvisibility=hidden \
  "$dir/mine/example_independent.c" -o "$dir/mine/libmine.so"
mine="$dir/mine/libmine.so"

ok "it renders the default scene" "$nuld" render default --backend "plugin:$mine" --res 48 -q -o "$dir/p.exr"
ok "the same render again" "$nuld" render default --backend "plugin:$mine" --res 48 -q --threads 1 -o "$dir/p1.exr"
cmp -s "$dir/p.exr" "$dir/p1.exr" 2>/dev/null || "$nuld" compare "$dir/p.exr" "$dir/p1.exr" | grep -q "^mse 0$" ||
  fail "a plugin's render is the same for any thread count"
grep -q "plugin" <("$nuld" help backends) || fail "nuld help backends lists plugin"

# A row of a study, beside the classic word it re-implements: a tie (within
# two standard errors) at two spp.
ok "a study with the plugin as a row" "$nuld" study render default \
  --backends "independent,plugin:$mine" --spp 4,16 --repeats 16 --integrator direct --res 64 \
  --reference-spp 256 --no-report -q -o "$dir/study"
python3 - "$dir/study/render.csv" "plugin:$mine" <<'PY' || fail "the plugin ties independent"
import csv, sys
rows = [r for r in csv.DictReader(open(sys.argv[1])) if r["backend"] == sys.argv[2]]
assert len(rows) == 2, rows
for r in rows:
    assert r["best_classic"] == "independent", r
    q, se = float(r["mse_ratio_best_classic"]), float(r["mse_ratio_best_classic_stderr"])
    print(f"spp {r['spp']}: {q:.3f} +- {se:.3f}")
    assert se > 0 and abs(q - 1) <= 2 * se, r
PY

# Misbehaving plugins, each refused naming the file and what is wrong.
bad="$plugins/libnuld_test_sampler_ok.so"
refused "a NaN" "expected numbers in [0, 1)" "$nuld" render default --backend "plugin:$bad:nan" --res 32 -q -o "$dir/x.exr"
refused "a 1.0" "gave (1," "$nuld" render default --backend "plugin:$bad:one" --res 32 -q -o "$dir/x.exr"
refused "a failed fill" "fill returned 7" "$nuld" render default --backend "plugin:$bad:fail" --res 32 -q -o "$dir/x.exr"
refused "a refusal" "refuses on purpose" "$nuld" render default --backend "plugin:$bad:refuse" --res 32 -q -o "$dir/x.exr"
refused "no entry" "no nuld_sampler_entry" "$nuld" render default --backend "plugin:$plugins/libnuld_test_sampler_no_entry.so" --res 32 -q -o "$dir/x.exr"
refused "another version" "version 99, expected 1" "$nuld" render default --backend "plugin:$plugins/libnuld_test_sampler_version99.so" --res 32 -q -o "$dir/x.exr"
refused "no such file" "$dir/none.so: no such file" "$nuld" render default --backend "plugin:$dir/none.so" --res 32 -q -o "$dir/x.exr"
refused "not a library" "the sampler plugin $source/README.md" "$nuld" render default --backend "plugin:$source/README.md" --res 32 -q -o "$dir/x.exr"
refused "the example's own refusal of arguments" "takes no arguments (got 'x=1')" "$nuld" render default --backend "plugin:$mine:x=1" --res 32 -q -o "$dir/x.exr"
refused "half its points written" "fill returned 0 but left sample" "$nuld" render default --backend "plugin:$bad:half" --res 32 -q -o "$dir/x.exr"
refused "an impure fill" "expected a pure function" "$nuld" render default --backend "plugin:$bad:impure" --res 32 -q -o "$dir/x.exr"
[[ ! -e "$dir/x.exr" ]] || fail "a refused plugin leaves no image"
# A crash cannot be recovered from, but it is named: the process ends by the
# signal (status 139) after a note naming the plugin.
"$nuld" render default --backend "plugin:$bad:crash" --res 32 -q -o "$dir/x.exr" >"$dir/out" 2>"$dir/err"
rc=$?
[[ $rc -eq 139 ]] && grep -qF "the sampler plugin $bad crashed" "$dir/err" ||
  { fail "a crashing plugin: exit $rc, expected 139 and a note naming it:"; cat "$dir/err"; }
[[ ! -e "$dir/x.exr" ]] || fail "a crashed render leaves no image"
# A fill that does not return is noted naming the plugin (here after 1 s).
NULD_PLUGIN_STALL_SECONDS=1 "$nuld" render default --backend "plugin:$bad:stall" --res 8 --spp 1 --threads 1 -q -o "$dir/s.exr" >"$dir/out" 2>"$dir/err" ||
  fail "a stalling plugin's render: exit $?"
grep -qF "the sampler plugin $bad has not returned from fill for 1 s" "$dir/err" ||
  { fail "a stalling plugin is noted by name:"; cat "$dir/err"; }

if [[ $failures -gt 0 ]]; then echo "$failures plugin check(s) failed"; exit 1; fi
echo "plugin checks passed"
