#!/usr/bin/env bash
# Builds the parser's libFuzzer target with clang and fuzzes it for SECONDS (default 60),
# starting from the seed corpus in tests/fuzz/corpus. New inputs go to build-fuzz/corpus.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds="${1:-60}"
scripts/install-deps.sh
scripts/build.sh fuzz
mkdir -p build-fuzz/corpus
build-fuzz/tests/parser_fuzz -max_total_time="$seconds" -max_len=4096 -timeout=10 -rss_limit_mb=4096 \
  build-fuzz/corpus tests/fuzz/corpus
