#!/usr/bin/env bash
# End-to-end checks of the nuld command line: the documented commands work and
# bad input fails with a message naming the problem (never a crash).
set -uo pipefail
nuld=$1
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
export NULD_CACHE="$dir/set-cache"  # the studies here make their own sets, not the user's
unset NULD_REFERENCE_CACHE  # references beside the sets of this cache
failures=0

ok() { # ok DESCRIPTION COMMAND...
  local what=$1; shift
  if ! "$@" >"$dir/out" 2>"$dir/err"; then
    echo "FAIL: $what: exited $?"; cat "$dir/err"; failures=$((failures + 1))
  fi
}
fails_with() { # fails_with DESCRIPTION PATTERN COMMAND...
  local what=$1 pattern=$2; shift 2
  "$@" >"$dir/out" 2>"$dir/err"
  local rc=$?
  if [[ $rc -eq 0 || $rc -ge 128 ]] || ! grep -q -- "$pattern" "$dir/err"; then
    echo "FAIL: $what: exit $rc, expected a message matching '$pattern', got:"; cat "$dir/err"
    failures=$((failures + 1))
  fi
}

# exits_with STATUS DESCRIPTION COMMAND...: the exit-code rule (docs/usage.md):
# 2 for a command line refused as written, 1 for what it names that cannot
# be used.
exits_with() {
  local status=$1 what=$2; shift 2
  "$@" >"$dir/out" 2>"$dir/err"
  local rc=$?
  if [[ $rc -ne $status ]]; then
    echo "FAIL: $what: exit $rc, expected $status:"; cat "$dir/err"; failures=$((failures + 1))
  fi
}
exits_with 2 "a zero side of --res" "$nuld" render default --res 0x10 -q -o "$dir/x.exr"
exits_with 2 "--spp 0" "$nuld" render default --spp 0 -q -o "$dir/x.exr"
exits_with 2 "--res-scale 0 of a study" "$nuld" study render default --res-scale 0 -o "$dir/x"
exits_with 2 "an unknown backend" "$nuld" render default --backend sobl -q -o "$dir/x.exr"
exits_with 2 "an option that does not apply" "$nuld" render default --assets "$dir" -q -o "$dir/x.exr"
exits_with 1 "a scene file that does not exist" "$nuld" render "$dir/none.json" -q -o "$dir/x.exr"
exits_with 1 "an image target whose file does not exist" "$nuld" generate --n 4 --target "image:$dir/none.png" -o "$dir/x.txt"

ok "help" "$nuld" help
grep -q "optimize" "$dir/out" || { echo "FAIL: help lists the subcommands"; failures=$((failures + 1)); }
ok "help optimize" "$nuld" help optimize
grep -q -- "--target" "$dir/out" || { echo "FAIL: help optimize prints optimize's options"; failures=$((failures + 1)); }
ok "help study render" "$nuld" help study render
grep -q -- "--backends" "$dir/out" || { echo "FAIL: help study render prints its options"; failures=$((failures + 1)); }
ok "generate sobol" "$nuld" generate --sequence sobol --n 100 --instances 3 -o "$dir/s.txt"
ok "generate mapped halton" "$nuld" generate --sequence halton --n 64 --target quarterdisc -o "$dir/q.ptsb"
# The blue-noise baselines, each way, and their options refused elsewhere.
ok "generate sot" "$nuld" generate --sequence sot --n 37 --iterations 20 --target quarterdisc -q -o "$dir/sot.txt"
ok "generate gbn-mapped" "$nuld" generate --sequence gbn-mapped --n 37 --iterations 20 --target quarterdisc -q -o "$dir/gbn.txt"
ok "generate gbn toroidal" "$nuld" generate --sequence gbn --boundary toroidal --n 16 --iterations 5 --instances 2 -q -o "$dir/gbnt.txt"
ok "eval sot" "$nuld" eval "$dir/sot.txt" --target quarterdisc
ok "generate sot in the square" "$nuld" generate --sequence sot --uniform-domain square --n 20 --iterations 10 -q -o "$dir/sotsq.txt"
grep -q "uniform_domain=square" "$dir/sotsq.txt" || { echo "FAIL: sot records its uniform domain"; failures=$((failures + 1)); }
fails_with "uniform domain without sot" "applies to --sequence sot" "$nuld" generate --sequence gbn --uniform-domain disc --n 4 -o "$dir/x.txt"
fails_with "sigma without gbn" "applies to --sequence gbn" "$nuld" generate --sequence sot --sigma 2 --n 4 -o "$dir/x.txt"
fails_with "iterations without blue noise" "applies to the blue-noise" "$nuld" generate --iterations 3 --n 4 -o "$dir/x.txt"
fails_with "toroidal gbn for a target" "toroidal variant is for the uniform" "$nuld" generate --sequence gbn --boundary toroidal --target quarterdisc --n 4 -o "$dir/x.txt"
fails_with "gbn bad sigma" "sigma must be" "$nuld" generate --sequence gbn --sigma 0 --n 4 -o "$dir/x.txt"
ok "eval" "$nuld" eval "$dir/s.txt"
grep -q '^l2star [0-9.e-]*$' "$dir/out" || { echo "FAIL: eval output lines"; cat "$dir/out"; failures=$((failures + 1)); }
[[ $(wc -l <"$dir/out") -eq 5 ]] && grep -q "^l2per " "$dir/out" || { echo "FAIL: eval all prints 5 metrics on a uniform set (l2per included)"; failures=$((failures + 1)); }
ok "eval target from metadata" "$nuld" eval "$dir/q.ptsb" --metric dstar --integrand disc
grep -q '^integration_rmse' "$dir/out" || { echo "FAIL: integrand output"; failures=$((failures + 1)); }
ok "help targets" "$nuld" help targets
grep -q "gaussian:mx,my,sigma" "$dir/out" && grep -q "disney\[:KEY=VALUE" "$dir/out" && grep -q "family:disney" "$dir/out" ||
  { echo "FAIL: help targets lists the target grammar"; failures=$((failures + 1)); }
ok "help backends" "$nuld" help backends
grep -q "sobol-tabulated" "$dir/out" && grep -q "optimized-both" "$dir/out" ||
  { echo "FAIL: help backends lists the backends"; failures=$((failures + 1)); }
# export: the instances of a text file kept apart, for numpy
ok "export npy" "$nuld" export "$dir/s.txt" -o "$dir/s.npy"
ok "export csv" "$nuld" export "$dir/s.txt" -o "$dir/s.csv"
[[ $(head -1 "$dir/s.csv") == "instance,x,y" && $(wc -l <"$dir/s.csv") -eq 301 ]] ||
  { echo "FAIL: export csv has a header and one line per point"; failures=$((failures + 1)); }
if [[ -x /usr/bin/python3 ]] && /usr/bin/python3 -c "import numpy" 2>/dev/null; then
  /usr/bin/python3 -c "
