#!/usr/bin/python3
"""dwatch.replay from in-memory numpy columns against `dwatch replay` of the same trace file.

    PYTHONPATH=build/python /usr/bin/python3 python/benchmarks/replay_columns.py [--tuple 1:1:1:1] [--runs 5]

Makes the Table I ensemble's trace for one tuple (`dwatch bench engine --write-trace`), replays it
with the command line (its "detecting" time: the detector alone, the file already read), loads it
into numpy columns (not timed: a user's logs are already in memory), then times dwatch.replay over
the columns, the whole call: building the trace from them and the detector, with the matches
counted (count_only=True: what the command line's figure does) and with every match kept as
arrays. Prints the medians and their ratios to the command line's detector time (target: 1.2).
"""

import argparse
import os
import pathlib
import re
import statistics
import subprocess
import sys
import tempfile
import time

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[1] / "tests"))
from conftest import read_columns  # noqa: E402

import dwatch  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parents[2]
EXE = os.environ.get("DWATCH_EXE", str(ROOT / "build" / "app" / "dwatch"))
WATCH = "modules(a b c d); (a.x1 = 0) and (b.x2 = 0) and (c.x3 = 0) and (d.x4 = 0)"


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--tuple", default="1:1:1:1")
    parser.add_argument("--runs", type=int, default=5)
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as folder:
        trace = pathlib.Path(folder) / "table1.jsonl"
        subprocess.run([EXE, "bench", "engine", "--tuple", args.tuple, "--which", "distributed",
                        "--write-trace", str(trace)], check=True, capture_output=True)
        detecting, matches = [], None
        for _ in range(args.runs):
            out = subprocess.run([EXE, "replay", str(trace), "--watch", WATCH], check=True, capture_output=True,
                                 text=True).stdout
            detecting.append(float(re.search(r"detecting ([0-9.]+) s", out).group(1)))
            matches = int(re.search(r"w1: (\d+) match", out).group(1))
        columns = read_columns(trace)
    cli = statistics.median(detecting)
    print(f"Table I [{args.tuple}] distributed: {len(columns['t'])} lines, {matches} matches")
    print(f"  dwatch replay, detecting (median of {args.runs}):      {cli * 1000:8.1f} ms")
    for count_only, label in ((True, "counted"), (False, "kept as arrays")):
        python = []
        for _ in range(args.runs):
            started = time.perf_counter()
            found = dwatch.replay(columns, WATCH, count_only=count_only)["w1"]
            python.append(time.perf_counter() - started)
            assert found.count == matches, (found.count, matches)
            del found
        py = statistics.median(python)
        print(f"  dwatch.replay from numpy columns, {label + ':':15} {py * 1000:8.1f} ms  "
              f"ratio {py / cli:.2f} (target 1.2)")


if __name__ == "__main__":
    main()
