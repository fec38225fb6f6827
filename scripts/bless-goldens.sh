#!/usr/bin/env bash
# Re-blesses the golden images in tests/golden/ from the current renderer (release build).
# Look at every image it writes before committing them.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/build.sh release
DWATCH_BLESS=1 build/tests/dw_golden_tests
git status --short tests/golden