import numpy as np, sys
a = np.load(sys.argv[1]); c = np.loadtxt(sys.argv[2], delimiter=',', skiprows=1)
assert a.shape == (3, 100, 2) and a.dtype == np.float64, a.shape
assert np.array_equal(c[:, 1:].reshape(3, 100, 2), a) and np.array_equal(c[::100, 0], [0, 1, 2])
" "$dir/s.npy" "$dir/s.csv" || { echo "FAIL: numpy reads the export"; failures=$((failures + 1)); }
fi
fails_with "export to an unknown format" "expected a name ending in .npy, .csv or .dat" "$nuld" export "$dir/s.txt" -o "$dir/s.xyz"
ok "plot" "$nuld" plot "$dir/q.ptsb" -o "$dir/q.png"
[[ -s "$dir/q.png" ]] || { echo "FAIL: plot wrote nothing"; failures=$((failures + 1)); }
ok "spectrum" "$nuld" spectrum "$dir/s.txt" -o "$dir/ps.png" --csv "$dir/ps.csv" --half-size 8
[[ $(head -1 "$dir/ps.csv") == "frequency,power" ]] || { echo "FAIL: spectrum csv header"; failures=$((failures + 1)); }

fails_with "unknown target" "unknown target 'blob'" "$nuld" generate --n 4 --target blob -o "$dir/x.txt"
fails_with "bad target numbers" "'x' is not a number" "$nuld" generate --n 4 --target gaussian:0.5,x,0.1 -o "$dir/x.txt"
fails_with "missing image" "nope.png" "$nuld" generate --n 4 --target image:"$dir/nope.png" -o "$dir/x.txt"
printf '0.1 0.2\n0.3\n' >"$dir/bad.txt"
fails_with "malformed point file" "bad.txt:2" "$nuld" eval "$dir/bad.txt"
fails_with "missing point file" "missing.txt" "$nuld" eval "$dir/missing.txt"
fails_with "output directory missing" "does not exist" "$nuld" generate --n 4 -o "$dir/no/dir/x.txt"
fails_with "bad N" "n" "$nuld" generate --n 0 -o "$dir/x.txt"

# optimize: an interrupted and resumed run ends identical to an uninterrupted one.
opt=(--target quarterdisc --n 32 --epochs 40 --boxes 512 --instances 2 --seed 5 -q)
ok "optimize" "$nuld" optimize "${opt[@]}" -o "$dir/full.txt"
ok "optimize, stopped" "$nuld" optimize "${opt[@]}" --stop-after 17 -o "$dir/resumed.txt"
[[ -f "$dir/resumed.txt.ckpt" && ! -f "$dir/resumed.txt" ]] || { echo "FAIL: stop-after leaves only a checkpoint"; failures=$((failures + 1)); }
# A rerun without --resume or --fresh never discards the checkpoint.
cp "$dir/resumed.txt.ckpt" "$dir/kept.ckpt"
fails_with "optimize over a checkpoint" "pass --resume to continue it, or --fresh" \
  "$nuld" optimize "${opt[@]}" -o "$dir/resumed.txt"
cmp -s "$dir/resumed.txt.ckpt" "$dir/kept.ckpt" || { echo "FAIL: the refused rerun changed the checkpoint"; failures=$((failures + 1)); }
ok "optimize, resumed" "$nuld" optimize "${opt[@]}" --resume -o "$dir/resumed.txt"
cmp -s "$dir/full.txt" "$dir/resumed.txt" || { echo "FAIL: resumed run differs from the uninterrupted one"; failures=$((failures + 1)); }
[[ ! -f "$dir/resumed.txt.ckpt" ]] || { echo "FAIL: checkpoint left after completion"; failures=$((failures + 1)); }
grep -q '^# final_metrics: l2asd=' "$dir/full.txt" || { echo "FAIL: final metrics metadata"; failures=$((failures + 1)); }
ok "optimize, stopped early" "$nuld" optimize "${opt[@]}" --stop-after 5 -o "$dir/o.txt"
fails_with "optimize resume with other settings" "other settings" \
  "$nuld" optimize --target quarterdisc --n 32 --epochs 40 --boxes 512 --instances 2 --seed 6 -q --resume -o "$dir/o.txt"
fails_with "optimize unknown target" "unknown target 'disk'" "$nuld" optimize --target disk --n 8 -o "$dir/x.txt"
# eval checks the integrand's name before printing any metric, refuses
# sphere sets for the square's integrands and says when the target misses
# part of the integrand's mass.
fails_with "eval unknown integrand" "unknown integrand 'foo'" "$nuld" eval "$dir/full.txt" --integrand foo
[[ ! -s "$dir/out" ]] || { echo "FAIL: eval printed metrics before refusing the integrand"; cat "$dir/out"; failures=$((failures + 1)); }
"$nuld" eval "$dir/full.txt" --integrand step >/dev/null 2>"$dir/err"
grep -q "has no density where step holds" "$dir/err" || { echo "FAIL: eval of quarterdisc sets against step names the missed mass"; cat "$dir/err"; failures=$((failures + 1)); }
fails_with "optimize bad mass" "expected mc:K" "$nuld" optimize --target uniform --n 8 --mass mc:lots -o "$dir/x.txt"
fails_with "optimize bad lr" "learning rates" "$nuld" optimize --target uniform --n 8 --lr -3 -o "$dir/x.txt"
fails_with "optimize unreadable image" "nope.exr" "$nuld" optimize --target image:"$dir/nope.exr" --n 8 -o "$dir/x.txt"
fails_with "optimize unknown preset" "unknown preset" "$nuld" optimize --target uniform --n 8 --preset turbo -o "$dir/x.txt"
# Enum options are checked against their name tables, aliases included, with
# the tables' one message.
fails_with "optimize unknown box kind" "--box-kind: unknown box kind 'cube' (expected multicorner, anchored or twopoint)" "$nuld" optimize --target uniform --n 8 --box-kind cube -o "$dir/x.txt"
ok "optimize box kind alias" "$nuld" optimize --target uniform --n 8 --epochs 2 --boxes 64 --box-kind two-point -q -o "$dir/alias.txt"
grep -q '^# settings: .*box_kind=twopoint ' "$dir/alias.txt" || { echo "FAIL: an alias is recorded by its name"; failures=$((failures + 1)); }
fails_with "generate unknown scrambling" "unknown scrambling 'xor' (expected owen, shift, cp, baker or none)" "$nuld" generate --sequence sobol --scramble xor --n 4 -o "$dir/x.txt"
fails_with "render unknown integrator" "unknown integrator 'mis' (expected path, direct, light or bsdf)" "$nuld" render default --integrator mis -q -o "$dir/x.exr"

