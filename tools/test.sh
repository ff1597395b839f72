#!/usr/bin/env bash
# Builds the project and runs the whole test suite (the README's test command).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-"$root/build"}
"$root/tools/build.sh" "$build"
cd "$build"
ctest --output-on-failure -j"$(nproc)"
