#!/usr/bin/python3
"""The cost of a module-step of a host program in Python, Lua and C++: the same 2-hop leader
election (scenarios/programs/leader_election.cpp, scenarios/lua/leader_election.lua and the
Python class of python/tests/test_python_programs.py, which give the same hashes).

    PYTHONPATH=build/python /usr/bin/python3 python/benchmarks/program_cost.py [--size 30 20] [--steps 200] [--runs 3]

Each scenario is the shipped one on a hex lattice of --size modules with its watchpoint left out,
so that a step is the programs and the step loop alone; `dwatch.Session.run()` over --steps steps
is timed (the median of --runs) and divided by modules x steps. The session's history (its
keyframes) is the same for the three and small next to the programs' cost. Prints each one's
microseconds per module-step and its ratio to C++'s, and checks the three end on one hash.
"""

import argparse
import pathlib
import re
import statistics
import sys
import tempfile
import time

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[1] / "tests"))
from test_python_programs import LeaderElection  # noqa: E402

import dwatch  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parents[2]


def without_watches(text: str, size: list, steps: int) -> str:
    """The scenario with no [[watch]], on a lattice of `size` modules, over `steps` steps."""
    text = re.sub(r"\[\[watch\]\].*?(?=\n\[)", "", text, flags=re.S)
    text = re.sub(r"(?m)^size = \[.*\]$", f"size = [{size[0]}, {size[1]}]", text)
    return re.sub(r"(?m)^steps = \d+$", f"steps = {steps}", text)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--size", type=int, nargs=2, default=[30, 20])
    parser.add_argument("--steps", type=int, default=200)
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--threads", type=int, default=1)
    args = parser.parse_args()
    module_steps = args.size[0] * args.size[1] * args.steps
    with tempfile.TemporaryDirectory() as folder:
        folder = pathlib.Path(folder)
        lua = (ROOT / "scenarios" / "lua" / "leader_election.toml").read_text()
        files = {
            "C++": (ROOT / "scenarios" / "leader_election.toml").read_text(),
            "Lua": lua,
            "Python": lua.replace('script = "leader_election.lua"', 'python = "leader_election"'),
        }
        (folder / "leader_election.lua").write_text((ROOT / "scenarios" / "lua" / "leader_election.lua").read_text())
        seconds, hashes = {}, {}
        for kind, text in files.items():
            path = folder / f"{kind}.toml"
            path.write_text(without_watches(text, args.size, args.steps))
            times = []
            for _ in range(args.runs):
                s = dwatch.Session(path, threads=args.threads, programs={"leader_election": LeaderElection})
                started = time.perf_counter()
                s.run()
                times.append(time.perf_counter() - started)
                hashes[kind] = s.hash()
            seconds[kind] = statistics.median(times)
    print(f"{module_steps} module-steps ({args.size[0]}x{args.size[1]} modules, {args.steps} steps), "
          f"{args.threads} thread(s), median of {args.runs}")
    for kind, s in seconds.items():
        print(f"  {kind:7s} {s * 1e3:8.1f} ms  {s / module_steps * 1e6:7.2f} us/module-step  "
              f"x{s / seconds['C++']:.1f} C++")
    if len(set(hashes.values())) != 1:
        sys.exit(f"the three programs ended on different hashes: {hashes}")


if __name__ == "__main__":
    main()
