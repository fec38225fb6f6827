#!/usr/bin/env bash
# Installs what dwatch needs, builds it, and runs the whole test suite.
#   scripts/test.sh            the suite, optimized build
#   scripts/test.sh --asan     the suite under AddressSanitizer + UndefinedBehaviorSanitizer
set -euo pipefail
cd "$(dirname "$0")/.."
kind=release
dir=build
skip=()
if [ "${1:-}" = "--asan" ]; then
  kind=asan; dir=build-asan
  # The three longest runs over ranks (a minute each under the sanitizers, one at a time) are left
  # to the optimized suite: under the sanitizers, the other MpiRun tests (the sliding modules' one
  # among them) go through the same physics-over-ranks code on smaller worlds. So is the Table I
  # time-travel soak (54 s under them, 6 s optimized): the push_wall soak, which stays, goes
  # through the same seeks and rollbacks. The plausibility scenes' long runs (a 10^3 pile for 600
  # steps, every scene over ranks: a minute each under them) measure physics, not memory: their
  # code runs under the sanitizers in the physics tests' smaller scenes.
  skip=(-E 'MpiRun\.(ManyBodiesMovingAtOnce|EveryOtherPhysicsScenario|AWallStruckAndTorn|ThePlausibilityScenesEqualOneProcess)|TimeTravelSoak\.Table1WithABudgetStop|PlausibilityStacks\.ATenCubedPileOfFreeBoxesRests|PlausibilityImpacts\.DemolitionNothingPassesThroughTheGroundOrAnotherBody')
fi
scripts/install-deps.sh
scripts/build.sh "$kind"
# intercept_tls_get_addr=0: ASan's tracking of dynamic TLS misreads that of a library opened with
# dlopen (OSMesa, loaded only to draw), and LeakSanitizer's tracer then crashed at exit ("Tracer
# caught signal 11", a DTLS range of 0x1c84-0x1800002d86) in most render tests' processes.
export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1:intercept_tls_get_addr=0 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
export LSAN_OPTIONS=suppressions=$PWD/tests/lsan.supp:print_suppressions=0
ctest --test-dir "$dir" --output-on-failure --parallel "$(nproc)" "${skip[@]}"