# Rendering: the built-in scene needs no files; compare prints mse and relmse.
ok "render default" "$nuld" render default --spp 2 --res 16x12 -q -o "$dir/a.exr"
grep -q '^rejected_samples 0$' "$dir/out" || { echo "FAIL: render reports rejected samples"; failures=$((failures + 1)); }
[[ -s "$dir/a.exr" && -s "$dir/a.png" ]] || { echo "FAIL: render wrote no EXR + PNG"; failures=$((failures + 1)); }
ok "render halton direct" "$nuld" render default --backend halton --integrator direct --spp 4 --res 16x12 -q -o "$dir/b.exr"
ok "render sobol-tabulated bsdf" "$nuld" render default --backend sobol-tabulated --integrator bsdf --spp 4 --res 16x12 -q -o "$dir/t.exr"
grep -q '^classic_fallbacks 0$' "$dir/out" && grep -q '^setup_seconds ' "$dir/out" ||
  { echo "FAIL: render reports fallbacks and setup"; cat "$dir/out"; failures=$((failures + 1)); }
ok "compare" "$nuld" compare "$dir/b.exr" "$dir/a.exr" --error-map "$dir/err.png"
grep -q '^mse [0-9.e+-]*$' "$dir/out" && grep -q '^relmse [0-9.e+-]*$' "$dir/out" &&
  grep -q '^mse_winsorized [0-9.e+-]*$' "$dir/out" && grep -q '^top_share [0-9.e+-]*$' "$dir/out" ||
  { echo "FAIL: compare output"; cat "$dir/out"; failures=$((failures + 1)); }
[[ -s "$dir/err.png" ]] || { echo "FAIL: compare wrote no error map"; failures=$((failures + 1)); }
# FLIP: HDR-FLIP with its exposures (EXRs), LDR-FLIP (PNGs), 0 against itself.
grep -q "^flip 0\.[0-9]" "$dir/out" && grep -q "^flip_exposures " "$dir/out" && [[ -s "$dir/b_flip.png" ]] ||
  { echo "FAIL: compare printed no HDR flip or map"; cat "$dir/out"; failures=$((failures + 1)); }
"$nuld" compare "$dir/b.png" "$dir/a.png" --error-map "$dir/e2.png" --flip-map "$dir/f2.png" >"$dir/out2" 2>/dev/null
grep -q "^flip 0\.[0-9]" "$dir/out2" && ! grep -q "^flip_exposures" "$dir/out2" && [[ -s "$dir/f2.png" ]] ||
  { echo "FAIL: compare printed no LDR flip"; cat "$dir/out2"; failures=$((failures + 1)); }
"$nuld" compare "$dir/a.exr" "$dir/a.exr" --error-map "$dir/e3.png" --flip-map "$dir/f3.png" >"$dir/out3"
grep -qx "flip 0" "$dir/out3" || { echo "FAIL: FLIP of an image against itself"; failures=$((failures + 1)); }
ok "generate disney target" "$nuld" generate --n 16 --target disney:roughness=0.3 -o "$dir/d.txt"
"$nuld" generate --sequence sobol --n 4 --instances 2 -o "$dir/u4.txt" >/dev/null 2>&1
ok "render optimized:FILE" "$nuld" render default --backend optimized:"$dir/u4.txt" --spp 4 --res 8 -q -o "$dir/c.exr"
# Every word `nuld help backends` prints, its aliases included, renders and
# joins both studies (PATHS: a point-set file, MODEL: a tiny uniform model).
"$nuld" train --target uniform --n 4 --hidden 8 --steps 2 --batch 2 --boxes 64 -q -o "$dir/u4.nuldnet" >/dev/null 2>&1
"$nuld" help backends >"$dir/backends.txt"
# The first section lists the words that serve everywhere; the last, those
# of study integrate alone.
words=$( (sed -n '/^Renders only/q;/^  [a-z]/p' "$dir/backends.txt" | awk '{print $1}'
  sed -n '/^Renders only/q;p' "$dir/backends.txt" | tr '\n' ' ' | grep -o 'also: [^)]*' | cut -d' ' -f2-) |
  sed -e 's|\[:\([A-Z]*\)\]|:\1|g' -e "s|PATHS|$dir/u4.txt|" -e "s|MODEL|$dir/u4.nuldnet|" | tr ' ' '\n' | grep -v '^$')
integrateOnly=$(sed -n '/^study integrate only/,$p' "$dir/backends.txt" | sed -n '/^  [a-z]/p' | awk '{print $1}')
[[ $(echo "$integrateOnly" | wc -l) -ge 4 ]] || { echo "FAIL: help backends lists the integration study's words"; failures=$((failures + 1)); }
[[ $(echo "$words" | wc -l) -ge 9 ]] || { echo "FAIL: help backends lists the registry's words"; echo "$words"; failures=$((failures + 1)); }
for word in $words; do
  ok "render --backend $word" "$nuld" render default --backend "$word" --spp 4 --res 8 -q -o "$dir/w.exr"
done
# `neural` alone is the shipped Disney-family model.
ok "render --backend neural (shipped model)" "$nuld" render default --backend neural --spp 4 --res 8 -q -o "$dir/w.exr"
# LibTorch is loaded by the process that makes a model's banks, and not by a
# later one that finds them all in the set cache (sampler/neural/neural_runtime.h).
for run in cold warm; do
  NULD_CACHE="$dir/neural-cache" LD_DEBUG=files "$nuld" render default --backend neural --spp 4 \
    --res 8 -q -o "$dir/n-$run.exr" >/dev/null 2>"$dir/ld-$run.txt" ||
    { echo "FAIL: render --backend neural ($run cache)"; failures=$((failures + 1)); }
done
grep -q "libnuld_torch.so" "$dir/ld-cold.txt" ||
  { echo "FAIL: the first neural render loads LibTorch's plugin"; failures=$((failures + 1)); }
grep -q "libnuld_torch.so" "$dir/ld-warm.txt" &&
  { echo "FAIL: a neural render from cached banks loads LibTorch"; failures=$((failures + 1)); }
idiff -q -fail 0 -warn 0 "$dir/n-cold.exr" "$dir/n-warm.exr" >/dev/null 2>&1 ||
  { echo "FAIL: the neural render from cached banks differs"; failures=$((failures + 1)); }
# The study's own words render too, making their sets into the set cache
# (the second time finding them there) and saying per pair what they served.
sets=(--opt-instances 2 --opt-epochs 5 --opt-lobe-epochs 5)
for word in optimized optimized-uniform optimized-bsdf optimized-both optimized-both+shift; do
  ok "render --backend $word" "$nuld" render default --backend "$word" --spp 4 --res 8 "${sets[@]}" -q -o "$dir/w.exr"
done
"$nuld" render default --backend optimized-both --spp 4 --res 8 "${sets[@]}" -q -o "$dir/w.exr" >"$dir/out" 2>&1
grep -q '^sets_made 0$' "$dir/out" && grep -q '^served_light [1-9]' "$dir/out" && grep -q '^served_bsdf [1-9]' "$dir/out" ||
  { echo "FAIL: a second optimized-both render finds its sets and serves both pairs"; cat "$dir/out"; failures=$((failures + 1)); }
