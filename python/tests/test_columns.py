"""dwatch.replay's columns (python/src/columns.cpp): checked as strictly as a trace file's lines."""

import numpy as np
import pytest

import dwatch
from conftest import dwatch as cli

BOTH = "modules(a b); a.x=1 and b.x=1"


def columns(**changed):
    out = {"t": [0, 0], "m": [0, 1], "nbrs": [[1], [0]], "vars": {"x": [1, 1]}}
    out.update(changed)
    return out


def test_good_columns_of_any_integer_type_match():
    for x in ([1, 1], np.array([1, 1], dtype=np.int8), np.array([1, 1], dtype=np.uint64), np.array([1, 1], dtype=object)):
        assert len(dwatch.replay(columns(vars={"x": x}), BOTH, algorithm="centralized")["w1"]) == 2
    assert len(dwatch.replay(columns(t=np.array([0, 0], dtype=np.uint32)), BOTH, algorithm="centralized")["w1"]) == 2


def test_a_float_is_refused_as_the_file_refuses_it(tmp_path):
    with pytest.raises(dwatch.TraceError) as raised:
        dwatch.replay(columns(vars={"x": [1.5, 1]}), BOTH, algorithm="centralized")
    assert str(raised.value) == "the columns: line 0: variable 'x' must be an integer, not 1.5"
    with pytest.raises(dwatch.TraceError, match=r"line 0: variable 'x' must be an integer, not 1.5 \(a float64 column\)"):
        dwatch.replay(columns(vars={"x": np.array([1.5, 1])}), BOTH, algorithm="centralized")
    # The same data as a file: refused too.
    trace = tmp_path / "t.jsonl"
    trace.write_text('{"t":0,"m":0,"nbrs":[1],"vars":{"x":1.5}}\n{"t":0,"m":1,"nbrs":[0],"vars":{"x":1}}\n')
    printed = cli("replay", str(trace), "--watch", BOTH, check=False)
    assert printed.returncode == 2 and "variable 'x' must be an integer" in printed.stderr


@pytest.mark.parametrize(
    "changed, message",
    [
        ({"vars": {"x": [1, np.nan]}}, "line 1: variable 'x' must be an integer, not nan"),
        ({"vars": {"x": np.array([1, 2**63], dtype=np.uint64)}}, "line 1: variable 'x' does not fit in a signed 64-bit integer"),
        ({"vars": {"x": [1, 2**63]}}, "line 1: variable 'x' does not fit in a signed 64-bit integer"),
        ({"vars": {"x": [1, 2**64]}}, "line 1: variable 'x' does not fit in a signed 64-bit integer"),
        ({"vars": {"x": ["1", 1]}}, "line 0: variable 'x' must be an integer, not '1'"),
        ({"vars": {"x": [True, True]}}, "line 0: variable 'x' must be an integer, not True"),
        ({"t": [0.5, 0]}, 'line 0: step "t" must be an integer, not 0.5'),
        ({"m": [0, 1.0]}, 'line 1: module id "m" must be an integer, not 1.0'),
        ({"nbrs": [[1], [0.0]]}, 'line 1: neighbour id "nbrs" must be an integer, not 0.0'),
        ({"nbrs": [[1], "0"]}, 'line 1: "nbrs" must be a sequence of neighbour ids'),
        ({"vars": {"x": [[1], [1]]}}, "variable 'x' must be a one-dimensional array of integers"),
        ({"vars": [1, 1]}, '"vars" must be a dict'),
        ({"Vars": {"x": [1, 1]}}, "unknown key 'Vars'"),
    ],
)
def test_a_bad_column_names_the_column_and_the_line(changed, message):
    with pytest.raises(dwatch.TraceError, match="^the columns: .*" + message.replace("(", r"\(").replace(")", r"\)")):
        dwatch.replay(columns(**changed), BOTH, algorithm="centralized")


def test_numpy_integer_scalars_in_per_line_neighbours_are_integers():
    nbrs = [list(np.array([1])), list(np.array([0], dtype=np.uint8))]
    assert len(dwatch.replay(columns(nbrs=nbrs), BOTH, algorithm="centralized")["w1"]) == 2
