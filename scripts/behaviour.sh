#!/usr/bin/env bash
# What dwatch does, as a fingerprint: runs every scenario in scenarios/ (`run`, with `--record`,
# then `replay` of the record) and every `.session` case of tests/, and prints, a line each, the
# state hashes, match counts and digests of the matches, the trace and the session's answers.
# Timings and peak memory are left out: two builds that behave alike print the same lines.
#   scripts/behaviour.sh DWATCH_EXE [STEPS]      (STEPS: cap on each run's steps, default 60; the
#                                                 million-module reconfigure_large runs 3, whose
#                                                 trace of 60 steps would take 6 GB)
# A renovation compares the output of the build before with the build after (`diff`); CI runs it
# so that a scenario or a case that stops working is seen.
set -euo pipefail
cd "$(dirname "$0")/.."
# A copy of the executable, so that a build relinking it meanwhile changes nothing here.
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
cp "$1" "$work/dwatch"
exe="$work/dwatch"
steps="${2:-60}"
# The scenarios are copied, so that every path a run or a session prints is the same in any checkout.
cp -r scenarios "$work/scenarios"
digest() { if [ -f "$1" ]; then sha256sum "$1" | cut -c1-16; else echo none; fi; }
# Every field of --stats that says what the run did, none that says how fast it did it.
facts() {
  python3 -c '
import json, sys
j = json.load(open(sys.argv[1]))
keep = [k for k in ("steps", "modules", "program_messages", "state_hash", "simulation_hash", "watchpoints_hash", "matches") if k in j]
out = " ".join(f"{k}={j[k]}" for k in keep)
for w in j.get("watches", []):
    out += " %s:%s" % (w.get("name"), w.get("matches"))
if "pause" in j: out += " pause=%s@%s" % (j["pause"]["watch"], j["pause"]["t"])
print(out)' "$1"
}
cd "$work"
for scenario in $(cd scenarios && ls *.toml lua/*.toml); do
  rm -f trace.jsonl matches.jsonl stats.json replayed.jsonl replayed.json
  code=0
  cap="$steps"
  [ "$scenario" = reconfigure_large.toml ] && cap=3
  "$exe" run "scenarios/$scenario" --steps "$cap" --record trace.jsonl --matches matches.jsonl --stats stats.json \
    >/dev/null 2>run.err || code=$?
  line="run $scenario exit=$code"
  [ -f stats.json ] && line+=" $(facts stats.json)"
  echo "$line matches=$(digest matches.jsonl) trace=$(digest trace.jsonl)"
  if [ -f trace.jsonl ]; then
    code=0
    "$exe" replay trace.jsonl --matches replayed.jsonl --stats replayed.json >/dev/null 2>replay.err || code=$?
    line="replay $scenario exit=$code"
    [ -f replayed.json ] && line+=" $(facts replayed.json)"
    echo "$line matches=$(digest replayed.jsonl)"
  fi
done
cases="$(find "$OLDPWD/tests" -type d -name session_cases | head -1)"
for case in $(cd "$cases" && ls *.session); do
  scenario="$(sed -n 's/^# scenario: //p' "$cases/$case" | head -1)"
  mkdir -p "session/$case" && cp "$cases/$case" "session/$case/" && cd "session/$case"
  code=0
  "$exe" session "../../scenarios/$scenario" --script "$case" >stdout 2>stderr || code=$?
  # `status` tells how the history is kept, which varies with the machine's speed: left out.
  python3 -c '
import json, sys
for line in open(sys.argv[1], errors="surrogateescape"):
    try:
        answer = json.loads(line)
    except ValueError:
        print(line, end="")
        continue
    if isinstance(answer, dict):
        answer.pop("history", None)
    print(json.dumps(answer))' stdout > answers
  echo "session $case exit=$code answers=$(digest answers) stderr=$(digest stderr)"
  cd ../..
done
