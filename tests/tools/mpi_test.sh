#!/usr/bin/env bash
# A job of K ranks (mpirun -np K) makes what one process makes: the render
# study's references, rows, images and sets, the integration study's rows and
# sets, and nuld optimize's file; a multi-rank reference stopped by
# --reference-stop-after or killed, and a stopped optimization, resume to
# the same result; a rank given a bad input stops the
# job with a message naming it; a command that does not split runs on rank 0
# alone. Measured times (the CSV's seconds columns,
# the images' and sets' time attributes) are the only differences allowed.
# Usage: mpi_test.sh NULD K
set -uo pipefail
nuld=$1
ranks=$2
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
# Every study keeps its sets in its own cache (OUT/cache), so that each job
# makes them and they are compared file by file.
export NULD_CACHE="$dir/set-cache"
unset NULD_REFERENCE_CACHE  # references beside the sets of this cache
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }

launch=(mpirun --oversubscribe)
# Open MPI refuses root unless told; CI runs as root.
[[ $(id -u) -eq 0 ]] && launch+=(--allow-run-as-root)
mpi=("${launch[@]}" -np "$ranks")
run() { # run LOG COMMAND... (fails the test when the command does)
  local log=$1; shift
  "$@" >"$dir/$log.out" 2>"$dir/$log.err" || { fail "$log: exit $?"; cat "$dir/$log.err"; }
}

# The CSV without the named columns (1-based, comma-separated list).
csv_without() { # csv_without FILE COLUMNS
  awk -F, -v drop="$2" 'BEGIN { n = split(drop, d, ","); for (i = 1; i <= n; ++i) skip[d[i]] = 1 }
    { line = ""; for (i = 1; i <= NF; ++i) if (!skip[i]) line = line $i ","; print line }' "$1"
}
# Every image and point set of study directory A has the same pixels or
# points (and metadata, but the optimization time) in B.
same_outputs() { # same_outputs A B WHAT
  local a=$1 b=$2 what=$3 f
  [[ $(cd "$a" && find . -type f | sort) == $(cd "$b" && find . -type f | sort) ]] ||
    fail "$what: the file lists differ"
  while IFS= read -r f; do
    idiff -q -fail 0 -warn 0 "$a/$f" "$b/$f" >/dev/null 2>&1 || fail "$what: $f: pixels differ"
  done < <(cd "$a" && find . -type f \( -name '*.exr' -o -name '*.png' \))
  # One interpreter for every set (a nuld per file would start LibTorch each time).
  /usr/bin/python3 - "$a" "$b" <<'PY' || fail "$what: point sets differ"
import pathlib, struct, sys
def load(path):  # the binary point-set layout of sampler/io/pointset_io.cpp
    data = path.read_bytes()
    dim, n, instances, meta_bytes = struct.unpack_from("<IQQI", data, 8)
    meta = [l for l in data[32:32 + meta_bytes].split(b"\n") if not l.startswith(b"optimize_seconds=")]
    # NULDPTS2 ends in a checksum of the bytes before it, optimize_seconds included.
    end = len(data) - 8 if data[:8] == b"NULDPTS2" else len(data)
    return dim, n, instances, meta, data[32 + meta_bytes:end]
a, b = (pathlib.Path(p) for p in sys.argv[1:3])
files = sorted(a.rglob("*.ptsb"))
bad = [str(f.relative_to(a)) for f in files if load(f) != load(b / f.relative_to(a))]
print("differ:", *bad) if bad else None
sys.exit(1 if bad or not files else 0)
PY
}

# The render study: a reference of 6 passes, plain, optimized and lobe-bank
# backends at two spp.
study=(study render --backends sobol,independent,optimized,optimized-bsdf --spp 2,4 --res 24
  --reference-spp 48 --reference-pass-spp 8 --opt-instances 3 --opt-epochs 20 --no-report -q)
