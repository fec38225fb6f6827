"""Type stubs of dwatch._dwatch, the compiled part of the package (python/src/)."""

import os
from typing import Any, Mapping, Optional, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt

__version__: str

class Error(Exception):
    """What dwatch refuses or fails to do; its message is the command line's."""

    file: Optional[str]
    """Where the (first) mistake is, when the error says: a file's path, "<watch NAME>", "<command>"."""
    line: Optional[int]
    column: Optional[int]

class ArgumentError(Error, ValueError):
    """An argument out of its range or not one of its words."""

class WatchError(Error, ValueError):
    """A watchpoint with mistakes: the first one's place and message, and the caret text of all."""

    message: str
    text: str

class ScenarioError(Error, ValueError):
    """A scenario file that cannot be loaded (file:line:col: error: ... lines)."""

class TraceError(Error, ValueError):
    """A trace file or trace columns with mistakes."""

class BudgetError(Error):
    """A watchpoint exceeded max_live and stopped; the others went on."""

    matches: dict[str, "Matches"]
    """Every watchpoint's matches, the stopped ones' up to their stop."""
    stopped: dict[str, str]
    """The stopped watchpoints and why."""

class CommandError(Error):
    """A session command that is wrong or failed, in `dwatch session`'s words."""

class Matches:
    """One watchpoint's matches, in the match log's order (by t, then by slot ids)."""

    @property
    def watch(self) -> str: ...
    @property
    def slot_names(self) -> list[str]: ...
    @property
    def t(self) -> npt.NDArray[np.int64]:
        """Watch step of each match, shape (n,)."""
    @property
    def detected(self) -> npt.NDArray[np.int64]:
        """Step during which each match was found (t + lag), shape (n,)."""
    @property
    def slots(self) -> npt.NDArray[np.int64]:
        """Module filling each slot, shape (n, len(slot_names))."""
    @property
    def count(self) -> int:
        """Every match, also when only counted (count_only=True, a `count` watchpoint): the arrays are then empty."""
    def records(self) -> np.recarray:
        """Fields t, detected and one per slot (slot_NAME for a slot named t or detected)."""
    def to_pandas(self) -> Any:
        """A pandas DataFrame of records(); needs pandas."""
    def __len__(self) -> int: ...

_Columns = Mapping[str, Any]
"""Trace columns: "t", "m" (one entry per line), "nbr_begin" + "nbrs" (offsets and flat ids) or
"nbrs" (a sequence per line), and "vars" (variable name -> one value per line)."""

def check(text: str, name: str = "w1") -> str:
    """What `dwatch check` prints for the watchpoint; raises WatchError."""

def replay(
    trace: Union[str, os.PathLike[str], _Columns],
    watches: Union[None, str, Sequence[str], Mapping[str, str]] = None,
    algorithm: str = "distributed",
    shape: Optional[str] = None,
    states: Optional[str] = None,
    max_live: int = 20000000,  # sim::kDefaultMatchBudget (sim/watch_spec.h): a stub says the value
    count_only: bool = False,
) -> dict[str, Matches]:
    """Watchpoints over a trace file or columns, as `dwatch replay` runs them."""

_Point = Tuple[float, float, float]

class Module:
    """A module's side of the host-program API during one call of a Python program's step(m)
    (the Lua hosts' m); unusable once that call has returned. Only dwatch makes them."""

    @property
    def id(self) -> int:
        """This module's id."""
    @property
    def step(self) -> int:
        """The step being run."""
    def get(self, name: str) -> int:
        """A variable's value at the step before (its initial value at 0)."""
    def set(self, name: str, value: int) -> None:
        """Assigns the variable's value at this step."""
    def param(self, name: str) -> int:
        """A parameter's value (the scenario's, or the default)."""
    def neighbors(self) -> list[int]:
        """The neighbours' ids, ascending."""
    def inbox(self) -> list[Tuple[int, list[int]]]:
        """This program's messages of the step before: [(sender, [words]), ...]."""
    def send(self, to: int, words: Sequence[int]) -> None:
        """Sends up to 8 integers to a neighbour."""
    def broadcast(self, words: Sequence[int]) -> None:
        """Sends the same message to every neighbour."""
    def random(self, n: int) -> int:
        """0 .. n - 1 (n = 0: 64 bits), a pure function of the run."""
    def position(self) -> Tuple[float, float, float]:
        """The body's centre (x, y, z) as the step began; physics only."""
    def moving(self) -> bool:
        """Whether a lattice move is under way; physics only."""
    def move(self, x: float, y: float, z: float) -> None:
        """A lattice move; physics only."""
    def push(self, x: float, y: float, z: float) -> None:
        """An impulse; physics only."""
    def pivot(self, about: int, x: float, y: float, z: float) -> None:
        """A pivot about a neighbour into the cell at (x, y, z) from this one; physics only."""

