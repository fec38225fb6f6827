#!/usr/bin/env bash
# Installs what dwatch needs, builds it, and runs the main demo: 2-hop leader election on a hex
# lattice with a bug, watched live by the paper's Fig. 2 watchpoint (two leaders within two hops),
# which pauses the run on the violation and rolls back to the step it happened, then draws that
# step headless to leader_election.png: the two leaders and the module between them outlined.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
scripts/build.sh release dwatch  # only what the demo runs: the test suite is scripts/test.sh's
echo
echo "\$ dwatch run scenarios/leader_election.toml --print 10 --render leader_election.png"
build/app/dwatch run scenarios/leader_election.toml --print 10 --render leader_election.png