# Fallbacks in words: a BSDF-only backend prints no light counters, and a
# learned backend that served less than all of its contexts says so once.
"$nuld" render default --backend optimized-bsdf --spp 4 --res 8 "${sets[@]}" -q -o "$dir/w.exr" >"$dir/out" 2>&1
grep -q '^served_bsdf [1-9]' "$dir/out" && ! grep -q '_light ' "$dir/out" ||
  { echo "FAIL: optimized-bsdf prints its bsdf counters and no light ones"; cat "$dir/out"; failures=$((failures + 1)); }
# (A family:disney model of the default scene's skin material, which serves
# that material's tables and no other's, every bin through its table.)
"$nuld" train --arch graph --target 'family:disney:basecolor=0.9/0.85/0.8,metallic=0,subsurface=0.8,specular=0.5,roughness=0.6,anisotropic=0,sheen=0.5,clearcoatgloss=1,res=64,mix=1' \
  --n 4 --hidden 8 --steps 2 --batch 2 --boxes 64 -q -o "$dir/skin.nuldnet" >/dev/null 2>&1
"$nuld" render default --backend neural:"$dir/skin.nuldnet" --lobe-routes table --spp 4 --res 16 -q -o "$dir/w.exr" >"$dir/out" 2>"$dir/err"
[[ $(grep -c '^nuld: note: neural:[^ ]* served [0-9]* % of its first-bounce contexts (bsdf [0-9]* of [0-9]*); the rest' "$dir/err") -eq 1 &&
   $(grep -c 'note' "$dir/err") -eq 1 ]] && grep -q '^fell_back_bsdf [1-9]' "$dir/out" ||
  { echo "FAIL: neural, serving part of its contexts, says so in one note"; cat "$dir/out" "$dir/err"; failures=$((failures + 1)); }
ok "bank" "$nuld" bank default --backend optimized-both --spp 4 --res 8 "${sets[@]}" -q -o "$dir/bankdir"
ok "render a bank directory" "$nuld" render default --backend optimized:"$dir/bankdir" --spp 4 --res 8 -q -o "$dir/w.exr"
# One seed default: with no --seed, a render finds the sets a bank made (a
# fresh cache, so that nothing above made them), and says so in a sentence.
NULD_CACHE="$dir/seed-cache" "$nuld" bank default --spp 4 --res 8 "${sets[@]}" -q >/dev/null 2>&1
NULD_CACHE="$dir/seed-cache" "$nuld" render default --backend optimized-both --spp 4 --res 8 "${sets[@]}" -q -o "$dir/w.exr" >"$dir/out" 2>"$dir/err"
grep -q '^sets_made 0$' "$dir/out" && grep -q '^setup_seconds ' "$dir/out" && ! grep -q '^sets_seconds' "$dir/out" &&
  grep -q '^nuld: optimized-both: its [1-9][0-9]* sets came from the set cache$' "$dir/err" ||
  { echo "FAIL: a render after nuld bank makes no set and says they came from the cache"; cat "$dir/out" "$dir/err"; failures=$((failures + 1)); }
# nuld bank after a render that made the sets: they came from the cache, and
# only sets this command made read "made". The listing (nuld bank and nuld
# cache list alike) shows seed and epochs, and each lobe target whole: rows
# whose targets share a long prefix differ.
export NULD_CACHE="$dir/list-cache"
"$nuld" render default --backend optimized-both --spp 4 --res 8 "${sets[@]}" --seed 3 -q -o "$dir/w.exr" >/dev/null 2>&1
"$nuld" bank default --spp 4 --res 8 "${sets[@]}" --seed 3 -q >"$dir/out" 2>"$dir/err"
head -1 "$dir/out" | grep -q '^spp  *pair  *state  *n  *instances  *seed  *epochs  *optimize_s  *size  *age  *kind  *nested  *union  *key  *target$' &&
  grep -q '^4  *light  *cached  *4  *2  *3  *5 .* envmap-compensated:procedural-sky$' "$dir/out" &&
  [[ $(grep -c '^4  *bsdf  *cached  *4  *2  *3  *5 .* disney:' "$dir/out") -ge 2 ]] && ! grep -q ' made ' "$dir/out" &&
  [[ -z $(grep ' bsdf ' "$dir/out" | awk '{print $NF}' | sort | uniq -d) ]] ||
  { echo "FAIL: nuld bank after a render lists its sets as cached, with seed, epochs and whole targets"; cat "$dir/out" "$dir/err"; failures=$((failures + 1)); }
"$nuld" bank default --backend optimized --spp 4 --res 8 --opt-instances 2 --opt-epochs 6 --seed 4 -q >"$dir/out" 2>&1
grep -q '^4  *light  *made  *4  *2  *4  *6 .* envmap-compensated:procedural-sky$' "$dir/out" ||
  { echo "FAIL: nuld bank says made for a set it made"; cat "$dir/out"; failures=$((failures + 1)); }
# --opt-nested with several --spp: one nested bank of the largest serves
# them all (made for the first, found for the second).
"$nuld" bank default --backend optimized --spp 4,8 --res 8 --opt-nested --opt-instances 2 --opt-epochs 6 --seed 5 -q >"$dir/nested" 2>&1
grep -q '^4  *light  *made  *8  *2  *5  *6 ' "$dir/nested" && grep -q '^8  *light  *cached  *8  *2  *5  *6 ' "$dir/nested" &&
  [[ $(grep ' light ' "$dir/nested" | awk '{print $(NF-1)}' | sort -u | wc -l) -eq 1 ]] ||
  { echo "FAIL: nuld bank --opt-nested makes one nested bank for all its --spp"; cat "$dir/nested"; failures=$((failures + 1)); }
"$nuld" cache list >"$dir/out" 2>&1
head -1 "$dir/out" | grep -q '^n  *instances  *seed  *epochs ' &&
  [[ $(grep 'envmap-compensated:procedural-sky$' "$dir/out" | awk '{print $3 "/" $4}' | sort | tr '\n' ' ') == "3/5 4/6 5/6 " ]] &&
  [[ -z $(grep 'disney:' "$dir/out" | awk '{print $NF}' | sort | uniq -d) ]] ||
  { echo "FAIL: nuld cache list tells rows of one target apart by seed and epochs, and shows whole targets"; cat "$dir/out"; failures=$((failures + 1)); }
# ... and tells a nested bank and the bank term's weight from the default
# sets, and lists a checkpoint left behind with its size.
grep -q ' 5  *6 .* optimized  *4,8  *3  *[0-9a-f]\{16\}  *envmap-compensated:procedural-sky$' "$dir/out" &&
  grep -q ' 4  *6 .* optimized  *-  *3  *[0-9a-f]\{16\}  *envmap-compensated:procedural-sky$' "$dir/out" ||
  { echo "FAIL: nuld cache list shows each entry's kind, nesting and union weight"; cat "$dir/out"; failures=$((failures + 1)); }
