#!/usr/bin/env bash
# Installs the build in BUILD_DIR into a fresh prefix, builds tests/install/consumer against it
# with find_package(dwatch), checks what the consumer finds, and makes the Debian package. Used
# by ctest.
set -euo pipefail
build="$(cd "$1" && pwd)"
source_dir="$(cd "$(dirname "$0")" && pwd)/consumer"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
cmake --install "$build" --prefix "$work/prefix" >/dev/null
test -x "$work/prefix/bin/dwatch"
test -f "$work/prefix/include/dwatch/watch/watchpoint.h"
cmake -S "$source_dir" -B "$work/build" -G Ninja -DCMAKE_PREFIX_PATH="$work/prefix" >/dev/null
cmake --build "$work/build" >/dev/null
out="$("$work/build/consumer")"
expected=$'1 0 1 2\n1 2 1 0\n2 matches'
if [ "$out" != "$expected" ]; then
  echo "consumer printed:"; echo "$out"; echo "expected:"; echo "$expected"; exit 1
fi
# A mistake in the watchpoint is a diagnostic with a caret, from the installed library.
if "$work/build/consumer" 'modules(a); (b.x = 1)' 2>"$work/err"; then echo "a bad watchpoint was accepted"; exit 1; fi
grep -q "<argument>:1:14: error: module 'b' is not declared" "$work/err"
"$work/prefix/bin/dwatch" --version | grep -q "^dwatch "
# The Python package, when built, imports from the prefix's Debian layout with Debian's python3,
# and from nowhere else (the build tree is not on its path).
if [ -d "$build/python/dwatch" ]; then
  (cd "$work" && PYTHONPATH="$work/prefix/lib/python3/dist-packages" /usr/bin/python3 -c '
import dwatch, sys
assert dwatch.__file__.startswith(sys.argv[1]), dwatch.__file__
assert "slots          1: a" in dwatch.check("modules(a); a.x = 1")
' "$work/prefix/lib/python3/dist-packages")
fi
# The Debian package holds the program and the package, and depends on what it links.
(cd "$work" && cpack -G DEB -B "$work/deb" --config "$build/CPackConfig.cmake" >/dev/null)
deb="$(ls "$work"/deb/dwatch_*.deb)"
dpkg-deb -c "$deb" >"$work/contents"
grep -q "./usr/bin/dwatch$" "$work/contents"
grep -q "./usr/lib/.*cmake/dwatch/dwatchConfig.cmake$" "$work/contents"
if [ -d "$build/python/dwatch" ]; then
  for f in _dwatch.cpython-.*\.so __init__.py _dwatch.pyi py.typed; do
    grep -q "./usr/lib/python3/dist-packages/dwatch/$f$" "$work/contents"
  done
fi
dpkg-deb -f "$deb" Depends | grep -q "libbullet"
echo "consumer: ok"