run render1 env NULD_CACHE="$dir/one/cache" "$nuld" "${study[@]}" -o "$dir/one"
run renderK env NULD_CACHE="$dir/many/cache" "${mpi[@]}" "$nuld" "${study[@]}" -o "$dir/many"
# render.csv columns 9-13, 15, 26 and 27: seconds, setup_seconds,
# total_seconds, equal_time_ratio and its error (from the times),
# rays_per_second, break_even_renders and its error (from the times too).
cmp -s <(csv_without "$dir/one/render.csv" 9,10,11,12,13,15,26,27) <(csv_without "$dir/many/render.csv" 9,10,11,12,13,15,26,27) ||
  fail "render.csv differs from the single process's"
[[ $(wc -l <"$dir/one/render.csv") -eq 9 ]] || fail "render.csv: expected 8 rows"
same_outputs "$dir/one" "$dir/many" "study render"

# An interrupted multi-rank reference resumes, also with another rank count.
run stop1 env NULD_CACHE="$dir/resumed/cache" "${mpi[@]}" "$nuld" "${study[@]}" -o "$dir/resumed" --reference-stop-after 1
# The reference's passes are kept in the reference cache (backends/reference_cache.h).
state() { cat "$1"/cache/references/*/reference.state 2>/dev/null; }
grep -q "passes_done=1" <(state "$dir/resumed") || fail "the first run did not stop after 1 pass"
[[ -e "$dir/resumed/render.csv" ]] && fail "a study with an incomplete reference rendered cells"
run stop2 env NULD_CACHE="$dir/resumed/cache" "${launch[@]}" -np 2 "$nuld" "${study[@]}" -o "$dir/resumed" --reference-stop-after 3
grep -q "passes_done=4" <(state "$dir/resumed") || fail "the second run did not stop after 4 passes"
run finish env NULD_CACHE="$dir/resumed/cache" "${mpi[@]}" "$nuld" "${study[@]}" -o "$dir/resumed"
for f in reference.exr reference.half0.exr reference.half1.exr; do
  idiff -q -fail 0 -warn 0 "$dir/one/default/$f" "$dir/resumed/default/$f" \
    >/dev/null 2>&1 || fail "the resumed reference ($f) differs from the single process's"
done
cmp -s <(csv_without "$dir/one/render.csv" 9,10,11,12,13,15,26,27) <(csv_without "$dir/resumed/render.csv" 9,10,11,12,13,15,26,27) ||
  fail "the resumed study's render.csv differs"

# A reference killed mid-job (SIGTERM to mpirun once a round is saved)
# resumes to the single process's image.
killed=(study render --backends sobol --spp 2 --res 96 --reference-spp 384 --reference-pass-spp 8
  --no-report -q)
run killed1 env NULD_CACHE="$dir/killed1/cache" "$nuld" "${killed[@]}" -o "$dir/killed1"
env NULD_CACHE="$dir/killed/cache" "${mpi[@]}" "$nuld" "${killed[@]}" -o "$dir/killed" >/dev/null 2>&1 &
job=$!
for _ in $(seq 600); do
  grep -qs "passes_done=[1-9]" <(state "$dir/killed") && break
  sleep 0.05
done
kill -TERM $job 2>/dev/null
wait $job 2>/dev/null
if grep -qs "passes_done=48" <(state "$dir/killed"); then
  echo "note: the reference finished before it could be interrupted"
elif ! grep -qs "passes_done=[1-9]" <(state "$dir/killed"); then
  fail "no reference round was saved before the kill"
fi
run killedResume env NULD_CACHE="$dir/killed/cache" "${mpi[@]}" "$nuld" "${killed[@]}" -o "$dir/killed"
idiff -q -fail 0 -warn 0 "$dir/killed1/default/reference.exr" "$dir/killed/default/reference.exr" \
  >/dev/null 2>&1 || fail "the reference resumed after a kill differs from the single process's"

# The integration study, its banks included.
integrate=(study integrate --integrands gaussian*step,envmap*cos --samplers independent,sobol,optimized
  --n 8,16 --instances 4 --optimized-instances 3 --opt-epochs 20 --no-plots -q)
run integrate1 env NULD_CACHE="$dir/int1/cache" "$nuld" "${integrate[@]}" -o "$dir/int1"
run integrateK env NULD_CACHE="$dir/intK/cache" "${mpi[@]}" "$nuld" "${integrate[@]}" -o "$dir/intK"
# integrate.csv columns 14-15: gen_seconds_per_set, setup_seconds_per_set.
cmp -s <(csv_without "$dir/int1/integrate.csv" 14,15) <(csv_without "$dir/intK/integrate.csv" 14,15) ||
  fail "integrate.csv differs from the single process's"
same_outputs "$dir/int1" "$dir/intK" "study integrate"

# nuld optimize splits its instances; the file is byte-identical, also after
# a stop and a resume.
opt=(optimize --target quarterdisc --n 32 --instances 5 --epochs 60 -q)
run opt1 "$nuld" "${opt[@]}" -o "$dir/one.ptsb"
run optK "${mpi[@]}" "$nuld" "${opt[@]}" -o "$dir/many.ptsb"
cmp -s "$dir/one.ptsb" "$dir/many.ptsb" || fail "optimize: the sets differ from the single process's"
run optStop "${mpi[@]}" "$nuld" "${opt[@]}" -o "$dir/resumed.ptsb" --stop-after 20
[[ -e "$dir/resumed.ptsb" ]] && fail "optimize --stop-after wrote the sets"
run optResume "${mpi[@]}" "$nuld" "${opt[@]}" -o "$dir/resumed.ptsb" --resume
cmp -s "$dir/one.ptsb" "$dir/resumed.ptsb" || fail "optimize: the resumed sets differ"
compgen -G "$dir/resumed.ptsb.ckpt*" >/dev/null && fail "optimize left its checkpoints"

# A bad input that a worker rank reads (the second cell of the first round:
# rank 1 with 2 ranks; with 3, a run under load had rank 2 report it first,
# so any worker's report counts) stops the whole job, with its message.
printf 'not a point set\n' >"$dir/bad.txt"
"${mpi[@]}" "$nuld" study render --backends sobol,"optimized:$dir/bad.txt" --spp 2 --res 8 \
  --reference-spp 8 --no-report -q -o "$dir/bad" >"$dir/bad.out" 2>"$dir/bad.err"
rc=$?
if [[ $rc -eq 0 ]] || ! grep -q "error on rank [1-9][0-9]* of $ranks: .*bad.txt" "$dir/bad.err"; then
  fail "a bad input on a worker rank: exit $rc, expected its error naming bad.txt, got:"
  cat "$dir/bad.err"
fi
[[ -e "$dir/bad/render.csv" ]] && grep -q "optimized" "$dir/bad/render.csv" &&
  fail "the bad cell was written"

# A command that does not split its work runs unchanged on rank 0 alone:
# the same file as one process, written once, and a note saying so.
run generate1 "$nuld" generate --sequence sobol --n 4 --instances 3 -o "$dir/g1.txt"
"${mpi[@]}" "$nuld" generate --sequence sobol --n 4 --instances 3 -o "$dir/g.txt" >/dev/null \
  2>"$dir/g.err" || { fail "generate under $ranks ranks: exit $?"; cat "$dir/g.err"; }
cmp -s "$dir/g1.txt" "$dir/g.txt" || fail "generate under $ranks ranks differs from one process"
grep -q "'nuld generate' does not split its work; it runs on rank 0 alone" "$dir/g.err" ||
  { fail "generate: no note about rank 0"; cat "$dir/g.err"; }
[[ $(grep -c "does not split" "$dir/g.err") -eq 1 ]] || fail "generate: the note printed more than once"

((failures == 0)) && echo "mpi_test ($ranks ranks): all checks passed"
exit $((failures > 0))