printf 'x%.0s' {1..2000} >"$NULD_CACHE/sets/left_n4_0123456789abcdef.ptsb.ckpt"
"$nuld" cache list >"$dir/out" 2>&1
grep -q '^1 checkpoint of sets being made or left by an interrupted run' "$dir/out" &&
  grep -q '^  2.0 KiB  [0-9]*s  left_n4_0123456789abcdef.ptsb.ckpt$' "$dir/out" ||
  { echo "FAIL: nuld cache list shows stale checkpoints with their size"; cat "$dir/out"; failures=$((failures + 1)); }
rm "$NULD_CACHE/sets/left_n4_0123456789abcdef.ptsb.ckpt"
export NULD_CACHE="$dir/set-cache"
# Sets for the MIS tables serve nothing under BSDF sampling alone through the
# tables, whose density differs between the two.
fails_with "a learned backend that serves nothing" "served no first-bounce sample" \
  "$nuld" render default --backend optimized:"$dir/bankdir" --spp 4 --res 8 --integrator bsdf --lobe-routes table -q -o "$dir/x.exr"
ok "study render every backend word" "$nuld" study render default --backends "$(echo $words | tr ' ' ',')" \
  --spp 4 --res 8 --repeats 1 --reference-spp 16 --no-report -q -o "$dir/words.study"
[[ $(tail -n +2 "$dir/words.study/render.csv" | wc -l) -eq $(echo "$words" | wc -l) ]] ||
  { echo "FAIL: the study has a row per backend word"; cat "$dir/words.study/render.csv"; failures=$((failures + 1)); }
# The integration study refuses a model of no integrand's target: there a
# quarterdisc model stands for MODEL.
"$nuld" train --target quarterdisc --n 4 --hidden 8 --steps 2 --batch 2 --boxes 64 -q -o "$dir/q4.nuldnet" >/dev/null 2>&1
ok "study integrate every backend word" "$nuld" study integrate --integrands 'quarterdisc*bilinear' \
  --samplers "$(echo $words $integrateOnly | sed "s|$dir/u4.nuldnet|$dir/q4.nuldnet|g" | tr ' ' ',')" --n 4 \
  --instances 4 --optimized-instances 4 --no-plots -q -o "$dir/words.integrate"

fails_with "render spp mismatch" "use --spp 4" "$nuld" render default --backend optimized:"$dir/u4.txt" --spp 8 --res 8 -q -o "$dir/x.exr"
fails_with "render unknown backend" "unknown backend 'sobel'" "$nuld" render default --backend sobel -q -o "$dir/x.exr"
fails_with "render bad resolution" "expected W or WxH" "$nuld" render default --res 12by4 -q -o "$dir/x.exr"
echo '{"camera": {"eye": [0, 1, 5], "look_at": [0, 0, 0], "fov": 40},' >"$dir/bad.json"
fails_with "render malformed json" "bad.json: malformed JSON" "$nuld" render "$dir/bad.json" -q -o "$dir/x.exr"
cat >"$dir/scene.json" <<'JSON'
{"camera": {"eye": [0, 1, 5], "look_at": [0, 0, 0], "fov": 40},
 "materials": {"default": {"type": "lambertian"}},
 "meshes": [{"file": "missing/mesh.ply"}]}
JSON
fails_with "render missing mesh" "mesh.ply' does not exist" "$nuld" render "$dir/scene.json" --assets "$dir" -q -o "$dir/x.exr"
echo "not an image" >"$dir/sky.exr"
cat >"$dir/scene2.json" <<'JSON'
{"camera": {"eye": [0, 1, 5], "look_at": [0, 0, 0], "fov": 40},
 "environment": {"file": "sky.exr"},
 "materials": {"default": {"type": "lambertian"}},
 "meshes": [{"shape": "sphere"}]}
JSON
fails_with "render unreadable map" "sky.exr" "$nuld" render "$dir/scene2.json" --assets "$dir" -q -o "$dir/x.exr"
fails_with "compare size mismatch" "differ in size" "$nuld" compare "$dir/c.exr" "$dir/a.exr"

# Neural generator: train a tiny model, stop and resume, generate from it.
ok "train tiny" "$nuld" train --target family:gaussian --n 8 --hidden 8 --steps 6 --batch 2 --boxes 64 --stop-after 3 -q -o "$dir/g.nuldnet"
[[ -f "$dir/g.nuldnet.ckpt" && ! -f "$dir/g.nuldnet" ]] || { echo "FAIL: train --stop-after leaves a checkpoint only"; failures=$((failures + 1)); }
ok "train resume" "$nuld" train --target family:gaussian --n 8 --hidden 8 --steps 6 --batch 2 --boxes 64 --resume -q -o "$dir/g.nuldnet"
grep -q '^mlp_seconds' "$dir/out" || { echo "FAIL: train prints the time split"; failures=$((failures + 1)); }
# Held-out validation at every checkpoint (every step here), untrained first,
# each step once across the stop and the resume.
[[ $(cut -d, -f1 "$dir/g.nuldnet.validation.csv" | tail -n +2 | tr '\n' ' ') == "0 1 2 3 4 5 6 " ]] && head -1 "$dir/g.nuldnet.validation.csv" | grep -q '^step,mean_train_loss,validation_l2$' \
  || { echo "FAIL: train writes the held-out curve"; cat "$dir/g.nuldnet.validation.csv"; failures=$((failures + 1)); }
grep -q '^kept best$' "$dir/out" && grep -q '^best_step [0-6]$' "$dir/out" && [[ ! -e "$dir/g.nuldnet.best" ]] \
  || { echo "FAIL: train keeps the best held-out weights"; cat "$dir/out"; failures=$((failures + 1)); }
