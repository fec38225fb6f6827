#!/usr/bin/env bash
# Installs the build in BUILD_DIR into a fresh prefix and runs the installed dwatch from another
# folder: it finds what it ships under its prefix (bench/shipped_files.h), never in the source
# tree it was built from. Shipped scenarios run from PREFIX/share/dwatch/scenarios, a Lua one with
# its script beside it, to the state hashes of the build tree's; the files the benches read are
# the prefix's, each replaced there by one that says so: `bench paper` runs the prefix's plot
# script, `bench lua` loads the prefix's Lua library. Used by ctest.
set -euo pipefail
build="$(cd "$1" && pwd)"
source_scenarios="$(cd "$(dirname "$0")/../../scenarios" && pwd)"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
cmake --install "$build" --prefix "$work/prefix" >/dev/null
dwatch="$work/prefix/bin/dwatch"
share="$work/prefix/share/dwatch"
for f in scenarios/token_ring.toml scenarios/token_ring_fault.toml scenarios/lua/token_hop.lua \
         scenarios/lua/token_ring.lua scenarios/lua/token_ring.toml plot_paper.py; do
  test -f "$share/$f" || { echo "not installed: share/dwatch/$f"; exit 1; }
done
mkdir "$work/elsewhere"
cd "$work/elsewhere"

# The scenarios under the prefix, by their paths there, as the build tree's dwatch runs them.
for scenario in token_ring.toml token_ring_fault.toml lua/token_ring.toml; do
  installed="$("$dwatch" run "$share/scenarios/$scenario" --no-progress --steps 30 | grep 'state hash')"
  built="$("$build/app/dwatch" run "$source_scenarios/$scenario" --no-progress --steps 30 | grep 'state hash')"
  if [ "$installed" != "$built" ]; then
    echo "$scenario: the installed dwatch says '$installed', the build tree's '$built'"; exit 1
  fi
done

# bench paper draws its plots with the prefix's plot script.
cat >"$share/plot_paper.py" <<'PY'
import pathlib, sys
pathlib.Path(sys.argv[1], "plotted_by").write_text(sys.argv[0])
PY
"$dwatch" bench paper --size 4 --steps 8 --repeat 1 --quick --out paper >paper.out 2>&1 ||
  { cat paper.out; exit 1; }
test "$(cat paper/plotted_by)" = "$share/plot_paper.py"

# bench lua reads the prefix's Lua library.
echo 'error("the installed library")' >"$share/scenarios/lua/token_ring.lua"
if "$dwatch" bench lua --quick --repeat 1 >lua.out 2>&1; then
  echo "bench lua ran without the installed library"; cat lua.out; exit 1
fi
grep -q "the installed library" lua.out || { cat lua.out; exit 1; }
echo "installed files: ok"
