"""dwatch from Python: distributed watchpoints over modular-robot ensembles.

    import dwatch
    print(dwatch.check("modules(a b c);(a.isLeader = 1) and (c.isLeader = 1)"))
    found = dwatch.replay("run.jsonl", {"two_leaders": "modules(a b c);(a.isLeader = 1) and (c.isLeader = 1)"})
    s = dwatch.Session("scenarios/leader_election.toml", threads=2)
    s.run(to_match="two_leaders")

The package wraps the libraries the `dwatch` command runs (no second implementation): the same
checks, the same matches, the same state hashes, and the command line's words in its errors.
`dwatch.scenario_path(name)` finds the scenarios shipped with it.
"""

import pathlib
import sys

from . import _build_info


def _interpreter_problem(version: tuple, executable: str, implementation: str = "cpython") -> str:
    """Why this interpreter cannot load the compiled part (built for one CPython), or ""."""
    built_for = "Python %d.%d (%s)" % (*_build_info.PYTHON_VERSION, _build_info.PYTHON_EXECUTABLE)
    if implementation == "cpython" and tuple(version[:2]) == tuple(_build_info.PYTHON_VERSION):
        return ""
    this = "%s %d.%d (%s)" % ("Python" if implementation == "cpython" else implementation, *version[:2], executable)
    return (
        f"dwatch {_build_info.VERSION} was built for {built_for}, and this is {this}, which cannot load it: "
        f"run {_build_info.PYTHON_EXECUTABLE}, or build dwatch for this interpreter (docs/python.md)"
    )


if _interpreter_problem(sys.version_info, sys.executable, sys.implementation.name):
    raise ImportError(_interpreter_problem(sys.version_info, sys.executable, sys.implementation.name))

from ._dwatch import (  # noqa: E402
    ArgumentError,
    BudgetError,
    CommandError,
    Error,
    Matches,
    Module,
    ScenarioError,
    Session,
    TraceError,
    WatchError,
    __version__,
    check,
    replay,
)


def _scenario_folders() -> list:
    """Where the shipped scenarios are: beside the package (a wheel's copy, or build/python's link to
    the source tree), else under the installed prefix (PREFIX/share/dwatch/scenarios)."""
    package = pathlib.Path(__file__).resolve().parent
    folders = [package / "scenarios", (package / _build_info.INSTALLED_SCENARIOS).resolve()]
    return [f for f in folders if f.is_dir()]


def scenarios() -> list:
    """The names of the shipped scenarios (`leader_election.toml`, `lua/gradient.toml`, ...), sorted."""
    for folder in _scenario_folders():
        return sorted(p.relative_to(folder).as_posix() for p in [*folder.glob("*.toml"), *folder.glob("lua/*.toml")])
    return []


def scenario_path(name: str) -> pathlib.Path:
    """The path of a scenario shipped with dwatch, by its name (`dwatch.scenarios()` lists them), so that
    examples run outside a checkout: `dwatch.Session(dwatch.scenario_path("leader_election.toml"))`.
    FileNotFoundError when there is none of that name."""
    relative = pathlib.PurePosixPath(name)
    if not relative.parts or relative.is_absolute() or ".." in relative.parts:
        raise ValueError(f"a shipped scenario's name is relative and stays in its folder, not {name!r}")
    for folder in _scenario_folders():
        path = folder / relative
        if path.is_file():
            return path
    raise FileNotFoundError(f"no shipped scenario is named {name!r}; there are: {', '.join(scenarios())}")


__all__ = [
    "ArgumentError",
    "BudgetError",
    "CommandError",
    "Error",
    "Matches",
    "Module",
    "ScenarioError",
    "Session",
    "TraceError",
    "WatchError",
    "__version__",
    "check",
    "replay",
    "scenario_path",
    "scenarios",
]