ok "train keep last" "$nuld" train --target quarterdisc --n 8 --hidden 8 --steps 4 --batch 2 --boxes 64 --keep last -q -o "$dir/l.nuldnet"
grep -q '^kept last$' "$dir/out" && [[ -f "$dir/l.nuldnet" && ! -e "$dir/l.nuldnet.best" ]] || { echo "FAIL: train --keep last"; cat "$dir/out"; failures=$((failures + 1)); }
ok "train balanced" "$nuld" train --target quarterdisc --n 8 --hidden 8 --steps 2 --batch 2 --boxes 64 --gradient balanced -q -o "$dir/b.nuldnet"
fails_with "train unknown gradient" "gradient" "$nuld" train --target quarterdisc --n 8 --steps 2 --gradient natural -q -o "$dir/x.nuldnet"
ok "train no validation" "$nuld" train --target quarterdisc --n 8 --hidden 8 --steps 2 --batch 2 --boxes 64 --validation 0 -q -o "$dir/v.nuldnet"
[[ -f "$dir/v.nuldnet" && ! -e "$dir/v.nuldnet.validation.csv" ]] && ! grep -q '^kept' "$dir/out" || { echo "FAIL: train --validation 0"; failures=$((failures + 1)); }
ok "generate --model" "$nuld" generate --model "$dir/g.nuldnet" --gamma 0.5,0.5,0.2 --instances 3 -o "$dir/ng.txt"
ok "eval neural set" "$nuld" eval "$dir/ng.txt" --metric l2
fails_with "generate --model with a sequence" "does not apply to --model" "$nuld" generate --model "$dir/g.nuldnet" --sequence halton --gamma 0.5,0.5,0.2 -o "$dir/x.txt"
fails_with "generate --model without gamma" "needs 3 --gamma values" "$nuld" generate --model "$dir/g.nuldnet" -o "$dir/x.txt"
fails_with "generate --model gamma range" "must lie in \[0, 1\]" "$nuld" generate --model "$dir/g.nuldnet" --gamma 0.5,0.5,2 -o "$dir/x.txt"
head -c 100 "$dir/g.nuldnet" >"$dir/cut.nuldnet"
fails_with "generate truncated model" "cut.nuldnet" "$nuld" generate --model "$dir/cut.nuldnet" -o "$dir/x.txt"
fails_with "generate foreign model" "not a nuld model file" "$nuld" generate --model "$dir/s.txt" -o "$dir/x.txt"
# The graph generator: train, generate; its options refused for the supplement's net.
ok "train graph" "$nuld" train --arch graph --discrepancy-gradient --stages 2 --target quarterdisc --n 12 --hidden 8 --steps 3 --batch 2 --boxes 64 -q -o "$dir/gr.nuldnet"
ok "generate graph" "$nuld" generate --model "$dir/gr.nuldnet" --instances 3 -o "$dir/gr.txt"
ok "train graph, Owen base" "$nuld" train --arch graph --base owen --target quarterdisc --n 12 --hidden 8 --steps 3 --batch 2 --boxes 64 -q -o "$dir/gro.nuldnet"
ok "generate graph, Owen base" "$nuld" generate --model "$dir/gro.nuldnet" --instances 3 -o "$dir/gro.txt"
ok "train graph, several sizes" "$nuld" train --arch graph --base owen --target quarterdisc --n 12,20 --hidden 8 --steps 4 --batch 2 --boxes 64 --validation 2 -q -o "$dir/grm.nuldnet"
ok "generate graph at an untrained N" "$nuld" generate --model "$dir/grm.nuldnet" --n 30 --instances 2 -o "$dir/grm30.txt"
grep -q "trained at N = 12,20; sets of 30 points extrapolate" "$dir/err" && [[ $(grep -vc '^#' "$dir/grm30.txt") -eq 60 ]] \
  || { echo "FAIL: a graph model makes sets of an untrained N and says so"; cat "$dir/err"; failures=$((failures + 1)); }
fails_with "the supplement's net at another N" "makes sets of 8 points only, not 9" "$nuld" generate --model "$dir/g.nuldnet" --n 9 --gamma 0.5,0.5,0.2 -o "$dir/x.txt"
fails_with "several sizes for the supplement's net" "several sizes need --arch graph" "$nuld" train --target quarterdisc --n 8,16 --steps 2 -q -o "$dir/x.nuldnet"
fails_with "bad size list" "expected positive integers separated by commas" "$nuld" train --arch graph --target quarterdisc --n 8,x --steps 2 -q -o "$dir/x.nuldnet"
fails_with "Owen base for the supplement's net" "applies to --arch graph only" "$nuld" train --base owen --target quarterdisc --n 8 --steps 2 -q -o "$dir/x.nuldnet"
fails_with "graph option without --arch graph" "applies to --arch graph only" "$nuld" train --target quarterdisc --n 8 --steps 2 --stages 2 -q -o "$dir/x.nuldnet"
# The periodic objective and shifted mapping.
ok "optimize l2per" "$nuld" optimize --target uniform --n 16 --objective l2per --epochs 20 -q -o "$dir/per.txt"
ok "eval l2per" "$nuld" eval "$dir/per.txt" --metric l2per
ok "map --shifts" "$nuld" map "$dir/per.txt" --target quarterdisc --shifts 3 --seed 2 -o "$dir/per3.txt"
[[ $(grep -vc '^#' "$dir/per3.txt") -eq 48 ]] || { echo "FAIL: map --shifts writes K sets per input set"; failures=$((failures + 1)); }
ok "optimize l2asd bank term" "$nuld" optimize --target uniform --n 8 --instances 4 --objective l2asd --union-weight 4 --epochs 20 -q -o "$dir/bank.txt"
grep -q 'union=4/4' "$dir/bank.txt" || { echo "FAIL: the bank term is recorded in the settings"; failures=$((failures + 1)); }
fails_with "bank term with soft boxes" "l2asd objective only" "$nuld" optimize --target uniform --n 8 --instances 4 --union-weight 1 --epochs 2 -q -o "$dir/x.txt"
fails_with "bank term with one instance" "needs >= 2 instances" "$nuld" optimize --target uniform --n 8 --objective l2asd --union-weight 1 --epochs 2 -q -o "$dir/x.txt"
fails_with "l2per on a non-uniform target" "not uniform" "$nuld" optimize --target quarterdisc --n 16 --objective l2per --epochs 2 -q -o "$dir/x.txt"
fails_with "eval l2per non-uniform" "measures uniform sets" "$nuld" eval "$dir/per3.txt" --metric l2per
fails_with "map --seed without --shifts" "give --shifts" "$nuld" map "$dir/per.txt" --target quarterdisc --seed 2 -o "$dir/x.txt"
fails_with "train unknown family" "unknown family 'blob'" "$nuld" train --target family:blob --n 8 --steps 2 -q -o "$dir/x.nuldnet"

# Render study: a tiny study, its table, a resumed rerun, the report; bad input.
ok "study render tiny" "$nuld" study render default --res 16x12 --spp 2,4 --reference-spp 16 --integrator direct --backends sobol,halton -q -o "$dir/study"
grep -q '^halton  *4 ' "$dir/out" || { echo "FAIL: study render prints its table"; failures=$((failures + 1)); }
[[ -f "$dir/study/index.html" && -f "$dir/study/render.csv" ]] || { echo "FAIL: study render writes CSV and report"; failures=$((failures + 1)); }
ok "study render rerun" "$nuld" study render default --res 16x12 --spp 2,4 --reference-spp 16 --integrator direct --backends sobol,halton -q --no-report -o "$dir/study"
# --opt-union-weight weighs every bank made for the exact L2asd: the map's sets
# by default too, not when they take the soft boxes; --opt-objective needs map sets.
ok "study render: the map's exact sets take --opt-union-weight" "$nuld" study render default --res 16x12 --spp 2 \
  --reference-spp 16 --integrator direct --backends optimized --opt-instances 2 --opt-epochs 5 \
  --opt-union-weight 0 -q --no-report -o "$dir/study-union"
