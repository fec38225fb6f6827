#!/usr/bin/env bash
# Installs what dwatch needs, builds it, and runs the whole test suite.
#   scripts/test.sh            the suite, optimized build
#   scripts/test.sh --asan     the suite under AddressSanitizer + UndefinedBehaviorSanitizer
set -euo pipefail
cd "$(dirname "$0")/.."
kind=release
dir=build
if [ "${1:-}" = "--asan" ]; then kind=asan; dir=build-asan; fi
scripts/install-deps.sh
scripts/build.sh "$kind"
export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
export LSAN_OPTIONS=suppressions=$PWD/tests/lsan.supp:print_suppressions=0
ctest --test-dir "$dir" --output-on-failure --parallel "$(nproc)"
