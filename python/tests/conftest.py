"""Fixtures of the Python package's tests: where the repository and the `dwatch` command are.

ctest runs these with PYTHONPATH at build/python, DWATCH_EXE the command built beside it and
DWATCH_SOURCE_DIR the repository (python/CMakeLists.txt); run by hand, the defaults below are the
release build's.
"""

import json
import os
import pathlib
import subprocess

import pytest

SOURCE = pathlib.Path(os.environ.get("DWATCH_SOURCE_DIR", pathlib.Path(__file__).resolve().parents[2]))
EXE = os.environ.get("DWATCH_EXE", str(SOURCE / "build" / "app" / "dwatch"))

LEADERS = "modules(a b c);(a.isLeader = 1) and (c.isLeader = 1)"


@pytest.fixture
def source() -> pathlib.Path:
    return SOURCE


def dwatch(*args: str, input: str | None = None, check: bool = True) -> subprocess.CompletedProcess:
    """Runs the command line, as a user would, with its output as text."""
    return subprocess.run([EXE, *args], input=input, capture_output=True, text=True, check=check, timeout=300)


def json_lines(text: str) -> list[dict]:
    return [json.loads(line) for line in text.splitlines() if line.strip()]


@pytest.fixture
def leaders(source) -> str:
    """The leader election scenario, the walkthrough's."""
    return str(source / "scenarios" / "leader_election.toml")


def session_answers(scenario: str, *commands: str) -> list[dict]:
    """What `dwatch session --script -` answers to the commands, one dict each."""
    return json_lines(dwatch("session", scenario, "--script", "-", input="\n".join(commands) + "\n").stdout)


def read_columns(path: pathlib.Path) -> dict:
    """A wptrace v1 file as the columns dwatch.replay takes (the flat neighbour form)."""
    import numpy as np

    t, m, begin, nbrs, values = [], [], [0], [], {}
    for line in path.read_text().splitlines():
        row = json.loads(line)
        if "t" not in row:
            continue  # the header
        t.append(row["t"])
        m.append(row["m"])
        nbrs.extend(row["nbrs"])
        begin.append(len(nbrs))
        for name, value in row["vars"].items():
            values.setdefault(name, []).append(value)
    return {
        "t": np.array(t, dtype=np.int64),
        "m": np.array(m, dtype=np.int64),
        "nbr_begin": np.array(begin, dtype=np.int64),
        "nbrs": np.array(nbrs, dtype=np.int64),
        "vars": {name: np.array(v, dtype=np.int64) for name, v in values.items()},
    }
