#!/usr/bin/env bash
# Fuzzes the readers with libFuzzer (tests/fuzz/README.md): builds the
# harnesses with clang, AddressSanitizer and UndefinedBehaviorSanitizer in
# build-fuzz/, then runs each for SECONDS (default 600) from a working corpus
# seeded with tests/fuzz/corpus/NAME, and prints executions, corpus growth and
# findings per harness. Crashing inputs land in build-fuzz/findings/NAME/.
# Usage: tools/fuzz.sh [SECONDS] [NAME...]   (default: every harness)
#        FUZZ_JOBS=2 runs that many harnesses at once.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build="$root/build-fuzz"
seconds=${1:-600}
shift || true
harnesses=("$@")
((${#harnesses[@]})) || harnesses=(scene_json ply gltf pointset_text pointset_binary model_file)
jobs=${FUZZ_JOBS:-1}

"$root/tools/setup.sh"
if [[ $(dpkg-query -W -f='${Status}' libclang-rt-14-dev 2>/dev/null) != "install ok installed" ]] ||
  ! command -v clang++-14 >/dev/null; then
  echo "fuzz: installing clang-14 and its libFuzzer runtime" >&2
  SUDO=""; [[ $(id -u) -ne 0 ]] && SUDO="sudo"
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends \
    clang-14 libclang-rt-14-dev >/dev/null
fi

# LibTorch's headers do not compile with clang in C++20; the fuzz build
# has no LibTorch plugin (sampler/neural/neural_runtime.h), which no reader needs.
flags="-fsanitize=address,undefined,fuzzer-no-link -fno-sanitize-recover=undefined -fno-omit-frame-pointer -g"
cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=Release -DNULD_FUZZ=ON -DNULD_NATIVE=OFF \
  -DNULD_BUILD_BENCHMARKS=OFF -DCMAKE_CXX_COMPILER=clang++-14 -DCMAKE_CXX_FLAGS="$flags" \
  -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined" >/dev/null
cmake --build "$build" -j"$(nproc)" --target "${harnesses[@]/#/fuzz_}"

export ASAN_OPTIONS=detect_leaks=0:abort_on_error=1
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
fuzz_one() {
  local name=$1 corpus="$build/corpus/$1" findings="$build/findings/$1/"
  mkdir -p "$corpus" "$findings"
  local seeds
  seeds=$(find "$root/tests/fuzz/corpus/$name" -type f | wc -l)
  # -timeout: an input that takes 10 s is a hang; -rss_limit_mb: one that
  # needs 2 GB is a size the reader should have refused.
  local dict=()
  [[ -f "$root/tests/fuzz/$name.dict" ]] && dict=(-dict="$root/tests/fuzz/$name.dict")
  "$build/tests/fuzz/fuzz_$name" "$corpus" "$root/tests/fuzz/corpus/$name" "${dict[@]}" \
    -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -print_final_stats=1 \
    -artifact_prefix="$findings" >"$build/fuzz_$name.log" 2>&1 || true
  local execs cov found
  execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$build/fuzz_$name.log" | tail -1)
  cov=$(grep -o 'cov: [0-9]*' "$build/fuzz_$name.log" | tail -1 | cut -d' ' -f2)
  found=$(find "$findings" -type f | wc -l)
  printf '%-16s %8s s %12s execs %6s edges %6s corpus (from %s seeds) %3s findings\n' "$name" \
    "$seconds" "${execs:-?}" "${cov:-?}" "$(find "$corpus" -type f | wc -l)" "$seeds" "$found"
}
export -f fuzz_one
export build root seconds
printf '%s\n' "${harnesses[@]}" | xargs -P "$jobs" -I{} bash -c 'fuzz_one {}'
echo "logs: $build/fuzz_NAME.log; crashing inputs: $build/findings/NAME/"
