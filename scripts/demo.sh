#!/usr/bin/env bash
# Installs what dwatch needs, builds it, and runs the main demo: the paper's Fig. 2 watchpoint
# (two leaders within two hops) replayed over a hex-lattice leader-election trace.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
scripts/build.sh release
case_dir=tests/conformance/02_leader_two_hop_hex
echo
echo "\$ dwatch check @$case_dir/watch.txt"
build/app/dwatch check "@$case_dir/watch.txt"
echo
echo "\$ dwatch replay $case_dir/trace.jsonl --watch @$case_dir/watch.txt --algorithm distributed"
build/app/dwatch replay "$case_dir/trace.jsonl" --watch "@$case_dir/watch.txt" --algorithm distributed --print 10