fails_with "study render: --opt-union-weight with soft map sets" "applies to banks optimized for the exact L2asd" \
  "$nuld" study render default --backends optimized --opt-objective soft --opt-union-weight 1 -o "$dir/x"
fails_with "study render: --opt-objective without map sets" "applies to the environment-map sets" \
  "$nuld" study render default --backends sobol,optimized-bsdf --opt-objective soft -o "$dir/x"
[[ $(wc -l <"$dir/study/render.csv") == 5 ]] || { echo "FAIL: a rerun adds no rows"; failures=$((failures + 1)); }
ok "study report" "$nuld" study report "$dir/study"
ok "study render lobe banks" "$nuld" study render default --res 8x6 --spp 2 --reference-spp 8 --integrator bsdf --backends optimized-bsdf,optimized-both --opt-epochs 5 --opt-instances 2 -q --no-report -o "$dir/lobes"
grep -q '^optimized-both  *2 ' "$dir/out" || { echo "FAIL: study render with lobe banks"; cat "$dir/out"; failures=$((failures + 1)); }
fails_with "study unknown backend" "unknown backend 'sobel'" "$nuld" study render default --backends sobol,sobel -o "$dir/s2"
fails_with "study bad spp" "spp" "$nuld" study render default --spp 4,x -o "$dir/s2"
fails_with "study bad resolution" "expected W or WxH" "$nuld" study render default --res 12by4 -o "$dir/s2"
fails_with "study rerun with other options" "reference-spp 16 there, 32 now" "$nuld" study render default --res 16x12 --spp 2 --reference-spp 32 --integrator direct --backends sobol -q -o "$dir/study"
fails_with "study rerun with other repeats" "repeats 1 there, 3 now" "$nuld" study render default --res 16x12 --spp 2 --reference-spp 16 --integrator direct --backends sobol --repeats 3 -q -o "$dir/study"
# The baselines: references.csv has the reference's own noise; a learned row
# gets its ratio to the best classic row; rows within 10x of the noise say so
# (a 16-spp reference against 4-spp rows); a reference without halves (an
# older nuld's) is refused, not reused.
grep -q '^scene,backend,spp,resolution,integrator,variance,relvariance,seconds,image,made_seconds,cache,key,entry$' "$dir/study/references.csv" ||
  { echo "FAIL: references.csv has the reference's variance"; cat "$dir/study/references.csv"; failures=$((failures + 1)); }
grep -q "reference too noisy for this row" "$dir/study/index.html" ||
  { echo "FAIL: the page flags rows the reference is too noisy for"; failures=$((failures + 1)); }
ok "study render classic baselines" "$nuld" study render default --res 16x12 --spp 4 --reference-spp 16 --integrator direct --backends sobol,sobol-tabulated,optimized-uniform --opt-epochs 5 --opt-instances 2 --repeats 2 -q --no-report -o "$dir/classic"
grep -q 'mse/classic.*best_classic' "$dir/out" && grep -q '^optimized-uniform .*[0-9]+-[0-9].*[0-9]+-[0-9].*[0-9]+-[0-9]' "$dir/out" &&
  grep -q "reference too noisy for this row" "$dir/out" ||
  { echo "FAIL: the table gives learned rows their ratio to the best classic and flags noisy references"; cat "$dir/out"; failures=$((failures + 1)); }
sed -i 's/ halves=2//' "$(awk -F, 'NR == 2 {print $NF}' "$dir/classic/references.csv")/reference.state"
fails_with "study render refuses a reference without halves" "without two independent halves" "$nuld" study render default --res 16x12 --spp 4 --reference-spp 16 --integrator direct --backends sobol,sobol-tabulated,optimized-uniform --opt-epochs 5 --opt-instances 2 --repeats 2 -q --no-report -o "$dir/classic"
fails_with "study report of a folder that does not exist" "empty_study: no such folder" "$nuld" study report "$dir/empty_study"
mkdir "$dir/empty_study" && echo study >"$dir/empty_study/.nuld-folder"
fails_with "study report of an empty study folder" "neither render.csv nor integrate.csv" "$nuld" study report "$dir/empty_study"

# Integration study: the 2D integrands need no files.
ok "study integrate tiny" "$nuld" study integrate --integrands gaussian*step,quarterdisc*bilinear --samplers independent,sobol --n 4,16 --instances 8 --no-plots -q -o "$dir/integ"
grep -q '^integrand,domain,sampler,n,instances,reference,mean,bias' "$dir/integ/integrate.csv" || { echo "FAIL: study integrate writes its CSV"; failures=$((failures + 1)); }
[[ $(wc -l <"$dir/integ/integrate.csv") == 9 ]] || { echo "FAIL: study integrate: 2 integrands x 2 samplers x 2 N rows"; failures=$((failures + 1)); }
fails_with "study integrate unknown sampler" "--samplers" "$nuld" study integrate --samplers sobel --n 4 -o "$dir/integ2"
fails_with "study integrate bad N" "--n" "$nuld" study integrate --n 4,0 -o "$dir/integ2"
fails_with "study integrate unknown integrand" "gauss" "$nuld" study integrate --integrands gauss --n 4 -o "$dir/integ2"

# Ctrl-C in a long run says where the checkpoint is (exit 128 + SIGINT).
timeout --preserve-status -s INT 3 "$nuld" optimize --target quarterdisc --n 4096 --epochs 2000 --checkpoint-every 1 \
  -o "$dir/interrupted.txt" >"$dir/out" 2>"$dir/err"
rc=$?
if [[ $rc -ne 130 ]] || ! grep -q "nuld: interrupted" "$dir/err"; then
  echo "FAIL: an interrupted optimize notes its checkpoint: exit $rc"; tail -c 300 "$dir/err"
  failures=$((failures + 1))
fi

# Progress to a file (not a terminal): at most one line per tenth of the work.
"$nuld" render default --spp 2 --res 64 -o "$dir/progress.exr" >/dev/null 2>"$dir/progress.err"
lines=$(grep -c '^render \[' "$dir/progress.err")
if ((lines < 1 || lines > 10)); then
  echo "FAIL: a render's progress off a terminal: $lines lines (expected 1 to 10)"
  failures=$((failures + 1))
fi

# Nothing lost: a study and a bank pointed at a folder holding files they did
# not write leave every one of them byte for byte, naming one of them; a
# render refuses a read-only output; a study's own folder takes its reruns.
mkdir -p "$dir/proj/plots" "$dir/proj/default" "$dir/mybank"
echo "<html>mine</html>" >"$dir/proj/index.html"
echo "my plot" >"$dir/proj/plots/render_default.png"
echo "my render" >"$dir/proj/default/sobol_spp4.exr"
echo "# my bank" >"$dir/mybank/README.md"
cp -r "$dir/proj" "$dir/proj.orig"
cp -r "$dir/mybank" "$dir/mybank.orig"
fails_with "a study into a folder of other files" "holds files nuld study did not write (e.g. " \
  "$nuld" study render default --res 8x6 --spp 4 --reference-spp 8 --backends sobol -q -o "$dir/proj"
