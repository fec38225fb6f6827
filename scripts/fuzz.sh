#!/usr/bin/env bash
# Builds the libFuzzer targets with clang, every library they reach instrumented, and fuzzes each
# for SECONDS (default 30), or for N executions with --runs N, starting from its seed corpus and
# what earlier runs kept; new inputs go to build-fuzz/corpus/NAME.
#   scripts/fuzz.sh [SECONDS | --runs N] [TARGET...]   targets: parser scenario trace session protocol lua
#                                                       (default: all)
# FUZZ_BUILD=asan uses the sanitizer test build's tree (build-asan, -O1, which builds the fuzz
# targets too) instead of build-fuzz (-O2, for long campaigns): CI then builds the libraries once.
# Prints, per target, the runs, the edges (cov) and features (ft) reached. Any crash, leak,
# undefined behaviour, input over FUZZ_TIMEOUT seconds (default 1) or allocation over 2 GB fails
# the script and leaves the input in build-fuzz/. On a loaded machine ASan's quarantine recycling
# alone can pause an input past a second (seen here, with inputs that run in 1 ms): CI allows 2.
set -euo pipefail
cd "$(dirname "$0")/.."
limit=(-max_total_time="${1:-30}")
until="${1:-30}s"
if [ "${1:-}" = --runs ]; then
  limit=(-runs="$2")
  until="$2 runs"
  shift
fi
export ASAN_OPTIONS="${ASAN_OPTIONS:-quarantine_size_mb=64}"
# UndefinedBehaviorSanitizer reports and carries on unless told to stop: its report is a finding.
export UBSAN_OPTIONS="${UBSAN_OPTIONS:-halt_on_error=1:print_stacktrace=1}"
shift || true
targets=("$@")
[ ${#targets[@]} -eq 0 ] && targets=(parser scenario trace session protocol lua)
kind="${FUZZ_BUILD:-fuzz}"
case "$kind" in fuzz | asan) ;; *) echo "fuzz: FUZZ_BUILD must be fuzz or asan" >&2; exit 2 ;; esac
build=build-$kind
scripts/install-deps.sh
scripts/build.sh "$kind" "${targets[@]/%/_fuzz}"

# Seeds, copied into build-fuzz/seeds/NAME: the parser's corpus and language cases; every
# scenario and scenario case file; every conformance trace; the session cases and the session
# corpus; the protocol corpus (requests, valid and hostile); every shipped Lua script and the Lua
# corpus (hostile snippets, findings).
seed_dir() {
  local dir=$build/seeds/$1
  rm -rf "$dir" && mkdir -p "$dir"
  case "$1" in
    parser) cp tests/fuzz/parser_corpus/* tests/watch/cases/*.watch "$dir" ;;
    scenario) cp scenarios/*.toml tests/scenarios/cases/*.toml "$dir" ;;
    trace) for c in tests/conformance/*/; do cp "$c/trace.jsonl" "$dir/$(basename "$c").jsonl"; done ;;
    session) cp tests/shell/session_cases/*.session tests/fuzz/session_corpus/* "$dir" ;;
    protocol) cp tests/fuzz/protocol_corpus/* "$dir" ;;
    lua) cp scenarios/lua/*.lua tests/fuzz/lua_corpus/* "$dir" ;;
  esac
  echo "$dir"
}
max_len() { case "$1" in trace) echo 16384 ;; *) echo 8192 ;; esac; }
# The session target reaches some 80,000 features, most of them rare: libFuzzer's entropic
# schedule then spends most of each run looking features up in its list of rare ones (measured:
# a sixth as many runs a minute); the plain schedule is used there.
schedule() { case "$1" in session) echo -entropic=0 ;; *) echo -entropic=1 ;; esac; }

summary=()
for t in "${targets[@]}"; do
  corpus=$build/corpus/$t
  mkdir -p "$corpus"
  log=$build/$t.log
  seeds=$(seed_dir "$t")
  if ! (cd "$build" && ./tests/${t}_fuzz "${limit[@]}" -max_len="$(max_len "$t")" "$(schedule "$t")" -timeout="${FUZZ_TIMEOUT:-1}" \
          -rss_limit_mb=2048 -malloc_limit_mb=2048 -print_final_stats=1 -artifact_prefix="$t-" \
          "../$corpus" "../$seeds") >"$log" 2>&1; then
    tail -40 "$log"
    echo "fuzz: $t FAILED; the input is in $build/$t-*" >&2
    exit 1
  fi
  runs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$log" | grep -o '[0-9]*$' || echo "?")
  last=$(grep -E '^#[0-9]+' "$log" | tail -1)
  cov=$(echo "$last" | grep -o 'cov: [0-9]*' | grep -o '[0-9]*' || echo "?")
  ft=$(echo "$last" | grep -o 'ft: [0-9]*' | grep -o '[0-9]*' || echo "?")
  summary+=("$(printf '%-9s %12s runs %7s edges %8s features (%s)' "$t" "$runs" "$cov" "$ft" "$until")")
done
echo "fuzz summary:"
printf '  %s\n' "${summary[@]}"
