#!/usr/bin/env bash
# Configures and builds dwatch into a build directory.
#   scripts/build.sh [release|asan|fuzz] [TARGET...]     (default: release, every target)
set -euo pipefail
cd "$(dirname "$0")/.."
kind="${1:-release}"
shift || true
targets=("$@")
case "$kind" in
  release) dir=build; flags=(-DCMAKE_BUILD_TYPE=Release) ;;
  # -O1 -g1: line tables for the sanitizers' reports, at a fraction of -O2 -g's compile time.
  # Built with clang, so that CI builds everything with both compilers (release: GCC). The fuzz
  # targets are built here too (DWATCH_FUZZ: the libraries carry coverage as well), so that CI
  # fuzzes them without building every library a third time (FUZZ_BUILD=asan scripts/fuzz.sh).
  asan) dir=build-asan; flags=(-DCMAKE_BUILD_TYPE=RelWithDebInfo "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O1 -g1"
                                -DDWATCH_SANITIZE=ON -DDWATCH_FUZZ=ON -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_C_COMPILER=clang) ;;
  fuzz) dir=build-fuzz; flags=(-DCMAKE_BUILD_TYPE=RelWithDebInfo -DDWATCH_FUZZ=ON -DDWATCH_TESTS=OFF
                               -DCMAKE_CXX_COMPILER=clang++) ;;
  *) echo "usage: scripts/build.sh [release|asan|fuzz]" >&2; exit 2 ;;
esac
cmake -S . -B "$dir" -G Ninja -DDWATCH_WERROR=ON "${flags[@]}" >/dev/null
if [ ${#targets[@]} -gt 0 ]; then
  cmake --build "$dir" --parallel "$(nproc)" --target "${targets[@]}"
else
  cmake --build "$dir" --parallel "$(nproc)"
fi