fails_with "a bank into a folder of other files" "mybank: holds files nuld bank did not write (e.g. README.md)" \
  "$nuld" bank default --backend optimized --spp 4 --res 8 --opt-instances 2 --opt-epochs 4 -q -o "$dir/mybank"
fails_with "a study report of a folder no study made" "not a folder nuld study made" "$nuld" study report "$dir/proj"
diff -r "$dir/proj" "$dir/proj.orig" >/dev/null && diff -r "$dir/mybank" "$dir/mybank.orig" >/dev/null &&
  [[ ! -e "$dir/proj/.nuld-folder" && ! -e "$dir/mybank/.nuld-folder" ]] ||
  { echo "FAIL: a refused study or bank left the folder's files as they were"; failures=$((failures + 1)); }
fails_with "a bank into a study's folder" "a folder nuld study wrote" \
  "$nuld" bank default --backend optimized --spp 4 --res 8 --opt-instances 2 --opt-epochs 4 -q -o "$dir/study"
ok "a bank into an empty folder, twice" "$nuld" bank default --backend optimized --spp 4 --res 8 --opt-instances 2 --opt-epochs 4 -q -o "$dir/emptybank"
ok "a bank rerun into its own folder" "$nuld" bank default --backend optimized --spp 4 --res 8 --opt-instances 2 --opt-epochs 4 -q -o "$dir/emptybank"
ok "render the marked bank folder" "$nuld" render default --backend optimized:"$dir/emptybank" --spp 4 --res 8 -q -o "$dir/eb.exr"
cp "$dir/eb.exr" "$dir/ro.exr" && chmod a-w "$dir/ro.exr" && cp "$dir/ro.exr" "$dir/ro.orig"
fails_with "a render over a read-only file" "ro.exr: is read-only; refusing to replace it" \
  "$nuld" render default --spp 1 --res 8 -q -o "$dir/ro.exr"
cmp -s "$dir/ro.exr" "$dir/ro.orig" || { echo "FAIL: a read-only output was replaced"; failures=$((failures + 1)); }
exits_with 2 "an output named .EXR" "$nuld" render default --spp 1 --res 8 -q -o "$dir/out.EXR"
# A dangling link is neither written through nor replaced (GNU cp's rule).
ln -s "$dir/nowhere/x.exr" "$dir/dangling.exr"
fails_with "a render through a dangling link" "dangling.exr: is a dangling symbolic link" \
  "$nuld" render default --spp 1 --res 8 -q -o "$dir/dangling.exr"
[[ -L "$dir/dangling.exr" && ! -e "$dir/nowhere" ]] || { echo "FAIL: a dangling link was replaced"; failures=$((failures + 1)); }
ln -s "$dir/nowhere/study" "$dir/dangling-study"
fails_with "a study into a dangling link" "dangling-study: is a dangling symbolic link" \
  "$nuld" study render default --res 8x6 --spp 4 --reference-spp 8 --backends sobol -q -o "$dir/dangling-study"

# Messages that tell the truth: a backend whose sets the integrator never
# draws is refused before rendering, saying so; one repeat decides nothing.
fails_with "optimized under the bsdf integrator" "the bsdf integrator samples BSDFs only" \
  "$nuld" render default --backend optimized --integrator bsdf --spp 4 --res 8 -q -o "$dir/x.exr"
fails_with "optimized-bsdf under the light integrator" "the light integrator samples the light only" \
  "$nuld" render default --backend optimized-bsdf --integrator light --spp 4 --res 8 -q -o "$dir/x.exr"
"$nuld" study render default --res 8x6 --spp 4 --reference-spp 8 --repeats 1 --backends sobol,halton -q --no-report -o "$dir/one" >"$dir/out" 2>&1
grep -q '^halton  *4 .* n/a ' "$dir/out" && ! grep -Eq '^halton .* (better|worse) ' "$dir/out" ||
  { echo "FAIL: a study of one repeat gives no verdict"; cat "$dir/out"; failures=$((failures + 1)); }
# A point-set file that names no target serves as uniform points, with a note.
"$nuld" generate --sequence sobol --n 4 --instances 4 -o "$dir/plain.txt" >/dev/null 2>&1
sed -i '/^# target/d' "$dir/plain.txt"
"$nuld" render default --backend optimized:"$dir/plain.txt" --spp 4 --res 8 -q -o "$dir/x.exr" >/dev/null 2>"$dir/err"
grep -q "plain.txt: names no target (no '# target: SPEC' line), so its points serve as uniform primary samples" "$dir/err" ||
  { echo "FAIL: a point file without a target is used with a note"; cat "$dir/err"; failures=$((failures + 1)); }
# One seed default everywhere: bank, then a study, then a render, with no
# --seed, make the map's sets once (the one entry is never written again).
export NULD_CACHE="$dir/flow-cache"
"$nuld" bank default --backend optimized --spp 4 --opt-instances 2 --opt-epochs 4 -q >"$dir/out" 2>&1
entries=("$NULD_CACHE"/sets/*.ptsb)
cp "${entries[0]}" "$dir/flow-set.orig"
"$nuld" study render default --res 8x6 --spp 4 --reference-spp 8 --repeats 2 --backends sobol,optimized \
  --opt-instances 2 --opt-epochs 4 -q --no-report -o "$dir/flow-study" >"$dir/out.study" 2>&1
"$nuld" render default --backend optimized --spp 4 --res 8 --opt-instances 2 --opt-epochs 4 -q -o "$dir/flow.exr" >"$dir/out" 2>"$dir/err"
entries=("$NULD_CACHE"/sets/*.ptsb)
[[ ${#entries[@]} -eq 1 ]] && cmp -s "${entries[0]}" "$dir/flow-set.orig" && grep -q '^optimized  *4 ' "$dir/out.study" &&
  grep -q '^nuld: optimized: its 1 sets came from the set cache$' "$dir/err" ||
  { echo "FAIL: bank, study and render with no seed make one set"; ls "$NULD_CACHE/sets"; cat "$dir/out.study" "$dir/err"; failures=$((failures + 1)); }
export NULD_CACHE="$dir/set-cache"

# Sizes are checked before memory is taken: refused at once, with the memory.
start=$(date +%s%N)
fails_with "generate beyond the machine's memory" "generate: --n 2000000000 x --instances 1 points needs about .* of memory, more than this machine's" \
  "$nuld" generate --n 2000000000 -o "$dir/big.txt"
(( ($(date +%s%N) - start) / 1000000 < 1000 )) || { echo "FAIL: the refusal of a huge --n took a second or more"; failures=$((failures + 1)); }
[[ ! -e "$dir/big.txt" ]] || { echo "FAIL: a refused generate wrote its output"; failures=$((failures + 1)); }

echo "$((failures == 0 ? 1 : 0)) passed, $failures failed"
exit $((failures > 0))
