#!/usr/bin/env bash
# Installs what dwatch needs, builds it, and runs the whole test suite.
#   scripts/test.sh            the suite, optimized build
#   scripts/test.sh --asan     the suite under AddressSanitizer + UndefinedBehaviorSanitizer
set -euo pipefail
cd "$(dirname "$0")/.."
kind=release
dir=build
retry=()
# Under ASan, a test that fails is run once more: LeakSanitizer's tracer, stopping the world at
# exit, can crash on a loaded machine while OSMesa's render threads unwind ("Tracer caught signal
# 11", seen once in two render tests while MPI tests ran beside). A real failure fails twice.
if [ "${1:-}" = "--asan" ]; then kind=asan; dir=build-asan; retry=(--repeat until-pass:2); fi
scripts/install-deps.sh
scripts/build.sh "$kind"
export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
export LSAN_OPTIONS=suppressions=$PWD/tests/lsan.supp:print_suppressions=0
ctest --test-dir "$dir" --output-on-failure --parallel "$(nproc)" "${retry[@]}"