class Snapshot:
    """A Session as it was (Session.snapshot()), to restore() it."""

    @property
    def current(self) -> int:
        """The step that was current."""
    @property
    def latest(self) -> int:
        """The last step that was simulated."""

class Session:
    """A debugging session over a scenario file, as `dwatch session` runs it."""

    def __init__(
        self,
        scenario: Union[str, os.PathLike[str]],
        threads: Optional[int] = None,
        seed: Optional[int] = None,
        history_mb: Optional[int] = None,
        programs: Optional[dict[str, Any]] = None,
    ) -> None: ...
    def close(self) -> None:
        """Frees the session now; any later call raises Error."""
    def fork(self) -> "Session":
        """An independent copy of the session, to try another branch beside this one."""
    def snapshot(self) -> Snapshot:
        """The session as it is now, everything that changes, for restore() (MuJoCo's mj_getState)."""
    def restore(self, snapshot: Snapshot) -> None:
        """Makes the session what it was at snapshot() (MuJoCo's mj_setState)."""
    def __enter__(self) -> "Session": ...
    def __exit__(self, *args: object) -> None: ...
    def command(self, line: str) -> Optional[dict[str, Any]]:
        """Any command of the session language; its answer."""
    def step(self, n: int = 1) -> dict[str, Any]: ...
    def run(self, t: Optional[int] = None, to_match: Optional[str] = None) -> dict[str, Any]: ...
    def continue_(self) -> dict[str, Any]: ...
    def seek(self, t: int) -> dict[str, Any]: ...
    def set(self, module: int, variable: str, value: int) -> dict[str, Any]: ...
    def remove(self, module: int) -> dict[str, Any]: ...
    def push(self, module: int, x: float, y: float, z: float) -> dict[str, Any]: ...
    def watch(
        self,
        name: str,
        text: str,
        algorithm: str = "distributed",
        shape: Optional[str] = None,
        states: Optional[str] = None,
        action: str = "log",
        max_live: int = 20000000,  # sim::kDefaultMatchBudget (sim/watch_spec.h): a stub says the value
    ) -> dict[str, Any]: ...
    def unwatch(self, name: str) -> dict[str, Any]: ...
    def action(self, name: str, action: str) -> dict[str, Any]: ...
    def matches(self, name: str) -> Matches: ...
    def why(
        self, m: int, var: str, t: Optional[int] = None, *, depth: int = 3, narrow: bool = False
    ) -> dict[str, Any]:
        """Why var of module m is what it is at step t: its causal history (`why`) as a dict."""
    def why_match(self, w: str, row: int, *, depth: int = 3, narrow: bool = False) -> dict[str, Any]:
        """Why watchpoint w matched in its row-th match: the cone of the values it read (`why match`)."""
    def state(self, module: int) -> dict[str, Any]:
        """The module at the current step: variables, neighbours, and with physics its pose after the step ('pose') and the one its neighbours were measured from, at the end of the step before ('nbrs_measured_from')."""
    def values(self, variable: str) -> np.ma.MaskedArray[Any, np.dtype[np.int64]]:
        """One variable of every module at the current step, shape (modules,), absent modules masked."""
    def neighbours(self) -> Tuple[npt.NDArray[np.int64], npt.NDArray[np.int64]]:
        """N(m, t) at the current step as compressed rows (indptr, indices)."""
    def _repr_png_(self) -> bytes:
        """The current view as PNG bytes, for Jupyter."""
    def present(self) -> npt.NDArray[np.bool_]:
        """Which modules are present at the current step, shape (modules,)."""
    def series(self, module: int, variable: str, first: int, last: int) -> np.ma.MaskedArray[Any, np.dtype[np.int64]]:
        """One variable of one module over steps first..last, shape (last - first + 1,), masked where absent."""
    def hash(self) -> str: ...
    def render(
        self, width: int = 1280, height: int = 720, camera: Optional[Tuple[_Point, _Point]] = None
    ) -> npt.NDArray[np.uint8]:
        """The 3D view of the current step, shape (height, width, 3)."""
    def save(self, path: Union[str, os.PathLike[str]], overwrite: bool = False) -> dict[str, Any]: ...
    def record(self, path: Union[str, os.PathLike[str]]) -> dict[str, Any]: ...
    @property
    def current(self) -> int: ...
    @property
    def latest(self) -> int: ...
    @property
    def end(self) -> int: ...
    @property
    def modules(self) -> int: ...
    @property
    def variables(self) -> list[str]: ...
    @property
    def watches(self) -> list[str]: ...
