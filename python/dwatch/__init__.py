"""dwatch from Python: distributed watchpoints over modular-robot ensembles.

    import dwatch
    print(dwatch.check("modules(a b c);(a.isLeader = 1) and (c.isLeader = 1)"))
    found = dwatch.replay("run.jsonl", {"two_leaders": "modules(a b c);(a.isLeader = 1) and (c.isLeader = 1)"})
    s = dwatch.Session("scenarios/leader_election.toml", threads=2)
    s.run(to_match="two_leaders")

The package wraps the libraries the `dwatch` command runs (no second implementation): the same
checks, the same matches, the same state hashes, and the command line's words in its errors.
"""

from ._dwatch import (
    ArgumentError,
    BudgetError,
    CommandError,
    Error,
    Matches,
    ScenarioError,
    Session,
    TraceError,
    WatchError,
    __version__,
    check,
    replay,
)

__all__ = [
    "ArgumentError",
    "BudgetError",
    "CommandError",
    "Error",
    "Matches",
    "ScenarioError",
    "Session",
    "TraceError",
    "WatchError",
    "__version__",
    "check",
    "replay",
]
